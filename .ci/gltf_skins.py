#!/usr/bin/env python3
"""What a GLB's skins should become in Blender, as JSON for .ci/blender_import.py.

Reads the GLB's JSON and BIN chunks with the standard library only (CI's system Python has no
numpy or gltf package), so the expectations come from the file and not from Blender:
- per skin: its name (Blender names the armature object after it) and its joints in skin
  order, each with its parent joint, its node extras, its axes at rest and how many
  vertices it binds;
- per skinned mesh node: its name, vertex count, vertices per joint, and every vertex's
  position in the rest pose (the POSITION accessor) and in the file's pose (skinned as a
  viewer does: the joints' global transformations times their inverse bind matrices);
- per --pose PREFIX: the first joint whose name starts with PREFIX, the joints below it, and
  how many vertices move when it turns (those bound to it or below it) and how many stay.
Every vertex must hang from exactly one joint with weight 1 (our rigid binding,
docs/kinematics.md); anything else is an error here, before Blender runs.

Usage: python3 .ci/gltf_skins.py FILE.glb [--pose PREFIX]... -o EXPECTED.json
"""
import argparse
import json
import math
import struct
import sys

COMPONENTS = {5120: "b", 5121: "B", 5122: "h", 5123: "H", 5125: "I", 5126: "f"}
NORMALIZE = {5121: 255.0, 5123: 65535.0}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(1)


def read_glb(path):
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or length != len(data):
        fail(f"{path}: not a glTF 2 binary of {len(data)} bytes")
    json_length, json_type = struct.unpack_from("<I4s", data, 12)
    if json_type != b"JSON":
        fail(f"{path}: the first chunk is not JSON")
    gltf = json.loads(data[20 : 20 + json_length])
    offset = 20 + json_length
    binary = b""
    if offset < len(data):
        bin_length, bin_type = struct.unpack_from("<I4s", data, offset)
        if bin_type != b"BIN\0":
            fail(f"{path}: the second chunk is not BIN")
        binary = data[offset + 8 : offset + 8 + bin_length]
    return gltf, binary


def accessor(gltf, binary, index):
    """The accessor's elements as tuples of floats (normalised integers scaled to 0..1)."""
    acc = gltf["accessors"][index]
    if "sparse" in acc or "bufferView" not in acc:
        fail(f"accessor {index}: sparse or without a buffer view")
    view = gltf["bufferViews"][acc["bufferView"]]
    code = COMPONENTS[acc["componentType"]]
    width = WIDTH[acc["type"]]
    element = struct.calcsize("<" + code * width)
    stride = view.get("byteStride", element)
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    scale = NORMALIZE.get(acc["componentType"]) if acc.get("normalized") else None
    out = []
    for i in range(acc["count"]):
        values = struct.unpack_from("<" + code * width, binary, start + i * stride)
        out.append(tuple(v / scale for v in values) if scale else values)
    return out


def mat_mul(a, b):
    """4x4 matrices as row-major lists of rows."""
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    sx, sy, sz = node.get("scale", [1, 1, 1])
    tx, ty, tz = node.get("translation", [0, 0, 0])
    rot = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]
    return [
        [rot[0][0] * sx, rot[0][1] * sy, rot[0][2] * sz, tx],
        [rot[1][0] * sx, rot[1][1] * sy, rot[1][2] * sz, ty],
        [rot[2][0] * sx, rot[2][1] * sy, rot[2][2] * sz, tz],
        [0, 0, 0, 1],
    ]


def transform(m, p):
    return [m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3] for r in range(3)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("glb")
    parser.add_argument("--pose", action="append", default=[], metavar="PREFIX")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()

    gltf, binary = read_glb(args.glb)
    nodes = gltf["nodes"]
    skins = gltf.get("skins", [])
    if not skins:
        fail(f"{args.glb}: no skins")
    # Blender's importer makes the first animation the armature's action, so the pose it shows
    # is that clip's (a grammar's first named pose): its keyframes stand in for the nodes' own
    # translations and rotations.
    animations = gltf.get("animations", [])
    if animations:
        first = animations[0]
        for channel in first["channels"]:
            target = channel["target"]
            if target.get("path") in ("translation", "rotation"):
                output = first["samplers"][channel["sampler"]]["output"]
                nodes[target["node"]][target["path"]] = list(accessor(gltf, binary, output)[0])
    parent = {}
    for i, node in enumerate(nodes):
        for child in node.get("children", []):
            parent[child] = i

    # Global transformation of every node (the scene graph's, root first).
    global_matrix = {}

    def world(i):
        if i not in global_matrix:
            local = node_matrix(nodes[i])
            global_matrix[i] = mat_mul(world(parent[i]), local) if i in parent else local
        return global_matrix[i]

    out_skins = []
    for s, skin in enumerate(skins):
        joints = skin["joints"]
        position_in_skin = {node: j for j, node in enumerate(joints)}
        ibms = accessor(gltf, binary, skin["inverseBindMatrices"])
        # Column-major MAT4 → rows; skinning matrix = global(joint) · IBM.
        skinning = [
            mat_mul(world(node), [[ibm[c * 4 + r] for c in range(4)] for r in range(4)])
            for node, ibm in zip(joints, ibms)
        ]
        out_joints = []
        for node, ibm in zip(joints, ibms):
            up = parent.get(node)
            out_joints.append(
                {
                    "name": nodes[node].get("name", ""),
                    "parent": position_in_skin.get(up),
                    "extras": nodes[node].get("extras"),
                    # The joint's x, y and z axes at rest in model space: the rotation the
                    # inverse bind matrix undoes (its transpose), i.e. the IBM's rows.
                    "rest_axes": [[ibm[c * 4 + r] for c in range(3)] for r in range(3)],
                    "vertices": 0,
                }
            )
        meshes = []
        for n, node in enumerate(nodes):
            if node.get("skin") != s:
                continue
            rest, posed, per_joint = [], [], {}
            for prim in gltf["meshes"][node["mesh"]]["primitives"]:
                attrs = prim["attributes"]
                positions = accessor(gltf, binary, attrs["POSITION"])
                bound = zip(accessor(gltf, binary, attrs["JOINTS_0"]), accessor(gltf, binary, attrs["WEIGHTS_0"]))
                for v, (p, (js, ws)) in enumerate(zip(positions, bound)):
                    weighted = [(j, w) for j, w in zip(js, ws) if w > 0]
                    if len(weighted) != 1 or abs(weighted[0][1] - 1) > 1e-6:
                        fail(f"{args.glb}: node {n} vertex {len(rest)} is not bound rigidly: {weighted}")
                    joint = weighted[0][0]
                    name = out_joints[joint]["name"]
                    per_joint[name] = per_joint.get(name, 0) + 1
                    out_joints[joint]["vertices"] += 1
                    rest.append(list(p))
                    posed.append(transform(skinning[joint], p))
            meshes.append(
                {
                    "name": node.get("name", ""),
                    "vertices": len(rest),
                    "per_joint": per_joint,
                    "rest": rest,
                    "posed": posed,
                }
            )
        out_skins.append({"name": skin.get("name", "Armature"), "joints": out_joints, "meshes": meshes})

    total = sum(m["vertices"] for skin in out_skins for m in skin["meshes"])
    poses = []
    for prefix in args.pose:
        found = [
            (s, j) for s, skin in enumerate(out_skins) for j, joint in enumerate(skin["joints"])
            if joint["name"].startswith(prefix)
        ]
        if not found:
            fail(f"{args.glb}: no joint named {prefix}…")
        s, j = found[0]
        joints = out_skins[s]["joints"]
        below = {j}
        while True:
            more = {k for k, joint in enumerate(joints) if joint["parent"] in below} - below
            if not more:
                break
            below |= more
        if len(below) == 1:
            fail(f"{args.glb}: joint {joints[j]['name']} has no joints below it")
        moved = sum(joints[k]["vertices"] for k in below)
        poses.append(
            {
                "skin": s,
                "joint": joints[j]["name"],
                "below": sorted(joints[k]["name"] for k in below),
                "moved": moved,
                "static": total - moved,
            }
        )

    with open(args.output, "w") as f:
        json.dump({"file": args.glb, "skins": out_skins, "poses": poses}, f)
    print(
        f"{args.glb}: {len(out_skins)} skin(s), "
        + ", ".join(f"{len(s['joints'])} joints" for s in out_skins)
        + f", {total} skinned vertices"
        + "".join(f"; turning {p['joint']} moves {p['moved']}, keeps {p['static']}" for p in poses)
    )


if __name__ == "__main__":
    main()
