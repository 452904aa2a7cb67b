//! Inserted assets wear their own materials and uvs, as CityEngine has them: an OBJ with an MTL
//! and a texture, written by the test, inserted and exported to GLB and OBJ; and a shape's
//! material attributes over the asset's.

use crate::common;

use std::path::Path;

use common::{TempDir, shapegram, stderr};

const BRICK: &[u8] = include_bytes!("../../../../examples/textures/brick.png");

/// A window: a textured glass pane (1 × 1 at z = 0) and a frame plate behind it (at z = −1),
/// each a material of the MTL; the glass's corners carry the whole texture.
const WINDOW_OBJ: &str = "mtllib window.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 -1
v 0 1 -1
v 1 1 -1
v 1 0 -1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
g glass
usemtl glass
f 1/1 2/2 3/3 4/4
g frame
usemtl frame
f 5/1 6/4 7/3 8/2
";

const WINDOW_MTL: &str = "newmtl glass
Kd 1 1 1
d 0.5
map_Kd window.png

newmtl frame
Kd 0.5 0.25 0.125
";

/// Writes the window asset and a grammar inserting it into `dir`; `ops` go before (`before`)
/// and after the insert.
fn project(dir: &TempDir, before: &str, after: &str) -> std::path::PathBuf {
    std::fs::write(dir.path("window.obj"), WINDOW_OBJ).unwrap();
    std::fs::write(dir.path("window.mtl"), WINDOW_MTL).unwrap();
    std::fs::write(dir.path("window.png"), BRICK).unwrap();
    std::fs::write(dir.path("other.png"), BRICK).unwrap();
    let grammar = dir.path("window.cga");
    std::fs::write(
        &grammar,
        format!("Lot --> s(4, 2, 1) {before} i(\"window.obj\") {after} Window.\n"),
    )
    .unwrap();
    grammar
}

fn derive(grammar: &Path, out: &Path) {
    let output = shapegram(&[
        "derive".as_ref(),
        grammar.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
}

/// What a GLB's materials are: name, base colour factor, colour map image name, and the
/// distinct TEXCOORD_0 values of the primitives using it (sorted), by material.
#[derive(Debug, PartialEq)]
struct Worn {
    name: Option<String>,
    factor: [f32; 4],
    image: Option<String>,
    uvs: Vec<[f32; 2]>,
}

fn read_worn(glb: &Path) -> Vec<Worn> {
    let gltf = gltf::Gltf::from_slice(&std::fs::read(glb).unwrap()).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let mut out: Vec<Worn> = gltf
        .materials()
        .map(|m| Worn {
            name: m.name().map(str::to_owned),
            factor: m.pbr_metallic_roughness().base_color_factor(),
            image: m
                .pbr_metallic_roughness()
                .base_color_texture()
                .and_then(|t| t.texture().source().name().map(str::to_owned)),
            uvs: Vec::new(),
        })
        .collect();
    for primitive in gltf.meshes().flat_map(|m| m.primitives()) {
        let Some(index) = primitive.material().index() else {
            continue;
        };
        let reader = primitive.reader(|_| Some(blob));
        if let Some(uvs) = reader.read_tex_coords(0) {
            out[index].uvs.extend(uvs.into_f32());
        }
    }
    for w in &mut out {
        w.uvs.sort_by(|a, b| a.partial_cmp(b).unwrap());
        w.uvs.dedup();
    }
    out
}

/// The bytes of each image the GLB embeds.
fn images(glb: &Path) -> Vec<Vec<u8>> {
    let gltf = gltf::Gltf::from_slice(&std::fs::read(glb).unwrap()).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    gltf.images()
        .map(|image| match image.source() {
            gltf::image::Source::View { view, .. } => {
                blob[view.offset()..view.offset() + view.length()].to_vec()
            }
            gltf::image::Source::Uri { .. } => panic!("an image outside the GLB"),
        })
        .collect()
}

/// glTF's linear-light factor of an sRGB channel.
fn linear(c: f32) -> f32 {
    ((c + 0.055) / 1.055).powf(2.4)
}

fn assert_factor(actual: [f32; 4], expected: [f32; 4]) {
    assert!(
        actual
            .iter()
            .zip(expected)
            .all(|(a, e)| (a - e).abs() < 1e-6),
        "{actual:?} != {expected:?}"
    );
}

const WHOLE: [[f32; 2]; 4] = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 1.0]];

#[test]
fn an_inserted_obj_keeps_its_materials_texture_and_uvs_in_glb_and_obj() {
    let dir = TempDir::new("asset-materials");
    let grammar = project(&dir, "", "");
    let glb = dir.path("window.glb");
    derive(&grammar, &glb);
    let worn = read_worn(&glb);
    assert_eq!(worn.len(), 2, "{worn:?}");
    assert_eq!(worn[0].name.as_deref(), Some("glass"));
    assert_factor(worn[0].factor, [1.0, 1.0, 1.0, 0.5]);
    assert_eq!(worn[0].image.as_deref(), Some("window.png"));
    // v turned down, as glTF has it: the pane's corners still span the whole texture.
    assert_eq!(worn[0].uvs, WHOLE);
    assert_eq!(worn[1].name.as_deref(), Some("frame"));
    assert_factor(
        worn[1].factor,
        [linear(0.5), linear(0.25), linear(0.125), 1.0],
    );
    assert_eq!(worn[1].image, None);
    assert_eq!(images(&glb), [BRICK], "the asset's image is embedded");

    let obj = dir.path("window.obj.out.obj");
    derive(&grammar, &obj);
    let text = std::fs::read_to_string(&obj).unwrap();
    let mut vts: Vec<&str> = text.lines().filter(|l| l.starts_with("vt ")).collect();
    vts.sort_unstable();
    assert_eq!(vts, ["vt 0 0", "vt 0 1", "vt 1 0", "vt 1 1"]);
    let mtl = std::fs::read_to_string(dir.path("window.obj.out.mtl")).unwrap();
    assert!(
        mtl.contains("newmtl glass\nKd 1 1 1\nd 0.5\nmap_Kd window.png\n"),
        "{mtl}"
    );
    assert!(
        mtl.contains("newmtl frame\nKd 0.5 0.25 0.125\nd 1\n"),
        "{mtl}"
    );
}

#[test]
fn a_colour_the_grammar_sets_wins_over_the_assets_and_its_opacity_stays() {
    for (before, after) in [("color(\"#ff0000\")", ""), ("", "color(1, 0, 0)")] {
        let dir = TempDir::new("asset-painted");
        let grammar = project(&dir, before, after);
        let glb = dir.path("window.glb");
        derive(&grammar, &glb);
        let worn = read_worn(&glb);
        assert_eq!(worn.len(), 2, "{before} {after}: {worn:?}");
        assert_eq!(worn[0].name.as_deref(), Some("glass"));
        // The 3-argument colour sets opacity 1, which leaves the asset's.
        assert_factor(worn[0].factor, [1.0, 0.0, 0.0, 0.5]);
        assert_eq!(worn[0].image.as_deref(), Some("window.png"));
        assert_factor(worn[1].factor, [1.0, 0.0, 0.0, 1.0]);
    }
}

#[test]
fn a_texture_and_a_name_the_grammar_sets_win_and_use_the_assets_uvs() {
    let dir = TempDir::new("asset-retextured");
    let grammar = project(
        &dir,
        "",
        "texture(\"other.png\") set(material.name, \"mine\")",
    );
    let glb = dir.path("window.glb");
    derive(&grammar, &glb);
    let worn = read_worn(&glb);
    assert_eq!(worn.len(), 2, "{worn:?}");
    for w in &worn {
        assert_eq!(w.image.as_deref(), Some("other.png"), "{w:?}");
        assert_eq!(w.uvs, WHOLE);
        assert!(w.name.as_deref().unwrap().starts_with("mine"), "{w:?}");
    }
    assert_eq!(worn[0].factor[3], 0.5);
}

#[test]
fn project_uv_replaces_the_assets_uvs() {
    let dir = TempDir::new("asset-projected");
    let grammar = project(&dir, "", "setupProjection(0, scope.xy, 2, 2) projectUV(0)");
    let glb = dir.path("window.glb");
    derive(&grammar, &glb);
    let worn = read_worn(&glb);
    // The pane is 4 × 2 after the insert: two tiles along u, one along v (turned down).
    assert_eq!(worn[0].image.as_deref(), Some("window.png"));
    assert_eq!(
        worn[0].uvs,
        [[0.0, 0.0], [0.0, 1.0], [2.0, 0.0], [2.0, 1.0]]
    );
}

#[test]
fn uv_edits_change_the_assets_own_uvs() {
    for (edits, us) in [
        // Half the extent per tile, then a quarter tile on: u from 0.25 to 2.25.
        ("tileUV(0, '0.5, 0) translateUV(0, 0.25, 0)", [0.25, 2.25]),
        // The pane is 4 m wide: a 2 m tile fits twice.
        ("tileUV(0, 2, 0)", [0.0, 2.0]),
        ("scaleUV(0, 3, 1)", [0.0, 3.0]),
    ] {
        let dir = TempDir::new("asset-uv-edits");
        let grammar = project(&dir, "", edits);
        let glb = dir.path("window.glb");
        derive(&grammar, &glb);
        let worn = read_worn(&glb);
        let expected = [[us[0], 0.0], [us[0], 1.0], [us[1], 0.0], [us[1], 1.0]];
        assert_eq!(worn[0].uvs, expected, "{edits}");
        // The frame has no texture: nothing is drawn through its uvs.
        assert!(worn[1].uvs.is_empty(), "{edits}");
    }
}

#[test]
fn an_inserted_glb_keeps_its_materials_texture_and_uvs() {
    let dir = TempDir::new("asset-glb");
    // The window as a GLB asset, retextured so that both its parts carry uvs.
    let grammar = project(&dir, "", "texture(\"other.png\")");
    derive(&grammar, &dir.path("asset.glb"));
    let inserting = dir.path("glb.cga");
    std::fs::write(&inserting, "Lot --> s(4, 2, 1) i(\"asset.glb\") Window.\n").unwrap();
    let glb = dir.path("window.glb");
    derive(&inserting, &glb);
    let worn = read_worn(&glb);
    assert_eq!(worn.len(), 2, "{worn:?}");
    assert_eq!(worn[0].name.as_deref(), Some("glass"));
    assert_factor(worn[0].factor, [1.0, 1.0, 1.0, 0.5]);
    assert_eq!(worn[1].name.as_deref(), Some("frame"));
    assert_factor(
        worn[1].factor,
        [linear(0.5), linear(0.25), linear(0.125), 1.0],
    );
    for w in &worn {
        assert_eq!(w.image.as_deref(), Some("other.png"), "{w:?}");
        assert_eq!(w.uvs, WHOLE);
    }
    assert_eq!(images(&glb), [BRICK]);

    // As in CityEngine, an asset some of whose faces lack uvs loses them all: the untextured
    // frame of the plain window carries none, so the glass's texture has nothing to go by.
    let grammar = project(&dir, "", "");
    derive(&grammar, &dir.path("asset.glb"));
    derive(&inserting, &glb);
    let plain = read_worn(&glb);
    assert_eq!(plain.len(), 2, "{plain:?}");
    assert_factor(plain[0].factor, [1.0, 1.0, 1.0, 0.5]);
    assert!(plain.iter().all(|w| w.image.is_none() && w.uvs.is_empty()));
    assert!(images(&glb).is_empty());
}

#[test]
fn pieces_split_from_an_asset_keep_its_materials_and_uvs() {
    let dir = TempDir::new("asset-split");
    let grammar = project(&dir, "", "");
    std::fs::write(
        &grammar,
        "Lot --> s(4, 2, 1) i(\"window.obj\") t(1, 0, 0) split(x) { ~1 : Piece. }*\n",
    )
    .unwrap();
    let glb = dir.path("window.glb");
    derive(&grammar, &glb);
    let worn = read_worn(&glb);
    assert_eq!(worn.len(), 2, "{worn:?}");
    assert_eq!(worn[0].name.as_deref(), Some("glass"));
    assert_eq!(worn[0].image.as_deref(), Some("window.png"));
    assert_factor(worn[0].factor, [1.0, 1.0, 1.0, 0.5]);
    // Four 1 m pieces of the 4 m pane: u steps by a quarter, v still spans the texture.
    let expected: Vec<[f32; 2]> = [0.0, 0.25, 0.5, 0.75, 1.0]
        .iter()
        .flat_map(|&u| [[u, 0.0], [u, 1.0]])
        .collect();
    assert_eq!(worn[0].uvs, expected);
    assert_eq!(worn[1].name.as_deref(), Some("frame"));
}
