#!/usr/bin/env python3
"""`make bench-count`'s tool (bench/bench_count.py, bench/count_steps.cpp) on a tiny chain.

    bench_count_test.py SOURCE_DIR PHYSIK_COUNT

- the parser reads a callgrind output file's `totals:` line by its `events:` line (callgrind
  leaves out trailing zeros), and refuses a file without one;
- a 10-bone chain counted over N and 2 N steps, schemes exact and implicit: every count positive
  and finite, and per bone-step the same for steps N+1 .. 2N as for the first N (within 2%: the
  exact step's work does not depend on the state, so a set-up counted with the steps, or steps
  not counted, would show as a ratio away from 1);
- the counted run is the run: its final_state_hash equals physik_count's without valgrind;
- bad options exit 2, naming the option.
Exits 77 (skipped) where valgrind is not installed (scripts/install-deps.sh installs it).
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SOURCE_DIR, BINARY = (sys.argv.pop(1), sys.argv.pop(1)) if len(sys.argv) > 2 else ("", "")
sys.path.insert(0, os.path.join(SOURCE_DIR, "bench"))
import bench_count  # noqa: E402  (bench/, found through SOURCE_DIR)

BONES, STEPS = 10, 20


class ParserTest(unittest.TestCase):
    def test_totals_line(self):
        with tempfile.NamedTemporaryFile("w", suffix=".out", delete=False) as f:
            f.write("version: 1\ncreator: callgrind-3.19.0\nevents: Ir\n"
                    "fn=(1) count_stepping_loop\n5 12\nsummary: 123456\ntotals: 123457\n")
        try:
            self.assertEqual(bench_count.callgrind_total(f.name), 123457)
        finally:
            os.unlink(f.name)

    def test_events_and_trailing_zeros(self):
        with tempfile.NamedTemporaryFile("w", suffix=".out", delete=False) as f:
            f.write("events: Ir Dr Dw I1mr D1mr D1mw ILmr DLmr DLmw\n"
                    "totals: 5215956 1420142 494122 1389 26385 25611 372 14\n")
        try:
            e = bench_count.callgrind_totals(f.name)
            self.assertEqual((e["Ir"], e["D1mw"], e["DLmr"], e["DLmw"]), (5215956, 25611, 14, 0))
        finally:
            os.unlink(f.name)

    def test_no_totals(self):
        with tempfile.NamedTemporaryFile("w", suffix=".out", delete=False) as f:
            f.write("version: 1\nevents: Ir\n")
        try:
            with self.assertRaisesRegex(ValueError, "no 'totals:'"):
                bench_count.callgrind_total(f.name)
        finally:
            os.unlink(f.name)


class CountTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.mkdtemp()
        cls.rows = {s: bench_count.case(BINARY, "chain", BONES, s, STEPS, cls.scratch)
                    for s in ("exact", "implicit")}

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch)

    def test_counts_positive_and_finite(self):
        for scheme, r in self.rows.items():
            for key in ("ir_first", "ir_double", "ir_per_bone_step", "ir_per_bone_step_next"):
                self.assertTrue(math.isfinite(r[key]) and r[key] > 0, f"{scheme} {key} {r[key]}")
            self.assertGreater(r["ir_double"], r["ir_first"], scheme)

    def test_next_steps_cost_the_same(self):
        for scheme, r in self.rows.items():
            self.assertAlmostEqual(r["next_over_first"], 1.0, delta=0.02,
                                   msg=f"{scheme}: {r['ir_per_bone_step']:.1f} then "
                                       f"{r['ir_per_bone_step_next']:.1f} Ir per bone-step")

    def test_counted_run_is_the_run(self):
        for scheme, r in self.rows.items():
            p = subprocess.run([BINARY, "--bones", str(BONES), "--scheme", scheme, "--steps",
                                str(2 * STEPS)], capture_output=True, text=True, check=True)
            self.assertEqual(json.loads(p.stdout)["final_state_hash"], r["final_state_hash"],
                             scheme)


class BadInputTest(unittest.TestCase):
    def test_driver(self):
        for args, option in ((["--scheme", "rk4"], "--scheme"), (["--bones", "0"], "--bones"),
                             (["--steps", "x"], "--steps")):
            p = subprocess.run([BINARY] + args, capture_output=True, text=True, check=False)
            self.assertEqual(p.returncode, 2, args)
            self.assertIn(option, p.stderr, args)

    def test_script(self):
        script = os.path.join(SOURCE_DIR, "bench", "bench_count.py")
        for args, option in ((["--sizes", "ten"], "--sizes"), (["--schemes", "rk4"], "--schemes")):
            p = subprocess.run([sys.executable, script, "--binary", BINARY] + args,
                               capture_output=True, text=True, check=False)
            self.assertEqual(p.returncode, 2, args)
            self.assertIn(option, p.stderr, args)


if __name__ == "__main__":
    if not BINARY:
        sys.exit("usage: bench_count_test.py SOURCE_DIR PHYSIK_COUNT")
    if shutil.which("valgrind") is None:
        print("valgrind not found: skipped (apt-get install valgrind)")
        sys.exit(77)
    unittest.main()
