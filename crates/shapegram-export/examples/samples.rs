//! Writes sample GLB/OBJ/STL files into a directory, for checking them with external tools:
//! `cargo run -p shapegram-export --example samples -- /tmp/samples` then
//! `node .ci/validate-gltf.js /tmp/samples/*.glb`. Files with skins (`skinned-*.glb`) must
//! pass with no warnings either.

use std::path::PathBuf;

use shapegram_export::{ExportOptions, save};
use shapegram_geom::extrude::extrude_polygon;
use shapegram_geom::kinematics::{Frame, Limits, Pose, Range, Skeleton};
use shapegram_geom::primitives::{cone, cuboid, cylinder, pyramid, quad, sphere};
use shapegram_geom::{Bone, Color, DAffine3, DQuat, DVec3, Lines, Mesh, Model, Part};

fn part(name: &str, hex: &str, mesh: Mesh, at: DVec3) -> Part {
    Part {
        texture: None,
        uvs: Vec::new(),
        bone: None,
        metadata: None,
        name: name.to_owned(),
        color: Color::from_hex(hex).unwrap_or_default(),
        mesh: mesh.transformed(&DAffine3::from_translation(at)),
        normals: Vec::new(),
        material: None,
        surface: None,
    }
}

/// A part shaded smooth: one normal per shared vertex.
fn smooth(name: &str, hex: &str, mesh: Mesh, at: DVec3) -> Part {
    let mut part = part(name, hex, mesh, at);
    part.normals = part.mesh.vertex_normals();
    part
}

/// A helix of `points` points as one line set.
fn helix(name: &str, hex: &str, points: u32, turns: f64) -> Lines {
    let step = turns * std::f64::consts::TAU / f64::from(points - 1);
    Lines {
        name: name.to_owned(),
        color: Color::from_hex(hex).unwrap_or_default(),
        points: (0..points)
            .map(|i| {
                let angle = step * f64::from(i);
                DVec3::new(angle.cos() + 6.0, angle / 4.0, angle.sin())
            })
            .collect(),
        segments: (1..points).map(|i| [i - 1, i]).collect(),
    }
}

fn annex() -> Mesh {
    let outline = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ]
    .map(|(x, z)| DVec3::new(x, 0.0, z));
    extrude_polygon(&outline, 1.5).unwrap_or_default()
}

/// A five-floor tower split sequentially upwards (each floor's joint on the plane under it),
/// its third floor turned by 35° about y and every floor a box with a glass band bound to its
/// section; a lot outside the skeleton.
fn skinned_tower() -> Result<Model, Box<dyn std::error::Error>> {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Tower");
    let planes = (1..5).map(|k| {
        let plane = Frame::from_translation(DVec3::new(0.0, 3.0 * f64::from(k), 0.0));
        (plane, format!("Floor {k}"))
    });
    let floors = skeleton.sequential(skeleton.root(), planes).to_vec();
    let mut limits = Limits::default();
    limits.rotation[1] = Range::new(-90.0, 90.0);
    skeleton.set_limits(floors[2], limits)?;
    skeleton.set_pose(
        floors[2],
        Pose {
            rotation: DVec3::new(0.0, 35.0, 0.0),
            translation: DVec3::ZERO,
        },
    )?;
    let mut parts = vec![part(
        "lot",
        "#7f8c8d",
        quad(12.0, 12.0),
        DVec3::new(-4.0, -0.01, -4.0),
    )];
    for (k, &section) in floors.iter().enumerate() {
        let y = 3.0 * k as f64;
        let bone = Some(Bone {
            skeleton: 0,
            section,
        });
        let mut floor = part(
            &format!("floor {k}"),
            "#c0392b",
            cuboid(DVec3::new(4.0, 2.8, 4.0)),
            DVec3::new(0.0, y, 0.0),
        );
        floor.bone = bone;
        let mut band = part(
            &format!("band {k}"),
            "#3a6ea5",
            cuboid(DVec3::new(4.2, 0.6, 4.2)),
            DVec3::new(-0.1, y + 1.0, -0.1),
        );
        band.bone = bone;
        parts.extend([floor, band]);
    }
    Ok(Model {
        parts,
        lines: Vec::new(),
        skeletons: vec![skeleton],
    })
}

/// A disc of 300 petals, each a section of its own (a component split of the centre) tilted
/// about its radius and bent a little, so the skin needs u16 joint indices.
fn skinned_flower() -> Result<Model, Box<dyn std::error::Error>> {
    let mut skeleton = Skeleton::new(Frame::IDENTITY, "Centre");
    let petals = 300;
    let frames = (0..petals).map(|i| {
        let angle = std::f64::consts::TAU * f64::from(i) / f64::from(petals);
        let rest = Frame {
            rotation: DQuat::from_rotation_y(angle),
            translation: DVec3::new(angle.cos(), 0.0, -angle.sin()) * 2.0,
        };
        (rest, format!("Petal {i}"))
    });
    let sections = skeleton.components(skeleton.root(), frames).to_vec();
    let mut limits = Limits::default();
    limits.rotation[2] = Range::new(-60.0, 60.0);
    let mut parts = Vec::new();
    for (i, &section) in sections.iter().enumerate() {
        skeleton.set_limits(section, limits)?;
        skeleton.set_pose(
            section,
            Pose {
                rotation: DVec3::new(0.0, 0.0, 20.0 + (i % 7) as f64 * 5.0),
                translation: DVec3::ZERO,
            },
        )?;
        let rest = skeleton.section(section).rest().to_affine();
        let petal = cuboid(DVec3::new(1.5, 0.05, 0.2))
            .transformed(&(rest * DAffine3::from_translation(DVec3::new(0.0, 0.0, -0.1))));
        parts.push(Part {
            bone: Some(Bone {
                skeleton: 0,
                section,
            }),
            ..part(&format!("petal {i}"), "#f1c40f", petal, DVec3::ZERO)
        });
    }
    Ok(Model {
        parts,
        lines: Vec::new(),
        skeletons: vec![skeleton],
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or("usage: samples <output dir>")?,
    );
    std::fs::create_dir_all(&dir)?;
    let scene = Model {
        skeletons: Vec::new(),
        parts: vec![
            part(
                "wall",
                "#c0392b",
                cuboid(DVec3::new(4.0, 3.0, 0.3)),
                DVec3::ZERO,
            ),
            part(
                "roof",
                "#2c3e50",
                pyramid(DVec3::new(4.0, 1.5, 2.0)),
                DVec3::new(0.0, 3.0, 0.0),
            ),
            part(
                "column",
                "#c0392b",
                cylinder(DVec3::new(0.4, 3.0, 0.4), 24),
                DVec3::new(5.0, 0.0, 0.0),
            ),
            part(
                "dome",
                "#27ae60",
                sphere(DVec3::splat(1.5), 32, 16),
                DVec3::new(-2.0, 0.0, 0.0),
            ),
            part(
                "glass spire",
                "#3a6ea580",
                cone(DVec3::new(1.0, 2.0, 1.0), 16),
                DVec3::new(0.0, 0.0, 3.0),
            ),
            part(
                "lot",
                "#7f8c8d",
                quad(10.0, 8.0),
                DVec3::new(-3.0, -0.01, -3.0),
            ),
            // Non-convex caps exercise the ear-clipping path.
            part("annex", "#2c3e50", annex(), DVec3::new(-3.0, 0.0, 1.0)),
            // Smooth next to flat in one colour: one primitive when merged.
            smooth(
                "smooth dome",
                "#27ae60",
                sphere(DVec3::splat(1.5), 32, 16),
                DVec3::new(-2.0, 0.0, -2.0),
            ),
        ],
        // The wall's colour: a LINES primitive beside its triangles.
        lines: vec![helix("helix", "#c0392b", 200, 3.0)],
    };
    // More than 65535 flat-shaded vertices, smooth vertices and points, so the u32 index paths
    // are exercised.
    let big = Model {
        skeletons: Vec::new(),
        parts: vec![
            part(
                "ball",
                "#cccccc",
                sphere(DVec3::splat(10.0), 256, 128),
                DVec3::ZERO,
            ),
            smooth(
                "smooth ball",
                "#cccccc",
                sphere(DVec3::splat(10.0), 400, 200),
                DVec3::new(12.0, 0.0, 0.0),
            ),
        ],
        lines: vec![helix("long helix", "#3a6ea5", 70_000, 50.0)],
    };
    let grouped = ExportOptions {
        group_by_part: true,
        ..ExportOptions::default()
    };
    let merged = ExportOptions::default();
    save(&scene, &dir.join("scene-grouped.glb"), &grouped)?;
    save(&scene, &dir.join("scene-merged.glb"), &merged)?;
    save(&Model::default(), &dir.join("empty.glb"), &merged)?;
    save(&big, &dir.join("big.glb"), &merged)?;
    save(&big, &dir.join("big-grouped.glb"), &grouped)?;
    save(&scene, &dir.join("scene.obj"), &grouped)?;
    save(&scene, &dir.join("scene.stl"), &merged)?;
    // Skins: u8 joints (the tower) and u16 joints (300 petals), merged and grouped; OBJ and STL
    // of the tower in its pose.
    let tower = skinned_tower()?;
    let flower = skinned_flower()?;
    save(&tower, &dir.join("skinned-tower.glb"), &merged)?;
    save(&tower, &dir.join("skinned-tower-grouped.glb"), &grouped)?;
    save(&flower, &dir.join("skinned-flower.glb"), &merged)?;
    save(&flower, &dir.join("skinned-flower-grouped.glb"), &grouped)?;
    save(&tower, &dir.join("skinned-tower.obj"), &grouped)?;
    save(&tower, &dir.join("skinned-tower.stl"), &merged)?;
    println!("wrote samples to {}", dir.display());
    Ok(())
}
