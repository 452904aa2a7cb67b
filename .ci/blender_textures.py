"""Imports the textured house's GLB into Blender with the stock glTF importer and checks that it
opens textured: both images packed at their sizes, each feeding a material's Base Color, and the
brick walls' UV map as the grammar made it (CGA's v up again after glTF's v down).

Run headless:
  blender -b --factory-startup --python-exit-code 1 --python .ci/blender_textures.py -- FILE.glb
Exits 1 on any failure, 0 otherwise.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_checks import check, run  # noqa: E402  (also gives numpy the alias the importer needs)

import bpy


def main():
    path = sys.argv[sys.argv.index("--") + 1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    sizes = {image.name: tuple(image.size) for image in bpy.data.images if image.size[0] > 0}
    check(sizes == {"brick.png": (128, 64), "tiles.png": (64, 64)}, f"images {sizes}")
    fed = {}
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        for link in material.node_tree.links:
            if link.from_node.type == "TEX_IMAGE" and link.to_socket.name == "Base Color":
                fed[link.from_node.image.name] = material
    check(sorted(fed) == ["brick.png", "tiles.png"], f"images feeding Base Color: {sorted(fed)}")
    brick = fed.get("brick.png")
    low, high = [float("inf")] * 2, [float("-inf")] * 2
    for obj in bpy.data.objects:
        if obj.type != "MESH" or brick is None:
            continue
        mesh = obj.data
        slots = [i for i, m in enumerate(mesh.materials) if m == brick]
        if not slots or not mesh.uv_layers:
            continue
        uv = mesh.uv_layers.active.data
        for polygon in mesh.polygons:
            if polygon.material_index not in slots:
                continue
            for loop in polygon.loop_indices:
                u, v = uv[loop].uv
                low = [min(low[0], u), min(low[1], v)]
                high = [max(high[0], u), max(high[1], v)]
    # 1 m tiles along the 20 m front and the 30 m sides, 0.5 m courses up the 6 m walls.
    ok = all(abs(a - b) < 1e-4 for a, b in zip(low + high, [0, 0, 30, 12]))
    check(ok, f"brick UVs from {low} to {high}, expected [0, 0] to [30, 12]")


run(main)
