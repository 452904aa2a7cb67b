//! Component tags: the tags operations give what they build (`extrude`, roofs, `taper`,
//! `envelope`), `tag` and `deleteTags`, the `isTagged` selectors and logical selector
//! expressions, `geometry.tags` and `geometry.hasTags`, tags through splits, and the roof edge
//! selectors, `comp(fv)` and `comp(h)`.

use crate::common;

use common::{assert_close, compile_errors, lot, numeric_reports, of, run};
use shapegram_eval::{InitialShape, Value};
use shapegram_geom::DVec2;

/// The areas reported under `key`, sorted.
fn areas(reports: &[(String, f64)], key: &str) -> Vec<f64> {
    let mut found = of(reports, key);
    found.sort_by(f64::total_cmp);
    found
}

/// Rules reporting each face's area under their own name.
const REPORT: &str = "
    B --> report(\"b\", geometry.area)
    S --> report(\"s\", geometry.area)
    T --> report(\"t\", geometry.area)
    O --> report(\"o\", geometry.area)
    C --> report(\"c\", geometry.area)
";

fn reports(rule: &str, w: f64, d: f64) -> Vec<(String, f64)> {
    numeric_reports(&format!("{rule}\n{REPORT}"), lot(w, d))
}

#[test]
fn extrude_tags_bottom_sides_and_top() {
    let r = reports(
        "Lot --> extrude(4) comp(f) { isTagged(\"extrude.bottom\") : B \
         | isTagged(\"extrude.side.outer\") : S | isTagged(\"extrude.top\") : T | all : O }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "b"), &[200.0]);
    assert_close(&areas(&r, "t"), &[200.0]);
    assert_close(&areas(&r, "s"), &[40.0, 40.0, 80.0, 80.0]);
    assert!(of(&r, "o").is_empty());
}

#[test]
fn tags_survive_a_split_and_cut_faces_have_none() {
    let r = reports(
        "Lot --> extrude(4) split(y) { 1 : A | ~1 : A }
         A --> comp(f) { isTagged(\"extrude.bottom\") : B | isTagged(\"extrude.top\") : T \
                       | isTagged(\"extrude.side\") : S | all : C }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "b"), &[200.0]);
    assert_close(&areas(&r, "t"), &[200.0]);
    // The lower piece's sides are 1 m high, the upper's 3 m; the two cut faces are untagged.
    assert_close(
        &areas(&r, "s"),
        &[10.0, 10.0, 20.0, 20.0, 30.0, 30.0, 60.0, 60.0],
    );
    assert_close(&areas(&r, "c"), &[200.0, 200.0]);
}

#[test]
fn component_faces_keep_their_tags() {
    let r = reports(
        "Lot --> extrude(4) comp(f) { side : Side | all : NIL }
         Side --> split(x) { ~1 : Part }*
         Part --> comp(f) { isTagged(\"extrude.side\") : S | all : O }",
        10.0,
        20.0,
    );
    // Every 1 m piece of the four walls is still a side.
    assert_eq!(of(&r, "s").len(), 60);
    assert!(of(&r, "o").is_empty());
}

#[test]
fn roofs_tag_bottom_slopes_and_gable_ends() {
    let gable = reports(
        "Lot --> roofGable(45) comp(f) { isTagged(\"roof.bottom\") : B \
         | isTagged(\"roof.side\") : S | isTagged(\"roof.top\") : T | all : O }",
        10.0,
        20.0,
    );
    let slope = 20.0 * 5.0 * 2f64.sqrt();
    assert_close(&areas(&gable, "b"), &[200.0]);
    assert_close(&areas(&gable, "t"), &[slope, slope]);
    assert_close(&areas(&gable, "s"), &[25.0, 25.0]);
    assert!(of(&gable, "o").is_empty());

    let hip = reports(
        "Lot --> roofHip(45) comp(f) { isTagged(\"roof.top\") : T | isTagged(\"roof.side\") : S \
         | all : O }",
        10.0,
        10.0,
    );
    let triangle = 0.5 * 10.0 * 5.0 * 2f64.sqrt();
    assert_close(&areas(&hip, "t"), &[triangle; 4]);
    assert!(of(&hip, "s").is_empty());
    assert_close(&areas(&hip, "o"), &[100.0]);

    // A shed's walls are outer sides; the query "roof.side" takes them too.
    let shed = reports(
        "Lot --> roofShed(45) comp(f) { isTagged(\"roof.side.outer\") : S \
         | isTagged(\"roof.top\") : T | isTagged(\"roof.bottom\") : B }",
        10.0,
        10.0,
    );
    assert_close(&areas(&shed, "t"), &[100.0 * 2f64.sqrt()]);
    assert_close(&areas(&shed, "s"), &[50.0, 50.0, 100.0]);
    assert_close(&areas(&shed, "b"), &[100.0]);
}

#[test]
fn taper_tags_its_base_and_sides() {
    let r = reports(
        "Lot --> taper(4) comp(f) { isTagged(\"taper.bottom\") : B | isTagged(\"taper.side\") : S }",
        10.0,
        10.0,
    );
    let side = 0.5 * 10.0 * (16.0f64 + 25.0).sqrt();
    assert_close(&areas(&r, "b"), &[100.0]);
    assert_close(&areas(&r, "s"), &[side; 4]);
}

#[test]
fn envelope_tags_bottom_base_walls_slopes_and_top() {
    let r = reports(
        "Lot --> envelope(normal, 6, 2, 45, 2, 45, 2, 45)
                 comp(f) { isTagged(\"envelope.bottom\") : B | isTagged(\"envelope.side.base\") : S \
                         | isTagged(\"envelope.side.slope\") : O | isTagged(\"envelope.top\") : T \
                         | all : C }",
        20.0,
        20.0,
    );
    let slope = 0.5 * (20.0 + 12.0) * 4.0 * 2f64.sqrt();
    assert_close(&areas(&r, "b"), &[400.0]);
    assert_close(&areas(&r, "s"), &[40.0; 4]);
    assert_close(&areas(&r, "o"), &[slope; 4]);
    assert_close(&areas(&r, "t"), &[144.0]);
    assert!(of(&r, "c").is_empty());
}

#[test]
fn logical_selectors_combine_tags_directions_and_conditions() {
    let r = reports(
        "Lot --> extrude(4) comp(f) { isTagged(\"extrude\") && !isTagged(\"extrude.side\") : T \
                                    | front || back : S \
                                    | geometry.area > 50 : B | all : O }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "t"), &[200.0, 200.0]);
    // Front and back are the 10 m walls, the 20 m ones larger than 50 m².
    assert_close(&areas(&r, "s"), &[40.0, 40.0]);
    assert_close(&areas(&r, "b"), &[80.0, 80.0]);
    assert!(of(&r, "o").is_empty());
}

#[test]
fn conditions_may_call_the_grammars_functions() {
    let r = reports(
        "big = geometry.area > 50
         Lot --> extrude(4) comp(f) { side && big : S | all : O }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "s"), &[80.0, 80.0]);
    assert_eq!(of(&r, "o").len(), 4);
}

#[test]
fn tag_and_delete_tags_change_faces_and_edges() {
    let r = reports(
        "Lot --> tag(\"lot.a\") tag(\"lot.b\") deleteTags(\"lot.b\") extrude(3)
                 comp(f) { isTagged(\"lot.a\") && isTagged(\"extrude.side\") : S \
                         | isTagged(\"lot\") : T | all : O }",
        10.0,
        20.0,
    );
    // Every face built on the lot keeps its tag.
    assert_eq!(of(&r, "s").len(), 4);
    assert_close(&areas(&r, "t"), &[200.0, 200.0]);
    assert!(of(&r, "o").is_empty());

    // Edge tags: the walls rise from the lot's tagged edges and take their tag as faces.
    let edges = reports(
        "Lot --> tag(\"rim\", edges) extrude(3)
                 comp(f) { geometry.hasTags(\"rim\", faces) : S | all : O }",
        10.0,
        20.0,
    );
    assert_eq!(of(&edges, "s").len(), 4);
    assert_close(&areas(&edges, "o"), &[200.0, 200.0]);
}

#[test]
fn geometry_tags_lists_sorted_matching_tags() {
    let text = "Lot --> tag(\"lot\") extrude(2)
                    report(\"n\", size(geometry.tags()))
                    report(\"first\", geometry.tags()[0])
                    report(\"extrude\", size(geometry.tags(\"extrude\")))
                    report(\"faces\", size(geometry.tags(\"\", faces)))
                    report(\"edges\", size(geometry.tags(\"\", edges)))
                    report(\"has\", geometry.hasTags(\"?.top\"))
                    deleteTags(\"lot\")
                    report(\"after\", geometry.hasTags(\"lot\"))
                    deleteTags()
                    report(\"none\", geometry.hasTags())";
    let d = run(text, lot(10.0, 20.0));
    let get = |key: &str| {
        d.reports
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .unwrap()
    };
    assert_eq!(get("n"), Value::Number(4.0));
    assert_eq!(get("first"), Value::string("extrude.bottom"));
    assert_eq!(get("extrude"), Value::Number(3.0));
    assert_eq!(get("faces"), Value::Number(4.0));
    assert_eq!(get("edges"), Value::Number(0.0));
    assert_eq!(get("has"), Value::Bool(true));
    assert_eq!(get("after"), Value::Bool(false));
    assert_eq!(get("none"), Value::Bool(false));
}

#[test]
fn roof_edges_are_eaves_hips_valleys_and_ridges() {
    let text = "Lot --> roofHip(45) comp(e) { eave : E | hip : H | valley : V | ridge : R }
        E --> report(\"e\", scope.sx)
        H --> report(\"h\", scope.sx) report(\"hy\", scope.ty)
        V --> report(\"v\", scope.sx)
        R --> report(\"r\", scope.sx)";
    let r = numeric_reports(text, lot(10.0, 20.0));
    assert_close(&areas(&r, "e"), &[10.0, 10.0, 20.0, 20.0]);
    let hip = 75f64.sqrt();
    assert_close(&areas(&r, "h"), &[hip; 4]);
    // Hips run upward, from the eaves.
    assert_close(&of(&r, "hy"), &[0.0; 4]);
    assert_close(&areas(&r, "r"), &[10.0]);
    assert!(of(&r, "v").is_empty());

    // An L-shaped footprint has one valley, from its inner corner.
    let l = InitialShape::from_xz(&[
        DVec2::new(0.0, 0.0),
        DVec2::new(20.0, 0.0),
        DVec2::new(20.0, 10.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(10.0, 20.0),
        DVec2::new(0.0, 20.0),
    ])
    .unwrap();
    let r = numeric_reports(text, l);
    assert_eq!(of(&r, "e").len(), 6);
    assert_close(&areas(&r, "v"), &[75f64.sqrt()]);
}

#[test]
fn face_vertices_and_holes() {
    let r = reports(
        "Lot --> extrude(4) comp(fv) { all : P }
         P --> report(\"p\", scope.sx)",
        10.0,
        20.0,
    );
    // Six faces of four corners each, every one a point.
    assert_close(&of(&r, "p"), &[0.0; 24]);
    let holes = reports("Lot --> comp(h) { all : C }", 10.0, 20.0);
    assert!(holes.is_empty());
}

#[test]
fn tag_queries_may_be_expressions() {
    let r = reports(
        "const family = \"extrude\"
         Lot --> extrude(4) comp(f) { isTagged(family + \".top\") : T | isTagged(family, e) : S }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "t"), &[200.0]);
    // Every other face shares an edge with a tagged face.
    assert_eq!(of(&r, "s").len(), 5);
    let text = "Lot --> extrude(4) comp(f) { isTagged(scope.sx) : X }";
    let error = common::try_run(text, lot(10.0, 20.0), &Default::default()).unwrap_err();
    assert!(error.to_string().contains("string"), "{error}");
}

#[test]
fn is_tagged_needs_a_query() {
    let errors = compile_errors("Lot --> comp(f) { isTagged(3) : X }");
    assert!(
        errors
            .iter()
            .any(|e| e.contains("takes a tag query, a string") && e.contains("1:19")),
        "{errors:?}"
    );
    let errors = compile_errors("Lot --> comp(f) { isTagged(\"a\", f) : X }");
    assert!(
        errors.iter().any(|e| e.contains("`e` or `v`")),
        "{errors:?}"
    );
}

#[test]
fn setback_tags_the_edges_of_strips_and_remainder() {
    let text = "Lot --> setback(4) { front : Strip | remainder : Rest }
        Strip --> comp(e) { isTagged(\"setback.front\") : F | isTagged(\"setback.back\") : K \
                          | isTagged(\"setback.side\") : S | all : O }
        Rest --> comp(e) { isTagged(\"setback.back\") : RK | isTagged(\"setback.remainder\") : R \
                         | all : RO }
        F --> report(\"f\", scope.sx)
        K --> report(\"k\", scope.sx)
        S --> report(\"s\", scope.sx)
        O --> report(\"o\", scope.sx)
        RK --> report(\"rk\", scope.sx)
        R --> report(\"r\", scope.sx)
        RO --> report(\"ro\", scope.sx)";
    let r = numeric_reports(text, lot(10.0, 20.0));
    assert_close(&areas(&r, "f"), &[10.0]);
    assert_close(&areas(&r, "k"), &[10.0]);
    assert_close(&areas(&r, "s"), &[4.0, 4.0]);
    assert!(of(&r, "o").is_empty());
    assert_close(&areas(&r, "rk"), &[10.0]);
    assert_close(&areas(&r, "r"), &[10.0, 16.0, 16.0]);
    assert!(of(&r, "ro").is_empty());
}

#[test]
fn trimmed_faces_keep_their_tags() {
    // Walls stretched past their ends are cut back at the corners by their trim planes, and
    // what is left is still a side.
    let r = reports(
        "Lot --> extrude(4) comp(f) { side : Side | all : NIL }
         Side --> s('1.5, '1, '1) center(x) trim()
                  comp(f) { isTagged(\"extrude.side\") : S | all : O }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "s"), &[40.0, 40.0, 80.0, 80.0]);
    assert!(of(&r, "o").is_empty());
}

#[test]
fn what_shapegram_lacks_of_tags_is_a_warning() {
    let warnings = compile_errors("Lot --> setTagsFromEdgeAttrs() tag(\"x\", vertices)");
    for expected in ["setTagsFromEdgeAttrs", "no vertex tags"] {
        assert!(
            warnings
                .iter()
                .any(|w| w.starts_with("warning") && w.contains(expected)),
            "{expected}: {warnings:?}"
        );
    }
}

#[test]
fn a_second_setback_replaces_the_first_ones_edge_tags() {
    // The old back edge of the first setback's remainder is, after a second setback of its
    // left edge, an edge of the second remainder's old outline: `setback.remainder` only.
    let text = "Lot --> setback(4) { front : NIL | remainder : Rest }
        Rest --> setback(2) { left : NIL | remainder : R2 }
        R2 --> comp(e) { isTagged(\"setback.back\") : K | isTagged(\"setback.remainder\") : E }
        K --> report(\"k\", scope.sx)
        E --> report(\"e\", scope.sx)";
    let r = numeric_reports(text, lot(10.0, 20.0));
    assert_close(&areas(&r, "k"), &[16.0]);
    assert_close(&areas(&r, "e"), &[8.0, 8.0, 16.0]);
}

/// Assets of two materials and groups: `pane.obj`, a glass pane (1 × 1 at z = 1) and a frame
/// plate (1 × 1 at z = 0, facing back) behind it, each a group and a material of its own.
struct Panes;

impl shapegram_eval::AssetLoader for Panes {
    fn load(&self, path: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        Err(format!("no mesh `{path}`"))
    }

    fn asset(&self, path: &str, _variant: u32) -> Result<shapegram_eval::Asset, String> {
        use shapegram_geom::{Color, DVec3, Mesh, Part};
        if path != "pane.obj" {
            return Err(format!("no asset `{path}`"));
        }
        let quad = |z: f64, back: bool| {
            let mut corners = vec![
                DVec3::new(0.0, 0.0, z),
                DVec3::new(1.0, 0.0, z),
                DVec3::new(1.0, 1.0, z),
                DVec3::new(0.0, 1.0, z),
            ];
            if back {
                corners.reverse();
            }
            Mesh::from_polygon(&corners)
        };
        let part = |name: &str, mesh| Part {
            material: Some(std::sync::Arc::from(name)),
            ..Part::new(name.to_owned(), Color::default(), mesh, Vec::new())
        };
        let parts = [
            part("glass", quad(1.0, false)),
            part("frame", quad(0.0, true)),
        ];
        let (mesh, look) = shapegram_eval::asset_look::AssetLook::from_parts(&parts);
        Ok(shapegram_eval::Asset {
            mesh: std::sync::Arc::new(mesh),
            proportional: false,
            look,
            groups: shapegram_eval::tags::face_groups(&parts),
        })
    }
}

#[test]
fn material_components_and_names() {
    let text = "Lot --> s(4, 2, 1) i(\"pane.obj\")
            report(\"all\", size(geometry.materials()))
            report(\"first\", geometry.materials()[0])
            comp(m) { findFirst(geometry.materials, \"frame\") >= 0 : Frame | all : Glass }
        Frame --> report(\"frame\", geometry.area) report(\"frame.n\", size(geometry.materials))
        Glass --> report(\"glass\", geometry.area) report(\"glass.name\", geometry.materials()[0])";
    let options = shapegram_eval::DeriveOptions {
        assets: Some(std::sync::Arc::new(Panes)),
        ..Default::default()
    };
    let d = common::try_run(text, lot(10.0, 10.0), &options).unwrap();
    let get = |key: &str| {
        d.reports
            .iter()
            .filter(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(get("all"), [Value::Number(2.0)]);
    assert_eq!(get("first"), [Value::string("glass")]);
    // One shape per material, each a 4 × 2 pane.
    assert_eq!(get("frame"), [Value::Number(8.0)]);
    assert_eq!(get("frame.n"), [Value::Number(1.0)]);
    assert_eq!(get("glass"), [Value::Number(8.0)]);
    assert_eq!(get("glass.name"), [Value::string("glass")]);

    // A shape without an asset wears one material, its own.
    let own = "Lot --> set(material.name, \"brick\") extrude(2)
            report(\"name\", geometry.materials()[0])
            comp(m) { 0 : M }
        M --> report(\"faces\", geometry.nFaces)";
    let r = run(own, lot(10.0, 10.0)).reports;
    assert_eq!(
        r,
        [
            ("name".to_owned(), Value::string("brick")),
            ("faces".to_owned(), Value::Number(6.0))
        ]
    );
}

#[test]
fn group_components_and_names_through_a_split() {
    let text = "Lot --> s(4, 2, 1) i(\"pane.obj\")
            report(\"names\", geometry.groups()[0] + \",\" + geometry.groups()[1])
            split(x) { ~1 : P }*
        P --> comp(g) { 1 : Frame | all : Glass }
        Frame --> report(\"frame\", geometry.area) report(\"frame.name\", geometry.groups()[0])
        Glass --> report(\"glass\", geometry.area)";
    let options = shapegram_eval::DeriveOptions {
        assets: Some(std::sync::Arc::new(Panes)),
        ..Default::default()
    };
    let d = common::try_run(text, lot(10.0, 10.0), &options).unwrap();
    let get = |key: &str| {
        d.reports
            .iter()
            .filter(|(k, _)| k == key)
            .map(|(_, v)| v.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(get("names"), [Value::string("glass,frame")]);
    // Each 1 m slice holds a 1 × 2 piece of both groups; the cut faces of the slices are
    // not the asset's.
    assert_eq!(get("frame"), vec![Value::Number(2.0); 4]);
    assert_eq!(get("frame.name"), vec![Value::string("frame"); 4]);
    assert_eq!(get("glass"), vec![Value::Number(2.0); 4]);
}

#[test]
fn merged_faces_and_offsets_keep_their_tags() {
    let r = reports(
        "Lot --> extrude(4) comp(f) { side = Walls | top : Top | all : NIL }
         Walls --> comp(f) { isTagged(\"extrude.side\") : S | all : O }
         Top --> offset(-1) comp(f) { inside && isTagged(\"extrude.top\") : T \
                                    | border && isTagged(\"extrude.top\") : C | all : O }",
        10.0,
        20.0,
    );
    assert_close(&areas(&r, "s"), &[40.0, 40.0, 80.0, 80.0]);
    // The inset 8 × 18 and the ring around it, all still the top.
    assert_close(&areas(&r, "t"), &[144.0]);
    assert_close(&[areas(&r, "c").iter().sum()], &[56.0]);
    assert!(of(&r, "o").is_empty());
}
