//! Forms that real CityEngine rule files use and our own examples did not: each test is a small
//! grammar of our own with the form a public rule file taught us.

use crate::common;

use common::{compile_errors, lot, names, run};

#[test]
fn case_right_after_a_bracket_chooses_up_to_the_matching_bracket() {
    // The chosen branch runs inside the brackets; what follows `]` runs on the restored shape.
    let grammar = "attr kind = \"MAJOR\"
        Lot --> extrude(4) [ case kind == \"MAJOR\": s('0.5, '1, '1) Lamp else: NIL ] Base";
    let d = run(grammar, lot(20.0, 30.0));
    assert_eq!(names(&d), ["Lamp", "Base"]);
    assert_eq!(d.leaves[0].scope.size.x, 10.0);
    assert_eq!(d.leaves[1].scope.size.x, 20.0);
    let d = run(
        &grammar.replace("\"MAJOR\"\n", "\"MINOR\"\n"),
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["Base"]);
}

#[test]
fn nested_cases_and_brackets_inside_a_bracketed_branch() {
    let grammar = "attr n = 2
        Lot --> [ case n > 1: [ t(1, 0, 0) A ] case n > 5 : B else: C ] [ D ] E";
    let d = run(grammar, lot(4.0, 4.0));
    assert_eq!(names(&d), ["A", "D", "E"]);
    assert_eq!(d.leaves[0].scope.origin.x, 1.0);
    assert_eq!(d.leaves[1].scope.origin.x, 0.0);
}

#[test]
fn percentages_right_after_a_bracket_draw_one_branch() {
    let d = run("Lot --> [ 100% : A else : B ] C", lot(4.0, 4.0));
    assert_eq!(names(&d), ["A", "C"]);
}

#[test]
fn a_bracketed_case_left_open_ends_at_the_next_rule() {
    let d = run("Lot --> [ case true: A else: B\nNext --> C", lot(4.0, 4.0));
    assert_eq!(names(&d), ["A"]);
}

#[test]
fn unary_plus_keeps_its_operand() {
    let d = run("const h = 2 ++.5\nLot --> extrude(h) X", lot(4.0, 4.0));
    assert_eq!(d.leaves[0].scope.size.y, 2.5);
}

#[test]
fn handle_annotations_are_skipped_whatever_they_hold() {
    let errors = errors(
        "@Handle(shape=Street^4, axis=x, translate={.1,0,0}, color=\"#FF11FF\")\n\
         attr w = 3\nLot --> extrude(w) Street",
    );
    assert!(errors.is_empty(), "{errors:?}");
}

#[test]
fn comp_function_entries_may_use_the_grouping_form() {
    // `street.back = v` gives the value as `street.back : v` does.
    let d = run(
        "const d = comp(fe) { front : 1 | back = 2 | all = 0 }\nLot --> setback(d) { all : Ring | remainder : Core }",
        lot(20.0, 30.0),
    );
    let core = d.leaves.iter().find(|l| d.name(l.name) == "Core").unwrap();
    assert_eq!((core.scope.size.x, core.scope.size.z), (20.0, 27.0));
}

#[test]
fn skipped_operations_keep_their_selector_words() {
    let diagnostics = compile_errors("Lot --> reduceGeometry(scope) X.");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with("warning: operation `reduceGeometry` is not supported yet"),
        "{}",
        diagnostics[0]
    );
}

#[test]
fn names_that_are_no_cityengine_operation_are_rule_calls() {
    // `innerCircle` and `bevel` appear in no CityEngine operation listing.
    let diagnostics = compile_errors("Lot --> innerCircle(2) X.");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with("warning: no rule `innerCircle`"),
        "{}",
        diagnostics[0]
    );
    let d = run(
        "Lot --> bevel(2)\nbevel(n) --> s(n, '1, '1) Done.",
        lot(20.0, 30.0),
    );
    assert_eq!(d.leaves.len(), 1);
    assert_eq!(
        (d.name(d.leaves[0].name), d.leaves[0].scope.size.x),
        ("Done", 2.0)
    );
}

/// The errors among the diagnostics of compiling `text`.
fn errors(text: &str) -> Vec<String> {
    compile_errors(text)
        .into_iter()
        .filter(|d| d.starts_with("error"))
        .collect()
}

#[test]
fn element_wise_operators_work_on_each_element() {
    // Complete_Street.cga filters a table's rows with `t[t[0:n, 1] .== category, 0]`.
    let grammar = "const t = [\"oak\", \"tree\"; \"bench\", \"furniture\"; \"elm\", \"tree\"]
        const trees = t[t[0:2, 1] .== \"tree\", 0]
        const scaled = [1, 2; 3, 4] .* 2 .+ [1, 1; 1, 1]
        const flags = .![true, false] .|| [false, false]
        Lot --> print(trees) print(scaled) print(flags) print(.-[1, 2]) print(3 .> [1, 5]) X.";
    let d = run(grammar, lot(4.0, 4.0));
    assert_eq!(
        d.prints,
        [
            "[oak,elm]",
            "[[3,5],[7,9]]",
            "[false,true]",
            "[-1,-2]",
            "[true,false]"
        ]
    );
    let errors = errors("Lot --> print([1, 2] .* [1, 2, 3]) X.");
    assert!(errors.is_empty(), "{errors:?}");
    let failed = common::try_run(
        "Lot --> print([1, 2] .* [1, 2, 3]) X.",
        lot(4.0, 4.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        failed.to_string(),
        "`.*` needs arrays of the same size, not 2 and 3 elements"
    );
}

#[test]
fn a_texture_space_split_takes_its_space_and_block() {
    // Complete_Street.cga splits lanes along v in unit space.
    let errors = errors("Street --> split(v, unitSpace, 0) { 0.2 : Curb | ~1 : Road }");
    assert!(errors.is_empty(), "{errors:?}");
}

#[test]
fn a_terminal_name_without_arguments_is_a_leaf_even_when_an_operation_has_its_name() {
    let d = run("Lot --> t(1, 0, 0) r.", lot(4.0, 4.0));
    assert_eq!(names(&d), ["r"]);
    assert_eq!(d.leaves[0].scope.origin.x, 1.0);
}

#[test]
fn colour_and_array_functions_of_the_reference() {
    // 6SetUp.cga turns a shutter's colour: colorHSVToHex(colorHexToH(c) - 185, …).
    let d = run(
        "const c = \"#ff0000\"
         Lot --> print(colorHSVToHex(colorHexToH(c) + 120, colorHexToS(c), colorHexToV(c)))
                 print(colorRGBOToHex(1, 0.5, 0, 1)) print(colorHexToO(\"#00000080\") * 255)
                 print(sum([1, 2, 3])) print([30, 10, 20][sortIndices([30, 10, 20])])
                 print(transpose([1, 2; 3, 4])) print(isNull(floatArray([\"1\", \"x\"])))
                 X.",
        lot(4.0, 4.0),
    );
    assert_eq!(
        d.prints,
        [
            "#00ff00",
            "#ff8000ff",
            "128",
            "6",
            "[10,20,30]",
            "[[1,3],[2,4]]",
            "[false,true]"
        ]
    );
}

#[test]
fn geometry_angle_gives_slope_azimuth_and_zenith() {
    // The lot's front edge faces +z, south: its facade's azimuth is 180.
    let d = run(
        "Lot --> extrude(10) comp(f) { front : F | right : R | top : T }
         F --> print(geometry.angle(maxSlope) + \" \" + geometry.angle(azimuth)) X.
         R --> print(geometry.angle(azimuth)) X.
         T --> print(geometry.angle(zenith) + \" \" + geometry.angle(maxSlope)) X.",
        lot(20.0, 30.0),
    );
    assert_eq!(d.prints, ["90 180", "90", "90 0"]);
    let roof = run(
        "Lot --> roofShed(30) comp(f) { all : A }
         A --> print(rint(geometry.angle(maxSlope)) + \" \" + rint(geometry.angle(azimuth))) X.",
        lot(20.0, 30.0),
    );
    // The bottom, the two gable ends and the high wall of the shed, then its slope, facing
    // south (+z).
    assert_eq!(roof.prints, ["0 0", "90 90", "90 0", "90 270", "30 180"]);
    let errors = errors("Lot --> print(geometry.angle(steepest)) X.");
    assert!(errors.is_empty(), "{errors:?}");
    // It asks about the shape alone, so an attribute may use it, unlike occlusion queries.
    let d = run(
        "attr slope = geometry.angle(maxSlope)\nLot --> print(slope) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["0"]);
    let failed = common::try_run(
        "Lot --> print(geometry.angle(steepest)) X.",
        lot(4.0, 4.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        failed.to_string(),
        "expected `maxSlope`, `azimuth` or `zenith`, found `steepest`"
    );
}

#[test]
fn file_functions_without_files() {
    let d = run(
        "Lot --> print(fileExists(\"facade.jpg\")) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["false"]);
    let failed = common::try_run(
        "Lot --> print(readTextFile(\"notes.txt\")) X.",
        lot(4.0, 4.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        failed.to_string(),
        "cannot read `notes.txt`: this derivation reads no files"
    );
}

#[test]
fn reference_functions_not_supported_yet_warn_at_check_and_stop_when_reached() {
    let diagnostics = compile_errors("Lot --> case false : print(isInside()) X. else : Y.");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with("warning: function `isInside` is not supported yet"),
        "{}",
        diagnostics[0]
    );
    let d = run(
        "Lot --> case false : print(edgeAttr.getFloat(\"w\")) X. else : Y.",
        lot(4.0, 4.0),
    );
    assert_eq!(names(&d), ["Y"]);
}

#[test]
fn a_dynamic_import_takes_named_attributes() {
    let errors = errors("Lot --> tower(12).Mass");
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with(
            "error: a dynamic import sets attributes: `id(name = value).Rule`\n --> test.cga:1:15"
        ),
        "{}",
        errors[0]
    );
}

#[test]
fn start_rule_print_as_a_function_and_geometry_questions_without_parentheses() {
    // Complete_Street.cga picks its street parts by `initialShape.startRule`.
    let d = run(
        "attr part = case initialShape.startRule == \"Street\" : \"lanes\" else : \"other\"
         @StartRule
         Street --> print(part) extrude(print(2) + 1) Mass
         Mass --> case geometry.isConcave : Concave. else : print(geometry.nEdges) t(0, 2, 0) print(scope.elevation) Box.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["lanes", "2", "12", "2"]);
    assert_eq!(names(&d), ["Box"]);
    assert_eq!(d.leaves[0].scope.size.y, 3.0);
}

#[test]
fn convert_takes_positions_and_angles_between_scope_and_world() {
    // The lot's right facade: its scope starts at (20, 0, 30) with x along −z.
    let d = run(
        "Lot --> extrude(10) comp(f) { right : R }
         R --> print(convert(scope, world, pos, [2, 1, 0]))
               print(convert(x, world, scope, pos, 20, 0, 26))
               print(rint(convert(y, scope, object, orient, 0, 0, 0)))
               X.",
        lot(20.0, 30.0),
    );
    assert_eq!(d.prints, ["[20,1,28]", "4", "90"]);
    let failed = common::try_run(
        "Lot --> print(convert(scope, screen, pos, [0, 0, 0])) X.",
        lot(4.0, 4.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        failed.to_string(),
        "expected the coordinate system `scope`, `pivot`, `object` or `world`, found `screen`"
    );
}

#[test]
fn start_and_extension_rules_are_rules_with_a_keyword() {
    let d = run(
        "Lot --> A.\nextension Roof --> Flat.\nstart Main --> extrude(1) Roof",
        lot(4.0, 4.0),
    );
    assert_eq!(names(&d), ["Flat"]);
}

#[test]
fn primitives_given_dimensions_stand_centred_on_the_scope_floor() {
    // The Swiss building rules and the solar-panel rules size their primitives in the call.
    let d = run(
        "Lot --> [ primitiveCube(4, 2, 6) Cube ] [ primitiveCylinder(8, 1, 3) Cylinder ] \
         primitiveQuad(5, 7) Quad",
        lot(20.0, 30.0),
    );
    assert_eq!(names(&d), ["Cube", "Cylinder", "Quad"]);
    let scope = |i: usize| {
        let s = &d.leaves[i].scope;
        (s.origin.to_array(), s.size.to_array())
    };
    assert_eq!(scope(0), ([8.0, 0.0, 12.0], [4.0, 2.0, 6.0]));
    assert_eq!(scope(1), ([9.0, 0.0, 14.0], [2.0, 3.0, 2.0]));
    assert_eq!(scope(2), ([7.5, 0.0, 11.5], [5.0, 0.0, 7.0]));
    // A quad on an upright face stands in the face's plane, centred in it.
    let d = run(
        "Lot --> extrude(4) comp(f) { front : primitiveQuad(2, 1) Q }",
        lot(20.0, 30.0),
    );
    let s = &d.leaves[0].scope;
    assert_eq!(s.size.to_array(), [2.0, 1.0, 0.0]);
    assert_eq!(s.origin.y, 1.5);
    // Negative dimensions mirror: still centred across, hanging below the floor.
    let d = run("Lot --> primitiveCube(-4, -2, 6) X", lot(20.0, 30.0));
    let s = &d.leaves[0].scope;
    assert_eq!(s.size.to_array(), [4.0, 2.0, 6.0]);
    assert_eq!(s.origin.to_array(), [12.0, 0.0, 12.0]);
    assert_eq!(s.axes.col(0).to_array(), [-1.0, 0.0, 0.0]);
    assert_eq!(s.axes.col(1).to_array(), [0.0, -1.0, 0.0]);
    let errors = compile_errors("Lot --> primitiveCube(1, 2) X");
    assert!(
        errors[0].starts_with("error: wrong number of arguments for `primitiveCube`"),
        "{errors:?}"
    );
}

#[test]
fn align_scope_to_geometry_with_two_arguments_takes_an_edge_of_face_0() {
    // Older street rules write `alignScopeToGeometry(yUp, dir)` for `(yUp, 0, dir)`.
    let d = run("Lot --> alignScopeToGeometry(yUp, 1) X", lot(4.0, 10.0));
    assert_eq!(d.leaves[0].scope.size.to_array(), [10.0, 0.0, 4.0]);
    let d = run(
        "Lot --> alignScopeToGeometry(yUp, longest) X",
        lot(4.0, 10.0),
    );
    assert_eq!(d.leaves[0].scope.size.to_array(), [10.0, 0.0, 4.0]);
}

/// Three box assets of different sizes, found by any search.
struct Boxes;

impl shapegram_eval::AssetLoader for Boxes {
    fn load(&self, path: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        use shapegram_geom::{DAffine3, DVec3, primitives};
        let (size, at) = match path {
            "small.obj" => (DVec3::new(2.0, 3.0, 2.0), DVec3::new(-1.0, 0.0, -1.0)),
            "wide.obj" => (DVec3::new(9.0, 3.0, 4.0), DVec3::ZERO),
            "tall.obj" => (DVec3::new(5.0, 20.0, 5.0), DVec3::new(0.5, 0.25, 0.0)),
            other => return Err(format!("no mesh `{other}`")),
        };
        let mesh = primitives::cuboid(size).transformed(&DAffine3::from_translation(at));
        Ok(std::sync::Arc::new(mesh))
    }

    fn search(&self, _query: &str) -> Result<Vec<std::sync::Arc<str>>, String> {
        Ok(vec![
            "small.obj".into(),
            "tall.obj".into(),
            "wide.obj".into(),
            "notes.txt".into(),
        ])
    }
}

/// The reports of `grammar` derived on a 10 × 5 lot with the [`Boxes`].
fn box_reports(grammar: &str) -> Vec<(String, shapegram_eval::Value)> {
    let options = shapegram_eval::DeriveOptions {
        assets: Some(std::sync::Arc::new(Boxes)),
        ..Default::default()
    };
    shapegram_eval::derive(&common::compile(grammar), &[lot(10.0, 5.0)], &options)
        .unwrap()
        .reports
}

#[test]
fn asset_info_gives_the_bounding_box_of_an_asset() {
    // The plant rules scale trees by `assetInfo(asset, tx)`; the instance reports by "sx".
    let r = box_reports(
        "Lot --> report(\"sx\", assetInfo(\"tall.obj\", \"sx\")) report(\"sy\", assetInfo(\"tall.obj\", sy)) \
         report(\"tx\", assetInfo(\"tall.obj\", tx)) report(\"ty\", assetInfo(\"tall.obj\", ty)) \
         report(\"tz\", assetInfo(\"small.obj\", tz)) report(\"cube\", assetInfo(\"builtin:cube\", sz))",
    );
    let numbers: Vec<(String, f64)> = r
        .into_iter()
        .map(|(k, v)| match v {
            shapegram_eval::Value::Number(n) => (k, n),
            v => panic!("{v:?}"),
        })
        .collect();
    let expected = [
        ("sx", 5.0),
        ("sy", 20.0),
        ("tx", 0.5),
        ("ty", 0.25),
        ("tz", -1.0),
        ("cube", 1.0),
    ];
    assert_eq!(numbers, expected.map(|(k, n)| (k.to_owned(), n)).to_vec());
    let errors = errors("Lot --> report(\"r\", assetInfo(\"a.obj\", rx))");
    assert!(errors.is_empty(), "{errors:?}");
}

#[test]
fn asset_best_size_picks_the_asset_closest_to_the_scope_along_the_axes_asked() {
    // The 10 × 5 lot: "xz" fits the 9 × 4 asset best, "x" too; a 20 high scope takes the
    // tall one by "y"; files that are not meshes take no part.
    let r = box_reports(
        "Lot --> report(\"xz\", assetBestSize(\"*\", \"xz\")) report(\"x\", assetBestSize(\"*\", \"x\")) \
         extrude(19) report(\"y\", assetBestSize(\"*\", \"y\"))",
    );
    let files: Vec<String> = r.into_iter().map(|(_, v)| v.to_string()).collect();
    assert_eq!(files, ["wide.obj", "wide.obj", "tall.obj"]);
}

#[test]
fn an_attribute_default_may_read_attributes_declared_after_it() {
    // The Complete Street rule: `attr Lane_Distribution = _initial` (a function reading
    // `Lane_Width`) comes before `attr Lane_Width = laneWidth - .2`, before `attr laneWidth`.
    let d = run(
        "attr share = initial\n\
         attr width = (lane - .2)\n\
         initial = case 10 / width >= 2.2 : 0.5 else : 1\n\
         attr lane = 3.5\n\
         Lot --> extrude(share * 10 + width) X",
        lot(4.0, 4.0),
    );
    assert_eq!(d.leaves[0].scope.size.y, 5.0 + 3.3);
    let errors = common::try_run(
        "attr a = b + 1\nattr b = a * 2\nLot --> extrude(a) X",
        lot(4.0, 4.0),
        &shapegram_eval::DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(errors.message, "the default of attribute `a` reads itself");
}

#[test]
fn set_moves_and_sizes_the_scope_along_one_axis() {
    // `set(scope.tx, …)` as the instance-placing rules write it.
    let d = run(
        "Lot --> extrude(4) set(scope.tx, 3) set(scope.sz, 2) set(scope.ty, scope.ty + 1) X",
        lot(10.0, 6.0),
    );
    let s = &d.leaves[0].scope;
    assert_eq!(s.origin.to_array(), [3.0, 1.0, 0.0]);
    assert_eq!(s.size.to_array(), [10.0, 4.0, 2.0]);
    let volume = d.leaves[0]
        .geometry
        .local_mesh(s.size)
        .unwrap()
        .signed_volume();
    assert!((volume - 80.0).abs() < 1e-9, "{volume}");
    let errors = compile_errors("Lot --> set(scope.rx, 30) X");
    assert!(
        errors[0].starts_with("error: `set` cannot write this shape attribute"),
        "{errors:?}"
    );
}

#[test]
fn offset_works_on_each_face_of_a_volume() {
    // The solar-panel rules offset a thin cube: every face gets its inset and border.
    let d = run(
        "Lot --> extrude(2) offset(-0.5, inside) comp(f) { all : F }",
        lot(4.0, 3.0),
    );
    // Six faces, each shrunk by 0.5 on every side: 3 × 2, 3 × 1 and 2 × 1, twice each.
    assert_eq!(d.leaves.len(), 6);
    let area: f64 = d
        .leaves
        .iter()
        .map(|l| l.geometry.local_mesh(l.scope.size).unwrap().area())
        .sum();
    assert!((area - 2.0 * (6.0 + 3.0 + 2.0)).abs() < 1e-9, "{area}");
    let d = run("Lot --> extrude(2) offset(-0.5, border) X", lot(4.0, 3.0));
    let s = d.leaves[0].scope.size;
    assert_eq!(s.to_array(), [4.0, 2.0, 3.0]);
}
