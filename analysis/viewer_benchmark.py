#!/usr/bin/env python3
"""The viewer's benchmarks (figures for the report, never test thresholds), written as an
experiment-like folder: OUT/summary.json with a "report" section that analysis/report.py
gathers into REPORT.md.

1. A 100-bone, 10,000-frame run: `physik rig chain 100` (bones 0.05 long, radius 0.02), its root
   pinned and its tip pulled sideways, `physik simulate --steps 9999 --every 1` (the initial
   state and 9,999 steps: 10,000 rows, all kept under the default cap), `physik view`. Measured:
   the page's size and the time `physik view` takes; in headless Chromium (SwiftShader, a
   1000 x 1000 window): the time from navigation to the first drawn frame, then playback for
   5 s, the frame rate from requestAnimationFrame timestamps (the viewer draws on every
   animation frame while it plays, placing all 100 capsules), with the median and 95th
   percentile frame times.
2. pinhead over 600 frames (models/scenes/pinhead_two_hands.json, --steps 599 --every 1): the
   page's size against the 2 MB target.
3. Screenshots of both pages, paused at their middle frame: OUT/chain100.png, OUT/pinhead600.png.
The run folders are removed once their pages are written (the chain's trajectory.csv is ~70 MB).
Where Chromium cannot start, part 1's browser figures say so.

Run: python3 analysis/viewer_benchmark.py --physik build/physik OUT [--models models]
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import headless_chromium  # noqa: E402

PLAY_SECONDS = 5.0
MEASURE_PLAYBACK = """
var done = arguments[arguments.length - 1], v = window.physikViewers[0], seconds = arguments[0];
v.speed = 10;
v.play();
var stamps = [], f0 = v.frame, r0 = v.renders;
function tick(t) {
  stamps.push(t);
  if (t - stamps[0] < 1000 * seconds && v.playing) requestAnimationFrame(tick);
  else done({stamps: stamps, frames_advanced: v.frame - f0, renders: v.renders - r0});
}
requestAnimationFrame(tick);
"""


def physik(binary, *args):
    subprocess.run([binary] + [str(a) for a in args], check=True)


def chain_run(binary, out):
    """The 100-bone, 10,000-frame run folder, and the page `physik view` makes of it."""
    rig = os.path.join(out, "chain100.json")
    physik(binary, "rig", "chain", 100, "--bone-length", 0.05, "--out", rig)
    with open(rig) as f:
        doc = json.load(f)
    for b in doc["bones"]:
        b["radius"] = 0.02  # drawn capsules in proportion to 0.05-long bones
    with open(rig, "w") as f:
        json.dump(doc, f)
    scene = os.path.join(out, "chain100_scene.json")
    with open(scene, "w") as f:
        json.dump({"rig": "chain100.json", "steps": 9999, "control_points": [
            {"name": "root", "bone": "b0", "alpha": 0.0, "target": [0, 0, 0]},
            {"name": "tip", "bone": "b99", "alpha": 1.0, "target": [2.5, 0, 3.0]}]}, f)
    run = os.path.join(out, "chain100_run")
    physik(binary, "simulate", scene, "--every", 1, "--quiet", "--out", run)
    page = os.path.join(out, "chain100.html")
    t0 = time.time()
    physik(binary, "view", run, "--out", page)
    seconds = time.time() - t0
    shutil.rmtree(run)
    return page, seconds


def first_frame(driver, page):
    """Loads the page; seconds from navigation to the viewer's first drawn frame."""
    t0 = time.time()
    driver.get("file://" + os.path.abspath(page))
    while not driver.execute_script(
            "return window.physikViewers && window.physikViewers[0].renders > 0"):
        time.sleep(0.02)
    return time.time() - t0


def playback(driver):
    """Plays the loaded page for PLAY_SECONDS: requestAnimationFrame timings."""
    driver.set_script_timeout(60 + PLAY_SECONDS)
    r = driver.execute_async_script(MEASURE_PLAYBACK, PLAY_SECONDS)
    gaps = [b - a for a, b in zip(r["stamps"], r["stamps"][1:])]
    span = (r["stamps"][-1] - r["stamps"][0]) / 1000
    return {"frames_in_page": driver.execute_script("return window.physikViewers[0].times.length"),
            "fps": len(gaps) / span, "median_frame_ms": statistics.median(gaps),
            "p95_frame_ms": sorted(gaps)[int(0.95 * (len(gaps) - 1))],
            "renders": r["renders"], "frames_advanced": r["frames_advanced"], "seconds": span}


def browse(chain_page, pinhead_page, out):
    """In headless Chromium: the chain page's first frame and playback, then a screenshot of each
    page (mid-run) in OUT; or {"error": why Chromium cannot start}."""
    driver, why = headless_chromium.start()
    if driver is None:
        return {"error": why}
    try:
        result = {"first_frame_s": first_frame(driver, chain_page)}
        result.update(playback(driver))
        for name, page in (("chain100", chain_page), ("pinhead600", pinhead_page)):
            if page != chain_page:
                first_frame(driver, page)
            driver.execute_script("var v = window.physikViewers[0]; v.pause(); "
                                  "v.setFrame(Math.floor(v.times.length / 2));")
            time.sleep(0.3)
            driver.save_screenshot(os.path.join(out, name + ".png"))
    finally:
        driver.quit()
    return result


def pinhead_page(binary, models, out):
    run = os.path.join(out, "pinhead600_run")
    physik(binary, "simulate", os.path.join(models, "scenes", "pinhead_two_hands.json"),
           "--steps", 599, "--every", 1, "--quiet", "--out", run)
    page = os.path.join(out, "pinhead600.html")
    physik(binary, "view", run, "--out", page)
    shutil.rmtree(run)
    return page


def data_bytes(page):
    """Bytes of the page's runs: its JSON data script (viewer/page.html)."""
    with open(page, encoding="utf-8") as f:
        text = f.read()
    start = text.index(">", text.index('id="physik-data"')) + 1
    return len(text[start:text.index("</script>", start)].encode("utf-8"))


def report(chain_page, view_s, browser, pinhead):
    mb = lambda p: os.path.getsize(p) / 1e6  # noqa: E731
    rows = [["100 bones, 10,000 frames: page size", "%.1f MB" % mb(chain_page)],
            ["100 bones, 10,000 frames: `physik view` time", "%.1f s" % view_s],
            ["pinhead, 600 frames: page size (target: at most 2 MB)", "%.2f MB" % mb(pinhead)],
            ["pinhead, 600 frames: of which the runs' data (the rest: three.js, the viewer)",
             "%.2f MB" % (data_bytes(pinhead) / 1e6)]]
    if "error" in browser:
        rows.append(["100 bones, 10,000 frames in headless Chromium", browser["error"]])
    else:
        rows += [["100 bones, 10,000 frames: navigation to first drawn frame",
                  "%.1f s" % browser["first_frame_s"]],
                 ["100 bones, 10,000 frames: playback frame rate (requestAnimationFrame)",
                  "%.1f frames/s (median %.1f ms, 95th percentile %.1f ms; %d draws in %.1f s)"
                  % (browser["fps"], browser["median_frame_ms"], browser["p95_frame_ms"],
                     browser["renders"], browser["seconds"])]]
    return {"title": "The viewer: page sizes and playback in headless Chromium",
            "claims": [],
            "notes": ["Benchmarks, not test thresholds; analysis/viewer_benchmark.py says how "
                      "each is measured. Headless Chromium renders WebGL on the CPU "
                      "(SwiftShader): a GPU draws faster. Pages inline three.js r111 (Debian's "
                      "libjs-three)."],
            "tables": [{"title": "Viewer benchmarks", "columns": ["measure", "value"],
                        "rows": rows}],
            "figures": [] if "error" in browser else ["chain100.png", "pinhead600.png"]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", help="the benchmark's folder (results/viewer_benchmark)")
    ap.add_argument("--physik", required=True, help="the physik binary")
    ap.add_argument("--models", default="models")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    chain_page, view_s = chain_run(a.physik, a.out)
    pinhead = pinhead_page(a.physik, a.models, a.out)
    browser = browse(chain_page, pinhead, a.out)
    summary = {"experiment": "viewer_benchmark", "chain100": browser,
               "chain100_page_bytes": os.path.getsize(chain_page), "view_seconds": view_s,
               "pinhead600_page_bytes": os.path.getsize(pinhead),
               "report": report(chain_page, view_s, browser, pinhead)}
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    for row in summary["report"]["tables"][0]["rows"]:
        print("  %s: %s" % tuple(row))


if __name__ == "__main__":
    main()
