"""The Python module against the examples: every kind of grammar, attributes, lots, generations,
buffers, errors. Run with `python -m unittest discover crates/shapegram-py/tests` in a venv where
`maturin develop` installed the module."""

import pathlib
import struct
import tempfile
import threading
import unittest

import shapegram

EXAMPLES = pathlib.Path(__file__).resolve().parents[3] / "examples"
HOUSE = EXAMPLES / "house.cga"
CHAIR = EXAMPLES / "chairs" / "chair.goal"
TOWN = EXAMPLES / "town.rpk"
MATERIALS = EXAMPLES / "chairs" / "materials"


class House(unittest.TestCase):
    def setUp(self):
        self.house = shapegram.Grammar.load(HOUSE)

    def test_buffers_have_the_c_abis_counts(self):
        mesh = self.house.derive()
        # docs/runtimes.md: the C ABI's counts for the house.
        self.assertEqual((mesh.vertex_count, mesh.triangle_count, len(mesh.parts)), (3442, 1720, 8))
        self.assertEqual((mesh.positions.typecode, mesh.positions.itemsize), ("f", 4))
        self.assertEqual((mesh.normals.typecode, mesh.normals.itemsize), ("f", 4))
        self.assertEqual((mesh.indices.typecode, mesh.indices.itemsize), ("I", 4))
        self.assertEqual(len(mesh.positions), 3 * 3442)
        self.assertEqual(len(mesh.normals), 3 * 3442)
        self.assertEqual(len(mesh.indices), 3 * 1720)
        self.assertEqual(max(mesh.indices), 3441)

    def test_parts_tile_the_buffers(self):
        mesh = self.house.derive()
        vertex = index = 0
        for part in mesh.parts:
            self.assertEqual((part.first_vertex, part.first_index), (vertex, index))
            vertex += part.vertex_count
            index += part.index_count
            self.assertTrue(part.name)
            self.assertEqual(len(part.color), 4)
            used = mesh.indices[part.first_index : part.first_index + part.index_count]
            self.assertTrue(all(part.first_vertex <= i < part.first_vertex + part.vertex_count for i in used))
        self.assertEqual((vertex, index), (mesh.vertex_count, 3 * mesh.triangle_count))
        self.assertIn("#e8dcc4", {part.color_hex for part in mesh.parts})

    def test_normals_are_unit_vectors(self):
        normals = self.house.derive().normals
        for i in range(0, len(normals), 3):
            x, y, z = normals[i : i + 3]
            self.assertAlmostEqual(x * x + y * y + z * z, 1.0, places=5)

    def test_same_settings_give_the_same_bytes(self):
        first = self.house.derive(seed=7, attrs={"storeys": 3})
        second = self.house.derive(seed=7, attrs={"storeys": 3})
        for name in ("positions", "normals", "indices"):
            self.assertEqual(getattr(first, name).tobytes(), getattr(second, name).tobytes())
        self.assertEqual([p.color for p in first.parts], [p.color for p in second.parts])

    def test_threads_derive_at_once_and_agree(self):
        expected = self.house.derive(seed=3).positions.tobytes()
        results = []

        def derive():
            results.append(self.house.derive(seed=3).positions.tobytes())

        threads = [threading.Thread(target=derive) for _ in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        self.assertEqual(results, [expected] * 4)

    def test_attributes_are_declared_with_their_types_defaults_and_places(self):
        attrs = [(a.name, a.type, a.default, a.location) for a in self.house.attrs]
        self.assertEqual(
            attrs,
            [
                ("storeys", "number", 2.0, f"{HOUSE}:8:6"),
                ("storeyH", "number", 3.0, f"{HOUSE}:9:6"),
                ("roofAngle", "number", 35.0, f"{HOUSE}:10:6"),
                ("wallColor", "string", "#e8dcc4", f"{HOUSE}:11:6"),
                ("roofColor", "string", "#8b3a2f", f"{HOUSE}:12:6"),
            ],
        )
        grammar = shapegram.Grammar.from_text("attr on = !false\nattr h = 2 * 3\nLot --> X.\n", name="a.cga")
        self.assertEqual([(a.type, a.default) for a in grammar.attrs], [("bool", True), (None, None)])
        self.assertEqual(
            repr(grammar.attrs[0]), "Attr(name=\"on\", type=\"bool\", default=True, location=\"a.cga:1:6\")"
        )

    def test_attributes_change_the_model(self):
        two = self.house.derive()
        three = self.house.derive(attrs={"storeys": 3, "wallColor": "#ff0000"})
        self.assertGreater(three.vertex_count, two.vertex_count)
        colors = {p.color_hex for p in three.parts}
        self.assertIn("#ff0000", colors)
        self.assertNotIn("#e8dcc4", colors)

    def test_an_attribute_of_the_wrong_type_is_refused(self):
        with self.assertRaises(shapegram.AttributeTypeError) as raised:
            self.house.derive(attrs={"storeys": "three"})
        self.assertEqual(
            str(raised.exception), f"{HOUSE}:8:6: the attribute `storeys` is a number, not a string"
        )
        with self.assertRaises(shapegram.AttributeTypeError):
            self.house.derive(attrs={"wallColor": True})
        with self.assertRaises(TypeError) as raised:
            self.house.derive(attrs={"storeys": [3]})
        self.assertEqual(
            str(raised.exception), "the attribute `storeys` takes a number, a string or a boolean, not list"
        )

    def test_an_unknown_attribute_is_refused_with_a_suggestion(self):
        with self.assertRaises(shapegram.UnknownAttributeError) as raised:
            self.house.derive(attrs={"storey": 3})
        self.assertEqual(str(raised.exception), "the grammar has no attribute `storey` (did you mean `storeys`?)")
        self.assertIsInstance(raised.exception, shapegram.Error)

    def test_lots(self):
        one = self.house.derive(lots=[[(0, 0, 0), (20, 0, 0), (20, 0, 30), (0, 0, 30)]])
        self.assertEqual(one.vertex_count, 3442)
        two = self.house.derive(
            lots=[
                [(0, 0, 0), (20, 0, 0), (20, 0, 30), (0, 0, 30)],
                [(40, 0, 0), (60, 0, 0), (60, 0, 30), (40, 0, 30)],
            ]
        )
        self.assertEqual(two.vertex_count, 2 * 3442)
        # Corners may be lists too (as JSON gives them).
        self.assertEqual(self.house.derive(lots=[[[0, 0, 0], [20, 0, 0], [20, 0, 30], [0, 0, 30]]]).vertex_count, 3442)
        # The roof overhangs each lot by 0.4 m.
        xs = two.positions[0::3]
        self.assertAlmostEqual(min(xs), -0.4, places=6)
        self.assertAlmostEqual(max(xs), 60.4, places=5)

    def test_bad_lots_are_value_errors(self):
        with self.assertRaises(ValueError) as raised:
            self.house.derive(lots=[[(0, 0, 0), (1, 0, 0)]])
        self.assertEqual(str(raised.exception), "lot 0: a lot needs 3 corners or more, not 2")
        with self.assertRaises(ValueError) as raised:
            self.house.derive(lots=[[(0, 0, 0), (1, 0, 0), (2, 0, 0)]])
        self.assertEqual(str(raised.exception), "lot 0: the lot has no area")
        with self.assertRaises(ValueError) as raised:
            self.house.derive(lots=[[(0, 0, 0), (1, 0, 0), (1, 0, float("nan"))]])
        self.assertEqual(str(raised.exception), "lot 0: a lot's corner is not finite")
        with self.assertRaises(ValueError) as raised:
            self.house.derive(lots=[[(0, 0), (1, 0), (1, 1)]])
        self.assertIn("expected a sequence of length 3 (got 2)", str(raised.exception))
        with self.assertRaises(TypeError):
            self.house.derive(lots=[[(0, 0, "a"), (1, 0, 0), (1, 0, 1)]])


class Kinds(unittest.TestCase):
    def test_every_kind_derives_from_its_file(self):
        for name in (
            "house.cga",
            "rotating_tower.mul",
            "sgl_medieval_house.sgl",
            "chairs/chair.goal",
            "bush-3d.lsys",
            "grotto.cave",
            "topo_house.grammar",
            "park.cga",
        ):
            with self.subTest(name):
                mesh = shapegram.Grammar.load(EXAMPLES / name).derive()
                self.assertGreater(mesh.triangle_count, 0)
                self.assertGreater(len(mesh.parts), 0)

    def test_topological_house_has_the_c_abis_counts(self):
        mesh = shapegram.Grammar.load(EXAMPLES / "topo_house.grammar").derive()
        self.assertEqual((mesh.vertex_count, mesh.triangle_count, len(mesh.parts)), (5994, 2996, 7))

    def test_a_kind_given_overrides_the_extension(self):
        text = (EXAMPLES / "tree-3d.lsys").read_text()
        tree = shapegram.Grammar.from_text(text, name="tree.txt", kind="lsys")
        self.assertEqual(tree.attrs, [])
        self.assertGreater(tree.derive().vertex_count, 0)
        with self.assertRaises(ValueError):
            shapegram.Grammar.from_text(text, kind="png")

    def test_generations_bound_an_l_system(self):
        bush = shapegram.Grammar.load(EXAMPLES / "bush-3d.lsys")
        counts = [bush.derive(generations=n).vertex_count for n in (1, 2, 3)]
        self.assertLess(counts[0], counts[1])
        self.assertLess(counts[1], counts[2])


class Errors(unittest.TestCase):
    def test_a_grammar_error_names_file_line_and_column(self):
        with self.assertRaises(shapegram.GrammarError) as raised:
            shapegram.Grammar.from_text("@StartRule\nLot --> extrude(4 Mass.\n", name="bad.cga")
        message = str(raised.exception)
        self.assertTrue(message.startswith("error: expected `,` or `)` in the argument list, found `Mass`"), message)
        self.assertIn("--> bad.cga:2:19", message)

    def test_a_derivation_error_names_its_place(self):
        folder = tempfile.mkdtemp()
        park = pathlib.Path(folder) / "park.cga"
        park.write_text((EXAMPLES / "park.cga").read_text())
        with self.assertRaises(shapegram.DeriveError) as raised:
            shapegram.Grammar.load(park).derive()
        self.assertIn("park.cga:21:", str(raised.exception))
        self.assertIn("tree-3d.lsys", str(raised.exception))

    def test_a_missing_file_is_an_os_error(self):
        with self.assertRaises(OSError) as raised:
            shapegram.Grammar.load("no/such/file.cga")
        self.assertIn("cannot read no/such/file.cga", str(raised.exception))

    def test_a_file_that_is_not_utf8_is_a_value_error(self):
        path = pathlib.Path(tempfile.mkdtemp()) / "latin1.cga"
        path.write_bytes(b"// caf\xe9\n")
        with self.assertRaises(ValueError) as raised:
            shapegram.Grammar.load(path)
        self.assertIn("is not UTF-8 (invalid byte at offset 6)", str(raised.exception))

    def test_attributes_of_a_grammar_without_any(self):
        cave = shapegram.Grammar.load(EXAMPLES / "grotto.cave")
        with self.assertRaises(shapegram.UnknownAttributeError):
            cave.derive(attrs={"size": 1})


class SkeletonsAndTextures(unittest.TestCase):
    def test_the_excavator_has_its_joints_and_each_vertex_its_joint(self):
        mesh = shapegram.Grammar.load(EXAMPLES / "excavator.cga").derive(attrs={"boomAngle": 45})
        self.assertEqual(mesh.vertex_joints.typecode, "I")
        self.assertEqual(len(mesh.vertex_joints), mesh.vertex_count)
        self.assertTrue(all(j < len(mesh.joints) for j in mesh.vertex_joints))
        self.assertIsNone(mesh.joints[0].parent)
        for i, joint in enumerate(mesh.joints):
            self.assertTrue(joint.parent is None or joint.parent < i, joint)
        boom = next(i for i, j in enumerate(mesh.joints) if j.name.startswith("Boom_"))
        self.assertEqual(mesh.joints[boom].rotation_limits_deg[2], (-40.0, 60.0))
        self.assertEqual(mesh.joints[boom].pose_rotation_deg, (0.0, 0.0, 45.0))
        self.assertGreater(sum(1 for j in mesh.vertex_joints if j == boom), 0)

    def test_the_house_has_no_joints_uvs_or_textures(self):
        mesh = shapegram.Grammar.load(HOUSE).derive()
        self.assertEqual((len(mesh.joints), len(mesh.vertex_joints)), (0, 0))
        self.assertEqual((len(mesh.uvs), len(mesh.textures)), (0, 0))
        self.assertTrue(all(part.texture is None and part.material is None for part in mesh.parts))

    def test_the_textured_house_has_uvs_and_its_images(self):
        mesh = shapegram.Grammar.load(EXAMPLES / "textured_house.cga").derive()
        self.assertEqual(len(mesh.uvs), 2 * mesh.vertex_count)
        self.assertEqual([t.path for t in mesh.textures], ["textures/brick.png", "textures/tiles.png"])
        self.assertTrue(all(t.data.startswith(b"\x89PNG") for t in mesh.textures))
        self.assertEqual(sorted(p.texture for p in mesh.parts if p.texture is not None), [0, 1])
        self.assertEqual(
            sorted((p.material, mesh.textures[p.texture].path) for p in mesh.parts if p.material),
            [("brick", "textures/brick.png"), ("roof_tiles", "textures/tiles.png")],
        )
        self.assertTrue(all(p.material is None for p in mesh.parts if p.texture is None))

    def test_the_topological_brick_house_has_uvs_and_its_images(self):
        mesh = shapegram.Grammar.load(EXAMPLES / "topo_brick_house.grammar").derive()
        self.assertEqual(len(mesh.uvs), 2 * mesh.vertex_count)
        self.assertEqual([t.path for t in mesh.textures], ["textures/brick.png", "textures/tiles.png"])
        self.assertEqual(mesh.textures[0].data, (EXAMPLES / "textures" / "brick.png").read_bytes())
        self.assertEqual(
            [(p.material, p.texture) for p in mesh.parts],
            [("Brick", 0), ("RoofTiles", 1), ("Stone", None), ("Stone", None), (None, None), ("Brick", 0), ("Glass", None)],
        )
        # The gable's top corner (0, 7, 4) facing -x: (z / 1.2, 1 - y / 0.6) in brick tiles.
        gable = mesh.parts[0]
        top = next(
            v for v in range(gable.first_vertex, gable.first_vertex + gable.vertex_count)
            if tuple(mesh.positions[3 * v:3 * v + 3]) == (0.0, 7.0, 4.0)
        )
        self.assertEqual(tuple(mesh.uvs[2 * top:2 * top + 2]), struct.unpack("2f", struct.pack("2f", 4 / 1.2, 1 - 7 / 0.6)))


class Packages(unittest.TestCase):
    """CityEngine rule packages (.rpk): examples/town.rpk, its rule file, assets and texture read
    from the archive (the C test checks the same counts)."""

    def check_town(self, grammar):
        mesh = grammar.derive()
        self.assertEqual((mesh.vertex_count, mesh.triangle_count, len(mesh.parts)), (58, 28, 3))
        self.assertEqual([t.path for t in mesh.textures], ["brick.png"])
        self.assertTrue(mesh.textures[0].data.startswith(b"\x89PNG"))
        return mesh

    def test_a_package_loads_from_its_file_and_from_its_bytes(self):
        from_file = shapegram.Grammar.load(TOWN)
        self.assertEqual(from_file.name, str(TOWN))
        first = self.check_town(from_file)
        from_bytes = shapegram.Grammar.from_package(TOWN.read_bytes(), name="town.rpk")
        self.assertEqual(from_bytes.name, "town.rpk")
        self.assertEqual(self.check_town(from_bytes).positions.tobytes(), first.positions.tobytes())
        named = shapegram.Grammar.load(TOWN, rule_file="town.cga")
        self.assertEqual(self.check_town(named).indices.tobytes(), first.indices.tobytes())

    def test_its_attributes_are_named_by_their_place_in_the_package(self):
        grammar = shapegram.Grammar.from_package(TOWN.read_bytes(), name="town.rpk")
        attrs = {a.name: a for a in grammar.attrs}
        self.assertEqual(sorted(attrs), ["height", "roofAngle", "roofColor"])
        self.assertEqual(attrs["height"].default, 9.0)
        self.assertEqual(attrs["height"].location, "town.rpk!/rules/town.cga:10:6")
        low = grammar.derive(attrs={"height": 3})
        top = max(low.positions[1::3])
        self.assertLess(top, max(grammar.derive().positions[1::3]))
        with self.assertRaises(shapegram.AttributeTypeError):
            grammar.derive(attrs={"height": "tall"})

    def test_a_rule_file_the_package_lacks_is_a_package_error(self):
        with self.assertRaises(shapegram.PackageError) as raised:
            shapegram.Grammar.load(TOWN, rule_file="nope.cga")
        self.assertIsInstance(raised.exception, shapegram.Error)
        self.assertEqual(
            str(raised.exception),
            f"{TOWN} has no rule file `nope.cga`; its rule files are rules/town.cga",
        )

    def test_damaged_and_foreign_packages_are_package_errors(self):
        whole = TOWN.read_bytes()
        for data in (whole[: len(whole) // 2], b"Lot --> X.", b""):
            with self.assertRaises(shapegram.PackageError) as raised:
                shapegram.Grammar.from_package(data, name="cut.rpk")
            self.assertTrue(
                str(raised.exception).startswith("cut.rpk is not a readable rule package (a 7-Zip archive): "),
                raised.exception,
            )
        with self.assertRaises(OSError) as raised:
            shapegram.Grammar.load("no/such/town.rpk")
        self.assertIn("cannot read the rule package no/such/town.rpk", str(raised.exception))

    def test_rule_file_is_for_packages_only(self):
        with self.assertRaises(ValueError) as raised:
            shapegram.Grammar.load(HOUSE, rule_file="house.cga")
        self.assertIn("rule_file picks a rule file of a rule package (.rpk)", str(raised.exception))


class Library(unittest.TestCase):
    def test_a_goal_grammar_derives_with_its_library(self):
        mesh = shapegram.Grammar.load(CHAIR, library=[MATERIALS]).derive()
        # As `shapegram derive examples/chairs/chair.goal --library examples/chairs/materials`
        # makes it: 72 triangles in three parts, which materials/wood.goal paints brown.
        self.assertEqual((mesh.vertex_count, mesh.triangle_count, len(mesh.parts)), (144, 72, 3))
        self.assertEqual({p.color_hex for p in mesh.parts}, {"#8b5a2b"})
        # Without it, the same geometry with its goal `wooden` left open: the default grey.
        alone = shapegram.Grammar.load(CHAIR).derive()
        self.assertEqual(alone.positions.tobytes(), mesh.positions.tobytes())
        self.assertEqual({p.color_hex for p in alone.parts}, {"#cccccc"})

    def test_a_library_is_files_and_folders_for_files_and_texts(self):
        # The chair's own folder, as strings: the chair itself is left out of it.
        folder = shapegram.Grammar.load(str(CHAIR), library=[str(CHAIR.parent)]).derive()
        self.assertEqual({p.color_hex for p in folder.parts}, {"#8b5a2b"})
        wood = MATERIALS / "wood.goal"
        chair = shapegram.Grammar.from_text(CHAIR.read_text(), name="chair.goal", library=[wood])
        self.assertEqual({p.color_hex for p in chair.derive().parts}, {"#8b5a2b"})

    def test_an_error_in_a_library_file_names_the_file(self):
        paint = pathlib.Path(tempfile.mkdtemp()) / "paint.goal"
        paint.write_text('// paints boxes\nfulfills(box) --> color("#ff0000"\n')
        with self.assertRaises(shapegram.GrammarError) as raised:
            shapegram.Grammar.load(CHAIR, library=[paint])
        message = str(raised.exception)
        self.assertTrue(message.startswith("error: unclosed `(`\n"), message)
        self.assertIn(f"--> {paint}:2:24", message)

    def test_a_library_is_refused_for_other_grammars(self):
        with self.assertRaises(shapegram.GrammarError) as raised:
            shapegram.Grammar.load(HOUSE, library=[MATERIALS])
        self.assertEqual(
            str(raised.exception), f"{HOUSE} is not a goal grammar: a library gives goal grammars their rules"
        )

    def test_bad_library_paths(self):
        with self.assertRaises(OSError) as raised:
            shapegram.Grammar.load(CHAIR, library=["no/such/library"])
        self.assertEqual(str(raised.exception), "the library no/such/library is neither a file nor a folder")
        with self.assertRaises(TypeError):
            shapegram.Grammar.load(CHAIR, library=str(MATERIALS))


if __name__ == "__main__":
    unittest.main()
