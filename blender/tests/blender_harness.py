"""What the Blender test scripts share (they run inside Blender: `blender -b --python X -- ...`):
their options after `--` (with --repo, the checkout), the add-on enabled from the repository, and
an empty scene between cases."""
import argparse
import os
import sys

import addon_utils
import bpy


def script_args(*options):
    """The options after `--`: --repo (default: this checkout) and each (flags, keywords) of
    `options`, as argparse.ArgumentParser.add_argument takes them."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--repo", default=os.path.join(here, "..", ".."))
    for flags, keywords in options:
        p.add_argument(*flags, **keywords)
    return p.parse_args(argv)


def enable_addon(repo, script, pythonpath=None):
    """Put the repository's blender/ (and the physik package's folder) on sys.path and enable
    physik_addon; exits 1 with a message naming `script` when it does not enable."""
    if pythonpath:
        sys.path.insert(0, os.path.abspath(pythonpath))
    sys.path.insert(0, os.path.join(repo, "blender"))
    mod = addon_utils.enable("physik_addon", default_set=True, handle_error=None)
    if mod is None:
        print("%s: the add-on did not enable" % script, file=sys.stderr)
        sys.exit(1)
    return mod


def clear_scene():
    """Every object, armature and action removed."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for arm in list(bpy.data.armatures):
        bpy.data.armatures.remove(arm)
    for action in list(bpy.data.actions):
        bpy.data.actions.remove(action)
