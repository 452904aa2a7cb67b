"""A pose made in Blender survives deriving the grammar again: poses the first file's armature,
keeps the pose by bone name as an animator's copied pose would, imports the second file (the
same grammar derived again after an edit that added sections) and pastes the pose by name.

Run headless:
  blender -b --factory-startup --python-exit-code 1 --python .ci/blender_repose.py -- \
      BEFORE.glb AFTER.glb BONE CHANGED
BONE is the prefix of the bone turned (20° about its local x, on top of the imported pose);
CHANGED is the prefix of the bone whose parts the edit changed. Checked, each printed as "ok"
or "FAIL":
- every bone of the first armature has a bone of the same name in the second;
- with the pose pasted by name, every vertex group of the first file but CHANGED's has as many
  vertices in the second, in the same places up to order (each within 1e-4 m of one of the
  other's), the turned bone's included.
Exits 1 on any failure, 0 otherwise.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_checks import check, run  # noqa: E402  (also gives numpy the alias the importer needs)

import bpy
from mathutils import Matrix
from mathutils.kdtree import KDTree

SAME = 1e-4  # metres
TURN = math.radians(20)


def load(glb):
    """The armature imported from a file, in an empty scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if bpy.ops.import_scene.gltf(filepath=glb) != {"FINISHED"}:
        raise RuntimeError(f"cannot import {glb}")
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    if len(armatures) != 1:
        raise RuntimeError(f"{glb}: {len(armatures)} armatures, expected 1")
    return armatures[0]


def groups_posed():
    """Each vertex group's vertices in world space as the depsgraph poses them, sorted."""
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    out = {}
    for obj in bpy.data.objects:
        if obj.type != "MESH":
            continue
        names = {g.index: g.name for g in obj.vertex_groups}
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        for v, posed in zip(obj.data.vertices, mesh.vertices):
            p = evaluated.matrix_world @ posed.co
            for g in v.groups:
                out.setdefault(names[g.group], []).append(tuple(p))
        evaluated.to_mesh_clear()
    return out


def same_places(points, theirs):
    """Whether two lists of points are the same up to order, each point within SAME of one of
    the other list and the counts equal."""
    if len(points) != len(theirs):
        return False
    for a, b in ((points, theirs), (theirs, points)):
        tree = KDTree(len(b))
        for i, p in enumerate(b):
            tree.insert(p, i)
        tree.balance()
        if any(tree.find(p)[2] > SAME for p in a):
            return False
    return True


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(argv) != 4:
        print("usage: blender -b --python blender_repose.py -- BEFORE.glb AFTER.glb BONE CHANGED")
        sys.exit(2)
    before, after, turned, changed = argv
    print(f"== a pose of {before} pasted on {after} in Blender {bpy.app.version_string}")

    arma = load(before)
    bone = next((b for b in arma.pose.bones if b.name.startswith(turned)), None)
    if not check(bone is not None, f"a bone named {turned}…"):
        return
    bone.matrix_basis = bone.matrix_basis @ Matrix.Rotation(TURN, 4, "X")
    turned = bone.name
    # The whole pose, by bone name: what copying a pose in Blender keeps.
    pose = {b.name: b.matrix_basis.copy() for b in arma.pose.bones}
    expected = groups_posed()
    changed_groups = {n for n in expected if n.startswith(changed)}

    arma = load(after)
    missing = [name for name in pose if name not in arma.pose.bones]
    check(
        not missing,
        f"all {len(pose)} bones of the first file are in the second "
        f"({len(arma.pose.bones)} bones; missing: {missing[:5]})",
    )
    for name, basis in pose.items():
        if name in arma.pose.bones:
            arma.pose.bones[name].matrix_basis = basis
    found = groups_posed()
    same, differ = [], []
    for name, points in expected.items():
        if name in changed_groups:
            continue
        (same if same_places(points, found.get(name, [])) else differ).append(name)
    check(
        not differ and any(n.startswith(turned) for n in same),
        f"{len(same)} vertex groups (the turned {turned} among them) posed alike in both "
        f"files, {len(changed_groups)} changed by the edit left out; differing: {differ[:5]}",
    )


run(main)
