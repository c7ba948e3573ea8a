"""Every script's --help is whole: the description it prints holds its docstring's first
paragraph, which ends a sentence (plot_pose.py and animate.py printed the docstring's first line
only, which stopped mid-sentence)."""
import ast
import os
import re
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SCRIPTS = sorted(
    [os.path.join(REPO, "analysis", f) for f in os.listdir(os.path.join(REPO, "analysis"))
     if f.endswith(".py")] +
    [os.path.join(REPO, "tests", "fuzz", "fuzz_cli.py")])  # bench_python.py needs the built module


def words(text):
    """text without its whitespace: argparse rewraps a description (and breaks at hyphens)"""
    return re.sub(r"\s+", "", text)


def command_line_scripts():
    """(path, first paragraph of its docstring) of every script with an argparse main."""
    out = []
    for path in SCRIPTS:
        source = open(path).read()
        if "argparse" not in source or "__main__" not in source:
            continue
        doc = ast.get_docstring(ast.parse(source)) or ""
        out.append((path, doc.split("\n\n")[0]))
    return out


class HelpTest(unittest.TestCase):
    def test_every_scripts_help_is_whole(self):
        scripts = command_line_scripts()
        self.assertGreater(len(scripts), 20)
        for path, first in scripts:
            with self.subTest(script=os.path.relpath(path, REPO)):
                self.assertRegex(first.rstrip(), r"[.:)]$", "the docstring's first paragraph "
                                 "ends mid-sentence")
                done = subprocess.run([sys.executable, path, "--help"], capture_output=True,
                                      text=True, cwd=REPO,
                                      env=dict(os.environ, MPLBACKEND="Agg"))
                self.assertEqual(done.returncode, 0, done.stderr)
                self.assertIn(words(first), words(done.stdout))


if __name__ == "__main__":
    unittest.main()
