//! Shared fixtures: a coloured sample model, expected counts, and GLB (un)framing by hand.
// Each test binary uses a different subset of these helpers.
#![allow(dead_code)]

use shapegram_geom::primitives::{cone, cuboid, cylinder, pyramid, quad, sphere};
use shapegram_geom::{Aabb, Color, DAffine3, DVec3, Mesh, Model, Part};

pub const RED: Color = Color::rgb(1.0, 0.0, 0.0);
pub const BLUE: Color = Color::rgb(0.0, 0.0, 1.0);
pub const GREEN: Color = Color::rgb(0.0, 0.5, 0.0);
pub const GLASS: Color = Color {
    r: 0.2,
    g: 0.4,
    b: 0.6,
    a: 0.5,
};
pub const GREY: Color = Color::rgb(0.5, 0.5, 0.5);

fn part(name: &str, color: Color, mesh: Mesh, at: DVec3) -> Part {
    Part {
        texture: None,
        uvs: Vec::new(),
        bone: None,
        metadata: None,
        name: name.to_owned(),
        color,
        mesh: mesh.transformed(&DAffine3::from_translation(at)),
        normals: Vec::new(),
        material: None,
        surface: None,
        instance: None,
    }
}

/// Six parts, five distinct colours (wall and column share red); the lot is an open quad, the
/// rest are disjoint closed solids. Coordinates are not all representable in f32 (0.1 steps).
pub fn sample_model() -> Model {
    Model {
        skeletons: Vec::new(),
        parts: vec![
            part(
                "front wall",
                RED,
                cuboid(DVec3::new(2.0, 3.0, 0.5)),
                DVec3::new(0.1, 0.0, 0.0),
            ),
            part(
                "roof",
                BLUE,
                pyramid(DVec3::new(2.0, 1.0, 0.5)),
                DVec3::new(0.1, 3.25, 0.0),
            ),
            part(
                "column",
                RED,
                cylinder(DVec3::new(0.4, 3.0, 0.4), 12),
                DVec3::new(3.0, 0.0, 0.3),
            ),
            part(
                "dome",
                GREEN,
                sphere(DVec3::splat(1.2), 16, 8),
                DVec3::new(-2.0, 0.0, 0.0),
            ),
            part(
                "spire",
                GLASS,
                cone(DVec3::new(1.0, 2.0, 1.0), 10),
                DVec3::new(0.0, 0.0, 2.0),
            ),
            part("lot", GREY, quad(6.0, 4.0), DVec3::new(-3.0, -0.01, -2.0)),
        ],
        lines: Vec::new(),
    }
}

/// The closed parts of [`sample_model`] only.
pub fn closed_model() -> Model {
    let mut model = sample_model();
    model.parts.retain(|p| p.name != "lot");
    model
}

/// What a reader should give back for one or more original meshes merged.
#[derive(Debug)]
pub struct Expected {
    pub faces: usize,
    pub triangles: usize,
    pub vertices: usize,
    /// Sum of face sizes: the vertex count of a flat-shaded file that shares vertices per face.
    pub corners: usize,
    /// Bounds of the positions rounded to f32.
    pub bounds_f32: Aabb,
    pub bounds: Aabb,
    pub volume: f64,
}

pub fn expected(meshes: &[&Mesh]) -> Expected {
    let mut all = Mesh::new();
    for m in meshes {
        all.append(m);
    }
    Expected {
        faces: all.face_count(),
        triangles: all.triangulate().len(),
        vertices: all.vertex_count(),
        corners: all.faces().map(<[u32]>::len).sum(),
        bounds_f32: Aabb::from_points(all.positions().iter().map(|p| p.as_vec3().as_dvec3()))
            .expect("fixture has vertices"),
        bounds: all.bounds().expect("fixture has vertices"),
        volume: all.signed_volume(),
    }
}

pub fn assert_close(actual: f64, expected: f64, relative: f64, what: &str) {
    let error = (actual - expected).abs() / expected.abs().max(1e-300);
    assert!(
        error <= relative,
        "{what}: {actual} vs {expected} (relative error {error:e} > {relative:e})"
    );
}

/// Splits GLB bytes into the parsed JSON chunk and the BIN chunk, checking the framing rules.
pub fn split_glb(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(word(4), 2, "GLB version");
    assert_eq!(word(8), bytes.len(), "header length");
    let json_len = word(12);
    assert_eq!(json_len % 4, 0, "JSON chunk is padded to 4 bytes");
    assert_eq!(&bytes[16..20], b"JSON");
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let rest = 20 + json_len;
    if rest == bytes.len() {
        return (json, Vec::new());
    }
    let bin_len = word(rest);
    assert_eq!(bin_len % 4, 0, "BIN chunk is padded to 4 bytes");
    assert_eq!(&bytes[rest + 4..rest + 8], b"BIN\0");
    assert_eq!(rest + 8 + bin_len, bytes.len());
    (json, bytes[rest + 8..].to_vec())
}

/// Frames JSON and BIN as GLB, for hand-made or patched files.
pub fn frame_glb(json: &serde_json::Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    text.resize(text.len().next_multiple_of(4), b' ');
    let mut bin = bin.to_vec();
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// A deterministic byte generator for garbage inputs (xorshift64).
pub fn garbage(len: usize, seed: u64) -> Vec<u8> {
    let mut state = seed | 1;
    (0..len)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 24) as u8
        })
        .collect()
}

/// A scratch directory unique to this process and test.
pub fn scratch_dir(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("shapegram-export-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
