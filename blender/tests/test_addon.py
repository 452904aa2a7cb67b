"""The add-on in a real Blender, headless:

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_addon.py \
        -- shapegram_blender.zip examples/

installs the zip, generates examples/house.cga on the default lot (objects, vertices, faces and
materials counted against the shipped module's own buffers and the C ABI's figures), regenerates
it in place with an attribute set in the panel, generates on a plane's three faces (a building
per face, each on its face), generates the textured house (its UV map and packed images) and
the rule package examples/town.rpk, and checks that a grammar error reaches the user with its
place."""

import json
import pathlib
import sys
import tempfile

import bpy

zip_path, examples = sys.argv[sys.argv.index("--") + 1 :]
house = str(pathlib.Path(examples) / "house.cga")

bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
bpy.ops.preferences.addon_enable(module="shapegram_blender")

from shapegram_blender import shapegram as engine  # noqa: E402 (installed just above)


def check(condition, what):
    if not condition:
        raise AssertionError(what)


def generated():
    return sorted((o for o in bpy.data.objects if "shapegram_lot" in o), key=lambda o: o.name)


def select(objects):
    for obj in bpy.context.view_layer.objects:
        obj.select_set(False)
    for obj in objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = objects[0] if objects else None


for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
settings = bpy.context.scene.shapegram
settings.grammar_path = house
check(bpy.ops.shapegram.reload() == {"FINISHED"}, "reload")
check(
    [(a.name, a.type) for a in settings.attrs]
    == [
        ("storeys", "number"),
        ("storeyH", "number"),
        ("roofAngle", "number"),
        ("wallColor", "string"),
        ("roofColor", "string"),
    ],
    f"the panel's attributes: {[(a.name, a.type) for a in settings.attrs]}",
)
check(
    (settings.attrs["storeys"].number, settings.attrs["wallColor"].text) == (2.0, "#e8dcc4"),
    "the grammar's defaults in the panel",
)
check(not any(a.use for a in settings.attrs), "no attribute set before the user sets one")

# The house on the default lot: one object, the module's buffers as they are.
check(bpy.ops.shapegram.generate() == {"FINISHED"}, "generate")
expected = engine.Grammar.load(house).derive()
(obj,) = generated()
check(len(bpy.data.objects) == 1, f"{len(bpy.data.objects)} objects")
mesh = obj.data
check((len(mesh.vertices), len(mesh.polygons)) == (3442, 1720), f"{len(mesh.vertices)} vertices, {len(mesh.polygons)} faces")
colors = sorted({p.color_hex for p in expected.parts})
check(sorted(m.name for m in mesh.materials) == colors, f"materials {[m.name for m in mesh.materials]}, colours {colors}")
check(len(colors) == 8, f"{len(colors)} colours")
check("#e8dcc4" in bpy.data.materials, "the wall colour's material")
# Each face has its part's material: the triangles of the first part.
first = expected.parts[0]
slot = [m.name for m in mesh.materials].index(first.color_hex)
faces = range(first.first_index // 3, (first.first_index + first.index_count) // 3)
check(all(mesh.polygons[f].material_index == slot for f in faces), "the first part's material")
# y up in the engine is z up here: (x, y, z) there is (x, -z, y) here. The house stands on its
# lot (x 0..20, z 0..30 there), its roof overhanging by 0.4 m.
def bounds(values):
    return (round(min(values), 4), round(max(values), 4))


check(bounds([v.co.x for v in mesh.vertices]) == bounds(expected.positions[0::3]) == (-0.4, 20.4), "x")
check(bounds([v.co.y for v in mesh.vertices]) == bounds([-z for z in expected.positions[2::3]]) == (-30.4, 0.4), "y")
check(bounds([v.co.z for v in mesh.vertices]) == bounds(expected.positions[1::3]), "z")
check(min(v.co.z for v in mesh.vertices) == 0, "the house stands on the ground")

# An attribute set in the panel, regenerated in place: the same object, three storeys.
storeys = next(a for a in settings.attrs if a.name == "storeys")
storeys.number = 3
check(storeys.use, "setting a value marks the attribute set")
select([obj])
check(bpy.ops.shapegram.regenerate() == {"FINISHED"}, "regenerate")
three = engine.Grammar.load(house).derive(attrs={"storeys": 3.0})
check(generated() == [obj] and obj.data == mesh, "regenerated in place")
check(len(mesh.vertices) == three.vertex_count != 3442, f"{len(mesh.vertices)} vertices after regenerating")
check(json.loads(obj["shapegram_settings"])["attrs"] == {"storeys": 3.0}, obj["shapegram_settings"])

# A plane of three 20 x 30 faces: a building on each, on its face (with the roof's overhang).
plane_mesh = bpy.data.meshes.new("plane")
corners = []
for i in range(3):
    x = 30.0 * i
    corners += [(x, 0, 0), (x + 20, 0, 0), (x + 20, 30, 0), (x, 30, 0)]
plane_mesh.from_pydata(corners, [], [(4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3) for i in range(3)])
plane = bpy.data.objects.new("plane", plane_mesh)
bpy.context.scene.collection.objects.link(plane)
select([plane])
check(bpy.ops.shapegram.generate() == {"FINISHED"}, "generate on the plane")
buildings = [o for o in generated() if o != obj]
check(len(buildings) == 3, f"{len(buildings)} buildings on 3 faces")
for i, building in enumerate(sorted(buildings, key=lambda o: min(v.co.x for v in o.data.vertices))):
    lot = json.loads(building["shapegram_lot"])
    derived = engine.Grammar.load(house).derive(attrs={"storeys": 3.0}, lots=[lot])
    vertices = building.data.vertices
    check(len(vertices) == derived.vertex_count, f"building {i}: {len(vertices)} vertices")
    xs = [v.co.x for v in vertices]
    ys = [v.co.y for v in vertices]
    inside = 30 * i - 0.5 <= min(xs) and max(xs) <= 30 * i + 20.5 and -0.5 <= min(ys) and max(ys) <= 30.5
    check(inside, f"building {i} lies on x {min(xs)}..{max(xs)}, y {min(ys)}..{max(ys)}")
    check(min(v.co.z for v in vertices) > -1e-4, f"building {i} stands on its face")

# The textured house: a UV map of the module's uvs (v flipped up) and its two images packed,
# each in the material of the parts that use it, multiplying their colour.
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
textured = str(pathlib.Path(examples) / "textured_house.cga")
settings.grammar_path = textured
check(bpy.ops.shapegram.reload() == {"FINISHED"}, "reload the textured house")
check(bpy.ops.shapegram.generate() == {"FINISHED"}, "generate the textured house")
# The panel keeps the storeys the user set for the house: this grammar declares them too.
check(settings.overrides() == {"storeys": 3.0}, f"kept overrides {settings.overrides()}")
expected = engine.Grammar.load(textured).derive(attrs={"storeys": 3.0})
(obj,) = generated()
mesh = obj.data
check(len(mesh.vertices) == expected.vertex_count, f"{len(mesh.vertices)} textured vertices")
check([layer.name for layer in mesh.uv_layers] == ["UVMap"], f"uv layers {list(mesh.uv_layers)}")
uv = mesh.uv_layers["UVMap"].data
for corner in (0, len(mesh.loops) // 2, len(mesh.loops) - 1):
    vertex = expected.indices[corner]
    want = (expected.uvs[2 * vertex], 1.0 - expected.uvs[2 * vertex + 1])
    check(all(abs(a - b) < 1e-6 for a, b in zip(uv[corner].uv, want)), f"corner {corner}: uv {tuple(uv[corner].uv)}, want {want}")
for part in expected.parts:
    if part.texture is None:
        continue
    texture = expected.textures[part.texture]
    # Named as the grammar names the material.
    material = mesh.materials[part.material]
    images = [n.image for n in material.node_tree.nodes if n.type == "TEX_IMAGE"]
    check(len(images) == 1 and images[0].name == texture.path, f"{material.name}: images {images}")
    width = int.from_bytes(texture.data[16:20], "big")
    height = int.from_bytes(texture.data[20:24], "big")
    check(images[0].packed_file is not None, f"{texture.path} is packed")
    check(tuple(images[0].size) == (width, height), f"{texture.path}: {tuple(images[0].size)} pixels, want {(width, height)}")
    slot = [m.name for m in mesh.materials].index(material.name)
    faces = range(part.first_index // 3, (part.first_index + part.index_count) // 3)
    check(all(mesh.polygons[f].material_index == slot for f in faces), f"{material.name} on its faces")
textures = sorted(t.path for t in expected.textures)
check(sorted(i.name for i in bpy.data.images if i.packed_file) == textures, f"packed images {list(bpy.data.images)}")
select([obj])
check(bpy.ops.shapegram.regenerate() == {"FINISHED"}, "regenerate the textured house")
check([layer.name for layer in obj.data.uv_layers] == ["UVMap"], "one UV map after regenerating")

# A CityEngine rule package: the rule file PRT runs, its attributes in the panel, generated with
# the brick texture packed from inside the archive.
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
town = str(pathlib.Path(examples) / "town.rpk")
settings.grammar_path = town
check(bpy.ops.shapegram.reload() == {"FINISHED"}, "reload the rule package")
check(
    [(a.name, a.type) for a in settings.attrs] == [("height", "number"), ("roofAngle", "number"), ("roofColor", "string")],
    f"the package's attributes: {[(a.name, a.type) for a in settings.attrs]}",
)
check(bpy.ops.shapegram.generate() == {"FINISHED"}, "generate the rule package")
expected = engine.Grammar.load(town).derive(attrs=settings.overrides())
(obj,) = generated()
check(len(obj.data.vertices) == expected.vertex_count, f"{len(obj.data.vertices)} vertices of the package's model")
brick = bpy.data.images.get("brick.png")
check(brick is not None and brick.packed_file is not None, f"packed images {list(bpy.data.images)}")
check([t.path for t in expected.textures] == ["brick.png"], f"the package's textures {expected.textures}")

# A grammar with an error: the operator fails with the place of it, and makes nothing.
bad = pathlib.Path(tempfile.mkdtemp()) / "bad.cga"
bad.write_text("@StartRule\nLot --> extrude(4 Mass.\n")
settings.grammar_path = str(bad)
count = len(bpy.data.objects)
try:
    bpy.ops.shapegram.generate()
    raise AssertionError("a grammar with an error generated")
except RuntimeError as error:
    check("bad.cga:2:" in str(error), f"the error says {error}")
check(len(bpy.data.objects) == count, "nothing made by a failed generation")

print(f"add-on: house {len(colors)} materials, regenerated in place, 3 buildings on 3 faces, textured house with {len(textures)} packed images, the town from its rule package")
