#!/usr/bin/env python3
"""The layers of docs/DESIGN.md ("Layers"), checked on every #include of the project's own code.

    physik/model  <-  physik/engine, physik/ik  <-  physik/posing  <-  physik/io  <-  reference  <-  tune
    <-  experiments  <-  cli (and bench)
    physik/io  <-  viewer  <-  cli, python      (run folders into an HTML page; MuJoCo-free)
    physik/io  <-  kdl  <-  experiments, cli, python, bench   (Orocos KDL's solvers on a scene)

A file may include its own layer and the layers below it, never one above or beside it. Besides:
  - the core (physik/) includes neither MuJoCo nor Ceres;
  - FCL (collision detection) is included only by physik/engine's .cpp files, never by a
    header, so no code above the engine compiles against it;
  - no header of physik/model, physik/engine, physik/ik or physik/posing reaches a JSON library, even through
    other headers (only physik/io and above read or write files);
  - inside physik/engine, the step (engine.h) and the run monitor (run_monitor.h) are the top: a stage or
    a measure never includes them (the measures they share are in measures.h);
  - inside physik/engine, no include runs back up: a file's unit (its .h and .cpp together) never
    includes, directly or through others, a unit that includes it (the units form a DAG).
Run: python3 tests/layering_test.py [REPO]  (ctest runs it as `layering`).
"""
import os
import re
import sys
import tempfile
import unittest

# layer -> the layers its files may include (its own included)
ALLOWED = {
    "physik/model": {"physik/model"},
    "physik/engine": {"physik/model", "physik/engine"},
    "physik/ik": {"physik/model", "physik/ik"},
    "physik/posing": {"physik/model", "physik/engine", "physik/ik", "physik/posing"},
    "physik/io": {"physik/model", "physik/engine", "physik/ik", "physik/posing", "physik/io"},
}
CORE = set(ALLOWED)
UPPER_ORDER = ["reference", "tune", "experiments", "cli"]
for k, layer in enumerate(UPPER_ORDER):
    ALLOWED[layer] = CORE | set(UPPER_ORDER[: k + 1])
ALLOWED["bench"] = CORE | set(UPPER_ORDER[:3]) | {"bench", "kdl"}
ALLOWED["python"] = CORE | set(UPPER_ORDER[:3]) | {"python", "viewer", "kdl"}
# the viewer reads run folders with the core's io alone; the CLI and the Python module use it
ALLOWED["viewer"] = CORE | {"viewer"}
ALLOWED["cli"] = ALLOWED["cli"] | {"viewer", "kdl"}
# Orocos KDL's solvers on a scene's goals sit on the core alone; the experiments, the CLI, the
# Python module and the benchmarks use them
ALLOWED["kdl"] = CORE | {"kdl"}
ALLOWED["experiments"] = ALLOWED["experiments"] | {"kdl"}
JSON_FREE = {"physik/model", "physik/engine", "physik/ik", "physik/posing"}
FORBIDDEN_IN_CORE = ("mujoco/", "ceres/")
FCL = "fcl/"

# inside physik/engine: the files only their own .cpp and the step may include
ENGINE_TOP = {"physik/engine/engine.h": {"physik/engine/engine.cpp"},
              "physik/engine/run_monitor.h": {"physik/engine/run_monitor.cpp", "physik/engine/engine.cpp"}}

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def layer_of(path):
    """The layer a repository-relative path belongs to, or None (tests, tools)."""
    parts = path.split("/")
    if parts[0] == "physik" and len(parts) > 2:
        return "physik/" + parts[1]
    return parts[0] if parts[0] in ALLOWED else None


def sources(repo):
    for top in ALLOWED:
        root = os.path.join(repo, top)
        if not os.path.isdir(root):
            continue
        for base, _, files in os.walk(root):
            for f in files:
                if f.endswith((".h", ".cpp")):
                    yield os.path.relpath(os.path.join(base, f), repo)


def includes(repo, path):
    with open(os.path.join(repo, path), encoding="utf-8") as f:
        return INCLUDE.findall(f.read())


def check(repo):
    """Every broken rule, as 'file: reason' lines."""
    problems = []
    files = sorted(set(sources(repo)))
    for path in files:
        layer = layer_of(path)
        for kind, inc in includes(repo, path):
            if kind == "<":
                if layer in CORE and inc.startswith(FORBIDDEN_IN_CORE):
                    problems.append("%s: the core includes <%s> (no MuJoCo, no Ceres in physik/)" % (path, inc))
                if inc.startswith(FCL) and not (layer == "physik/engine" and path.endswith(".cpp")):
                    problems.append("%s: includes <%s> (FCL only in physik/engine's .cpp files)"
                                    % (path, inc))
                continue
            if layer == "physik/engine" and inc in ENGINE_TOP and path not in ENGINE_TOP[inc]:
                problems.append("%s: includes \"%s\", above the stages inside physik/engine" % (path, inc))
            target = layer_of(inc)
            if target is None:
                if os.path.exists(os.path.join(repo, inc)):
                    problems.append("%s: includes \"%s\", outside every layer" % (path, inc))
                continue
            if target not in ALLOWED[layer]:
                problems.append("%s: includes \"%s\": layer %s may not depend on %s"
                                % (path, inc, layer, target))
    problems += engine_cycles(repo, files)
    # transitive: the JSON-free layers' headers never reach nlohmann
    for path in files:
        if layer_of(path) in JSON_FREE and path.endswith(".h"):
            chain = reaches_json(repo, path, [])
            if chain:
                problems.append("%s: reaches a JSON library through %s" % (path, " -> ".join(chain)))
    return problems


def engine_cycles(repo, files):
    """Every include inside physik/engine that runs back up: an edge of the unit graph (a unit is
    x.h with x.cpp) that lies on a cycle, as 'file: reason' lines."""
    unit = lambda p: os.path.splitext(p)[0]
    edges = {}
    for path in files:
        if layer_of(path) != "physik/engine":
            continue
        for kind, inc in includes(repo, path):
            if kind == '"' and layer_of(inc) == "physik/engine" and unit(inc) != unit(path):
                edges.setdefault(unit(path), {}).setdefault(unit(inc), path)

    def reaches(a, b):  # is unit b reachable from unit a
        seen, todo = set(), [a]
        while todo:
            u = todo.pop()
            if u == b:
                return True
            if u not in seen:
                seen.add(u)
                todo.extend(edges.get(u, {}))
        return False

    problems = []
    for a in sorted(edges):
        for b, path in sorted(edges[a].items()):
            if reaches(b, a):
                problems.append("%s: includes \"%s.h\", which includes %s back (an include running "
                                "back up inside physik/engine)" % (path, b, a))
    return problems


def reaches_json(repo, path, stack):
    if path in stack:
        return None
    for kind, inc in includes(repo, path):
        if kind == "<" and inc.startswith("nlohmann/"):
            return stack + [path, "<" + inc + ">"]
        if kind == '"' and os.path.exists(os.path.join(repo, inc)):
            found = reaches_json(repo, inc, stack + [path])
            if found:
                return found
    return None


REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class LayeringTest(unittest.TestCase):
    def test_the_tree_keeps_its_layers(self):
        problems = check(REPO)
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def write(self, root, path, text):
        full = os.path.join(root, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w") as f:
            f.write(text)

    def test_an_upward_include_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/io/scene_io.h", "#pragma once\n")
            self.write(root, "physik/engine/step.h", '#include "physik/io/scene_io.h"\n')
            self.assertEqual(len(check(root)), 1)
            self.assertIn("physik/engine may not depend on physik/io", check(root)[0])

    def test_a_sideways_include_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/engine/state.h", "#pragma once\n")
            self.write(root, "physik/ik/ccd.cpp", '#include "physik/engine/state.h"\n')
            self.assertIn("physik/ik may not depend on physik/engine", check(root)[0])

    def test_posing_may_not_include_io(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/io/scene_io.h", "#pragma once\n")
            self.write(root, "physik/posing/s.cpp", '#include "physik/io/scene_io.h"\n')
            self.assertIn("physik/posing may not depend on physik/io", check(root)[0])

    def test_json_reached_through_a_model_header_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/model/a.h", '#include "physik/model/b.h"\n')
            self.write(root, "physik/model/b.h", "#include <nlohmann/json.hpp>\n")
            problems = check(root)
            self.assertTrue(any("physik/model/a.h: reaches a JSON library" in p for p in problems), problems)

    def test_mujoco_in_the_core_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/io/x.cpp", "#include <mujoco/mujoco.h>\n")
            self.assertIn("no MuJoCo", check(root)[0])

    def test_fcl_outside_the_engine_sources_fails(self):
        with tempfile.TemporaryDirectory() as root:
            fcl = "#include <fcl/narrowphase/distance.h>\n"
            self.write(root, "physik/engine/collision.cpp", fcl)
            self.write(root, "physik/engine/collision.h", "#include <fcl/geometry/shape/capsule.h>\n")
            self.write(root, "reference/r.cpp", "#include <fcl/narrowphase/distance.h>\n")
            self.assertEqual(sorted(check(root)), [
                "physik/engine/collision.h: includes <fcl/geometry/shape/capsule.h> "
                "(FCL only in physik/engine's .cpp files)",
                "reference/r.cpp: includes <fcl/narrowphase/distance.h> "
                "(FCL only in physik/engine's .cpp files)"])

    def test_a_stage_including_the_step_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/engine/engine.h", "#pragma once\n")
            self.write(root, "physik/engine/run_monitor.h", "#pragma once\n")
            self.write(root, "physik/engine/engine.cpp", '#include "physik/engine/run_monitor.h"\n')
            self.write(root, "physik/engine/damping.cpp", '#include "physik/engine/engine.h"\n')
            self.write(root, "physik/posing/p.cpp", '#include "physik/engine/engine.h"\n')
            self.assertEqual(check(root), ['physik/engine/damping.cpp: includes "physik/engine/engine.h", '
                                           'above the stages inside physik/engine'])

    def test_an_include_back_up_inside_the_engine_fails(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "physik/engine/state.h", '#include "physik/engine/workspace.h"\n')
            self.write(root, "physik/engine/workspace.h", "#pragma once\n")
            self.write(root, "physik/engine/workspace.cpp", '#include "physik/engine/state.h"\n')
            self.write(root, "physik/engine/damping.cpp", '#include "physik/engine/state.h"\n')
            problems = check(root)
            self.assertEqual(len(problems), 2, problems)
            self.assertTrue(any(p.startswith("physik/engine/workspace.cpp: includes") for p in problems))
            self.assertTrue(all("back up" in p for p in problems))

    def test_the_viewer_may_not_include_the_reference(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "reference/compare.h", "#pragma once\n")
            self.write(root, "viewer/x.cpp", '#include "reference/compare.h"\n')
            self.assertIn("layer viewer may not depend on reference", check(root)[0])

    def test_reference_may_not_include_tune(self):
        with tempfile.TemporaryDirectory() as root:
            self.write(root, "tune/tuner.h", "#pragma once\n")
            self.write(root, "reference/x.cpp", '#include "tune/tuner.h"\n')
            self.assertIn("layer reference may not depend on tune", check(root)[0])


if __name__ == "__main__":
    if len(sys.argv) > 1 and os.path.isdir(sys.argv[1]):
        REPO = os.path.abspath(sys.argv.pop(1))
    unittest.main()
