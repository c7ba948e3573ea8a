#!/usr/bin/env bash
# The main job: run every experiment, draw every figure, write results/REPORT.md and
# results/REPORT.html (the report with the experiments' runs in embedded 3D viewers).
# Environment: PHYSIK (the built binary), PYTHON (an interpreter with matplotlib), RESULTS.
set -euo pipefail
cd "$(dirname "$0")/.."
PHYSIK=${PHYSIK:-build/physik}
PYTHON=${PYTHON:-/usr/bin/python3}
RESULTS=${RESULTS:-results}
export MPLBACKEND=Agg
start=$(date +%s)
mkdir -p "$RESULTS"
"$PHYSIK" experiment list | cut -f1 > "$RESULTS/order.txt"
"$PHYSIK" params --json > "$RESULTS/params.json"  # the report's settings table reads it
# the experiments, JOBS at a time (each is one process on one core: ik_comparison and
# linearisation take about six minutes each), each logging to $RESULTS/logs/<name>.log; a failed
# experiment's log is printed and the run stops with its exit status
JOBS=${JOBS:-2}
mkdir -p "$RESULTS/logs"
echo "== experiments ($(wc -l < "$RESULTS/order.txt"), $JOBS at a time) =="
run_experiment() {
  local name=$1 t0 rc=0
  t0=$(date +%s)
  "$PHYSIK" experiment run "$name" --out "$RESULTS" --models models > "$RESULTS/logs/$name.log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "[$name] FAILED (exit $rc); its log, $RESULTS/logs/$name.log:" >&2
    cat "$RESULTS/logs/$name.log" >&2
    return 255  # xargs stops at once
  fi
  echo "[$name] done in $(( $(date +%s) - t0 )) s"
}
export -f run_experiment
export PHYSIK RESULTS
xargs -P "$JOBS" -n 1 bash -c 'run_experiment "$0"' < "$RESULTS/order.txt"
echo "== figures =="
while read -r name; do
  script="analysis/plot_${name}.py"
  if [ -f "$script" ]; then
    echo "[$name] $script"
    "$PYTHON" "$script" "$RESULTS/$name"
  else
    echo "[$name] no analysis script" >&2
    exit 1
  fi
done < "$RESULTS/order.txt"
echo "== animations (Figs 7, 10, 11) =="
"$PYTHON" analysis/animate.py --experiment "$RESULTS/fig7_cannon"
"$PYTHON" analysis/animate.py --experiment "$RESULTS/fig10_interpolation" --view front
"$PYTHON" analysis/animate.py --experiment "$RESULTS/fig11_sit" --view side
echo "== viewer benchmark =="
"$PYTHON" analysis/viewer_benchmark.py "$RESULTS/viewer_benchmark" --physik "$PHYSIK" \
  --models models
echo "== report =="
"$PYTHON" analysis/report.py "$RESULTS" --physik "$PHYSIK"
echo "reproduce: done in $(( $(date +%s) - start )) s; see $RESULTS/REPORT.md and REPORT.html"
