"""read_table against the schema an experiment writes (summary.json "tables"): a CSV whose
header or row count disagrees with it is refused naming the file; a column the table lacks is a
KeyError naming the file and the column; a CSV with no schema beside it is read unchecked."""
import json
import os
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import physik_plot  # noqa: E402

SCHEMA = {"tables": {"sweep": {"file": "sweep.csv", "rows": 2, "columns": [
    {"name": "damping", "unit": "N s/m", "doc": "c", "format": "g6", "csv": True},
    {"name": "steps_to_converge", "unit": "steps", "doc": "steps", "format": "int", "csv": True},
    {"name": "physical", "unit": "", "doc": "summary only", "format": "flag", "csv": False}]}}}


def folder(d, csv_text, schema=SCHEMA):
    with open(os.path.join(d, "sweep.csv"), "w") as f:
        f.write(csv_text)
    if schema is not None:
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump(schema, f)
    return os.path.join(d, "sweep.csv")


class TablesTest(unittest.TestCase):
    def test_a_table_matching_its_schema_is_read(self):
        with tempfile.TemporaryDirectory() as d:
            t = physik_plot.read_table(folder(d, "damping,steps_to_converge\n1,20\n10,-1\n"))
            self.assertEqual(t["steps_to_converge"], [20.0, -1.0])
            self.assertEqual(physik_plot.schema_columns(physik_plot.table_schema(t.path)),
                             ["damping", "steps_to_converge"])

    def test_a_renamed_column_is_refused_naming_the_file(self):
        with tempfile.TemporaryDirectory() as d:
            path = folder(d, "damping,steps\n1,20\n10,-1\n")
            with self.assertRaises(ValueError) as e:
                physik_plot.read_table(path)
            self.assertIn("sweep.csv", str(e.exception))
            self.assertIn("steps_to_converge", str(e.exception))

    def test_a_missing_row_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            with self.assertRaises(ValueError) as e:
                physik_plot.read_table(folder(d, "damping,steps_to_converge\n1,20\n"))
            self.assertIn("1 rows", str(e.exception))

    def test_an_unknown_column_names_the_file_and_the_column(self):
        with tempfile.TemporaryDirectory() as d:
            t = physik_plot.read_table(folder(d, "damping,steps_to_converge\n1,20\n10,-1\n"))
            with self.assertRaises(KeyError) as e:
                t["steps_to_settle"]
            self.assertIn("sweep.csv", str(e.exception))
            self.assertIn("steps_to_settle", str(e.exception))

    def test_without_a_schema_the_table_is_read_unchecked(self):
        with tempfile.TemporaryDirectory() as d:
            t = physik_plot.read_table(folder(d, "a,b\n1,x\n", schema=None))
            self.assertEqual(t["a"], [1.0])
            self.assertEqual(t["b"], ["x"])


if __name__ == "__main__":
    unittest.main()
