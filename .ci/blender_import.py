"""Imports a skinned GLB into Blender with the stock glTF importer and checks what it made.

Run headless:
  blender -b --factory-startup --python-exit-code 1 --python .ci/blender_import.py -- FILE.glb EXPECTED.json
EXPECTED.json comes from .ci/gltf_skins.py (the skins, joints, vertices and poses read from the
same GLB). The import uses the importer's default options (Bone Dir "Temperance", Guess
Original Bind Pose on). Checked, each printed as "ok" or "FAIL":
- one armature object per skin, named after the skin, with one bone per joint, named after
  it, parented as the joints are;
- every skinned mesh: an Armature modifier on its skin's armature, one vertex group per joint,
  every vertex in exactly one group with weight 1, as many vertices in each group as the file
  binds to the joint;
- the vertices in the rest pose (armature in Rest Position) are the file's POSITIONs, and in
  the imported pose they are where glTF skinning puts them (Blender's z-up: x, -z, y);
- the joint extras (`shapegram.joint`) on the pose bones and the bones, equal to the file's;
- for each pose of EXPECTED.json: turning that pose bone by 20° about its local x turns exactly
  the vertices in the groups of it and the bones below it about that axis (each moves by the
  chord of its distance from the axis, within 1e-4 m; those on the axis stay) and moves no
  other vertex by more than 1e-6 m.
Exits 1 on any failure (and, with --python-exit-code 1, on an uncaught exception), 0 otherwise.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_checks import check, run  # noqa: E402  (also gives numpy the alias the importer needs)

import bpy
from mathutils import Matrix, Vector

MOVED = 1e-4  # a vertex of the turned parts moves further than this (metres)
STATIC = 1e-6  # every other vertex stays this close
SAME = 1e-4  # positions compared with the file's (f32 data, posed through a few joints)
TURN = math.radians(20)


def to_blender(p):
    """glTF's y-up point in Blender's z-up space, as the importer converts it."""
    return Vector((p[0], -p[2], p[1]))


def world_positions(objects):
    """Every vertex of the objects in world space, as the depsgraph evaluates them (modifiers
    applied), per object name."""
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    out = {}
    for obj in objects:
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        out[obj.name] = [evaluated.matrix_world @ v.co for v in mesh.vertices]
        evaluated.to_mesh_clear()
    return out


def same_values(a, b):
    """Extras as Blender keeps them (ID properties: dicts and float arrays) against the file's."""
    if isinstance(b, dict):
        return isinstance(a, dict) and a.keys() == b.keys() and all(same_values(a[k], b[k]) for k in b)
    if isinstance(b, list):
        return len(a) == len(b) and all(same_values(x, y) for x, y in zip(a, b))
    if isinstance(b, float):
        return abs(a - b) <= 1e-12 * max(1.0, abs(b))
    return a == b


def as_python(value):
    return value.to_dict() if hasattr(value, "to_dict") else value


def axis_name(v):
    """The signed axis nearest to a unit vector, e.g. "+y"."""
    i = max(range(3), key=lambda k: abs(v[k]))
    return ("+" if v[i] > 0 else "-") + "xyz"[i] + ("" if abs(v[i]) > 0.9999 else "~")


def bone_axes(bone, joint):
    """The bone's rest x, y and z axes in its joint's axes, e.g. "x=+x y=+y z=+z" (a "~"
    marks an axis that is no joint axis)."""
    rest = bone.matrix_local.to_3x3()
    axes = [to_blender(axis) for axis in joint["rest_axes"]]
    return " ".join(
        f"{name}={axis_name(Vector([column.dot(a) for a in axes]))}"
        for name, column in zip("xyz", rest.transposed())
    )


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(argv) != 2:
        print("usage: blender -b --factory-startup --python blender_import.py -- FILE.glb EXPECTED.json")
        sys.exit(2)
    glb, expected_path = argv
    with open(expected_path) as f:
        expected = json.load(f)

    print(f"== {glb} in Blender {bpy.app.version_string}")
    # An empty scene: no default cube, camera or light among the imported objects.
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.import_scene.gltf(filepath=glb)
    if not check(result == {"FINISHED"}, f"import: {result}"):
        return

    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    check(
        len(armatures) == len(expected["skins"]),
        f"{len(armatures)} armature object(s) ({', '.join(o.name for o in armatures)}) "
        f"for {len(expected['skins'])} skin(s)",
    )
    skinned = []
    for skin in expected["skins"]:
        arma = bpy.data.objects.get(skin["name"])
        if not check(arma is not None and arma.type == "ARMATURE", f"armature object {skin['name']}"):
            continue
        joints = skin["joints"]
        bones = arma.data.bones
        check(
            len(bones) == len(joints),
            f"{skin['name']}: {len(bones)} bones for {len(joints)} joints",
        )
        missing = [j["name"] for j in joints if j["name"] not in bones]
        check(not missing, f"{skin['name']}: a bone named after every joint (missing: {missing[:5]})")
        wrong_parent = [
            j["name"] for j in joints if j["name"] in bones
            and (bones[j["name"]].parent.name if bones[j["name"]].parent else None)
            != (joints[j["parent"]]["name"] if j["parent"] is not None else None)
        ]
        check(not wrong_parent, f"{skin['name']}: every bone's parent is its joint's parent (wrong: {wrong_parent[:5]})")

        # Where the joint extras land.
        with_extras = [j for j in joints if isinstance(j["extras"], dict) and j["name"] in bones]
        places = {"pose bone": arma.pose.bones, "bone": bones}
        for place, items in places.items():
            found = [j for j in with_extras if all(k in items[j["name"]] for k in j["extras"])]
            equal = [
                j for j in found
                if all(same_values(as_python(items[j["name"]][k]), v) for k, v in j["extras"].items())
            ]
            check(
                len(equal) == len(with_extras),
                f"{skin['name']}: joint extras on the {place}s: {len(found)} of {len(with_extras)}, "
                f"{len(equal)} equal to the file's",
            )
        print(f"  note armature object custom properties: {sorted(arma.keys()) or 'none'}")

        # Bone axes: the importer's "Bone Dir" heuristic turns each bone so that its y axis
        # (head → tail) lies along one of the joint's axes; the pose bone's local axes are then
        # a signed permutation of the joint's (glTF) axes, in which the extras' limits are.
        # Shown per permutation, with the bones' lengths (glTF has none: the importer guesses).
        layouts = {}
        for j in joints:
            bone = bones.get(j["name"])
            if bone is not None:
                layouts.setdefault(bone_axes(bone, j), []).append(f"{bone.name}({bone.length:.3g} m)")
        for layout, names in sorted(layouts.items(), key=lambda item: -len(item[1])):
            shown = " ".join(names[:6]) + (" …" if len(names) > 6 else "")
            print(f"  note bone axes in joint axes {layout}: {len(names)} bones: {shown}")

        for mesh in skin["meshes"]:
            obj = bpy.data.objects.get(mesh["name"])
            if not check(obj is not None and obj.type == "MESH", f"mesh object {mesh['name']}"):
                continue
            skinned.append((obj, mesh, skin, arma))
            modifiers = [m for m in obj.modifiers if m.type == "ARMATURE" and m.object == arma]
            check(
                bool(modifiers) or (obj.parent == arma and obj.parent_type == "ARMATURE"),
                f"{obj.name}: Armature modifier on {arma.name} ({[m.name for m in modifiers]}, parent {obj.parent and obj.parent.name})",
            )
            check(
                len(obj.data.vertices) == mesh["vertices"],
                f"{obj.name}: {len(obj.data.vertices)} vertices, the file has {mesh['vertices']}",
            )
            groups = {g.index: g.name for g in obj.vertex_groups}
            check(
                sorted(groups.values()) == sorted(j["name"] for j in joints),
                f"{obj.name}: {len(groups)} vertex groups, one per joint",
            )
            not_rigid = [
                v.index for v in obj.data.vertices
                if len(v.groups) != 1 or abs(v.groups[0].weight - 1) > 1e-6
            ]
            check(not not_rigid, f"{obj.name}: every vertex in exactly one group with weight 1 (not: {len(not_rigid)})")
            counts = {}
            for v in obj.data.vertices:
                for g in v.groups:
                    counts[groups[g.group]] = counts.get(groups[g.group], 0) + 1
            differ = {n: (counts.get(n, 0), c) for n, c in mesh["per_joint"].items() if counts.get(n, 0) != c}
            differ.update({n: (c, 0) for n, c in counts.items() if n not in mesh["per_joint"]})
            check(not differ, f"{obj.name}: vertices per group as bound in the file (differ: {dict(list(differ.items())[:5])})")

    if not skinned:
        return
    objects = [obj for obj, _, _, _ in skinned]

    # Rest and imported pose against the file.
    for arma in armatures:
        arma.data.pose_position = "REST"
    rest = world_positions(objects)
    for arma in armatures:
        arma.data.pose_position = "POSE"
    posed = world_positions(objects)
    for obj, mesh, _, _ in skinned:
        if len(rest[obj.name]) != mesh["vertices"]:
            continue
        for label, got, want in (("rest pose", rest, "rest"), ("imported pose", posed, "posed")):
            error = max((g - to_blender(w)).length for g, w in zip(got[obj.name], mesh[want]))
            check(error <= SAME, f"{obj.name}: {label} vertices as in the file (largest distance {error:.2g} m)")

    # Turning a bone moves exactly the parts below it.
    for pose in expected["poses"]:
        skin = expected["skins"][pose["skin"]]
        arma = bpy.data.objects.get(skin["name"])
        name = pose["joint"]
        if arma is None or name not in arma.pose.bones:
            check(False, f"no pose bone {name}")
            continue
        pose_bone = arma.pose.bones[name]
        joint = next(j for j in skin["joints"] if j["name"] == name)
        below = {b.name for b in [pose_bone.bone] + list(pose_bone.bone.children_recursive)}
        check(
            below == set(pose["below"]),
            f"turning {name}: {len(below)} bones at and below it, the file has {len(pose['below'])} joints",
        )
        before = world_positions(objects)
        # The turn is about the bone's local x through its head, in world space: the line
        # through the posed bone's origin along its x column. A vertex below the bone moves by
        # the chord 2·r·sin(10°) of its distance r from that line; the few on the line (balls'
        # poles, pins) stay and are counted apart.
        frame = arma.matrix_world @ pose_bone.matrix
        origin, axis = frame.translation.copy(), frame.col[0].xyz.normalized()
        basis = pose_bone.matrix_basis.copy()
        pose_bone.matrix_basis = basis @ Matrix.Rotation(TURN, 4, "X")
        after = world_positions(objects)
        pose_bone.matrix_basis = basis
        moved = on_axis = static = 0
        wrong = []
        for obj in objects:
            groups = {g.index: g.name for g in obj.vertex_groups}
            for v, p, q in zip(obj.data.vertices, before[obj.name], after[obj.name]):
                d = (q - p).length
                if any(groups[g.group] in below for g in v.groups):
                    r = (p - origin).cross(axis).length
                    chord = 2 * r * math.sin(TURN / 2)
                    ok = abs(d - chord) <= SAME
                    if chord > MOVED:
                        moved += 1
                        ok = ok and d > MOVED
                    else:
                        on_axis += 1
                else:
                    ok = d <= STATIC
                    static += ok
                if not ok:
                    group = groups[v.groups[0].group] if v.groups else None
                    wrong.append(f"{obj.name} vertex {v.index} ({group}) moved {d:.3g} m")
        print(
            f"  turning {name} by 20° about its local x (bone axes in joint axes: "
            f"{bone_axes(pose_bone.bone, joint)}): {moved} vertices moved, {on_axis} on the axis "
            f"stayed, {static} static"
        )
        check(
            not wrong and moved + on_axis == pose["moved"] and static == pose["static"],
            f"turning {name}: {moved + on_axis} vertices at or below it (the file binds {pose['moved']}) "
            f"turned about its axis, {static} others static (want {pose['static']})"
            + (f"; wrong: {len(wrong)}, e.g. {'; '.join(wrong[:3])}" if wrong else ""),
        )


run(main)
