#!/usr/bin/env python3
"""The docs' contract with the code, checked by ctest (`docs`):

  1. every ```sh and ```python block of README.md and docs/*.md runs and exits 0, in a scratch
     folder per page (blocks of one page in order, sharing it), against the built binary: the
     folder links build/ to the build tree and models/, analysis/, examples/, python/ to the
     repository. A block preceded by `<!-- doc-test: skip (reason) -->` is not run; a ```bash or
     ```shell fence is refused, so a runnable block cannot hide from this test;
  2. a C++ block after `<!-- example: FILE -->` equals FILE (ctest builds and runs FILE);
  3. every cited experiment (experiment `NAME`) is in `physik experiment list`, and every cited
     claim (claim `EXPERIMENT/NAME`, or a README `<!-- headline: EXPERIMENT/NAME -->`) is named
     in that experiment's source (`.named("NAME")` in experiments/EXPERIMENT*.cpp);
  4. no issue number ("issue 12") in the user-facing text: README.md, docs/, CHANGELOG.md,
     models/README.md, blender/README.md, `physik --help-all` and `physik experiment list`.

The sections that source files cite are checked by tests/doc_citations_test.py.
Run: python3 tests/doc_test.py REPO BUILD_DIR [--no-run]   (--no-run skips item 1)
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

BLOCK = re.compile(r"((?:<!--[^\n]*-->\s*\n)?)```([a-z]*)\n(.*?)```", re.S)
LINKED = ("models", "analysis", "examples", "python", "scripts")
ISSUE = re.compile(r"\bissues? #?\d+", re.I)


def pages(repo):
    return [os.path.join(repo, "README.md")] + sorted(glob.glob(os.path.join(repo, "docs", "*.md")))


def blocks(path):
    """(language, code, the comment line before the fence or '') for each fenced block."""
    text = open(path, encoding="utf-8").read()
    return [(m.group(2), m.group(3), m.group(1).strip()) for m in BLOCK.finditer(text)]


def scratch(repo, build):
    """A scratch folder that looks like the repository root with the build in build/."""
    folder = tempfile.mkdtemp(prefix="physik_doc_test_")
    os.symlink(os.path.abspath(build), os.path.join(folder, "build"))
    for name in LINKED:
        os.symlink(os.path.join(os.path.abspath(repo), name), os.path.join(folder, name))
    return folder


def run_page(repo, build, path):
    """Run the page's runnable blocks in order; the failures as one-line messages."""
    errors, folder = [], None
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.path.join(os.path.abspath(build), "python"))
    rel = os.path.relpath(path, repo)
    for k, (lang, code, mark) in enumerate(blocks(path)):
        if lang in ("bash", "shell"):
            errors.append("%s: block %d: fence ```%s; use ```sh (run) or mark it skipped" % (rel, k + 1, lang))
        if lang not in ("sh", "python") or mark.startswith("<!-- doc-test: skip"):
            continue
        folder = folder or scratch(repo, build)
        argv = ["bash", "-e", "-o", "pipefail", "-c", code] if lang == "sh" else [sys.executable, "-c", code]
        if lang == "python":
            argv[0] = "/usr/bin/python3"
        done = subprocess.run(argv, cwd=folder, env=env, capture_output=True, text=True, timeout=900)
        if done.returncode != 0:
            tail = (done.stderr or done.stdout).strip().splitlines()[-3:]
            errors.append("%s: block %d (```%s, line '%s') exited %d: %s" % (
                rel, k + 1, lang, code.strip().splitlines()[0][:60], done.returncode, " | ".join(tail)))
    if folder:
        shutil.rmtree(folder)
    return errors


def check_examples(repo):
    errors = []
    for path in pages(repo):
        text = open(path, encoding="utf-8").read()
        for src, block in re.findall(r"<!-- example: (\S+) -->\s*```cpp\n(.*?)```", text, re.S):
            if open(os.path.join(repo, src), encoding="utf-8").read() != block:
                errors.append("%s: the example block differs from %s; copy the file into it" %
                              (os.path.relpath(path, repo), src))
    return errors


def experiment_names(build):
    out = subprocess.run([os.path.join(build, "physik"), "experiment", "list"], capture_output=True,
                         text=True, check=True).stdout
    return {line.split("\t")[0] for line in out.splitlines() if line.strip()}, out


def claim_names(repo, experiment, known):
    """The claims experiments/<experiment>.cpp and its parts (<experiment>_*.cpp) name; a part
    whose name is itself an experiment's (contacts_cost beside contacts) is that experiment's."""
    def owner(stem):  # the longest experiment name the file's name starts with
        names = [k for k in known if stem == k or stem.startswith(k + "_")]
        return max(names, key=len) if names else None

    names = set()
    for src in glob.glob(os.path.join(repo, "experiments", experiment + "*.cpp")):
        if owner(os.path.basename(src)[:-len(".cpp")]) == experiment:
            names |= set(re.findall(r'\.named\("([^"]+)"\)', open(src, encoding="utf-8").read()))
    return names


def check_citations(repo, build):
    """Item 3: cited experiments and claims exist."""
    known, _ = experiment_names(build)
    errors, seen = [], 0
    for path in pages(repo):
        text = open(path, encoding="utf-8").read()
        rel = os.path.relpath(path, repo)
        for name in re.findall(r"\bexperiments? `([a-z0-9_]+)`", text):
            seen += 1
            if name not in known:
                errors.append("%s: cites experiment `%s`, which `physik experiment list` lacks" % (rel, name))
        cited = re.findall(r"\bclaim `([a-z0-9_]+)/([a-z0-9-]+)`", text)
        cited += re.findall(r"<!-- headline: ([a-z0-9_]+)/([a-z0-9-]+) -->", text)
        for exp, claim in cited:
            seen += 1
            if exp not in known:
                errors.append("%s: cites claim `%s/%s` of an unknown experiment" % (rel, exp, claim))
            elif claim not in claim_names(repo, exp, known):
                errors.append("%s: cites claim `%s/%s`, but experiments/%s*.cpp names no such claim "
                              "(.named(\"%s\"))" % (rel, exp, claim, exp, claim))
    if not seen:
        errors.append("no experiment or claim citation found: the pattern must have changed")
    return errors


def check_issue_numbers(repo, build):
    """Item 5: no issue numbers where a user reads."""
    files = pages(repo) + [os.path.join(repo, f) for f in
                           ("CHANGELOG.md", "models/README.md", "blender/README.md")]
    texts = {os.path.relpath(p, repo): open(p, encoding="utf-8").read() for p in files
             if os.path.isfile(p)}
    physik = os.path.join(build, "physik")
    texts["physik --help-all"] = subprocess.run([physik, "--help-all"], capture_output=True,
                                                text=True).stdout
    texts["physik experiment list"] = experiment_names(build)[1]
    return ["%s: '%s' (no issue numbers in user-facing text)" % (where, m.group(0))
            for where, text in texts.items() for m in ISSUE.finditer(text)]


BAD_PAGE = """# Bad

See experiment `no_such_experiment` and claim `damping_sweep/no-such-claim`; issue 12.
Claim `contacts_cost/coil-step` is contacts_cost's, not claim `contacts/coil-step`.

```sh
false
```

```bash
true
```

<!-- doc-test: skip (not run) -->
```sh
false
```
"""


def self_check(build):
    """The checks find each fault of a page made to fail (so that a pass means something)."""
    with tempfile.TemporaryDirectory() as repo:
        os.makedirs(os.path.join(repo, "docs"))
        os.makedirs(os.path.join(repo, "experiments"))
        with open(os.path.join(repo, "README.md"), "w") as f:
            f.write(BAD_PAGE)
        # contacts_cost.cpp names a claim: contacts_cost's, which contacts may not cite
        with open(os.path.join(repo, "experiments", "contacts_cost.cpp"), "w") as f:
            f.write('report.named("coil-step");\n')
        errors = check_citations(repo, build) + run_page(
            repo, build, os.path.join(repo, "README.md"))
        errors += check_issue_numbers(repo, build)
    expected = ["experiment `no_such_experiment`", "claim `damping_sweep/no-such-claim`",
                "claim `contacts/coil-step`", "'issue 12'",
                "block 1 (```sh, line 'false') exited 1", "fence ```bash"]
    missing = [e for e in expected if not any(e in err for err in errors)]
    wrong = [e for e in errors if "contacts_cost/coil-step" in e]
    if missing or wrong or len([e for e in errors if "exited" in e]) != 1:
        sys.exit("doc_test self-check: the checks missed %s (or wrongly flagged %s) in %s"
                 % (missing, wrong, errors))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    repo, build = sys.argv[1], sys.argv[2]
    self_check(build)
    errors = check_examples(repo) + check_citations(repo, build)
    errors += check_issue_numbers(repo, build)
    ran = 0
    if "--no-run" not in sys.argv:
        for path in pages(repo):
            errors += run_page(repo, build, path)
            ran += 1
    for e in errors:
        print(e, file=sys.stderr)
    if errors:
        sys.exit(1)
    print("docs: examples, citations and issue numbers checked; %d pages run" % ran)


if __name__ == "__main__":
    main()
