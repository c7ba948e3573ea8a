#!/usr/bin/env python3
"""Every citation of a doc section in the code resolves: a comment or string that says
`docs/engine.md "Implicit step"`, `DESIGN.md "Layers"`, `README "Presets"` or
`models/README.md "Scenes"` names a document that exists and has a heading with that text.

A bare DESIGN.md means docs/DESIGN.md; a bare README means the top README.md; other paths are
from the repository's root (docs/ may be left out for a file there). Sources: the tracked C++,
Python and shell files (the docs' own links are the docs' business).
Run: python3 tests/doc_citations_test.py [REPO]  (ctest runs it as `doc_citations`).
"""
import os
import re
import subprocess
import sys
import tempfile
import unittest

CITATION = re.compile(r'(?<!["\w/.-])((?:[\w.-]+/)*(?:[A-Za-z_]+\.md|README))[, ]*"([A-Za-z][^"\n]{1,79})"')
SOURCES = (".cpp", ".h", ".py", ".sh")


def document(repo, name):
    """The path a cited name means, or None when no such document exists."""
    if name == "README":
        name = "README.md"
    candidates = [name] if "/" in name else [name, os.path.join("docs", name)]
    if name == "DESIGN.md":
        candidates = [os.path.join("docs", "DESIGN.md")]
    for c in candidates:
        if os.path.isfile(os.path.join(repo, c)):
            return c
    return None


def headings(repo, path):
    with open(os.path.join(repo, path), encoding="utf-8") as f:
        return [line.lstrip("#").strip().lower() for line in f if line.startswith("#")]


COMMENT = re.compile(r"^\s*(?://+|#+)\s?")


def citations(repo, files):
    """(file, line number, document name, section) for every citation in `files`, also one split
    over two comment lines (`docs/engine.md` at the end of one, `"The implicit scheme"` on the
    next): each line is read joined with the next comment line's text."""
    out = []
    for path in files:
        with open(os.path.join(repo, path), encoding="utf-8", errors="replace") as f:
            lines = f.read().split("\n")
        for n, line in enumerate(lines, 1):
            found = CITATION.findall(line)
            nxt = lines[n] if n < len(lines) else ""
            if COMMENT.match(line) and COMMENT.match(nxt):
                joined = line.rstrip() + " " + COMMENT.sub("", nxt, count=1)
                own = set(found) | set(CITATION.findall(nxt))
                found += [c for c in CITATION.findall(joined) if c not in own]
            for doc, section in found:
                out.append((path, n, doc, section))
    return out


def problems(repo, files):
    bad = []
    for path, n, doc, section in citations(repo, files):
        target = document(repo, doc)
        if target is None:
            bad.append('%s:%d: cites %s "%s": no such document' % (path, n, doc, section))
        elif not any(h.startswith(section.lower()) for h in headings(repo, target)):
            bad.append('%s:%d: cites %s "%s": %s has no such section' % (path, n, doc, section, target))
    return bad


def tracked(repo):
    out = subprocess.run(["git", "ls-files"], cwd=repo, capture_output=True, text=True, check=True)
    # this file's own examples and fixtures cite sections on purpose
    return [p for p in out.stdout.split() if p.endswith(SOURCES) and p != "tests/doc_citations_test.py"]


REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class DocCitationsTest(unittest.TestCase):
    def test_every_citation_in_the_code_resolves(self):
        found = problems(REPO, tracked(REPO))
        self.assertEqual(found, [], "\n" + "\n".join(found))

    def test_a_missing_section_and_a_missing_document_fail(self):
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, "docs"))
            with open(os.path.join(root, "docs", "DESIGN.md"), "w") as f:
                f.write("# Design\n\n## Layers\n")
            with open(os.path.join(root, "a.cpp"), "w") as f:
                f.write('// see DESIGN.md "Layers", and DESIGN.md "Nowhere"\n'
                        '// and docs/engine.md "Implicit step"\n')
            found = problems(root, ["a.cpp"])
            self.assertEqual(len(found), 2, found)
            self.assertIn('cites DESIGN.md "Nowhere": docs/DESIGN.md has no such section', found[0])
            self.assertIn("no such document", found[1])

    def test_a_citation_split_over_two_comment_lines_is_checked(self):
        with tempfile.TemporaryDirectory() as root:
            os.makedirs(os.path.join(root, "docs"))
            with open(os.path.join(root, "docs", "DESIGN.md"), "w") as f:
                f.write("# Design\n\n## Layers\n")
            with open(os.path.join(root, "a.h"), "w") as f:
                f.write('// the layers, as in DESIGN.md\n// "Layers"; the forces, DESIGN.md\n'
                        '// "Elsewhere" here\n')
            found = problems(root, ["a.h"])
            self.assertEqual(len(found), 1, found)
            self.assertIn('a.h:2: cites DESIGN.md "Elsewhere": docs/DESIGN.md has no such section',
                          found[0])


if __name__ == "__main__":
    if len(sys.argv) > 1 and os.path.isdir(sys.argv[1]):
        REPO = os.path.abspath(sys.argv.pop(1))
    unittest.main()
