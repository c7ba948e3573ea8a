"""The panel's engine settings, stored on the scene (Scene.physik), and the scene-file `params`
they stand for (models/README.md, "Engine parameters").

Choosing a preset fills the fields with that preset's values (physik/model/params.h); the
fields can then be changed one by one. Damping is a value or "auto" (the critically damped
choice of the engine's "Beyond the paper" work; the engine decides what auto means).
"""
import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty

# the presets' values of the fields below (physik/model/params.h); the engine owns the rest
PRESETS = {
    "original": {"damping": 3.0, "control_k": 10.0, "control_spring": "linear",
                 "interpolation": "linear", "integration": "articulated"},
    "paper": {"damping": 20.0, "control_k": 30.0, "control_spring": "linear",
              "interpolation": "linear", "integration": "articulated"},
}


def _apply_preset(self, _context):
    for key, value in PRESETS[self.preset].items():
        setattr(self, key, value)
    self.damping_mode = 'VALUE'


class PhysikSettings(bpy.types.PropertyGroup):
    preset: EnumProperty(
        name="Preset", update=_apply_preset, default="original",
        items=[("original", "Original", "the original add-on's values: damping 3, k 10"),
               ("paper", "Paper", "the paper's Sec. 4 values: damping 20, k 30")])
    integration: EnumProperty(
        name="Integration", default="articulated",
        items=[("articulated", "Articulated", "the original's: bones turn, FK from the root"),
               ("free-rods", "Free rods", "the paper's text: independent rods held by joint forces"),
               ("implicit", "Implicit", "linearised backward Euler over the exact articulated solve: "
                "stable for any dt and damping")])
    damping_mode: EnumProperty(
        name="Damping", default='VALUE',
        items=[('VALUE', "Value", "force -c v at both ends of every bone"),
               ('AUTO', "Auto", "critical damping of the slowest linearised mode, chosen by the engine")])
    damping: FloatProperty(name="c (N s/m)", default=3.0, min=0.0, soft_max=50.0)
    control_spring: EnumProperty(
        name="Spring law", default="linear",
        items=[("linear", "Linear", "F = -k (a - t)"),
               ("capped", "Capped", "F = -k min(|a - t|, cap) (a - t)/|a - t|")])
    control_k: FloatProperty(name="k (N/m)", default=10.0, min=0.0, soft_max=200.0)
    control_cap: FloatProperty(name="Cap", default=1.0, min=0.0, description="rig units")
    interpolation: EnumProperty(
        name="Interpolation", default="linear",
        items=[("none", "None", "targets jump"),
               ("linear", "Linear", "a target jump is spread along a line"),
               ("polar-head", "Polar, head", "an arc about the head of the pulled bone"),
               ("polar-com", "Polar, centre of mass", "an arc about the rig's centre of mass (eq. 12)")])
    steps_per_frame: IntProperty(name="Steps per frame", default=1, min=1, soft_max=100)
    bake_every: IntProperty(name="Bake every", default=1, min=1, soft_max=100,
                            description="one keyframe every N steps")
    max_steps: IntProperty(name="Steps", default=600, min=1, soft_max=10000,
                           description="steps for Solve (at most) and Bake")


def params_dict(settings):
    """The scene file's `params` for these settings."""
    return {
        "preset": settings.preset,
        "integration": settings.integration,
        "damping": "auto" if settings.damping_mode == 'AUTO' else settings.damping,
        "control_spring": settings.control_spring,
        "control_k": settings.control_k,
        "control_cap": settings.control_cap,
        "interpolation": settings.interpolation,
    }


def register():
    bpy.utils.register_class(PhysikSettings)
    bpy.types.Scene.physik = bpy.props.PointerProperty(type=PhysikSettings)


def unregister():
    del bpy.types.Scene.physik
    bpy.utils.unregister_class(PhysikSettings)
