"""The sidebar panel."""

import bpy


class SHAPEGRAM_PT_panel(bpy.types.Panel):
    """Grammar, seed, attributes and the generate buttons."""

    bl_label = "Shapegram"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Shapegram"

    def draw(self, context):
        settings = context.scene.shapegram
        layout = self.layout
        row = layout.row(align=True)
        row.prop(settings, "grammar_path", text="")
        row.operator("shapegram.reload", text="", icon="FILE_REFRESH")
        layout.prop(settings, "seed")
        layout.prop(settings, "generations")
        if settings.attrs:
            box = layout.box()
            box.label(text="Attributes")
            for attr in settings.attrs:
                row = box.row()
                row.prop(attr, "use", text="")
                field = {"number": "number", "string": "text", "bool": "flag"}.get(attr.type, "number")
                row.prop(attr, field, text=attr.name)
        layout.operator("shapegram.generate", icon="MOD_BUILD")
        layout.operator("shapegram.regenerate", icon="FILE_REFRESH")
