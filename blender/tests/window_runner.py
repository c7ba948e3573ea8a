#!/usr/bin/env python3
"""Run a Blender script in a real Blender window on a virtual X display (Xvfb), for what
background mode (-b) cannot do: window-manager timers, modal operators, key events, viewport
drawing (ctest: blender_window; blender/bench_live.py uses it too).

    window_runner.py --blender blender [--size 800x600] [--timeout 300] [--result FILE] \\
        [--event-simulate] SCRIPT [-- SCRIPT_ARGS...]

Blender runs as `xvfb-run -a -s "-screen 0 WxHx24" blender --factory-startup
--window-geometry 0 0 W H [--enable-event-simulate] --python SCRIPT -- SCRIPT_ARGS
[--result FILE]`, with TMPDIR in a scratch folder (Blender's quit.blend and autosaves land there).
With --result, the script must write that JSON file ({"failed": [...], ...}); a missing file, a
non-empty "failed" or a non-zero exit fails the run.

Run it with the system Python (/usr/bin/python3, as ctest does): a pyenv python3 puts its own
bin folder first on PATH, and Blender's embedded Python then takes that interpreter's standard
library (no numpy there; the add-on then reports that numpy cannot be imported).

Exit status: Blender's (0 passed), 1 a failure the runner saw (timeout, no result), 77 skipped:
xvfb-run is not installed (Debian: apt-get install xvfb; scripts/install-deps.sh installs it).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

SKIP = 77  # ctest SKIP_RETURN_CODE


def parse_args(argv):
    if "--" in argv:
        k = argv.index("--")
        argv, script_args = argv[:k], argv[k + 1:]
    else:
        script_args = []
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--blender", default="blender")
    p.add_argument("--size", default="800x600", help="window size WxH (pixels)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds before Blender is killed")
    p.add_argument("--result", help="JSON file the script writes (passed to it as --result)")
    p.add_argument("--event-simulate", action="store_true",
                   help="Blender's --enable-event-simulate (Window.event_simulate; real input ignored)")
    p.add_argument("script")
    args = p.parse_args(argv)
    args.script_args = script_args
    try:
        args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    except ValueError:
        p.error("--size: expected WxH, got %r" % args.size)
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    xvfb_run = shutil.which("xvfb-run")
    if xvfb_run is None:
        print("SKIPPED: xvfb-run not found; a Blender window needs an X display "
              "(Debian: apt-get install xvfb)")
        return SKIP
    blender = shutil.which(args.blender)
    if blender is None:
        print("window_runner.py: Blender not found: %s" % args.blender, file=sys.stderr)
        return 1
    with tempfile.TemporaryDirectory(prefix="physik_window_") as tmp:
        script_args = list(args.script_args)
        if args.result:
            if os.path.exists(args.result):
                os.remove(args.result)
            script_args += ["--result", os.path.abspath(args.result)]
        env = dict(os.environ, TMPDIR=tmp)
        # a sanitizer build preloads the ASan runtime for Blender (which loads the module), not
        # for the X server
        preload = env.pop("LD_PRELOAD", None)
        cmd = [xvfb_run, "-a", "-s", "-screen 0 %dx%dx24" % (args.width, args.height)]
        if preload:
            cmd += [shutil.which("env") or "/usr/bin/env", "LD_PRELOAD=" + preload]
        cmd += [blender, "--factory-startup",
                "--window-geometry", "0", "0", str(args.width), str(args.height)]
        if args.event_simulate:
            cmd.append("--enable-event-simulate")
        cmd += ["--python", os.path.abspath(args.script), "--"] + script_args
        try:
            rc = subprocess.run(cmd, env=env, timeout=args.timeout).returncode
        except subprocess.TimeoutExpired:
            print("window_runner.py: Blender did not finish within %g s" % args.timeout,
                  file=sys.stderr)
            return 1
    if not args.result:
        return rc
    try:
        with open(args.result, encoding="utf-8") as f:
            result = json.load(f)
    except (OSError, ValueError) as e:
        print("window_runner.py: no result from the script (%s); Blender exited %d" % (e, rc),
              file=sys.stderr)
        return 1
    failed = result.get("failed", ["(no 'failed' list)"])
    print("window_runner.py: %d passed, %d failed; Blender exited %d"
          % (len(result.get("passed", [])), len(failed), rc))
    return 0 if rc == 0 and not failed else 1


if __name__ == "__main__":
    sys.exit(main())
