#!/usr/bin/env python3
"""`cmake --install` puts a working physik package under the prefix (ctest python_install).

usage: check_install.py BUILD_DIR INSTALL_SUBDIR SCENE
Installs the build into a scratch prefix, imports physik from there in a fresh interpreter (from
another working directory, with only that folder on PYTHONPATH), runs SCENE and checks the final
state hash against the build tree's module."""
import os
import subprocess
import sys
import tempfile


def main(build, subdir, scene):
    with tempfile.TemporaryDirectory() as prefix:
        subprocess.run(["cmake", "--install", build, "--prefix", prefix], check=True,
                       stdout=subprocess.DEVNULL)
        code = ("import physik, physik.sweep, sys; "
                "print(physik.__file__); "
                "print(physik.Simulation(physik.Scene.load(sys.argv[1])).run()['final_state_hash'])")
        env = dict(os.environ, PYTHONPATH=os.path.join(prefix, subdir), PYTHONDONTWRITEBYTECODE="1")
        installed = subprocess.run([sys.executable, "-c", code, scene], env=env, cwd=prefix,
                                   capture_output=True, text=True, check=True).stdout.split()
        env["PYTHONPATH"] = os.path.join(build, "python")
        tree = subprocess.run([sys.executable, "-c", code, scene], env=env, cwd=prefix,
                              capture_output=True, text=True, check=True).stdout.split()
    assert installed[0].startswith(prefix), installed
    assert installed[1] == tree[1], (installed, tree)
    print("installed physik at %s: %s" % (installed[0], installed[1]))


if __name__ == "__main__":
    main(*sys.argv[1:])
