#!/usr/bin/env python3
"""Where a build's time goes: per target and per translation unit, from scripts/time_command.py's log.

    scripts/build_times.py LOG [--top N] [--csv FILE] [--jobs J]

Prints the whole build's CPU time (user + sys of every compile and link), the CPU time per
target (CMake's `CMakeFiles/<target>.dir/` in the object's path; a link under its output's name),
the N most expensive translation units, and what the CPU time implies on an idle machine of J
cores: at best CPU / J, and never less than the longest single command. `--csv` writes one row
per command with the target it belongs to.
"""
import argparse
import collections
import csv
import re
import sys


def read_log(path):
    """Rows of the launcher's log: dicts with kind, output, target, cpu, wall, rss_mib."""
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            parts = line.rstrip("\n").split("\t")
            if len(parts) != 6:
                sys.exit(f"build_times.py: {path}:{n}: expected 6 tab-separated fields")
            kind, output, user, system, wall, rss = parts
            rows.append({"kind": kind, "output": output, "target": target_of(kind, output),
                         "cpu": float(user) + float(system), "wall": float(wall),
                         "rss_mib": int(rss) / 1024})
    return rows


def target_of(kind, output):
    """The CMake target a compile or link belongs to."""
    m = re.search(r"CMakeFiles/([^/]+)\.dir/", output)
    if m:
        return m.group(1)
    name = output.rsplit("/", 1)[-1]
    return re.sub(r"^lib|\.(a|so)$|\.cpython.*$", "", name) or output


def source_of(output):
    """A translation unit's source, from its object path (CMakeFiles/t.dir/a/b.cpp.o -> a/b.cpp)."""
    m = re.search(r"CMakeFiles/[^/]+\.dir/(.*)\.o$", output)
    return m.group(1) if m else output


def print_summary(rows, top, jobs):
    total = sum(r["cpu"] for r in rows)
    compiles = [r for r in rows if r["kind"] == "compile"]
    links = [r for r in rows if r["kind"] == "link"]
    longest = max((r["cpu"] for r in rows), default=0.0)
    print(f"{len(compiles)} compiles, {len(links)} links: CPU {total:.0f} s "
          f"(compile {sum(r['cpu'] for r in compiles):.0f} s, "
          f"link {sum(r['cpu'] for r in links):.0f} s)")
    print(f"on an idle {jobs}-core machine: at least {max(total / jobs, longest):.0f} s wall "
          f"({total / jobs / 60:.1f} min; the longest command {longest:.0f} s)")
    per_target = collections.defaultdict(lambda: [0, 0.0])
    for r in rows:
        per_target[r["target"]][0] += 1
        per_target[r["target"]][1] += r["cpu"]
    print(f"\n{'target':<28}{'commands':>9}{'CPU s':>9}{'share':>8}")
    for name, (count, cpu) in sorted(per_target.items(), key=lambda kv: -kv[1][1]):
        print(f"{name:<28}{count:>9}{cpu:>9.1f}{100 * cpu / total:>7.1f}%")
    print(f"\nthe {top} most expensive translation units")
    print(f"{'CPU s':>7}{'RSS MiB':>9}  source (target)")
    for r in sorted(compiles, key=lambda r: -r["cpu"])[:top]:
        print(f"{r['cpu']:>7.1f}{r['rss_mib']:>9.0f}  {source_of(r['output'])} ({r['target']})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log", help="the log scripts/time_command.py appended to")
    ap.add_argument("--top", type=int, default=25, help="translation units to list (25)")
    ap.add_argument("--jobs", type=int, default=2, help="cores of the machine to estimate for (2)")
    ap.add_argument("--csv", help="write one row per command to this file")
    args = ap.parse_args()
    rows = read_log(args.log)
    if not rows:
        sys.exit(f"build_times.py: {args.log}: no commands logged")
    print_summary(rows, args.top, args.jobs)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=["kind", "target", "output", "cpu", "wall", "rss_mib"])
            w.writeheader()
            for r in rows:
                w.writerow({k: (round(v, 3) if isinstance(v, float) else v) for k, v in r.items()})
        print(f"\nrows: {args.csv}")


if __name__ == "__main__":
    main()
