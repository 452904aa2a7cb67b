//! Every grammar in `examples/` compiles without errors and derives the model it promises.

mod common;

use std::path::PathBuf;

use common::example;
use shapegram_eval::{DeriveOptions, derive};

#[test]
fn office() {
    let program = example("office.cga");
    let d = derive(
        &program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    assert_eq!(d.stats.leaves, 1047);
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // Four facades of 8 floors; the 16 m wide tower faces hold 5 tiles, the 24 m ones 7.
    assert_eq!(count("Floor"), Some(32));
    assert_eq!(count("Tile"), Some(8 * 2 * (5 + 7)));
    assert_eq!(count("Shop"), Some(3));
    let bounds = d.to_model().bounds().unwrap();
    // Podium 5 m + 8 floors of 3.4 m + a 1.2 m roof box.
    assert!((bounds.max.y - 33.4).abs() < 1e-9, "{:?}", bounds.max);
    assert!((bounds.size().x - 20.0).abs() < 1e-9 && (bounds.size().z - 30.0).abs() < 1e-9);
}

#[test]
fn house() {
    let program = example("house.cga");
    let d = derive(
        &program,
        &[common::lot(12.0, 9.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // Front: ground floor + 1 storey; three other walls: 2 storeys each.
    assert_eq!(count("Storey"), Some(7));
    assert_eq!(count("Window"), Some(28));
    assert_eq!(count("Door"), Some(1));
    let model = d.to_model();
    let roof = model.parts.iter().find(|p| p.name == "Roof").unwrap();
    assert!(roof.mesh.is_watertight());
    let bounds = model.bounds().unwrap();
    // The ridge runs along the 12 m front: 4.5 m + 0.4 m eaves at 35° above the 6 m walls.
    let ridge = 6.0 + 4.5 * 35f64.to_radians().tan();
    let roof_top = roof.mesh.bounds().unwrap().max.y;
    assert!((roof_top - ridge).abs() < 1e-6, "{roof_top}");
    // The chimney, 3.3 m above the walls, tops the ridge.
    assert!((bounds.max.y - 9.3).abs() < 1e-6, "{:?}", bounds.max);
    assert!(
        bounds.min.x < -0.39 && bounds.max.x > 12.39,
        "eaves overhang the walls"
    );
}

#[test]
fn block_is_the_readme_tutorial() {
    let readme =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let file = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/block.cga"),
    )
    .unwrap();
    assert!(
        readme.contains(&format!("```\n{file}```")),
        "README and examples/block.cga differ"
    );
    let program = example("block.cga");
    let d = derive(
        &program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // 12 m: a 4 m ground floor and two floors; tiles: 6 per floor on the 20 m faces, 9 on the 30 m.
    assert_eq!(count("Floor"), Some(8));
    assert_eq!(count("Tile"), Some(2 * 2 * (6 + 9)));
    assert_eq!(count("Window"), Some(60));
    let roof = d.to_model();
    let roof = roof.parts.iter().find(|p| p.name == "Roof").unwrap();
    assert!(roof.mesh.is_watertight());
}
