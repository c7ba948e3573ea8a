"""PhysIK for Blender: physics-based posing on an armature.

The rig and control points are plain Blender data (armature_io, control_points); the engine is
reached only through engine.py (the `physik` Python module). Submodules that need
bpy are imported in register(), so rig_format can be used (and tested) outside Blender.
Install: blender/README.md.
"""
bl_info = {
    "name": "PhysIK",
    "author": "PhysIK testbed",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > PhysIK",
    "description": "Physics-based inverse kinematics (Choi 2019): rigs, control points, solve",
    "category": "Animation",
}


def _classes():
    from . import operators, ui
    return operators.CLASSES + ui.CLASSES


def register():
    import bpy
    from . import settings
    settings.register()
    for cls in _classes():
        bpy.utils.register_class(cls)


def unregister():
    import bpy
    from . import settings
    for cls in reversed(_classes()):
        bpy.utils.unregister_class(cls)
    settings.unregister()
