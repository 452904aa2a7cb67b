"""The panel's operators: read the grammar's attributes, generate, regenerate in place.

A generated object keeps what made it in custom properties (its lot, grammar, seed, attributes,
generations), so that regenerating it derives the same lot again with the panel's settings."""

import json
import pathlib

import bpy

from . import build
from . import shapegram as engine

# Custom properties of a generated object.
LOT = "shapegram_lot"
GRAMMAR = "shapegram_grammar"
SETTINGS = "shapegram_settings"
COLLECTION = "Shapegram"

# Loaded grammars by path, with the file's modification time.
_grammars = {}


def load(path):
    """The grammar in the file at `path`, loaded again when the file changed."""
    path = bpy.path.abspath(path)
    stamp = pathlib.Path(path).stat().st_mtime_ns
    cached = _grammars.get(path)
    if cached is None or cached[0] != stamp:
        cached = _grammars[path] = (stamp, engine.Grammar.load(path))
    return cached[1]


def _derive(settings, lot):
    grammar = load(settings.grammar_path)
    generations = settings.generations if settings.generations >= 0 else None
    lots = None if lot is None else [lot]
    return grammar.derive(seed=settings.seed, attrs=settings.overrides(), lots=lots, generations=generations)


def _collection(context):
    collection = bpy.data.collections.get(COLLECTION)
    if collection is None:
        collection = bpy.data.collections.new(COLLECTION)
    if collection.name not in context.scene.collection.children:
        context.scene.collection.children.link(collection)
    return collection


def _record(obj, settings, lot):
    obj[GRAMMAR] = settings.grammar_path
    obj[LOT] = json.dumps(lot)
    obj[SETTINGS] = json.dumps(
        {"seed": settings.seed, "generations": settings.generations, "attrs": settings.overrides()}
    )


class SHAPEGRAM_OT_reload(bpy.types.Operator):
    """Read the grammar file and list its attributes"""

    bl_idname = "shapegram.reload"
    bl_label = "Reload Grammar"

    def execute(self, context):
        settings = context.scene.shapegram
        try:
            grammar = load(settings.grammar_path)
        except (engine.Error, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        kept = {a.name: (a.use, a.number, a.text, a.flag) for a in settings.attrs}
        settings.attrs.clear()
        for declared in grammar.attrs:
            attr = settings.attrs.add()
            attr.name = declared.name
            attr.type = declared.type or "expression"
            if declared.name in kept:
                attr.number, attr.text, attr.flag = kept[declared.name][1:]
                attr.use = kept[declared.name][0]
            elif declared.default is not None:
                # The field shows the grammar's default; only a value the user sets is passed.
                field = {"number": "number", "string": "text", "bool": "flag"}[declared.type]
                setattr(attr, field, declared.default)
                attr.use = False
        return {"FINISHED"}


class SHAPEGRAM_OT_generate(bpy.types.Operator):
    """Derive the grammar on each face of the selected meshes, or on the default lot"""

    bl_idname = "shapegram.generate"
    bl_label = "Generate"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings = context.scene.shapegram
        sources = [o for o in context.selected_objects if o.type == "MESH" and LOT not in o]
        lots = [build.lot_of_face(o, p) for o in sources for p in o.data.polygons] or [None]
        stem = pathlib.Path(settings.grammar_path).stem or "shapegram"
        collection = _collection(context)
        made = []
        try:
            for lot in lots:
                result = _derive(settings, lot)
                data = bpy.data.meshes.new(stem)
                build.fill(data, result)
                obj = bpy.data.objects.new(stem, data)
                _record(obj, settings, lot)
                collection.objects.link(obj)
                made.append(obj)
        except (engine.Error, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        for obj in context.selected_objects:
            obj.select_set(False)
        for obj in made:
            obj.select_set(True)
        context.view_layer.objects.active = made[-1]
        self.report({"INFO"}, f"{len(made)} model(s) generated")
        return {"FINISHED"}


class SHAPEGRAM_OT_regenerate(bpy.types.Operator):
    """Derive the selected generated objects again with the panel's grammar, seed and attributes,
    each on its own lot, refilling their meshes in place"""

    bl_idname = "shapegram.regenerate"
    bl_label = "Regenerate"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings = context.scene.shapegram
        targets = [o for o in context.selected_objects if LOT in o]
        if not targets:
            self.report({"ERROR"}, "select objects made by Shapegram to regenerate them")
            return {"CANCELLED"}
        try:
            for obj in targets:
                lot = json.loads(obj[LOT])
                result = _derive(settings, lot)
                build.fill(obj.data, result)
                _record(obj, settings, lot)
        except (engine.Error, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, f"{len(targets)} model(s) regenerated")
        return {"FINISHED"}
