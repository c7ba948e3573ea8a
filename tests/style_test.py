#!/usr/bin/env python3
"""No function in the repository runs over 60 lines, in C++ or in Python; no source cites an issue.

A function's length is counted from the line that starts its signature to the line of its closing
brace (C++) or its last statement (Python), blank lines and comments included: what a reader has to
hold at once.
- Python: every `def` (nested ones too), from the standard `ast` module.
- C++: every definition that starts at column 0 (free functions, out-of-class members, gtest
  TEST bodies; namespaces are not indented in the repository's style, .clang-format), up to the
  next line that starts with `}`. Member functions defined inside a class body are not measured.
Issue numbers ("issue 12") are history: they belong in the commit log, not in the sources (the doc
test checks the pages users read); the two tests that must name the pattern are exempt.
Sources: the tracked .cpp, .h and .py files. Line width is clang-format's check (.ci/run).
Run: python3 tests/style_test.py [REPO]  (ctest runs it as `style`).
"""
import ast
import os
import re
import subprocess
import sys
import unittest

MAX_LINES = 60
NOT_A_DEFINITION = ("//", "#", "}", "namespace", "using", "struct", "class", "enum", "template",
                    "extern", "static_assert", "typedef", "{", "/*", "*")


def cpp_functions(text):
    """(first line number, length, signature) of each column-0 definition in C++ source."""
    lines = text.split("\n")
    out, i = [], 0
    while i < len(lines):
        line = lines[i]
        if (not line or line[0].isspace() or line.startswith(NOT_A_DEFINITION) or "(" not in line
                or "=" in line.split("(")[0]):  # a variable's initialiser, not a signature
            i += 1
            continue
        j = i  # the line with the body's opening brace, unless a ';' ends a declaration first
        while j < len(lines) and "{" not in lines[j] and ";" not in lines[j]:
            j += 1
        if j == len(lines) or "{" not in lines[j] or ";" in lines[j].split("{")[0]:
            i = j + 1
            continue
        if lines[j].count("{") == lines[j].count("}") and lines[j].rstrip()[-1:] in ("}", ";"):
            i = j + 1  # a one-line body, or a declaration with a braced default ("= {});")
            continue
        k = j + 1
        while k < len(lines) and not lines[k].startswith("}"):
            k += 1
        out.append((i + 1, k - i + 1, line.strip()[:80]))
        i = k + 1
    return out


def python_functions(text):
    """(first line number, length, name) of each def in Python source."""
    tree = ast.parse(text)
    return [(n.lineno, n.end_lineno - n.lineno + 1, n.name) for n in ast.walk(tree)
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]


def long_functions(repo):
    files = subprocess.check_output(["git", "ls-files", "*.cpp", "*.h", "*.py"], cwd=repo,
                                    text=True).split()
    found = []
    for f in files:
        with open(os.path.join(repo, f), encoding="utf-8") as fh:
            text = fh.read()
        measure = python_functions if f.endswith(".py") else cpp_functions
        for line, length, name in measure(text):
            if length > MAX_LINES:
                found.append(f"{f}:{line}: {name} is {length} lines (at most {MAX_LINES})")
    return found


ISSUE = re.compile(r"\bissues? #?[0-9]+", re.IGNORECASE)
CITES_THE_PATTERN = ("tests/doc_test.py", "tests/style_test.py")


def issue_citations(repo):
    """file:line of each issue number in the tracked sources."""
    files = subprocess.check_output(["git", "ls-files", "*.cpp", "*.h", "*.py"], cwd=repo,
                                    text=True).split()
    found = []
    for f in files:
        if f in CITES_THE_PATTERN:
            continue
        with open(os.path.join(repo, f), encoding="utf-8") as fh:
            for n, line in enumerate(fh, 1):
                if ISSUE.search(line):
                    found.append(f"{f}:{n}: {line.strip()}")
    return found


class Detector(unittest.TestCase):
    def test_counts_a_cpp_body_from_signature_to_brace(self):
        body = "\n".join(["  x += 1;"] * 3)
        text = f"namespace a {{\n\nint f(int x,\n      int y) {{\n{body}\n  return x;\n}}\n\n}}  // a\n"
        self.assertEqual(cpp_functions(text), [(3, 7, "int f(int x,")])

    def test_skips_declarations_one_liners_and_types(self):
        text = ("int g(int x);\nint h() { return 1; }\nconst char* k = R\"(\n{\n)\";\nstruct S {\n  int m() {\n    return 2;\n"
                "  }\n};\n")
        self.assertEqual(cpp_functions(text), [])

    def test_skips_a_declaration_with_a_braced_default(self):
        text = "int f(int x,\n      const Options& o = {});\nint g() {\n  return 1;\n}\n"
        self.assertEqual(cpp_functions(text), [(3, 3, "int g() {")])

    def test_counts_a_gtest_body(self):
        text = "TEST(Suite, Name) {\n  EXPECT_EQ(1, 1);\n}\n"
        self.assertEqual(cpp_functions(text), [(1, 3, "TEST(Suite, Name) {")])

    def test_finds_issue_numbers(self):
        self.assertTrue(ISSUE.search("// Study (issue 7): the solvers"))
        self.assertTrue(ISSUE.search("# see Issue #15"))
        self.assertFalse(ISSUE.search("// a known issue: the cap"))

    def test_counts_nested_python_defs(self):
        text = "def f():\n    def g():\n        return 1\n    return g\n"
        self.assertEqual(sorted(python_functions(text)), [(1, 4, "f"), (2, 2, "g")])


class Repository(unittest.TestCase):
    def test_no_function_runs_over_60_lines(self):
        found = long_functions(REPO)
        self.assertEqual(found, [], "\n" + "\n".join(found))

    def test_no_source_cites_an_issue(self):
        found = issue_citations(REPO)
        self.assertEqual(found, [], "\n" + "\n".join(found))


if __name__ == "__main__":
    REPO = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(__file__), ".."))
    unittest.main()
