//! Texturing: projections frozen in world space, uv sets made from them, edited, and carried
//! along when the geometry moves; texture layers.

use crate::common;

use common::{compile_errors, lot, run, try_run};
use shapegram_eval::{Derivation, DeriveOptions, Leaf};
use shapegram_geom::{AlphaMode, DVec2, Finish, MapTransform};

/// A 20 m wide, 6 m high facade, its rule body given.
fn facade(body: &str) -> Derivation {
    run(
        &format!("Lot --> extrude(6) comp(f) {{ front : Facade }}\nFacade --> {body}\n"),
        lot(20.0, 30.0),
    )
}

/// The smallest and largest uv of set `set` over a leaf's vertices.
fn range(leaf: &Leaf, set: usize) -> (DVec2, DVec2) {
    let mesh = leaf.world_mesh().expect("the leaf has geometry");
    let uvs = leaf.uvs(set, &mesh).expect("the leaf has the uv set");
    let low = uvs.iter().fold(DVec2::INFINITY, |a, b| a.min(*b));
    let high = uvs.iter().fold(DVec2::NEG_INFINITY, |a, b| a.max(*b));
    (low, high)
}

fn assert_range(leaf: &Leaf, set: usize, low: [f64; 2], high: [f64; 2]) {
    let (l, h) = range(leaf, set);
    let close = |a: DVec2, b: [f64; 2]| (a - DVec2::from(b)).length() < 1e-9;
    assert!(
        close(l, low) && close(h, high),
        "uv set {set}: {l} … {h}, expected {low:?} … {high:?}"
    );
}

#[test]
fn project_uv_measures_the_facade_in_texture_tiles() {
    let d = facade("setupProjection(0, scope.xy, 5, 3) projectUV(0) Wall");
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [4.0, 2.0]);
    // Without projectUV there are no uvs, whatever was set up.
    let d = facade("setupProjection(0, scope.xy, 5, 3) Wall");
    assert!(
        d.leaves[0]
            .uvs(0, &d.leaves[0].world_mesh().unwrap())
            .is_none()
    );
}

#[test]
fn a_projection_set_up_on_the_facade_runs_on_across_its_tiles() {
    let d =
        facade("setupProjection(0, scope.xy, 5, 3) split(x) { 4 : Tile }*\nTile --> projectUV(0)");
    let starts: Vec<f64> = d.leaves.iter().map(|l| range(l, 0).0.x).collect();
    let expected = [0.0, 0.8, 1.6, 2.4, 3.2];
    assert_eq!(starts.len(), 5);
    for (s, e) in starts.iter().zip(expected) {
        assert!((s - e).abs() < 1e-9, "{starts:?}");
    }
    // Set up in each tile instead, every tile starts again at 0.
    let d =
        facade("split(x) { 4 : Tile }*\nTile --> setupProjection(0, scope.xy, 5, 3) projectUV(0)");
    assert!(d.leaves.iter().all(|l| range(l, 0).0.x.abs() < 1e-9));
}

#[test]
fn relative_sizes_offsets_and_the_uw_factor() {
    // '0.5 of 20 m is a 10 m tile; the offset −'0.25 puts the texture's origin 5 m before
    // the facade's, so u runs from 0.5.
    let d = facade("setupProjection(0, scope.xy, '0.5, '1, '-0.25, 0) projectUV(0) Wall");
    assert_range(&d.leaves[0], 0, [0.5, 0.0], [2.5, 1.0]);
    // ~3: whole tiles of about 3 m, 7 of them over 20 m.
    let d = facade("setupProjection(0, scope.xy, ~3, 6) projectUV(0) Wall");
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [7.0, 1.0]);
    // The deprecated five-argument form's uwFactor: u also advances along the facade's
    // depth, 1/5 per metre, so the 2 m deep block reaches 22/5.
    let d = facade("setupProjection(0, scope.xy, 5, 5, 1) extrude(2) projectUV(0) Block");
    let (low, high) = range(&d.leaves[0], 0);
    assert!(
        (low.x - 0.0).abs() < 1e-9 && (high.x - 4.4).abs() < 1e-9,
        "{low} {high}"
    );
}

#[test]
fn world_axes_project_from_the_world_origin() {
    let d = run(
        "Lot --> setupProjection(0, world.xz, 10, 10) projectUV(0) Ground",
        lot(20.0, 30.0),
    );
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [2.0, 3.0]);
}

#[test]
fn uvs_stay_on_their_vertices_when_the_geometry_moves_stretches_or_flips() {
    let still = facade("setupProjection(0, scope.xy, 5, 3) projectUV(0) Wall");
    for moves in [
        "t(3, 1, -2)",
        "r(0, 30, 10)",
        "r(scopeCenter, 45, 0, 0)",
        "s('2, '0.5, 0)",
        "s(-20, 6, 0)",
        "mirror(true, false, false)",
        "center(x)",
    ] {
        let moved = facade(&format!(
            "setupProjection(0, scope.xy, 5, 3) projectUV(0) {moves} Wall"
        ));
        let (a, b) = (&still.leaves[0], &moved.leaves[0]);
        let (mesh_a, mesh_b) = (a.world_mesh().unwrap(), b.world_mesh().unwrap());
        let mut uv_a = a.uvs(0, &mesh_a).unwrap();
        let mut uv_b = b.uvs(0, &mesh_b).unwrap();
        let key = |p: &DVec2| ((p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64);
        uv_a.sort_by_key(key);
        uv_b.sort_by_key(key);
        assert_eq!(uv_a.len(), uv_b.len(), "{moves}");
        for (p, q) in uv_a.iter().zip(&uv_b) {
            assert!((*p - *q).length() < 1e-9, "{moves}: {p} vs {q}");
        }
    }
}

#[test]
fn tile_scale_translate_and_rotate_edit_the_uvs() {
    let project = "setupProjection(0, scope.xy, 5, 3) projectUV(0)";
    let d = facade(&format!("{project} tileUV(0, '1, '1) Wall"));
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [1.0, 1.0]);
    // 2 m tiles along u (20 m: 10 of them); 0 leaves v alone.
    let d = facade(&format!("{project} tileUV(0, 2, 0) Wall"));
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [10.0, 2.0]);
    let d = facade(&format!("{project} tileUV(0, ~3, 0) Wall"));
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [7.0, 2.0]);
    let d = facade(&format!("{project} scaleUV(0, 1, -1) Wall"));
    assert_range(&d.leaves[0], 0, [0.0, -2.0], [4.0, 0.0]);
    let d = facade(&format!(
        "{project} translateUV(0, 0.5, 0) offsetUV(0, 0, 1) Wall"
    ));
    assert_range(&d.leaves[0], 0, [0.5, 1.0], [4.5, 3.0]);
    let d = facade(&format!("{project} rotateUV(0, 90) Wall"));
    assert_range(&d.leaves[0], 0, [-2.0, 0.0], [0.0, 4.0]);
}

#[test]
fn sets_are_copied_and_deleted_and_inserts_bring_their_own() {
    let project = "setupProjection(0, scope.xy, 5, 3) projectUV(0)";
    let d = facade(&format!("{project} copyUV(0, 2) deleteUV(0) Wall"));
    let leaf = &d.leaves[0];
    let mesh = leaf.world_mesh().unwrap();
    assert!(leaf.uvs(0, &mesh).is_none());
    assert_range(leaf, 2, [0.0, 0.0], [4.0, 2.0]);
    let d = facade(&format!("{project} primitiveCube() Box"));
    assert!(
        d.leaves[0]
            .uvs(0, &d.leaves[0].world_mesh().unwrap())
            .is_none()
    ); // A quad brings uv set 0 across it, and only that, whatever the projection gave before.
    let d = facade(&format!(
        "{project} copyUV(0, 2) t(0, 0, 1) primitiveQuad() Sign"
    ));
    assert_range(&d.leaves[0], 0, [0.0, 0.0], [1.0, 1.0]);
    assert_eq!(d.leaves[0].texturing().unwrap().uvs[2], None);
}

#[test]
fn texture_layers_are_set_by_texture_and_material_attributes() {
    let d = facade(
        "texture(\"brick.jpg\") set(material.dirtmap, \"dirt.png\") set(material.map5, \"n.png\") Wall",
    );
    let maps = &d.leaves[0].texturing().unwrap().maps;
    let path = |i: usize| maps[i].as_ref().map(|t| &*t.path);
    assert_eq!(path(0), Some("brick.jpg"));
    assert_eq!(path(2), Some("dirt.png"));
    assert_eq!(path(5), Some("n.png"));
    // Without an asset folder, no image is read: the texture is known by its path alone.
    assert!(maps[0].as_ref().unwrap().image.is_none());
    let d = facade("texture(\"brick.jpg\") texture(\"\") Wall");
    assert_eq!(d.leaves[0].texturing().unwrap().maps[0], None);
    // Shapes that never texture carry nothing.
    let d = facade("Wall");
    assert!(d.leaves[0].texturing().is_none());
}

#[test]
fn bad_uv_sets_sizes_and_axes_are_errors_at_their_place() {
    let grammar = |body: &str| {
        format!("Lot --> extrude(6) comp(f) {{ front : Facade }}\nFacade --> {body}\n")
    };
    let error = try_run(
        &grammar("setupProjection(12, scope.xy, 5, 3) Wall"),
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        error.message,
        "uv set 12: expected a whole number from 0 to 9"
    );
    let error = try_run(
        &grammar("setupProjection(0, scope.xy, 0, 3) Wall"),
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(
        error.message,
        "a texture width of 0: expected a length other than 0"
    );
    let errors = compile_errors(&grammar("setupProjection(0, scope.xx, 5, 3) Wall"));
    assert!(
        errors[0].contains("expected projection axes such as `scope.xy` or `world.xz`")
            && errors[0].contains("test.cga:2:"),
        "{errors:?}"
    );
}

#[test]
fn material_attributes_are_kept_clamped_and_reach_the_model() {
    let d = facade(
        "set(material.metallic, 0.8) set(material.roughness, 1.5) set(material.specular.r, 0.5) \
         set(material.shininess, 40) set(material.emissive.g, 0.25) set(material.ambient.b, 1) \
         set(material.reflectivity, 0.3) set(material.bumpValue, 2) \
         set(material.opacitymap.mode, \"mask\") set(material.opacitymap.cutoff, 0.2) \
         set(material.doubleSided, false) set(material.shader, \"CityEnginePBRShader\") \
         split(x) { 10 : Wall | 10 : set(material.roughness, 0.5) Wall }",
    );
    let finish = |i: usize| d.leaves[i].texturing().unwrap().finish;
    assert_eq!(
        finish(0),
        Finish {
            metallic: Some(0.8),
            roughness: Some(1.0),
            emissive: Some([0.0, 0.25, 0.0]),
            specular: Some([0.5, 0.0, 0.0]),
            ambient: Some([0.0, 0.0, 1.0]),
            shininess: Some(40.0),
            reflectivity: Some(0.3),
            bump_value: Some(2.0),
            alpha_mode: Some(AlphaMode::Mask),
            alpha_cutoff: Some(0.2),
            double_sided: Some(false),
        }
    );
    assert_eq!(finish(1).roughness, Some(0.5));
    // One part per material: the two walls differ in roughness alone.
    let model = d.to_model();
    let roughness: Vec<Option<f32>> = model
        .parts
        .iter()
        .map(|p| p.surface.as_ref().unwrap().finish.roughness)
        .collect();
    assert_eq!(roughness, [Some(1.0), Some(0.5)]);
    // Shapes that set none carry no surface; `color.rgb` and `color.a` are the colour's.
    let d = facade("set(material.color.rgb, \"#ff0000\") set(material.color.a, 0.5) Wall");
    let part = &d.to_model().parts[0];
    assert!(part.surface.is_none());
    assert_eq!(part.color.to_array(), [1.0, 0.0, 0.0, 0.5]);
}

#[test]
fn bad_material_attribute_values_are_errors_at_their_place() {
    let error = |body: &str| {
        try_run(
            &format!("Lot --> extrude(6) comp(f) {{ front : Facade }}\nFacade --> {body}\n"),
            lot(20.0, 30.0),
            &DeriveOptions::default(),
        )
        .unwrap_err()
    };
    let e = error("set(material.opacitymap.mode, \"cutout\") Wall");
    assert_eq!(e.message, "unknown opacity map mode `cutout`");
    // At the value: `"cutout"` starts 41 bytes into the second line, which starts at byte 46.
    assert_eq!(e.span.map(|s| s.start), Some(87));
    let e = error("set(material.metallic, \"high\") Wall");
    assert_eq!(e.message, "expected a number, found a string");
    let e = error("set(material.doubleSided, 1) Wall");
    assert_eq!(e.message, "expected true or false, found a number");
}

/// Every image is the brick PNG.
struct Images;

impl shapegram_eval::AssetLoader for Images {
    fn load(&self, path: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        Err(format!("no mesh {path}"))
    }

    fn image(&self, _: &str) -> Result<Option<std::sync::Arc<[u8]>>, String> {
        Ok(Some(std::sync::Arc::from(
            &include_bytes!("../../../../examples/textures/brick.png")[..],
        )))
    }
}

#[test]
fn every_layer_reads_its_image_and_parts_carry_the_layers_with_uvs() {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(Images)),
        ..DeriveOptions::default()
    };
    let grammar = |body: &str| {
        format!("Lot --> extrude(6) comp(f) {{ front : Facade }}\nFacade --> {body}\n")
    };
    let layers = "set(material.normalmap, \"n.png\") set(material.roughnessmap, \"r.png\")";
    let with_uvs = format!("setupProjection(0, scope.xy, 5, 3) projectUV(0) {layers} Wall");
    let d = try_run(&grammar(&with_uvs), lot(20.0, 30.0), &options).unwrap();
    let part = &d.to_model().parts[0];
    let maps = &part.surface.as_ref().unwrap().maps;
    assert_eq!(maps.normal.as_ref().map(|t| &*t.path), Some("n.png"));
    assert!(maps.normal.as_ref().unwrap().image.is_some());
    assert_eq!(maps.roughness.as_ref().map(|t| &*t.path), Some("r.png"));
    assert!(part.texture.is_none());
    assert_eq!(part.uvs.len(), part.mesh.vertex_count());
    // Without uv set 0 there is nothing to place the layers with.
    let d = try_run(
        &grammar(&format!("{layers} Wall")),
        lot(20.0, 30.0),
        &options,
    )
    .unwrap();
    let part = &d.to_model().parts[0];
    assert!(part.surface.is_none() && part.uvs.is_empty());
}

#[test]
fn normalize_uv_maps_the_uvs_onto_the_unit_square() {
    let project = "setupProjection(0, scope.xy, 5, 3) projectUV(0) translateUV(0, 3, -1)";
    let normalized = |args: &str| facade(&format!("{project} normalizeUV(0, {args}) Wall"));
    // Before: u from 3 to 7 and v from -1 to 1 over the 20 × 6 facade.
    assert_range(
        &normalized("uv, collectiveAllFaces").leaves[0],
        0,
        [0.0, 0.0],
        [1.0, 1.0],
    );
    // One scale for both: the larger extent (4) becomes 1.
    assert_range(
        &normalized("uvUniform, collectiveAllFaces").leaves[0],
        0,
        [0.0, 0.0],
        [1.0, 0.5],
    );
    assert_range(
        &normalized("u, separatePerFace").leaves[0],
        0,
        [0.0, -1.0],
        [1.0, 1.0],
    );
    assert_range(
        &normalized("v, collectiveAllFaces").leaves[0],
        0,
        [3.0, 0.0],
        [7.0, 1.0],
    );
    let errors = compile_errors("Lot --> normalizeUV(0, w, collectiveAllFaces)");
    assert!(
        errors[0].contains("expected `uv`, `uvUniform`, `u` or `v`"),
        "{errors:?}"
    );
    let warnings = compile_errors("Lot --> normalizeUV(0, uv, separatePerFace)");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("normalizes the faces of a shape together"),
        "{warnings:?}"
    );
}

#[test]
fn map_transforms_of_every_layer_reach_the_parts_that_draw_them() {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(Images)),
        ..DeriveOptions::default()
    };
    let grammar = |body: &str| {
        format!("Lot --> extrude(6) comp(f) {{ front : Facade }}\nFacade --> {body}\n")
    };
    let body = "setupProjection(0, scope.xy, 5, 3) projectUV(0) texture(\"a.png\") \
                set(material.colormap.su, 2) set(material.colormap.sv, 0.5) \
                set(material.colormap.tu, 0.25) set(material.colormap.tv, -1) \
                set(material.colormap.rw, 30) set(material.map5.rw, 90) \
                set(material.metallicmap.tu, 3) \
                split(x) { 10 : Wall. | 10 : set(material.colormap.su, 1) Wall. }";
    let d = try_run(&grammar(body), lot(20.0, 30.0), &options).unwrap();
    assert_eq!(compile_errors(&grammar(body)), Vec::<String>::new());
    let model = d.to_model();
    assert_eq!(model.parts.len(), 2, "the two walls differ in su alone");
    let transforms = model.parts[0].surface.as_ref().unwrap().transforms;
    assert_eq!(
        transforms[0],
        MapTransform {
            su: 2.0,
            sv: 0.5,
            tu: 0.25,
            tv: -1.0,
            rw: 30.0,
        }
    );
    assert_eq!(transforms[5].rw, 90.0);
    assert_eq!(transforms[9].tu, 3.0);
    assert!(transforms[1].is_identity());
    assert_eq!(
        model.parts[1].surface.as_ref().unwrap().transforms[0].su,
        1.0
    );
    // Without uvs nothing is drawn, and nothing is transformed.
    let d = try_run(
        &grammar("texture(\"a.png\") set(material.colormap.su, 2) Wall"),
        lot(20.0, 30.0),
        &options,
    )
    .unwrap();
    assert!(d.to_model().parts[0].surface.is_none());
    let e = try_run(
        &grammar("set(material.colormap.rw, \"left\") Wall"),
        lot(20.0, 30.0),
        &options,
    )
    .unwrap_err();
    assert_eq!(e.message, "expected a number, found a string");
    // At the value: `"left"` starts 37 bytes into the second line, which starts at byte 46.
    assert_eq!(e.span.map(|s| s.start), Some(83));
}

#[test]
fn uv_queries_read_the_uv_sets_over_the_geometry() {
    let queries = "print(geometry.hasUVs()) print(geometry.hasUVs(2)) \
                   print(geometry.uMin()) print(geometry.uMax(0)) \
                   print(geometry.vMin()) print(geometry.vMax()) \
                   print(geometry.du(0, uvSpace)) print(geometry.dv(0, unitSpace))";
    // u from 3 to 7 and v from -1 to 1 over the 20 × 6 facade, in tiles of 5 × 3 m.
    let d = facade(&format!(
        "setupProjection(0, scope.xy, 5, 3) projectUV(0) translateUV(0, 3, -1) {queries} Wall"
    ));
    assert_eq!(d.prints, ["true", "false", "3", "7", "-1", "1", "4", "6"]);
    // Without uvs, no set and zero bounds.
    let d = facade(&format!("{queries} Wall"));
    assert_eq!(d.prints, ["false", "false", "0", "0", "0", "0", "0", "0"]);
    let error = try_run(
        "Lot --> print(geometry.du(0, metres))",
        lot(20.0, 30.0),
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(error.message, "expected `uvSpace` or `unitSpace`");
    let errors = compile_errors("Lot --> print(geometry.du(0))");
    assert!(
        errors[0].contains("the signature is `geometry.du(uvSet, uvSpace | unitSpace)`"),
        "{errors:?}"
    );
}

/// `Images`, and one asset: `w.obj`, a 1 × 1 quad in the xy-plane whose uvs run from (0, 0)
/// to (2, 3).
struct Window;

impl shapegram_eval::AssetLoader for Window {
    fn load(&self, path: &str) -> Result<std::sync::Arc<shapegram_geom::Mesh>, String> {
        Err(format!("no mesh {path}"))
    }

    fn asset(&self, path: &str, variant: u32) -> Result<shapegram_eval::Asset, String> {
        if path != "w.obj" {
            return Images.asset(path, variant);
        }
        let quad = shapegram_geom::Mesh::from_faces(
            vec![
                shapegram_geom::DVec3::new(0.0, 0.0, 0.0),
                shapegram_geom::DVec3::new(1.0, 0.0, 0.0),
                shapegram_geom::DVec3::new(1.0, 1.0, 0.0),
                shapegram_geom::DVec3::new(0.0, 1.0, 0.0),
            ],
            [[0u32, 1, 2, 3]],
        );
        let part = shapegram_geom::Part {
            uvs: vec![
                DVec2::ZERO,
                DVec2::new(2.0, 0.0),
                DVec2::new(2.0, 3.0),
                DVec2::new(0.0, 3.0),
            ],
            ..shapegram_geom::Part::new(String::new(), Default::default(), quad, Vec::new())
        };
        let (mesh, look) = shapegram_eval::asset_look::AssetLook::from_parts(&[part]);
        Ok(shapegram_eval::Asset {
            mesh: std::sync::Arc::new(mesh),
            proportional: false,
            look,
            groups: None,
        })
    }

    fn image(&self, path: &str) -> Result<Option<std::sync::Arc<[u8]>>, String> {
        Images.image(path)
    }
}

fn with_window(text: &str) -> Derivation {
    let options = DeriveOptions {
        assets: Some(std::sync::Arc::new(Window)),
        ..DeriveOptions::default()
    };
    try_run(text, lot(20.0, 30.0), &options).unwrap()
}

const UV_QUERIES: &str = "print(geometry.hasUVs()) print(geometry.uMin()) print(geometry.uMax()) \
                          print(geometry.vMin()) print(geometry.vMax()) \
                          print(geometry.du(0, uvSpace)) print(geometry.du(0, unitSpace)) \
                          print(geometry.dv(0, unitSpace))";

#[test]
fn uv_queries_read_the_uvs_an_inserted_asset_brings_and_its_cut_pieces_keep() {
    // The window stretched to 4 × 2 m: u from 0 to 2 over 4 m, v from 0 to 3 over 2 m.
    let d = with_window(&format!(
        "Lot --> s(4, 2, 0) i(\"w.obj\") {UV_QUERIES} \
         split(x) {{ 1 : Left | ~1 : NIL }}\nLeft --> {UV_QUERIES} scaleUV(0, 3, 1) {UV_QUERIES} L."
    ));
    assert_eq!(
        d.prints,
        [
            "true", "0", "2", "0", "3", "2", "4", "2", // the whole window
            "true", "0", "0.5", "0", "3", "0.5", "1", "2", // its left metre
            "true", "0", "1.5", "0", "3", "1.5", "1", "2", // u scaled by 3 there
        ]
    );
    // `projectUV(0)` replaces them; a shape without the asset has none.
    let d = with_window(&format!(
        "Lot --> s(4, 2, 0) i(\"w.obj\") setupProjection(0, scope.xy, 8, 1) projectUV(0) \
         {UV_QUERIES} X.\n"
    ));
    assert_eq!(d.prints, ["true", "0", "0.5", "0", "2", "0.5", "4", "2"]);
}

/// The uvs of each face of a leaf's drawn part, in the order of its corners.
fn face_uvs(d: &Derivation) -> Vec<Vec<[f64; 2]>> {
    let model = d.to_model();
    let part = &model.parts[0];
    let round = |x: f64| (x * 1e9).round() / 1e9 + 0.0;
    part.mesh
        .faces()
        .map(|face| {
            face.iter()
                .map(|&v| {
                    let uv = part.uvs[v as usize];
                    [round(uv.x), round(uv.y)]
                })
                .collect()
        })
        .collect()
}

#[test]
fn primitive_cubes_cover_every_face_with_the_whole_texture() {
    let whole = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    for cube in [
        "primitiveCube()",
        "primitiveCube(4, 3, 2)",
        "i(\"builtin:cube\")",
    ] {
        let d = with_window(&format!(
            "Lot --> s(5, 2, 3) {cube} texture(\"a.png\") {UV_QUERIES} Cube.\n"
        ));
        assert_eq!(face_uvs(&d), vec![whole.clone(); 6], "{cube}");
        // Over all six faces u and v run from 0 to 1; on the largest face (5 × 3 or 4 × 3
        // at the bottom), one unit of u spans its 3 m edge along z.
        assert_eq!(&d.prints[..6], ["true", "0", "1", "0", "1", "1"], "{cube}");
        // A face split off the cube keeps its own uvs, whatever its neighbours have.
        let d = with_window(&format!(
            "Lot --> s(5, 2, 3) {cube} comp(f) {{ front : Front | all : NIL }}\n\
             Front --> texture(\"a.png\") {UV_QUERIES} F.\n"
        ));
        assert_eq!(face_uvs(&d), vec![whole.clone()], "{cube}");
        let (width, height) = if cube.contains('4') {
            ("4", "3")
        } else {
            ("5", "2")
        };
        assert_eq!(
            d.prints,
            ["true", "0", "1", "0", "1", "1", width, height],
            "{cube}"
        );
    }
    // `builtin:cube:notex` brings none.
    let d = with_window(&format!(
        "Lot --> s(5, 2, 3) i(\"builtin:cube:notex\") texture(\"a.png\") {UV_QUERIES} Cube.\n"
    ));
    assert_eq!(d.prints, ["false", "0", "0", "0", "0", "0", "0", "0"]);
    assert!(d.to_model().parts[0].uvs.is_empty());
    // Untextured, a cube is drawn as before: eight corners shared by its faces.
    let d = with_window("Lot --> s(5, 2, 3) primitiveCube() Cube.\n");
    assert_eq!(d.to_model().parts[0].mesh.vertex_count(), 8);
}
