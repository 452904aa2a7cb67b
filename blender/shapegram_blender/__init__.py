"""Shapegram for Blender: derive a grammar file onto the selected mesh's faces (one building per
face) or onto the default 20 x 30 lot, with a seed and the grammar's attributes from a panel in
the 3D view's sidebar, and regenerate the results in place. The engine is the `shapegram`
module built for CPython 3.11+ (abi3) and shipped in this folder (docs/runtimes.md)."""

bl_info = {
    "name": "Shapegram",
    "author": "Shapegram",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > Shapegram",
    "description": "Procedural models from shape grammars (CGA, L-systems, caves, topological grammars)",
    "category": "Add Mesh",
}

from . import operators, panel, settings  # noqa: E402 (bl_info comes first, as Blender reads it)

_classes = (
    settings.ShapegramAttr,
    settings.ShapegramSettings,
    operators.SHAPEGRAM_OT_reload,
    operators.SHAPEGRAM_OT_generate,
    operators.SHAPEGRAM_OT_regenerate,
    panel.SHAPEGRAM_PT_panel,
)


def register():
    import bpy

    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.shapegram = bpy.props.PointerProperty(type=settings.ShapegramSettings)


def unregister():
    import bpy

    del bpy.types.Scene.shapegram
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
