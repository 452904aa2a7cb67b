//! The pavilion example (`examples/materials.cga`) through `shapegram derive`: material
//! attributes beyond colour as glTF PBR materials with their textures, and as MTL statements.

use crate::common;

use common::{TempDir, example, shapegram, stderr};

#[test]
fn the_pavilion_has_pbr_materials_in_glb_and_their_statements_in_the_mtl() {
    let dir = TempDir::new("pavilion");
    let out = dir.path("pavilion.glb");
    let output = shapegram(&[
        "derive".as_ref(),
        example("materials.cga").as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let gltf = gltf::Gltf::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let material = |name: &str| {
        gltf.materials()
            .find(|m| m.name() == Some(name))
            .unwrap_or_else(|| panic!("no material {name}"))
    };
    let copper = material("copper").pbr_metallic_roughness();
    assert_eq!(
        (copper.metallic_factor(), copper.roughness_factor()),
        (1.0, 0.35)
    );
    let glass = material("glass");
    assert_eq!(glass.alpha_mode(), gltf::material::AlphaMode::Blend);
    assert!(glass.double_sided());
    assert!((glass.pbr_metallic_roughness().base_color_factor()[3] - 0.3).abs() < 1e-6);
    let trellis = material("trellis");
    assert_eq!(trellis.alpha_mode(), gltf::material::AlphaMode::Mask);
    assert_eq!(trellis.alpha_cutoff(), Some(0.5));
    // The lattice turned 45° on its uvs: about the uvs' origin, which glTF's v-down space has
    // at its top, so the offset moves it back by (−sin 45°, 1 − cos 45°).
    let base = trellis
        .pbr_metallic_roughness()
        .base_color_texture()
        .unwrap();
    let turned = &base.texture().index();
    let json = gltf.document.as_json();
    let info = json.materials[trellis.index().unwrap()]
        .pbr_metallic_roughness
        .base_color_texture
        .as_ref()
        .unwrap();
    assert_eq!(info.index.value(), *turned);
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let transform = &info.extensions.as_ref().unwrap().others["KHR_texture_transform"];
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(
        close(number(&transform["offset"][0]), -half)
            && close(number(&transform["offset"][1]), 1.0 - half)
            && close(number(&transform["rotation"]), std::f64::consts::FRAC_PI_4)
            && transform.get("scale").is_none(),
        "{transform}"
    );
    assert_eq!(
        gltf.extensions_used().collect::<Vec<_>>(),
        ["KHR_texture_transform"]
    );
    let normal = material("brick")
        .normal_texture()
        .expect("the bricks' normal map");
    assert_eq!(normal.texture().source().name(), Some("brick_normal.png"));
    let lamp = material("lamp").emissive_factor();
    assert!(
        lamp[0] == 1.0 && lamp[1] > lamp[2] && lamp[2] > 0.0,
        "{lamp:?}"
    );
    // The normal-mapped walls carry tangents; nothing else does.
    let tangents: Vec<Option<&str>> = gltf
        .meshes()
        .flat_map(|m| m.primitives())
        .filter(|p| p.get(&gltf::Semantic::Tangents).is_some())
        .map(|p| p.material().name())
        .collect();
    assert_eq!(tangents, [Some("brick")]);

    let obj = dir.path("pavilion.obj");
    let output = shapegram(&[
        "derive".as_ref(),
        example("materials.cga").as_os_str(),
        "-o".as_ref(),
        obj.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let mtl = std::fs::read_to_string(dir.path("pavilion.mtl")).unwrap();
    for line in [
        "newmtl brick\nKd 1 1 1\nd 1\nmap_Kd brick.png\nPr 0.9\nnorm brick_normal.png\n",
        "d 0.3\nKs 0.9 0.9 0.9\nNs 96\nPr 0.05\n",
        "Ke 1 0.85 0.55\n",
        "map_Kd lattice.png\nmap_d lattice.png\n",
        "Pr 0.35\nPm 1\n",
    ] {
        assert!(mtl.contains(line), "{line:?} in\n{mtl}");
    }
    assert!(dir.path("brick_normal.png").exists());
}
