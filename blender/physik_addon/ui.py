"""The PhysIK panel: 3D viewport sidebar (N), tab "PhysIK". The engine's fields are the ones
settings.py built from the engine's parameter table."""
import bpy

from . import engine, settings


class PHYSIK_PT_panel(bpy.types.Panel):
    bl_label = "PhysIK"
    bl_idname = "PHYSIK_PT_panel"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "PhysIK"

    def draw(self, context):
        layout = self.layout
        s = context.scene.physik
        row = layout.row(align=True)
        row.operator("physik.import_rig", text="Import rig", icon='IMPORT')
        row.operator("physik.export_rig", text="Export rig", icon='EXPORT')
        layout.operator("physik.add_control_point", icon='EMPTY_SINGLE_ARROW')
        row = layout.row(align=True)
        row.operator("physik.add_orientation_target", text="Orientation", icon='EMPTY_ARROWS')
        row.operator("physik.add_aim_target", text="Aim", icon='LIGHT_SPOT')
        obj = context.active_object
        if obj is not None and obj.type == 'ARMATURE':
            mine = [o for o in context.scene.objects if o.type == 'EMPTY'
                    and (o.get("physik_armature") == obj or o.get("fwik_armature") == obj)]
            n = sum(1 for o in mine if "physik_target" not in o)
            layout.label(text="%d control point(s), %d bone target(s)" % (n, len(mine) - n))
        col = layout.column()
        if hasattr(s, "preset"):
            col.prop(s, "preset")
            _engine_fields(col, s)
        col.prop(s, "steps_per_frame")
        col.prop(s, "bake_every")
        col.prop(s, "max_steps")
        col.prop(s, "collide")
        row = layout.row(align=True)
        row.operator("physik.simulate", icon='PLAY')
        row.operator("physik.solve", icon='CHECKMARK')
        row = layout.row(align=True)
        row.operator("physik.bake", icon='KEYINGSET')
        row.operator("physik.reset", icon='LOOP_BACK')
        if not engine.available():
            layout.label(text="engine not built: see README", icon='ERROR')


def _engine_fields(col, s):
    for name in settings.PANEL_ROWS:
        if not hasattr(s, name):
            continue
        if name == "damping" and hasattr(s, "damping_mode"):
            row = col.row(align=True)
            row.prop(s, "damping_mode", expand=True)
            sub = row.row()
            sub.enabled = s.damping_mode == 'VALUE'
            sub.prop(s, "damping", text="")
        elif name != "control_cap" or getattr(s, "control_spring", "") == "capped":
            col.prop(s, name)


CLASSES = (PHYSIK_PT_panel,)
