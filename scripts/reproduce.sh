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
echo "== experiments ($(wc -l < "$RESULTS/order.txt")) =="
"$PHYSIK" experiment run --out "$RESULTS" --models models
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
