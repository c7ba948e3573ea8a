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


OBSTACLES = "PhysIK Obstacles"  # the add-on's collection of box obstacles (scene_dict.py)


def clear_scene():
    """Every object, armature and action removed, and the obstacles' collection."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    if OBSTACLES in bpy.data.collections:
        bpy.data.collections.remove(bpy.data.collections[OBSTACLES])
    for arm in list(bpy.data.armatures):
        bpy.data.armatures.remove(arm)
    for action in list(bpy.data.actions):
        bpy.data.actions.remove(action)


def box_mesh(name, lo=(-1.0, -1.0, -1.0), hi=(1.0, 1.0, 1.0), collection=OBSTACLES):
    """A mesh object `name` holding the box lo..hi in its own axes (8 vertices, vertex k at
    hi[a] where bit a of k is set, else lo[a]; 6 faces), linked to `collection`, which is made
    and linked to the scene when missing. Blender's default cube is lo = -1, hi = 1."""
    verts = [tuple(hi[a] if k >> a & 1 else lo[a] for a in range(3)) for k in range(8)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    coll = bpy.data.collections.get(collection)
    if coll is None:
        coll = bpy.data.collections.new(collection)
        bpy.context.scene.collection.children.link(coll)
    coll.objects.link(obj)
    return obj
