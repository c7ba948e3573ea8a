#!/usr/bin/env bash
# The main job: run every experiment, draw every figure, write results/REPORT.md.
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
echo "== report =="
"$PYTHON" analysis/report.py "$RESULTS"
echo "reproduce: done in $(( $(date +%s) - start )) s; see $RESULTS/REPORT.md"
