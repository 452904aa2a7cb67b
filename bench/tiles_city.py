#!/usr/bin/env python3
"""A city of many lots written as 3D Tiles, cell by cell: wall time and peak memory.

Writes a GeoJSON file of N lots of 20 x 30 m (local metres, 25 m apart east and 40 m north, in
rows of ceil(sqrt(N)) lots; the same N always gives the same bytes), derives it with
examples/house.cga into a tileset (`--tiles`) under /usr/bin/time -v and prints one line per
city: lots, tiles, output size, wall time, CPU time and the maximum resident set. Not part of
CI; run it with a release build. The houses of 100,000 lots take about 3 GB of tiles:
bench/tiles_city.cga (about 30 leaves a lot) takes less than a tenth of that.

    cargo build --release -p shapegram
    python3 bench/tiles_city.py 10000
    python3 bench/tiles_city.py --grammar bench/tiles_city.cga 10000 100000
    python3 bench/tiles_city.py 10000 -- --meshopt --metadata     # more options for derive
    python3 bench/tiles_city.py --lots-only 100000 > city.geojson   # just the lots

Arguments after `--` are passed on to `shapegram derive` (and printed with the city's line).

Environment: SHAPEGRAM (the binary, default target/release/shapegram), WORK (a scratch folder
with room for the tiles, default /tmp/shapegram-tiles-bench; each city's tiles are removed
after it is measured).
"""

import json
import math
import os
import re
import shutil
import subprocess
import sys


def city(n):
    """The GeoJSON text of n lots."""
    columns = max(1, math.ceil(math.sqrt(n)))
    features = []
    for i in range(n):
        x, y = (i % columns) * 25.0, (i // columns) * 40.0
        ring = [[x, y], [x + 20, y], [x + 20, y + 30], [x, y + 30], [x, y]]
        features.append({"type": "Feature", "properties": {},
                         "geometry": {"type": "Polygon", "coordinates": [ring]}})
    return json.dumps({"type": "FeatureCollection", "features": features},
                      separators=(",", ":"))


def folder_size(path):
    return sum(os.path.getsize(os.path.join(root, f))
               for root, _, files in os.walk(path) for f in files)


def measure(binary, grammar, work, n, extra):
    lots = os.path.join(work, f"city-{n}.geojson")
    with open(lots, "w") as f:
        f.write(city(n))
    tiles = os.path.join(work, f"tiles-{n}")
    shutil.rmtree(tiles, ignore_errors=True)
    run = subprocess.run(
        ["/usr/bin/time", "-v", binary, "derive", grammar, "--lots", lots, "--tiles", tiles,
         "--max-shapes", "100000000", *extra],
        check=True, capture_output=True, text=True)
    err = run.stderr

    def field(name):
        return re.search(re.escape(name) + r": (.+)", err).group(1).strip()

    wall = field("Elapsed (wall clock) time (h:mm:ss or m:ss)")
    parts = [float(p) for p in wall.split(":")]
    seconds = sum(p * 60 ** k for k, p in enumerate(reversed(parts)))
    cpu = float(field("User time (seconds)")) + float(field("System time (seconds)"))
    peak = int(field("Maximum resident set size (kbytes)")) * 1024
    wrote = re.search(r"tileset\.json: (.+)", err).group(1)
    size = folder_size(tiles)
    shutil.rmtree(tiles)
    os.remove(lots)
    options = "".join(f" {arg}" for arg in extra)
    print(f"{os.path.basename(grammar)}{options}, {n:>7} lots: {wrote}; {size / 1e9:.3f} GB; "
          f"wall {seconds:.1f} s, "
          f"CPU {cpu:.1f} s, peak memory {peak / 2**20:.0f} MiB", flush=True)


def main(args):
    if args and args[0] == "--lots-only":
        sys.stdout.write(city(int(args[1])))
        return
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    binary = os.environ.get("SHAPEGRAM", os.path.join(root, "target", "release", "shapegram"))
    work = os.environ.get("WORK", "/tmp/shapegram-tiles-bench")
    os.makedirs(work, exist_ok=True)
    grammar = os.path.join(root, "examples", "house.cga")
    if args and args[0] == "--grammar":
        grammar, args = os.path.abspath(args[1]), args[2:]
    extra = []
    if "--" in args:
        at = args.index("--")
        args, extra = args[:at], args[at + 1:]
    for n in [int(a) for a in args] or [10000]:
        measure(binary, grammar, work, n, extra)


if __name__ == "__main__":
    main(sys.argv[1:])
