"""Tiled cities from Python: `shapegram.derive_tiles` whole and in shards, with metadata and
encoded vertices, `merge_tiles`, their errors, and the shards run as tasks of a Dask `distributed.LocalCluster` on loopback (worker
processes), merged into the single run's bytes (docs/tiles.md, "Many machines").

The Dask test needs `dask[distributed]` in the venv; without it the test is skipped, unless
SHAPEGRAM_REQUIRE_DASK=1 (as in CI) makes that a failure. With SHAPEGRAM_BIN naming the
`shapegram` binary, the single run is also compared with `shapegram derive --tiles`."""

import importlib.util
import json
import os
import pathlib
import subprocess
import tempfile
import unittest

import shapegram

ROOT = pathlib.Path(__file__).resolve().parents[3]
HOUSE = ROOT / "examples" / "house.cga"
LOTS = 300
# 50 m cells and parent tiles of 200 m over the 300 lots' 445 × 670 m, centred on the origin:
# 137 cells hold lots, under 16 parent tiles.
TILE_SIZE = 50.0


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def files(folder):
    """Every file under `folder`, by its path relative to it, with its bytes."""
    folder = pathlib.Path(folder)
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def glb_json(path):
    """A GLB's JSON chunk: its length is the u32 at byte 12, its text starts at byte 20."""
    data = pathlib.Path(path).read_bytes()
    return json.loads(data[20:20 + int.from_bytes(data[12:16], "little")])


def size(files):
    return sum(len(data) for data in files.values())


TMP = None
DIR = LOTS_FILE = WHOLE = WHOLE_FILES = None


def setUpModule():
    """The footprints, and the single run every other run is compared with."""
    global TMP, DIR, LOTS_FILE, WHOLE, WHOLE_FILES
    TMP = tempfile.TemporaryDirectory()
    DIR = pathlib.Path(TMP.name)
    LOTS_FILE = DIR / "city.geojson"
    LOTS_FILE.write_text(load("tiles_city", ROOT / "bench" / "tiles_city.py").city(LOTS))
    WHOLE = shapegram.derive_tiles(HOUSE, LOTS_FILE, DIR / "whole", tile_size=TILE_SIZE)
    WHOLE_FILES = files(DIR / "whole")


def tearDownModule():
    TMP.cleanup()


class City(unittest.TestCase):
    def setUp(self):
        self.dir, self.lots, self.whole, self.whole_files = DIR, LOTS_FILE, WHOLE, WHOLE_FILES

    def test_the_whole_run_tiles_every_lot(self):
        self.assertEqual({k: self.whole[k] for k in ("near", "far", "lots", "derived")},
                         {"near": 137, "far": 16, "lots": LOTS, "derived": LOTS})
        self.assertGreater(self.whole["leaves"], 0)
        self.assertIn("tileset.json", self.whole_files)
        self.assertEqual(sum(1 for f in self.whole_files if f.startswith("near/")), 137)

    def test_the_whole_run_is_the_commands(self):
        binary = os.environ.get("SHAPEGRAM_BIN")
        if not binary:
            self.skipTest("SHAPEGRAM_BIN names no shapegram binary")
        out = self.dir / "cli"
        subprocess.run([binary, "derive", "-q", HOUSE, "--lots", self.lots, "--tiles", out,
                        "--tile-size", str(TILE_SIZE)], check=True)
        self.assertTrue(files(out) == self.whole_files, "the tiles differ from the command's")

    def test_shards_merged_in_place_are_the_whole_run(self):
        out = self.dir / "in-place"
        counts = [shapegram.derive_tiles(HOUSE, [self.lots], out, shard=(k, 2),
                                         tile_size=TILE_SIZE) for k in range(2)]
        self.assertEqual([c["far"] for c in counts], [8, 8])
        merged = shapegram.merge_tiles([out], out)
        self.assertEqual(merged, {"near": 137, "far": 16, "lots": LOTS})
        merged_files = files(out)
        for k in range(2):
            del merged_files[f"tileset.shard-{k}-of-2.json"]
        self.assertTrue(merged_files == self.whole_files, "the merged tiles differ")

    def test_skipped_parts_of_the_file_are_warnings(self):
        lots = self.dir / "with-a-point.geojson"
        lots.write_text('{"type": "FeatureCollection", "features": ['
                        '{"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}},'
                        '{"type": "Feature", "geometry": {"type": "Polygon",'
                        ' "coordinates": [[[0, 0], [20, 0], [20, 30], [0, 30], [0, 0]]]}}]}')
        with self.assertWarnsRegex(
                UserWarning, r"with-a-point\.geojson: skipped 1 geometry that is not polygons"):
            counts = shapegram.derive_tiles(HOUSE, lots, self.dir / "with-a-point")
        self.assertEqual((counts["near"], counts["far"], counts["lots"]), (1, 1, 1))

    def test_bad_input_raises_clear_exceptions(self):
        out = self.dir / "bad"
        with self.assertRaisesRegex(ValueError, r"shards of 3 are numbered 0 to 2"):
            shapegram.derive_tiles(HOUSE, self.lots, out, shard=(3, 3))
        with self.assertRaisesRegex(ValueError, r"at least 1 shard"):
            shapegram.derive_tiles(HOUSE, self.lots, out, shard=(0, 0))
        with self.assertRaisesRegex(ValueError, r"unknown coordinate system 'mars'"):
            shapegram.derive_tiles(HOUSE, self.lots, out, crs="mars")
        with self.assertRaisesRegex(ValueError, r"tile_size is 0"):
            shapegram.derive_tiles(HOUSE, self.lots, out, tile_size=0)
        with self.assertRaisesRegex(OSError, r"cannot read .*nowhere\.geojson"):
            shapegram.derive_tiles(HOUSE, self.dir / "nowhere.geojson", out)
        with self.assertRaisesRegex(OSError, r"cannot read .*nowhere\.cga"):
            shapegram.derive_tiles(self.dir / "nowhere.cga", self.lots, out)
        with self.assertRaisesRegex(OSError, r"expected an \.obj, \.geojson or \.json file"):
            shapegram.derive_tiles(HOUSE, HOUSE, out)
        # Local metres read as longitudes and latitudes: 710 m north is past the pole.
        with self.assertRaisesRegex(OSError, r"city\.geojson: feature"):
            shapegram.derive_tiles(HOUSE, self.lots, out, crs="wgs84")
        with self.assertRaisesRegex(OSError, r"no shard of a tileset"):
            shapegram.merge_tiles([self.dir], out)
        part = self.dir / "part0"
        shapegram.derive_tiles(HOUSE, self.lots, part, shard=(0, 2), tile_size=TILE_SIZE)
        with self.assertRaisesRegex(OSError, r"missing shard 1/2"):
            shapegram.merge_tiles([part], out)
        self.assertFalse((out / "tileset.json").exists())


class Encoded(unittest.TestCase):
    """`metadata`, `quantize` and `meshopt`: `derive --tiles`' --metadata, --quantize and
    --meshopt."""

    def setUp(self):
        self.dir, self.lots, self.whole, self.whole_files = DIR, LOTS_FILE, WHOLE, WHOLE_FILES

    def derive(self, name, **options):
        out = self.dir / name
        counts = shapegram.derive_tiles(HOUSE, self.lots, out, tile_size=TILE_SIZE, **options)
        self.assertEqual((counts["near"], counts["far"], counts["lots"]), (137, 16, LOTS))
        return out, files(out)

    def test_tiles_carry_the_extensions_asked_for(self):
        quantized, quantized_files = self.derive("quantized", quantize=True)
        meshopt, meshopt_files = self.derive("meshopt-metadata", metadata=True, meshopt=True)
        described, described_files = self.derive("metadata", metadata=True)
        for tile in ("near/0_0.glb", "far/0_0.glb"):
            self.assertEqual(glb_json(quantized / tile)["extensionsRequired"],
                             ["KHR_mesh_quantization"])
            document = glb_json(meshopt / tile)
            self.assertEqual(document["extensionsRequired"],
                             ["KHR_mesh_quantization", "EXT_meshopt_compression"])
            self.assertEqual(document["extensionsUsed"],
                             ["EXT_mesh_features", "EXT_structural_metadata",
                              "KHR_mesh_quantization", "EXT_meshopt_compression"])
            table = document["extensions"]["EXT_structural_metadata"]["propertyTables"][0]
            self.assertEqual(table, glb_json(described / tile)["extensions"]
                             ["EXT_structural_metadata"]["propertyTables"][0])
            self.assertNotIn("extensionsUsed", glb_json(self.dir / "whole" / tile))
        # Smaller: the houses' vertices dominate the tiles.
        self.assertLess(size(quantized_files), size(self.whole_files))
        self.assertLess(size(meshopt_files), size(described_files))
        # tileset.json lists 3D Tiles extensions only: the glTF ones are in each tile.
        self.assertNotIn("extensionsUsed", json.loads(quantized_files["tileset.json"]))

    def test_meshopt_wins_over_quantize_as_in_the_command(self):
        _, both = self.derive("both", quantize=True, meshopt=True)
        _, meshopt = self.derive("meshopt", meshopt=True)
        self.assertTrue(both == meshopt, "quantize=True, meshopt=True is meshopt=True")

    def test_encoded_tiles_are_the_commands(self):
        binary = os.environ.get("SHAPEGRAM_BIN")
        if not binary:
            self.skipTest("SHAPEGRAM_BIN names no shapegram binary")
        for flags, options in [(["--metadata", "--meshopt"], {"metadata": True, "meshopt": True}),
                               (["--quantize", "--normals"], {"quantize": True, "normals": True})]:
            name = "-".join(f.strip("-") for f in flags)
            out = self.dir / f"cli-{name}"
            subprocess.run([binary, "derive", "-q", HOUSE, "--lots", self.lots, "--tiles", out,
                            "--tile-size", str(TILE_SIZE), *flags], check=True)
            _, ours = self.derive(f"py-{name}", **options)
            self.assertEqual(sorted(ours), sorted(files(out)))
            self.assertTrue(ours == files(out), f"{flags}: the tiles differ from the command's")

    def test_shards_of_other_encodings_are_not_merged(self):
        part0, part1 = self.dir / "enc-part0", self.dir / "enc-part1"
        shapegram.derive_tiles(HOUSE, self.lots, part0, shard=(0, 2), tile_size=TILE_SIZE,
                               meshopt=True)
        shapegram.derive_tiles(HOUSE, self.lots, part1, shard=(1, 2), tile_size=TILE_SIZE)
        out = self.dir / "enc-merged"
        with self.assertRaisesRegex(OSError, r"shard 1/2 is not of the run of .*encoding"):
            shapegram.merge_tiles([part0, part1], out)
        self.assertFalse((out / "tileset.json").exists())
        with self.assertRaisesRegex(TypeError, r"'str' object is not an instance of 'bool'"):
            shapegram.derive_tiles(HOUSE, self.lots, out, meshopt="yes")


try:
    import distributed
except ImportError:
    distributed = None


@unittest.skipIf(distributed is None and not os.environ.get("SHAPEGRAM_REQUIRE_DASK"),
                 "dask[distributed] is not installed")
class Dask(unittest.TestCase):
    def setUp(self):
        self.dir, self.lots, self.whole_files = DIR, LOTS_FILE, WHOLE_FILES

    def test_a_local_cluster_derives_the_shards_of_the_single_run(self):
        if distributed is None:
            self.fail("SHAPEGRAM_REQUIRE_DASK is set: install dask[distributed]")
        example = load("dask_tiles", ROOT / "examples" / "dask" / "dask_tiles.py")
        out, parts = self.dir / "dask", self.dir / "dask.shards"
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      host="127.0.0.1", dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            shards, merged = example.derive_city(client, HOUSE, self.lots, out, 3, parts,
                                                 tile_size=TILE_SIZE)
            workers = client.run(os.getpid)
        self.assertEqual(len(set(workers.values()) - {os.getpid()}), 2, "two worker processes")
        self.assertEqual([s["far"] for s in shards], [5, 5, 6])
        self.assertEqual(sum(s["lots"] for s in shards), LOTS)
        self.assertEqual(merged, {"near": 137, "far": 16, "lots": LOTS})
        for k in range(3):
            self.assertTrue((parts / str(k) / f"tileset.shard-{k}-of-3.json").is_file())
        merged_files = files(out)
        self.assertEqual(sorted(merged_files), sorted(self.whole_files))
        for name, data in self.whole_files.items():
            self.assertTrue(merged_files[name] == data, f"{name} differs")


if __name__ == "__main__":
    unittest.main()
