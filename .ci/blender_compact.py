"""Imports compact GLBs (shared vertices, merged coplanar rectangles; plain and --quantize) into
Blender with the stock glTF importer and checks that each opens whole: as many triangles as the
file's primitives hold and the model's bounds where the file's POSITION bounds say (glTF's y up
is Blender's z up; a quantised file's nodes scale its integers back, within a grid step).
Primitives without normals (flat parts, whose faces share their corners) must come in
flat-shaded: their polygons not smooth, each corner's normal its polygon's normal.

Run headless:
  blender -b --factory-startup --python-exit-code 1 --python .ci/blender_compact.py -- \
      PLAIN.glb [QUANTIZED.glb ...]
The first file gives the expectations (read from its JSON with the standard library). Exits 1
on any failure, 0 otherwise.
"""
import json
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_checks import check, run  # noqa: E402  (also gives numpy the alias the importer needs)

import bpy
from mathutils import Vector


def expectations(path):
    """Triangles and glTF-space bounds of a float GLB whose mesh nodes have no transformation."""
    with open(path, "rb") as f:
        data = f.read()
    length, kind = struct.unpack_from("<II", data, 12)
    assert kind == 0x4E4F534A, "the first chunk is JSON"
    document = json.loads(data[20:20 + length])
    accessors = document["accessors"]
    triangles = flat = 0
    low, high = [float("inf")] * 3, [float("-inf")] * 3
    for mesh in document["meshes"]:
        for primitive in mesh["primitives"]:
            count = accessors[primitive["indices"]]["count"] // 3
            triangles += count
            if "NORMAL" not in primitive["attributes"]:
                flat += count
            position = accessors[primitive["attributes"]["POSITION"]]
            low = [min(a, b) for a, b in zip(low, position["min"])]
            high = [max(a, b) for a, b in zip(high, position["max"])]
    return triangles, flat, low, high


def flat_shaded(mesh, polygon):
    """Whether Blender shades `polygon` flat: not smooth, and every corner's normal its own."""
    if polygon.use_smooth:
        return False
    return all(
        (mesh.loops[loop].normal - polygon.normal).length < 1e-4 for loop in polygon.loop_indices
    )


def imported(path):
    """Triangles, flat-shaded triangles and glTF-space bounds of the meshes Blender makes of
    `path`."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    triangles = flat = 0
    low, high = [float("inf")] * 3, [float("-inf")] * 3
    for obj in bpy.data.objects:
        if obj.type != "MESH":
            continue
        mesh = obj.data
        mesh.calc_normals_split()
        triangles += sum(len(p.vertices) - 2 for p in mesh.polygons)
        flat += sum(len(p.vertices) - 2 for p in mesh.polygons if flat_shaded(mesh, p))
        for vertex in obj.data.vertices:
            x, y, z = obj.matrix_world @ Vector(vertex.co)
            gltf = (x, z, -y)
            low = [min(a, b) for a, b in zip(low, gltf)]
            high = [max(a, b) for a, b in zip(high, gltf)]
    return triangles, flat, low, high


def main():
    paths = sys.argv[sys.argv.index("--") + 1:]
    triangles, flat, low, high = expectations(paths[0])
    # The quantisation grid's step: 32,767 steps each side of the centre of the largest extent.
    step = max(h - l for l, h in zip(low, high)) / 2 / 32767
    for path in paths:
        name = os.path.basename(path)
        got, got_flat, got_low, got_high = imported(path)
        check(got == triangles, f"{name}: {got} triangles, expected {triangles}")
        # At least the triangles without normals in the file; Blender may find more flat.
        check(got_flat >= flat, f"{name}: {got_flat} flat-shaded triangles, expected {flat}")
        close = all(abs(a - b) <= step + 1e-4 for a, b in zip(got_low + got_high, low + high))
        check(close, f"{name}: bounds {got_low} to {got_high}, expected {low} to {high}")


run(main)
