"""Shared fixtures of the physik package's tests: the repository, the CLI binary, and a runner
that returns the CLI's exit status, stderr and JSON outputs. ctest sets PYTHONPATH (the build
tree's python/), PHYSIK_BINARY and PHYSIK_SOURCE_DIR (python/CMakeLists.txt)."""
import json
import math
import os
import subprocess

import pytest

SOURCE_DIR = os.environ.get("PHYSIK_SOURCE_DIR") or os.path.dirname(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BINARY = os.environ.get("PHYSIK_BINARY") or os.path.join(SOURCE_DIR, "build", "physik")
SCENES = os.path.join(SOURCE_DIR, "models", "scenes")
RIGS = os.path.join(SOURCE_DIR, "models", "rigs")


def scene_path(name):
    return os.path.join(SCENES, name + ".json")


def cli(*args, cwd=None):
    """Run the CLI; (exit status, stdout, stderr)."""
    p = subprocess.run([BINARY] + [str(a) for a in args], capture_output=True, text=True, cwd=cwd)
    return p.returncode, p.stdout, p.stderr


def cli_error(*args):
    """The CLI's one-line bad-input message (exit 2 asserted), without its "physik: error: "."""
    status, _, err = cli(*args)
    assert status == 2, (args, status, err)
    lines = [l for l in err.splitlines() if l.startswith("physik: error: ")]
    assert len(lines) == 1, err
    return lines[0][len("physik: error: "):]


def read_json(path):
    with open(path) as f:
        return json.load(f)


def json_like(value):
    """A Python value as the CLI's JSON writes it: non-finite floats become null (nlohmann)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: json_like(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_like(v) for v in value]
    return value


def without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


@pytest.fixture
def tmp(tmp_path):
    return str(tmp_path)
