"""The panel's settings, kept in the scene: the grammar file, seed, generations and one entry per
attribute the grammar declares."""

import bpy


def _mark_set(attr, _context):
    # Only attributes the user touched override the grammar's defaults.
    attr.use = True


class ShapegramAttr(bpy.types.PropertyGroup):
    """One attribute the grammar declares, and the value the panel gives it."""

    type: bpy.props.EnumProperty(
        items=(
            ("number", "Number", ""),
            ("string", "String", ""),
            ("bool", "Boolean", ""),
            ("expression", "Expression", "the default is an expression: its type is not known"),
        )
    )
    use: bpy.props.BoolProperty(name="Set", description="Override the grammar's default")
    number: bpy.props.FloatProperty(update=_mark_set)
    text: bpy.props.StringProperty(update=_mark_set)
    flag: bpy.props.BoolProperty(update=_mark_set)

    def value(self):
        """The value given, as the engine takes it."""
        return {"number": self.number, "string": self.text, "bool": self.flag}.get(self.type, self.number)


class ShapegramSettings(bpy.types.PropertyGroup):
    """What the next derivation uses."""

    grammar_path: bpy.props.StringProperty(name="Grammar", subtype="FILE_PATH")
    seed: bpy.props.IntProperty(name="Seed", min=0, default=0)
    generations: bpy.props.IntProperty(
        name="Generations", min=-1, default=-1, description="-1: the grammar's own"
    )
    attrs: bpy.props.CollectionProperty(type=ShapegramAttr)

    def overrides(self):
        """The attributes the user set, as a dict for `Grammar.derive`."""
        return {a.name: a.value() for a in self.attrs if a.use}
