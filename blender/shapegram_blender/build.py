"""Derived buffers to Blender meshes and materials, and mesh faces to lots.

Shapegram is y-up, Blender z-up: a point (x, y, z) of the engine is (x, -z, y) in Blender, a
quarter turn about x, which keeps counter-clockwise polygons counter-clockwise. Textured parts
get a UV map (the engine's v points down as glTF's does, Blender's up) and materials whose
image, packed into the .blend file, multiplies the part's colour as in the GLB."""

import array
import math
import pathlib
import tempfile

import bpy
from mathutils import Matrix

# Engine to Blender coordinates.
Y_UP_TO_Z_UP = Matrix.Rotation(math.pi / 2, 4, "X")


def lot_of_face(obj, polygon):
    """The corners of a mesh face in world space, as an engine lot (y up)."""
    world = obj.matrix_world
    corners = []
    for index in polygon.vertices:
        x, y, z = world @ obj.data.vertices[index].co
        corners.append((x, z, -y))
    return corners


def _linear(channel):
    # Blender's material colours are scene-linear; the grammar's are sRGB.
    return channel / 12.92 if channel <= 0.04045 else ((channel + 0.055) / 1.055) ** 2.4


def _image(texture):
    """The texture's image, named after its path and packed into the .blend, made on first use."""
    found = bpy.data.images.get(texture.path)
    if found is not None:
        return found
    suffix = ".png" if texture.data.startswith(b"\x89PNG") else ".jpg"
    # Blender reads images from files only: the bytes go through a temporary one, then are
    # packed, so the image outlives it.
    with tempfile.TemporaryDirectory() as folder:
        file = pathlib.Path(folder) / f"texture{suffix}"
        file.write_bytes(texture.data)
        image = bpy.data.images.load(str(file))
        image.pack()
    image.name = texture.path
    return image


def material(part, texture=None):
    """The material of a part, made on first use: named as the grammar names it
    (`set(material.name, …)`), else after its colour (`#rrggbb`) and texture path when textured.
    A name already taken by another colour or image gets Blender's `.001` suffix."""
    if part.material:
        name = part.material
    else:
        name = part.color_hex if texture is None else f"{part.color_hex} {texture.path}"
    r, g, b, a = part.color
    color = (_linear(r), _linear(g), _linear(b), a)
    key = f"{part.color_hex} {texture.path if texture else ''}"
    for found in bpy.data.materials:
        if found.get("shapegram_key") == key and (found.name == name or found.name.startswith(f"{name}.")):
            return found
    made = bpy.data.materials.new(name)
    made["shapegram_key"] = key
    made.diffuse_color = color
    made.use_nodes = True
    nodes = made.node_tree.nodes
    principled = nodes.get("Principled BSDF")
    if principled is not None:
        principled.inputs["Base Color"].default_value = color
        principled.inputs["Alpha"].default_value = a
        if texture is not None:
            image = nodes.new("ShaderNodeTexImage")
            image.image = _image(texture)
            tint = nodes.new("ShaderNodeMixRGB")
            tint.blend_type = "MULTIPLY"
            tint.inputs["Fac"].default_value = 1.0
            tint.inputs["Color2"].default_value = color
            links = made.node_tree.links
            links.new(image.outputs["Color"], tint.inputs["Color1"])
            links.new(tint.outputs["Color"], principled.inputs["Base Color"])
    if a < 1.0:
        made.blend_method = "BLEND"
    return made


def _uvs(data, result):
    """The engine's uvs as the mesh's UV map, one per face corner, v flipped to point up."""
    uvs = result.uvs
    corners = array.array("f", bytes(8 * len(result.indices)))
    for corner, vertex in enumerate(result.indices):
        corners[2 * corner] = uvs[2 * vertex]
        corners[2 * corner + 1] = 1.0 - uvs[2 * vertex + 1]
    layer = data.uv_layers.get("UVMap") or data.uv_layers.new(name="UVMap")
    layer.data.foreach_set("uv", corners)


def fill(data, result):
    """Replaces the geometry and materials of the Blender mesh `data` with the engine's `result`."""
    data.clear_geometry()
    data.materials.clear()
    triangles = result.triangle_count
    data.vertices.add(result.vertex_count)
    data.vertices.foreach_set("co", result.positions)
    data.loops.add(3 * triangles)
    # Blender's vertex indices are signed: the same bytes as "i" are copied in one go.
    indices = array.array("i")
    indices.frombytes(memoryview(result.indices).cast("B"))
    data.loops.foreach_set("vertex_index", indices)
    data.polygons.add(triangles)
    data.polygons.foreach_set("loop_start", array.array("i", range(0, 3 * triangles, 3)))
    data.polygons.foreach_set("loop_total", array.array("i", [3]) * triangles)
    slots = {}
    material_index = array.array("i", [0]) * triangles
    for part in result.parts:
        texture = None if part.texture is None else result.textures[part.texture]
        key = (part.color_hex, None if texture is None else texture.path, part.material)
        slot = slots.get(key)
        if slot is None:
            slot = slots[key] = len(data.materials)
            data.materials.append(material(part, texture))
        first = part.first_index // 3
        material_index[first : first + part.index_count // 3] = array.array("i", [slot]) * (part.index_count // 3)
    data.polygons.foreach_set("material_index", material_index)
    if len(result.uvs):
        _uvs(data, result)
    data.update(calc_edges=True)
    # The engine's normals (flat faces have vertices of their own, smooth parts share them).
    normals = result.normals
    data.polygons.foreach_set("use_smooth", array.array("b", [1]) * triangles)
    data.use_auto_smooth = True
    data.normals_split_custom_set_from_vertices(
        [(normals[i], normals[i + 1], normals[i + 2]) for i in range(0, len(normals), 3)]
    )
    data.transform(Y_UP_TO_Z_UP)
