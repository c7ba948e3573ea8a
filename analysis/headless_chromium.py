"""Headless Chromium through chromedriver (Debian's chromium, chromium-driver and
python3-selenium), as the viewer's tests and benchmark drive it. SwiftShader renders WebGL on
the CPU: --use-angle=swiftshader --enable-unsafe-swiftshader; as root the sandbox is off and the
browser's background services with it; every start gets a fresh profile folder.
"""
import os
import shutil
import tempfile


def start(width=1000, height=1000):
    """(driver, None), or (None, the reason Chromium cannot start)."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service
    except ImportError as e:
        return None, "python3-selenium is missing (%s)" % e
    o = Options()
    o.binary_location = shutil.which("chromium") or "/usr/bin/chromium"
    args = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader", "--window-size=%d,%d" % (width, height),
            "--user-data-dir=" + tempfile.mkdtemp(prefix="physik_chromium_")]
    if os.geteuid() == 0:
        args += ["--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]
    for a in args:
        o.add_argument(a)
    o.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    try:
        service = Service(shutil.which("chromedriver") or "/usr/bin/chromedriver")
        return webdriver.Chrome(service=service, options=o), None
    except Exception as e:  # no binary, no driver, or a browser that will not start
        return None, "Chromium cannot start: %s" % str(e).strip().splitlines()[0]
