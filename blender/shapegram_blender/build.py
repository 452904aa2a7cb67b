"""Derived buffers to Blender meshes and materials, and mesh faces to lots.

Shapegram is y-up, Blender z-up: a point (x, y, z) of the engine is (x, -z, y) in Blender, a
quarter turn about x, which keeps counter-clockwise polygons counter-clockwise."""

import array
import math

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


def material(part):
    """The material named after the part's colour (`#rrggbb`), made on first use."""
    found = bpy.data.materials.get(part.color_hex)
    if found is not None:
        return found
    made = bpy.data.materials.new(part.color_hex)
    r, g, b, a = part.color
    color = (_linear(r), _linear(g), _linear(b), a)
    made.diffuse_color = color
    made.use_nodes = True
    principled = made.node_tree.nodes.get("Principled BSDF")
    if principled is not None:
        principled.inputs["Base Color"].default_value = color
        principled.inputs["Alpha"].default_value = a
    if a < 1.0:
        made.blend_method = "BLEND"
    return made


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
        slot = slots.get(part.color_hex)
        if slot is None:
            slot = slots[part.color_hex] = len(data.materials)
            data.materials.append(material(part))
        first = part.first_index // 3
        material_index[first : first + part.index_count // 3] = array.array("i", [slot]) * (part.index_count // 3)
    data.polygons.foreach_set("material_index", material_index)
    data.update(calc_edges=True)
    # The engine's normals (flat faces have vertices of their own, smooth parts share them).
    normals = result.normals
    data.polygons.foreach_set("use_smooth", array.array("b", [1]) * triangles)
    data.use_auto_smooth = True
    data.normals_split_custom_set_from_vertices(
        [(normals[i], normals[i + 1], normals[i + 2]) for i in range(0, len(normals), 3)]
    )
    data.transform(Y_UP_TO_Z_UP)
