#!/usr/bin/env python3
"""A city's footprints derived into a 3D Tiles tileset by a Dask cluster, shard by shard.

Each of N tasks calls `shapegram.derive_tiles(..., shard=(k, N))` on a worker: it reads the
whole footprint file, derives its share of the parent tiles and writes their tiles with its part
of tileset.json into a folder of its own (OUT_DIR.shards/K unless --parts says where). The
client then calls `shapegram.merge_tiles`, which copies the tiles into OUT_DIR and writes
tileset.json: the same bytes as one `shapegram derive --tiles` run. Dask schedules the tasks;
nothing here knows about machines (docs/tiles.md, "Many machines").

    python examples/dask/dask_tiles.py examples/house.cga city.geojson city/ --shards 3
    python examples/dask/dask_tiles.py examples/house.cga city.geojson city/ --meshopt --metadata
    python examples/dask/dask_tiles.py house.cga city.geojson city/ --scheduler tcp://host:8786

Without --scheduler it starts a `distributed.LocalCluster` on loopback (worker processes). On
several machines the folders must be ones every worker and the client see (a shared disk), or
copied to the client before the merge.
"""

import argparse
import os
import sys

import shapegram


def derive_city(client, grammar, lots, out_dir, shards, parts_dir, **options):
    """Derives the lots of `lots` with `grammar` into `out_dir` in `shards` Dask tasks on
    `client`; shard K writes into parts_dir/K, where its files stay. `options` are
    derive_tiles' (tile_size, crs, halo, seed, attrs, metadata, quantize, meshopt, normals). Returns each shard's counts (from
    derive_tiles) and the merged tileset's (from merge_tiles)."""
    grammar, lots, out_dir, parts_dir = (
        os.path.abspath(p) for p in (grammar, lots, out_dir, parts_dir))
    parts = [os.path.join(parts_dir, str(k)) for k in range(shards)]
    # shapegram.derive_tiles itself is the task: workers need the module, not this script.
    futures = [
        client.submit(shapegram.derive_tiles, grammar, lots, part, shard=(k, shards),
                      pure=False, **options)
        for k, part in enumerate(parts)
    ]
    shard_counts = client.gather(futures)
    return shard_counts, shapegram.merge_tiles(parts, out_dir)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("grammar")
    parser.add_argument("lots", help="a GeoJSON or OBJ file of footprints")
    parser.add_argument("out_dir")
    parser.add_argument("--shards", type=int, default=3)
    parser.add_argument("--parts", help="where the shards write (default: OUT_DIR.shards)")
    parser.add_argument("--tile-size", type=float, default=200.0)
    parser.add_argument("--crs", default="local")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--metadata", action="store_true", help="each lot a feature of its tiles")
    parser.add_argument("--quantize", action="store_true", help="KHR_mesh_quantization")
    parser.add_argument("--meshopt", action="store_true",
                        help="quantised and EXT_meshopt_compression")
    parser.add_argument("--scheduler", help="a running scheduler's address; a LocalCluster "
                                            "on loopback without it")
    parser.add_argument("--workers", type=int, default=2, help="the LocalCluster's workers")
    args = parser.parse_args()

    from distributed import Client, LocalCluster

    parts = args.parts or args.out_dir.rstrip("/") + ".shards"
    options = dict(tile_size=args.tile_size, crs=args.crs, seed=args.seed, metadata=args.metadata,
                   quantize=args.quantize, meshopt=args.meshopt)
    if args.scheduler:
        with Client(args.scheduler) as client:
            _, counts = derive_city(client, args.grammar, args.lots, args.out_dir, args.shards,
                                 parts, **options)
    else:
        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                          host="127.0.0.1", dashboard_address=None) as cluster, \
                Client(cluster) as client:
            _, counts = derive_city(client, args.grammar, args.lots, args.out_dir, args.shards,
                                 parts, **options)
    print(f"wrote {os.path.join(args.out_dir, 'tileset.json')}: {counts['near']} near tiles, "
          f"{counts['far']} far tiles of {counts['lots']} lots", file=sys.stderr)


if __name__ == "__main__":
    main()
