"""python/sweeps/compare_experiment.py on a real pair: the damping_sweep experiment (quick) and a
physik.sweep of the same grid agree on every column the experiment's schema (its summary.json
"tables") lists; a changed cell is found (exit 1); an experiment folder without the schema is
refused naming its summary.json (exit 2)."""
import csv
import json
import os
import subprocess
import sys

from conftest import BINARY, SCENES, SOURCE_DIR, read_json

SCRIPT = os.path.join(SOURCE_DIR, "python", "sweeps", "compare_experiment.py")


def compare(exp_csv, results_csv):
    p = subprocess.run([sys.executable, SCRIPT, "damping_sweep", exp_csv, results_csv],
                       capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def sweep_like(tmp_path, exp_csv):
    """Run physik.sweep over the experiment's scenes and dampings (its quick run: 100 steps)."""
    with open(exp_csv) as f:
        rows = list(csv.DictReader(f))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    spec = {"name": "quick_damping", "steps": 100, "stop_when_converged": True,
            "scenes": [os.path.join(SCENES, s + ".json") for s in scenes],
            "grid": {"damping": [float(d) for d in dict.fromkeys(r["damping"] for r in rows)]}}
    spec_path = tmp_path / "spec.json"
    spec_path.write_text(json.dumps(spec))
    out = tmp_path / "sweep"
    subprocess.run([sys.executable, "-m", "physik.sweep", str(spec_path), "--out", str(out)],
                   check=True, capture_output=True)
    return str(out / "results.csv")


def test_the_sweep_agrees_with_the_experiment_on_its_schemas_columns(tmp_path):
    exp = tmp_path / "exp"
    subprocess.run([BINARY, "experiment", "run", "damping_sweep", "--quick", "--out", str(exp),
                    "--models", os.path.join(SOURCE_DIR, "models")],
                   check=True, capture_output=True)
    exp_csv = str(exp / "damping_sweep" / "sweep.csv")
    results = sweep_like(tmp_path, exp_csv)
    status, out = compare(exp_csv, results)
    assert status == 0, out
    schema = read_json(str(exp / "damping_sweep" / "summary.json"))["tables"]["sweep"]
    names = [c["name"] for c in schema["columns"] if c["csv"]]
    assert "compared on %s (not in the sweep: none), 0 differ" % ", ".join(names) in out

    with open(results) as f:
        rows = list(csv.DictReader(f))
    fields = list(rows[0].keys())
    rows[0]["steps_run"] = str(int(rows[0]["steps_run"]) + 1)
    changed = str(tmp_path / "changed.csv")
    with open(changed, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    status, out = compare(exp_csv, changed)
    assert status == 1 and "row 1 differs" in out, out

    os.remove(str(exp / "damping_sweep" / "summary.json"))
    status, out = compare(exp_csv, results)
    assert status == 2 and "summary.json" in out, out
