"""The panel's settings, stored on the scene (Scene.physik), and the scene-file `params` they
stand for (models/README.md, "Engine parameters").

The engine's settings come from the engine: with the `physik` module importable, register()
reads physik.param_table() (engine.param_table) and builds one property per row of PANEL_ROWS
from its row (kind, choices, range, unit, doc), the preset list from its presets, and every
default from its default preset (the table's "default_preset", the preset a scene that names
none gets). Choosing a preset fills the fields with that preset's values from the same table;
the fields can then be changed one by one. So no engine value is typed here: when the engine's
presets or default change, the panel follows. Damping is a value or "auto" (the table's
`damping_auto`; the engine decides what auto means).

Without the module nothing here can run the engine (Solve, Simulate and Bake say so), so the
settings hold only the add-on's own fields (steps per frame, bake every, steps, collide) and
params_dict is empty. Collide is the scene's `ground`, `self_collision` and `obstacles` (the
mesh objects of the collection "PhysIK Obstacles"), not a param (scene_dict.collision_dict).
"""
import struct

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty

from . import engine

# the table's rows the panel shows, in order; damping and damping_auto are one control
PANEL_ROWS = ("scheme", "damping", "control_spring", "control_k", "control_cap",
              "interpolation")
LABELS = {"damping": "c", "control_spring": "Spring law", "control_k": "k", "control_cap": "Cap"}
TABLE = None  # the engine's table while registered (None without the module)
CLASSES = []


def _rows(table):
    return {row["name"]: row for row in table["params"]}


def _preset_values(table, preset):
    """{field: value} of a preset for the panel's fields (damping_mode from damping_auto)."""
    rows = _rows(table)
    values = {name: rows[name]["defaults"][preset] for name in PANEL_ROWS if name in rows}
    if "damping_auto" in rows:
        values["damping_mode"] = 'AUTO' if rows["damping_auto"]["defaults"][preset] else 'VALUE'
    return values


def _apply_preset(self, _context):
    for key, value in _preset_values(TABLE, self.preset).items():
        setattr(self, key, value)


def _label(row):
    name = LABELS.get(row["name"], row["name"].replace("_", " ").capitalize())
    return "%s (%s)" % (name, row["unit"]) if row.get("unit") and row["kind"] == "real" else name


def _row_property(row, default):
    """A Blender property for a parameter-table row (kind, choices, range, doc)."""
    text = dict(name=_label(row), description=row["doc"], default=default)
    rng = row.get("range") or {}
    if row["kind"] == "choice":
        items = [(c, c.replace("-", " ").capitalize(), row["doc"]) for c in row["choices"]]
        return EnumProperty(items=items, **text)
    if row["kind"] == "boolean":
        return BoolProperty(**text)
    bounds = {}
    if "lo" in rng:
        bounds["min"] = rng["lo"]
    if "hi" in rng:
        bounds["max"] = rng["hi"]
    if row["kind"] == "integer":
        return IntProperty(**text, **{k: int(v) for k, v in bounds.items()})
    text["default"] = float(default)
    return FloatProperty(**text, **bounds)


def _preset_items(table):
    """(name, label, tooltip) per preset: the tooltip lists its values of the panel's fields."""
    items = []
    for preset in table["presets"]:
        values = ", ".join("%s %s" % (k, v) for k, v in _preset_values(table, preset).items())
        default = " (the engine's default)" if preset == table["default_preset"] else ""
        items.append((preset, preset.capitalize(), "the engine's preset%s: %s" % (default, values)))
    return items


def _engine_annotations(table):
    """The engine's fields: the preset, and one property per row of PANEL_ROWS it has."""
    default = table["default_preset"]
    values = _preset_values(table, default)
    rows = _rows(table)
    out = {"preset": EnumProperty(name="Preset", items=_preset_items(table), default=default,
                                  update=_apply_preset)}
    for name in PANEL_ROWS:
        if name in rows:
            out[name] = _row_property(rows[name], values[name])
    if "damping" in rows and "damping_auto" in rows:
        out["damping_mode"] = EnumProperty(
            name="Damping", default=values["damping_mode"],
            items=[('VALUE', "Value", rows["damping"]["doc"]),
                   ('AUTO', "Auto", rows["damping_auto"]["doc"])])
    return out


def _own_annotations():
    return {
        "steps_per_frame": IntProperty(name="Steps per frame", default=1, min=1, soft_max=100),
        "bake_every": IntProperty(name="Bake every", default=1, min=1, soft_max=100,
                                  description="one keyframe every N steps"),
        "max_steps": IntProperty(name="Steps", default=600, min=1, soft_max=10000,
                                 description="steps for Solve (at most) and Bake"),
        "collide": BoolProperty(
            name="Collide", default=False,
            description="contacts: a floor (normal +Z) at the rig's lowest rest point, where its "
                        "lowest bone capsule touches, the bones' capsules against each other, and "
                        "each mesh in the collection 'PhysIK Obstacles' as a box (its oriented "
                        "bounding box) (the scene's ground, self_collision and obstacles); "
                        "gravity stays off"),
    }


def _as_stored(value):
    """A preset's value as a Blender field holds it (FloatProperty is single precision)."""
    if isinstance(value, float):
        return struct.unpack("f", struct.pack("f", value))[0]
    return value


def params_dict(settings):
    """The scene file's `params` for these settings ({} without the engine): the preset, and
    each field that differs from the preset's value. A field left at its preset's value is not
    sent, so the engine uses the preset's own double, not Blender's single-precision copy."""
    if TABLE is None:
        return {}
    preset = _preset_values(TABLE, settings.preset)
    combined = hasattr(settings, "damping_mode")  # damping and damping_auto: one control
    out = {"preset": settings.preset}
    for name in PANEL_ROWS:
        if hasattr(settings, name) and not (combined and name == "damping"):
            value = getattr(settings, name)
            if value != _as_stored(preset[name]):
                out[name] = value
    if combined:
        preset_auto = preset["damping_mode"] == 'AUTO'
        if settings.damping_mode == 'AUTO':
            if not preset_auto:
                out["damping"] = "auto"
        elif preset_auto or settings.damping != _as_stored(preset["damping"]):
            out["damping"] = settings.damping
    return out


def register():
    global TABLE
    TABLE = engine.param_table() if engine.available() else None
    annotations = _own_annotations()
    if TABLE is not None:
        annotations.update(_engine_annotations(TABLE))
    cls = type("PhysikSettings", (bpy.types.PropertyGroup,), {"__annotations__": annotations})
    bpy.utils.register_class(cls)
    CLASSES[:] = [cls]
    bpy.types.Scene.physik = bpy.props.PointerProperty(type=cls)


def unregister():
    del bpy.types.Scene.physik
    for cls in CLASSES:
        bpy.utils.unregister_class(cls)
    CLASSES.clear()
