#!/usr/bin/env python3
"""Prints the Shapegram metadata of a GLB's nodes, one JSON object per line.

Each line is {"node": index, "name": ..., "mesh": index or null, "parent": index or null,
"instances": n, plus the keys of the node's extras["shapegram"]: "rule", "path", "attributes",
"goals", "tags", "reports", and "leaves" on a lot's node}. "instances" is the number of copies the
node draws (its EXT_mesh_gpu_instancing count, else 1); "parent" is the node that lists it as a
child (a leaf's lot node under --metadata). Nodes without Shapegram metadata are left out unless
--all is given. Only the standard library is used: the JSON chunk is read straight from the GLB
framing (docs/export.md, "Metadata").

Usage: python3 tools/glb_metadata.py [--all] FILE.glb
"""
import json
import struct
import sys


def json_chunk(data):
    """The parsed JSON chunk of GLB bytes."""
    magic, version, _length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        raise ValueError("not a GLB 2.0 file")
    chunk_length, chunk_type = struct.unpack_from("<II", data, 12)
    if chunk_type != 0x4E4F534A:
        raise ValueError("the first chunk is not JSON")
    return json.loads(data[20:20 + chunk_length])


def rows(document, everything=False):
    """One dict per node (with metadata, unless `everything`)."""
    accessors = document.get("accessors", [])
    nodes = document.get("nodes", [])
    parents = {child: index for index, node in enumerate(nodes)
               for child in node.get("children", [])}
    for index, node in enumerate(nodes):
        meta = node.get("extras", {}).get("shapegram")
        if meta is None and not everything:
            continue
        gpu = node.get("extensions", {}).get("EXT_mesh_gpu_instancing")
        copies = 1
        if gpu:
            first = next(iter(gpu["attributes"].values()))
            copies = accessors[first]["count"]
        row = {"node": index, "name": node.get("name"), "mesh": node.get("mesh"),
               "parent": parents.get(index), "instances": copies}
        row.update(meta or {})
        yield row


def main(argv):
    everything = "--all" in argv
    files = [a for a in argv if a != "--all"]
    if len(files) != 1:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    with open(files[0], "rb") as f:
        document = json_chunk(f.read())
    for row in rows(document, everything):
        print(json.dumps(row, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
