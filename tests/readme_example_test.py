#!/usr/bin/env python3
"""README.md's embedding example is examples/embed_posing.cpp, which ctest builds and runs
(example_embed_posing): the README's code block after "<!-- example: FILE -->" must equal FILE.
Run: python3 tests/readme_example_test.py [REPO]"""
import re
import sys

repo = sys.argv[1] if len(sys.argv) > 1 else "."
readme = open(repo + "/README.md", encoding="utf-8").read()
found = re.findall(r"<!-- example: (\S+) -->\s*```cpp\n(.*?)```", readme, re.S)
if not found:
    sys.exit("README.md: no '<!-- example: FILE -->' code block")
for path, block in found:
    text = open(repo + "/" + path, encoding="utf-8").read()
    if block != text:
        sys.exit("README.md: the example block differs from %s; copy the file into it" % path)
print("README examples match:", ", ".join(p for p, _ in found))
