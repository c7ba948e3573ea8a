"""Install the add-on the way a user does, from a zip, and enable it (ctest: blender_install):

    BLENDER_USER_SCRIPTS=<scratch dir> blender -b --factory-startup --python-exit-code 1 \
        --python blender/tests/test_install.py -- --repo .

The zip of blender/physik_addon/ is built in a temporary folder and installed with
bpy.ops.preferences.addon_install into $BLENDER_USER_SCRIPTS/addons (the test refuses to run
without that variable, so it never writes into the user's own Blender configuration); then
addon_enable, and a rig import through the installed copy.
"""
import argparse
import os
import sys
import tempfile
import zipfile

import bpy


def fail(msg):
    print("test_install.py: FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def zip_addon(repo, folder):
    src = os.path.join(repo, "blender", "physik_addon")
    path = os.path.join(folder, "physik_addon.zip")
    with zipfile.ZipFile(path, "w") as z:
        for name in sorted(os.listdir(src)):
            if name.endswith(".py"):
                z.write(os.path.join(src, name), "physik_addon/" + name)
    return path


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--repo", required=True)
    repo = os.path.abspath(p.parse_args(argv).repo)
    scripts = os.environ.get("BLENDER_USER_SCRIPTS")
    if not scripts:
        fail("set BLENDER_USER_SCRIPTS to a scratch folder (refusing to install into ~/.config)")
    with tempfile.TemporaryDirectory() as tmp:
        result = bpy.ops.preferences.addon_install(filepath=zip_addon(repo, tmp), overwrite=True)
    if result != {'FINISHED'}:
        fail("addon_install returned %s" % result)
    installed = os.path.join(scripts, "addons", "physik_addon", "__init__.py")
    if not os.path.isfile(installed):
        fail("not installed at " + installed)
    if bpy.ops.preferences.addon_enable(module="physik_addon") != {'FINISHED'}:
        fail("addon_enable failed")
    mod = sys.modules.get("physik_addon")
    if mod is None or os.path.realpath(mod.__file__) != os.path.realpath(installed):
        fail("the enabled add-on is not the installed copy: %s" % (mod and mod.__file__))
    if bpy.ops.physik.import_rig(filepath=os.path.join(repo, "models", "rigs", "hand.json")) != {'FINISHED'}:
        fail("import_rig through the installed add-on failed")
    arm = bpy.context.active_object
    if arm is None or arm.type != 'ARMATURE' or len(arm.data.bones) != 16:
        fail("the imported hand is not a 16-bone armature")
    print("test_install.py: installed into %s, enabled, imported hand.json (16 bones)" % scripts)


main()
