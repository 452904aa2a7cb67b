//! Functions of the CGA reference's function list that real rule files call: each with the
//! values CityEngine gives and the error a wrong argument gets, at the argument.

use crate::common;

use common::{compile_errors, lot, lots_in_a_row, run, try_run};
use shapegram_eval::DeriveOptions;
use std::sync::Arc;

use shapegram_eval::{AssetLoader, InitialShape};
use shapegram_geom::DVec2;

/// The message of the derivation's error and the text its span covers.
fn failure(grammar: &str) -> (String, String) {
    let error = try_run(grammar, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
    let span = error.span.expect("the error has a place");
    let covered = grammar[span.start as usize..span.end as usize].to_owned();
    (error.message, covered)
}

#[test]
fn color_ramps_pick_one_of_36_colours_clamped_at_the_ends() {
    let d = run(
        "Lot --> print(colorRamp(\"yellowToRed\", 0)) print(colorRamp(\"yellowToRed\", 0.5))
                 print(colorRamp(\"yellowToRed\", 1)) print(colorRamp(\"yellowToRed\", 0.999))
                 print(colorRamp(\"yellowToRed\", -0.2)) print(colorRamp(\"yellowToRed\", 7))
                 print(colorRamp(\"spectrum\", 0.25)) print(colorRamp(\"whiteToBlack\", 0.5))
                 print(colorRamp(\"brownToBlue\", 0.5)) print(colorRamp(\"greenToRed\", 0.02))
                 print(colorRamp(\"redToBlue\", 1)) print(colorRamp(\"orangeToBlue\", 0))
                 X.",
        lot(4.0, 4.0),
    );
    assert_eq!(
        d.prints,
        [
            "#F5F500", "#F57700", "#F50000", "#F50000", "#F5F500", "#F50000", "#39A9DF", "#7B7B7B",
            "#F2F8BC", "#3BA800", "#3661CF", "#FFC800"
        ]
    );
}

#[test]
fn a_colour_ramp_colours_the_shape() {
    let d = run(
        "Lot --> color(colorRamp(\"whiteToBlack\", 0.5)) X.",
        lot(4.0, 4.0),
    );
    let c = d.color(&d.leaves[0]);
    assert_eq!(
        [c.r, c.g, c.b].map(|v| (v * 255.0).round()),
        [123.0, 123.0, 123.0]
    );
}

#[test]
fn an_unknown_colour_ramp_is_an_error_at_its_name() {
    let (message, at) = failure("Lot --> print(colorRamp(\"rainbow\", 0.5)) X.");
    assert_eq!(
        message,
        "`rainbow` is no colour ramp: expected `whiteToBlack`, `greenToRed`, `yellowToRed`, \
         `redToBlue`, `orangeToBlue`, `brownToBlue`, `spectrum`"
    );
    assert_eq!(at, "\"rainbow\"");
    let (message, at) = failure("Lot --> print(colorRamp(\"spectrum\", \"half\")) X.");
    assert_eq!(message, "expected a number, found a string");
    assert_eq!(at, "\"half\"");
}

#[test]
fn sel_turns_a_string_into_a_selector_word() {
    // The reference's `sel` is a cast (`set(sel("material.color." + c), 0.5)`), not a
    // conditional: a word built as a string goes where a selector goes.
    let d = run(
        "axis(i) = case i == 0 : \"x\" else : \"y\"
         Lot --> print(sel(\"front\")) print(getGeoCoord(sel(axis(0))))
                 print(geometry.isOriented(sel(\"top\"))) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["front", "0", "true"]);
    let d = run(
        "Lot --> color(0, 0, 0) set(sel(\"material.color.r\"), 0.5) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.color(&d.leaves[0]).r, 0.5);
    let diagnostics =
        compile_errors("f(c) = \"material.color.\" + c\nLot --> set(sel(f(\"r\")), 0.5) X.");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with(
            "error: `set(sel(…), …)` needs the name as a string literal: a name computed \
             during the derivation is not supported\n --> test.cga:2:17"
        ),
        "{}",
        diagnostics[0]
    );
    let (message, at) = failure("Lot --> print(sel(3)) X.");
    assert_eq!(message, "expected a string, found a number");
    assert_eq!(at, "3");
}

#[test]
fn geo_coordinates_are_the_local_frame_without_a_georeference() {
    let d = run(
        "Lot --> t(3, 2, 5) print(getGeoCoord(x)) print(getGeoCoord(y))
                 print(getGeoCoord(lon)) print(getGeoCoord(\"lat\")) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["3", "-5", "0", "0"]);
    let (message, at) = failure("Lot --> print(getGeoCoord(z)) X.");
    assert_eq!(message, "expected `x`, `y`, `lon` or `lat`, found `z`");
    assert_eq!(at, "z");
}

#[test]
fn edge_attributes_without_a_street_graph_are_their_defaults() {
    let d = run(
        "Lot --> print(edgeAttr.getFloat(\"width\")) print(edgeAttr.getString(\"name\") == \"\")
                 print(edgeAttr.getBool(\"oneway\")) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["0", "true", "false"]);
    let (message, at) = failure("Lot --> print(edgeAttr.getFloat(2)) X.");
    assert_eq!(message, "expected a string, found a number");
    assert_eq!(at, "2");
}

#[test]
fn is_oriented_asks_whether_some_face_faces_the_selector() {
    let d = run(
        "Lot --> print(geometry.isOriented(top)) print(geometry.isOriented(side))
                 print(geometry.isOriented(world.up)) print(geometry.isOriented(world.down))
                 extrude(3) Mass
         Mass --> print(geometry.isOriented(side)) print(geometry.isOriented(bottom))
                  comp(f) { top : Roof }
         Roof --> print(geometry.isOriented(world.up)) print(geometry.isOriented(world.side)) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(
        d.prints,
        [
            "true", "false", "true", "false", "true", "true", "true", "false"
        ]
    );
    let (message, at) = failure("Lot --> print(geometry.isOriented(inside)) X.");
    assert_eq!(
        message,
        "`inside` is no orientation: expected a face selector such as `front`, `side`, \
         `object.top`, `world.north` or `street.front`"
    );
    assert_eq!(at, "inside");
}

#[test]
fn the_implemented_functions_check_without_warnings() {
    let diagnostics = compile_errors(
        "Lot --> print(colorRamp(\"spectrum\", 0.5)) print(sel(\"x\"))
                 print(getGeoCoord(lat)) print(edgeAttr.getBool(\"a\"))
                 print(geometry.isOriented(front)) X.",
    );
    assert!(diagnostics.is_empty(), "{diagnostics:?}");
    let diagnostics = compile_errors("Lot --> print(colorRamp(\"spectrum\")) X.");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    assert!(
        diagnostics[0].starts_with("error: wrong number of arguments for `colorRamp`"),
        "{}",
        diagnostics[0]
    );
}

#[test]
fn area_with_a_selector_sums_the_faces_it_selects() {
    let d = run(
        "Lot --> extrude(3) Mass
         Mass --> print(geometry.area(side)) print(geometry.area(top)) print(geometry.area(surface))
                  print(geometry.area(world.down)) print(geometry.area()) print(geometry.area) X.",
        lot(4.0, 5.0),
    );
    assert_eq!(d.prints, ["54", "20", "94", "20", "94", "94"]);
    let (message, at) = failure("Lot --> print(geometry.area(border)) X.");
    assert_eq!(
        message,
        "`border` is no orientation: expected a face selector such as `front`, `side`, \
         `object.top`, `world.north` or `street.front`"
    );
    assert_eq!(at, "border");
}

#[test]
fn initial_shapes_have_a_name_and_an_object_frame() {
    let d = shapegram_eval::derive(
        &common::compile("Lot --> print(initialShape.name) X."),
        &lots_in_a_row(2, 4.0, 4.0, 10.0),
        &DeriveOptions::default(),
    )
    .unwrap();
    assert_eq!(d.prints, ["shape_0", "shape_1"]);
    assert_eq!(d.print_lots, [0, 1]);
    // A lot whose first edge runs along +z: its object frame is turned about y.
    let turned = InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(0.0, 4.0),
        DVec2::new(-3.0, 4.0),
        DVec2::new(-3.0, 0.0),
    ])
    .unwrap();
    let d = run(
        "Lot --> print(initialShape.origin.ox) print(initialShape.origin.oy)
                 print(initialShape.origin.oz) print(scope.ry) X.",
        turned,
    );
    let angles: Vec<f64> = d.prints.iter().map(|p| p.parse().unwrap()).collect();
    common::assert_close(&angles, &[0.0, -90.0, 0.0, -90.0]);
}

#[test]
fn tree_keys_follow_the_reference_example() {
    // The reference's own example: each rule's successors are numbered in order, and the key
    // names the rule application the shape belongs to.
    let d = run(
        "Init --> print(getTreeKey() + \" - Init\") center(xz) extrude(10) comp(f) { front : Facade }
         Facade --> print(getTreeKey() + \" - Facade\") split(y) { '0.5 : Floor }*
         Floor --> print(getTreeKey() + \" - Floor\")
                   split(x) { '0.1 : Wall | '0.3 : Window | '0.1 : Wall }*
         Wall --> print(getTreeKey() + \" - Wall\")
         Window --> print(getTreeKey() + \" - Window\")",
        lot(4.0, 4.0),
    );
    let mut prints = d.prints.clone();
    prints.sort();
    assert_eq!(
        prints,
        [
            "0; - Init",
            "0;0; - Facade",
            "0;0;0; - Floor",
            "0;0;0;0; - Wall",
            "0;0;0;1; - Window",
            "0;0;0;2; - Wall",
            "0;0;0;3; - Wall",
            "0;0;0;4; - Window",
            "0;0;0;5; - Wall",
            "0;0;1; - Floor",
            "0;0;1;0; - Wall",
            "0;0;1;1; - Window",
            "0;0;1;2; - Wall",
            "0;0;1;3; - Wall",
            "0;0;1;4; - Window",
            "0;0;1;5; - Wall",
        ]
    );
    // The key stays the rule's while the rule runs, in split parts too.
    let d = run(
        "A --> print(getTreeKey) split(x) { 2 : B print(getTreeKey) | 3 : C print(getTreeKey) }",
        lot(5.0, 4.0),
    );
    assert_eq!(d.prints, ["0;", "0;", "0;"]);
    // Terminal successors take their places too.
    let d = run(
        "A --> split(x) { 1 : X. | 1 : B | 1 : Y. | 1 : B }
         B --> print(getTreeKey)",
        lot(4.0, 4.0),
    );
    assert_eq!(d.prints, ["0;1;", "0;3;"]);
}

#[test]
fn get_material_lists_the_attributes_set_or_all_of_them() {
    let d = run(
        "Lot --> color(0.5, 0.6, 0.7) set(material.metallic, 0.25) set(material.name, \"brick\")
                 print(getMaterial(used, changed)) print(nRows(getMaterial(shape, all)))
                 print(nRows(getMaterial(geometry, changed)))
                 print(getMaterial(shape, all)[6, 1]) X.",
        lot(4.0, 4.0),
    );
    assert_eq!(
        d.prints,
        [
            "[[name,brick],[color.r,0.5],[color.g,0.6],[color.b,0.7],[metallic,0.25]]",
            "32",
            "0",
            "1"
        ]
    );
    let (message, at) = failure("Lot --> print(getMaterial(mine, all)) X.");
    assert_eq!(
        message,
        "expected `used`, `shape` or `geometry`, found `mine`"
    );
    assert_eq!(at, "mine");
    let (message, at) = failure("Lot --> print(getMaterial(used, some)) X.");
    assert_eq!(message, "expected `changed` or `all`, found `some`");
    assert_eq!(at, "some");
}

/// Assets holding one MTL file, `materials/brick.mtl`.
struct MaterialFiles;

impl AssetLoader for MaterialFiles {
    fn load(&self, path: &str) -> Result<Arc<shapegram_geom::Mesh>, String> {
        Err(format!("no mesh `{path}`"))
    }

    fn text(&self, path: &str) -> Result<Arc<str>, String> {
        match path {
            "materials/brick.mtl" => Ok("# two materials: the first is read\n\
                 newmtl brick\nKd 0.5 0.25 0.125\nd 0.75\nNs 16\nKs 0.1 0.2 0.3\n\
                 map_Kd tex/brick.png\nbump tex/brick_bump.png\n\
                 newmtl other\nKd 1 1 1\n"
                .into()),
            other => Err(format!("no file `{other}`")),
        }
    }
}

#[test]
fn read_material_reads_an_mtl_files_first_material() {
    let options = DeriveOptions {
        assets: Some(Arc::new(MaterialFiles)),
        ..DeriveOptions::default()
    };
    let grammar = "Lot --> print(readMaterial(\"materials/brick.mtl\")) X.";
    let d = shapegram_eval::derive(&common::compile(grammar), &[lot(4.0, 4.0)], &options).unwrap();
    assert_eq!(
        d.prints,
        [
            "[[name,brick],[color.r,0.5],[color.g,0.25],[color.b,0.125],[opacity,0.75],\
          [specular.r,0.1],[specular.g,0.2],[specular.b,0.3],[shininess,16],\
          [colormap,materials/tex/brick.png],[bumpmap,materials/tex/brick_bump.png]]"
        ]
    );
    let failed = |grammar: &str| {
        let e = shapegram_eval::derive(&common::compile(grammar), &[lot(4.0, 4.0)], &options)
            .unwrap_err();
        let span = e.span.unwrap();
        (
            e.message,
            grammar[span.start as usize..span.end as usize].to_owned(),
        )
    };
    assert_eq!(
        failed("Lot --> print(readMaterial(\"metal.cgamat\")) X."),
        (
            "cannot read `metal.cgamat`: CityEngine's .cgamat format is not supported".to_owned(),
            "\"metal.cgamat\"".to_owned()
        )
    );
    assert_eq!(
        failed("Lot --> print(readMaterial(\"brick.png\")) X.").0,
        "`brick.png` is no material file: expected a .mtl (or .cgamat) file"
    );
    assert_eq!(
        failed("Lot --> print(readMaterial(\"gone.mtl\")) X.").0,
        "no file `gone.mtl`"
    );
}

/// Assets holding one mesh, `box.obj` (a unit cube).
struct OneBox;

impl AssetLoader for OneBox {
    fn load(&self, path: &str) -> Result<Arc<shapegram_geom::Mesh>, String> {
        match path {
            "box.obj" => Ok(Arc::new(shapegram_geom::primitives::cuboid(
                shapegram_geom::DVec3::ONE,
            ))),
            other => Err(format!("no mesh `{other}`")),
        }
    }
}

#[test]
fn an_inserted_asset_is_an_instance_until_an_operation_changes_its_geometry() {
    let options = DeriveOptions {
        assets: Some(Arc::new(OneBox)),
        ..DeriveOptions::default()
    };
    let grammar = "Lot --> s(2, 2, 2) print(geometry.isInstanced()) i(\"box.obj\") \
                   print(geometry.isInstanced()) t(1, 0, 0) r(0, 30, 0) \
                   print(geometry.isInstanced()) Kept Cut Faces\n\
                   Kept --> print(geometry.isInstanced()) X.\n\
                   Cut --> split(x) { 1 : print(geometry.isInstanced()) X. }\n\
                   Faces --> comp(f) { top : print(geometry.isInstanced()) X. }\n";
    let d = shapegram_eval::derive(&common::compile(grammar), &[lot(4.0, 4.0)], &options).unwrap();
    // Before the insert, after it, moved and turned, in a successor, then cut by a split and
    // by a comp.
    assert_eq!(
        d.prints,
        ["false", "true", "true", "true", "false", "false"]
    );
}
