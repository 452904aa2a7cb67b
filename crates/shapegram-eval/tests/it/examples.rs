//! Every grammar in `examples/` compiles without errors and derives the model it promises.

use crate::common;

use std::path::PathBuf;

use common::example;
use shapegram_eval::{DeriveOptions, derive};

/// The example `name` derived on a 20 × 30 lot (the CLI's default).
fn on_default_lot(name: &str) -> shapegram_eval::Derivation {
    let lot = common::lot(20.0, 30.0);
    derive(&example(name), &[lot], &DeriveOptions::default()).unwrap()
}

#[test]
fn office() {
    let d = on_default_lot("office.cga");
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
    // Windows: 4 on each 12 m storey, 3 on each 9 m one, and 2 on each side of the door.
    assert_eq!(count("Window"), Some(4 * 3 + 3 * 4 + 2 * 2));
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
    let d = on_default_lot("block.cga");
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // 12 m: a 4 m ground floor and two floors; tiles: 6 per floor on the 20 m faces, 9 on the 30 m.
    assert_eq!(count("Floor"), Some(8));
    assert_eq!(count("Tile"), Some(2 * 2 * (6 + 9)));
    assert_eq!(count("Window"), Some(60));
    let roof = d.to_model();
    let roof = roof.parts.iter().find(|p| p.name == "Roof").unwrap();
    assert!(roof.mesh.is_watertight());
}

/// Whether `p` lies inside the closed mesh: an odd number of its triangles above `p` (a
/// vertical ray; `p` is chosen off any vertex or edge).
fn inside(mesh: &shapegram_geom::Mesh, p: shapegram_geom::DVec3) -> bool {
    let mut crossings = 0;
    for i in 0..mesh.face_count() {
        let corners: Vec<_> = mesh.face_points(i).collect();
        let [a, b, c] = [corners[0], corners[1], corners[2]];
        let area = |u: shapegram_geom::DVec3, v: shapegram_geom::DVec3| {
            (u.x - p.x) * (v.z - p.z) - (v.x - p.x) * (u.z - p.z)
        };
        let (s, t, u) = (area(a, b), area(b, c), area(c, a));
        if !((s > 0.0 && t > 0.0 && u > 0.0) || (s < 0.0 && t < 0.0 && u < 0.0)) {
            continue;
        }
        let total = s + t + u;
        let y = (t * a.y + u * b.y + s * c.y) / total;
        if y > p.y {
            crossings += 1;
        }
    }
    crossings % 2 == 1
}

/// The genus of a closed triangle mesh: its number of through holes (Euler: V − E + F = 2 − 2g).
fn genus(mesh: &shapegram_geom::Mesh) -> i64 {
    let v = mesh.vertex_count() as i64;
    let f = mesh.face_count() as i64;
    (2 - (v - f / 2)) / 2
}

#[test]
fn aqueduct_carves_an_arch_through_the_wall_for_every_bay() {
    let d = on_default_lot("aqueduct.cga");
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // 42 m in bays of about 6.5 m below (6) and 3.25 m above (13).
    assert_eq!(count("Bay"), Some(6 + 13));
    assert_eq!(d.solids.len(), 1);
    let aqueduct = &d.solids[0];
    assert_eq!(aqueduct.name, "aqueduct");
    assert_eq!(aqueduct.color.to_hex(), "#c8b28a");
    assert!(aqueduct.mesh.is_watertight());
    assert_eq!(aqueduct.normals.len(), aqueduct.mesh.vertex_count());
    // One solid with a hole through it per upper arch (the lower arches open onto the ground,
    // notches rather than holes).
    assert_eq!(genus(&aqueduct.mesh), 13);
    let size = aqueduct.mesh.bounds().unwrap().size();
    // 42 long, 20 high, 4 deep with a cornice standing out 0.3 m on either side.
    assert!(
        (size - shapegram_geom::DVec3::new(42.0, 20.0, 4.6))
            .abs()
            .max_element()
            < 0.1,
        "{size}"
    );
    // Centred on the 20 m lot, the first lower bay spans x = -11 to -4: the middle of its
    // arch is open, the pier after it is stone.
    let (x0, z) = (-7.5 + 0.013, 15.017);
    assert!(!inside(
        &aqueduct.mesh,
        shapegram_geom::DVec3::new(x0, 5.0, z)
    ));
    assert!(inside(
        &aqueduct.mesh,
        shapegram_geom::DVec3::new(x0 + 3.5, 5.0, z)
    ));
}

#[test]
fn outcrop_fuses_its_blocks_and_keeps_the_tunnel_open() {
    let program = example("outcrop.cga");
    let lot = common::lot(20.0, 30.0);
    let run = |seed: u64| {
        let options = DeriveOptions {
            seed,
            ..DeriveOptions::default()
        };
        derive(&program, std::slice::from_ref(&lot), &options).unwrap()
    };
    for seed in [0, 3] {
        let d = run(seed);
        assert_eq!(d.solids.len(), 1);
        let rock = &d.solids[0];
        assert_eq!(rock.name, "outcrop");
        assert!(rock.mesh.is_watertight(), "seed {seed}");
        // Cut flat at the ground.
        let bounds = rock.mesh.bounds().unwrap();
        assert!(bounds.min.y.abs() < 1e-9, "{bounds:?}");
        // The bore runs along x through the middle of the lot, with room to walk.
        for x in [0.37, 6.13, 10.07, 13.91, 19.63] {
            let p = shapegram_geom::DVec3::new(x, 1.51, 15.013);
            assert!(!inside(&rock.mesh, p), "seed {seed}: rock at {p}");
        }
        // Fourteen slabs of 1.1 m with 0.3 m gaps along the 20 m path.
        assert_eq!(
            d.leaves.iter().filter(|l| d.name(l.name) == "Slab").count(),
            14
        );
    }
    assert_ne!(run(0).solids, run(3).solids);
}

#[test]
fn villa_sets_back_a_garden_and_paths_and_builds_a_u() {
    let d = on_default_lot("villa.cga");
    let leaf = |name: &str| -> Vec<&shapegram_eval::Leaf> {
        d.leaves.iter().filter(|l| d.name(l.name) == name).collect()
    };
    // One hedge along the street (the lot's front, z = 30), 1.1 m high.
    let hedge = leaf("Hedge");
    assert_eq!(hedge.len(), 1);
    let bounds = hedge[0].world_mesh().unwrap().bounds().unwrap();
    assert!(
        (bounds.max.z - 30.0).abs() < 1e-9 && (bounds.min.z - 29.2).abs() < 1e-9,
        "{bounds:?}"
    );
    assert!((bounds.max.y - 1.1).abs() < 1e-9);
    // Paths round the plot behind the garden (all four of its edges), a pool in the courtyard.
    assert_eq!(leaf("Path").len(), 4);
    assert_eq!(leaf("Pool").len(), 1);
    // The U is as wide as the plot inside the paths (20 − 2 · 1.5), its roof 0.5 beyond.
    let model = d.to_model();
    let roof = model.parts.iter().find(|p| p.name == "Roof").unwrap();
    let roof_bounds = roof.mesh.bounds().unwrap();
    assert!(
        (roof_bounds.size().x - (17.0 + 1.0)).abs() < 1e-9,
        "{roof_bounds:?}"
    );
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    assert_eq!(count("Facade"), Some(8));
}

#[test]
fn implicit_examples_take_lots_of_any_shape() {
    let skewed = shapegram_eval::InitialShape::from_xz(
        &[(0.0, 40.0), (30.0, 45.0), (25.0, 80.0), (0.0, 70.0)]
            .map(|(x, z)| shapegram_geom::DVec2::new(x, z)),
    )
    .unwrap();
    for name in ["aqueduct.cga", "outcrop.cga"] {
        let d = derive(
            &example(name),
            std::slice::from_ref(&skewed),
            &DeriveOptions::default(),
        )
        .unwrap();
        assert_eq!(d.solids.len(), 1, "{name}");
        assert!(d.solids[0].mesh.is_watertight(), "{name}");
    }
}

#[test]
fn twisted_tower_narrows_and_turns_as_one_solid_with_its_spire_in_line() {
    let d = on_default_lot("twisted_tower.cga");
    let count = |rule: &str| d.stats.rules.iter().find(|(n, _)| n == rule).map(|r| r.1);
    // 64 m of 4 m floors, each a slab and its glazing; the podium and the spire.
    assert_eq!(count("Floor"), Some(16));
    assert_eq!(d.stats.leaves, 1 + 2 * 16 + 1);
    let bounds = d.to_model().bounds().unwrap();
    assert!(
        (bounds.max.y - (4.0 + 64.0 + 16.0)).abs() < 1e-9,
        "{bounds:?}"
    );
    let volume = |names: &[&str]| -> f64 {
        d.leaves
            .iter()
            .filter(|l| names.contains(&d.name(l.name)))
            .map(|l| {
                let mesh = l.world_mesh().unwrap();
                assert!(mesh.is_watertight(), "{}", d.name(l.name));
                mesh.signed_volume()
            })
            .sum()
    };
    // The floors fill the frustum from the 14 m square to the 9.8 m one, less the 0.14 % the
    // twist's straight walls cut off; the spire is a pyramid over the 9.8 m square.
    let frustum = 64.0 / 3.0 * (196.0 + 96.04 + 14.0 * 9.8);
    let shaft = volume(&["Slab", "Glazing"]);
    assert!(
        shaft < frustum && (shaft - frustum).abs() < 2e-3 * frustum,
        "{shaft} of {frustum}"
    );
    let pyramid = 96.04 * 16.0 / 3.0;
    let spire = volume(&["Spire"]);
    assert!(
        spire < pyramid && (spire - pyramid).abs() < 2e-3 * pyramid,
        "{spire}"
    );
    // Turned by 50°, the spire still stands square on the shaft's top: `r` turns the way
    // `twist` does.
    let options = DeriveOptions {
        attrs: vec![("turn".into(), shapegram_eval::Value::Number(50.0))],
        ..DeriveOptions::default()
    };
    let d = derive(
        &example("twisted_tower.cga"),
        &[common::lot(20.0, 30.0)],
        &options,
    )
    .unwrap();
    let corners = |name: &str| -> Vec<shapegram_geom::DVec3> {
        let leaf = d
            .leaves
            .iter()
            .rev()
            .find(|l| d.name(l.name) == name)
            .unwrap();
        let mesh = leaf.world_mesh().unwrap();
        let mut points: Vec<_> = mesh
            .positions()
            .iter()
            .copied()
            .filter(|p| (p.y - 68.0).abs() < 1e-9)
            .collect();
        points.sort_by(|a, b| a.x.total_cmp(&b.x));
        points.dedup_by(|a, b| a.abs_diff_eq(*b, 1e-9));
        points
    };
    let (top, base) = (corners("Glazing"), corners("Spire"));
    assert_eq!((top.len(), base.len()), (4, 4), "{top:?} {base:?}");
    assert!(
        top.iter().zip(&base).all(|(a, b)| a.abs_diff_eq(*b, 1e-9)),
        "{top:?} against {base:?}"
    );
}
