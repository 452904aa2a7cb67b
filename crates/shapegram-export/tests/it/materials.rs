//! Material attributes beyond colour, colour map and name (`Part::surface`): PBR materials in
//! GLB with their textures embedded and their alpha modes, and the MTL statements of OBJ.

use crate::common;

use std::sync::Arc;

use common::split_glb;
use serde_json::json;
use shapegram_export::{ExportOptions, write_glb, write_obj};
use shapegram_geom::{
    AlphaMode, Color, DVec2, DVec3, Finish, MapTransform, Maps, Mesh, Model, Part, Surface, Texture,
};

const BRICK: &[u8] = include_bytes!("../../../../examples/textures/brick.png");

/// A texture of the brick image under `path`.
fn image(path: &str) -> Option<Arc<Texture>> {
    Some(Arc::new(Texture {
        path: Arc::from(path),
        image: Some(Arc::from(BRICK)),
    }))
}

/// A 2 × 1 quad at height `y` with uvs, the colour map `colormap` (if any) and `surface`.
fn quad(y: f64, colormap: Option<&str>, surface: Surface) -> Part {
    let positions = vec![
        DVec3::new(0.0, y, 0.0),
        DVec3::new(2.0, y, 0.0),
        DVec3::new(2.0, y, -1.0),
        DVec3::new(0.0, y, -1.0),
    ];
    Part {
        name: "Quad".to_owned(),
        color: Color::rgb(1.0, 1.0, 1.0),
        uvs: positions.iter().map(|p| DVec2::new(p.x, -p.z)).collect(),
        mesh: Mesh::from_faces(positions, [[0u32, 1, 2, 3]]),
        texture: colormap.and_then(image),
        surface: Some(Arc::new(surface)),
        ..Part::default()
    }
}

fn model(parts: Vec<Part>) -> Model {
    Model {
        parts,
        ..Model::default()
    }
}

/// Every attribute and layer set, with a masked opacity.
fn full_surface() -> Surface {
    Surface {
        finish: Finish {
            metallic: Some(0.25),
            roughness: Some(0.5),
            emissive: Some([1.0, 0.5, 0.0]),
            specular: Some([0.5, 0.5, 0.5]),
            ambient: Some([0.25, 0.25, 0.25]),
            shininess: Some(40.0),
            reflectivity: Some(0.5),
            bump_value: Some(2.0),
            alpha_mode: Some(AlphaMode::Mask),
            alpha_cutoff: Some(0.25),
            double_sided: Some(true),
        },
        maps: Maps {
            bump: image("bump.png"),
            dirt: image("dirt.png"),
            specular: image("spec.png"),
            opacity: image("alpha.png"),
            normal: image("normal.png"),
            emissive: image("glow.png"),
            occlusion: image("ao.png"),
            roughness: image("rough.png"),
            metallic: image("metal.png"),
        },
        transforms: Default::default(),
    }
}

#[test]
fn glb_writes_each_attribute_into_a_pbr_material_with_its_textures() {
    let bytes = write_glb(
        &model(vec![quad(0.0, Some("wall.png"), full_surface())]),
        &ExportOptions::default(),
    );
    let (json, _) = split_glb(&bytes);
    // Emissive (1, 0.5, 0) in linear light; G is sRGB 0.5 decoded (as JSON reads the f32).
    let half: f64 = ((0.5f32 + 0.055) / 1.055)
        .powf(2.4)
        .to_string()
        .parse()
        .unwrap();
    assert_eq!(
        json["materials"][0],
        json!({
            "name": "#ffffff",
            "alphaMode": "MASK",
            "alphaCutoff": 0.25,
            "doubleSided": true,
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "baseColorTexture": { "index": 0, "texCoord": 0 },
                "metallicFactor": 0.25,
                "roughnessFactor": 0.5,
                "metallicRoughnessTexture": { "index": 4, "texCoord": 0 },
            },
            "normalTexture": { "index": 1, "scale": 1.0, "texCoord": 0 },
            "occlusionTexture": { "index": 3, "strength": 1.0, "texCoord": 0 },
            "emissiveTexture": { "index": 2, "texCoord": 0 },
            "emissiveFactor": [1.0, half, 0.0],
        })
    );
    // The images glTF can use, once each: the colour map, then the layers in CGA's order. The
    // bump, dirt and specular maps, a separate opacity map and the second of the
    // metallic-roughness pair have no place.
    let names: Vec<&str> = json["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["wall.png", "normal.png", "glow.png", "ao.png", "rough.png"]
    );
}

#[test]
fn a_normal_map_alone_gives_the_part_uvs_and_an_emissive_map_alone_shines_as_it_is() {
    let surface = Surface {
        maps: Maps {
            normal: image("normal.png"),
            emissive: image("glow.png"),
            ..Maps::default()
        },
        ..Surface::default()
    };
    let bytes = write_glb(
        &model(vec![quad(0.0, None, surface)]),
        &ExportOptions::default(),
    );
    let (json, _) = split_glb(&bytes);
    let material = &json["materials"][0];
    assert_eq!(material["normalTexture"]["index"], 0);
    assert_eq!(material["emissiveTexture"]["index"], 1);
    assert_eq!(material["emissiveFactor"], json!([1.0, 1.0, 1.0]));
    assert!(material["pbrMetallicRoughness"]["baseColorTexture"].is_null());
    let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
    assert!(attributes["TEXCOORD_0"].is_u64(), "{attributes}");
}

#[test]
fn alpha_modes_follow_the_opacity_map_mode() {
    let with_mode = |mode: Option<AlphaMode>, cutoff: Option<f32>| Surface {
        finish: Finish {
            alpha_mode: mode,
            alpha_cutoff: cutoff,
            ..Finish::default()
        },
        ..Surface::default()
    };
    let parts = vec![
        quad(0.0, None, with_mode(Some(AlphaMode::Blend), None)),
        quad(1.0, None, with_mode(Some(AlphaMode::Mask), None)),
        quad(2.0, None, with_mode(Some(AlphaMode::Opaque), None)),
        quad(3.0, None, with_mode(None, Some(0.7))),
    ];
    let (json, _) = split_glb(&write_glb(&model(parts), &ExportOptions::default()));
    let modes: Vec<(&str, Option<f64>)> = json["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| (m["alphaMode"].as_str().unwrap(), m["alphaCutoff"].as_f64()))
        .collect();
    // The mask's cutoff is CGA's default, 0.5; a cutoff without the mask changes nothing
    // but still tells the material apart.
    assert_eq!(
        modes,
        [
            ("BLEND", None),
            ("MASK", Some(0.5)),
            ("OPAQUE", None),
            ("OPAQUE", None)
        ]
    );
}

#[test]
fn materials_stay_apart_when_any_attribute_differs() {
    let metallic = |m: f32| Surface {
        finish: Finish {
            metallic: Some(m),
            ..Finish::default()
        },
        ..Surface::default()
    };
    let mut plain = quad(3.0, None, Surface::default());
    plain.surface = None;
    let parts = vec![
        quad(0.0, None, metallic(0.5)),
        quad(1.0, None, metallic(0.5)),
        quad(2.0, None, metallic(1.0)),
        plain,
    ];
    let (json, _) = split_glb(&write_glb(&model(parts), &ExportOptions::default()));
    let factors: Vec<f64> = json["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            m["pbrMetallicRoughness"]["metallicFactor"]
                .as_f64()
                .unwrap()
        })
        .collect();
    assert_eq!(factors, [0.5, 1.0, 0.0]);
    // Without a surface, the material is what it always was: matte, single-sided.
    let plain = &json["materials"][2];
    assert_eq!(plain["pbrMetallicRoughness"]["roughnessFactor"], 0.9);
    assert_eq!(plain["doubleSided"], json!(false), "{plain}");
    assert_eq!(plain["emissiveFactor"], json!([0.0, 0.0, 0.0]), "{plain}");
}

#[test]
fn layers_without_an_image_or_without_uvs_are_left_out() {
    let mut no_uvs = quad(0.0, None, full_surface());
    no_uvs.uvs.clear();
    let missing = Surface {
        maps: Maps {
            normal: Some(Arc::new(Texture {
                path: "gone.png".into(),
                image: None,
            })),
            ..Maps::default()
        },
        ..Surface::default()
    };
    let parts = vec![no_uvs, quad(1.0, None, missing)];
    let bytes = write_glb(&model(parts), &ExportOptions::default());
    let (json, _) = split_glb(&bytes);
    assert!(json.get("images").is_none(), "{}", json["images"]);
    for material in json["materials"].as_array().unwrap() {
        assert!(material.get("normalTexture").is_none(), "{material}");
    }
    // The attributes stay.
    assert_eq!(json["materials"][0]["alphaMode"], "MASK");
}

#[test]
fn mtl_writes_the_attributes_and_maps_obj_can_carry() {
    let (_, mtl) = write_obj(
        &model(vec![quad(0.0, Some("wall.png"), full_surface())]),
        &ExportOptions::default(),
        "m.mtl",
    );
    let material: Vec<&str> = mtl
        .lines()
        .skip_while(|l| !l.starts_with("newmtl"))
        .collect();
    assert_eq!(
        material,
        [
            "newmtl color_ffffff",
            "Ka 0.25 0.25 0.25",
            "Kd 1 1 1",
            "d 1",
            "map_Kd wall.png",
            "Ks 0.5 0.5 0.5",
            "Ns 40",
            "Ke 1 0.5 0",
            "Pr 0.5",
            "Pm 0.25",
            "map_Ks spec.png",
            "map_Bump -bm 2 bump.png",
            "norm normal.png",
            "map_d alpha.png",
            "map_Ke glow.png",
            "map_Pr rough.png",
            "map_Pm metal.png",
        ]
    );
}

#[test]
fn save_writes_every_layer_image_beside_the_mtl() {
    let dir = common::scratch_dir("material_layers");
    let model = model(vec![quad(0.0, None, full_surface())]);
    shapegram_export::save(&model, &dir.join("m.obj"), &ExportOptions::default()).unwrap();
    for name in [
        "bump.png",
        "spec.png",
        "normal.png",
        "glow.png",
        "metal.png",
    ] {
        assert_eq!(std::fs::read(dir.join(name)).unwrap(), BRICK, "{name}");
    }
}

#[test]
fn normal_mapped_primitives_carry_tangents_along_u() {
    let surface = Surface {
        maps: Maps {
            normal: image("normal.png"),
            ..Maps::default()
        },
        ..Surface::default()
    };
    let parts = vec![quad(0.0, Some("wall.png"), surface), {
        let mut plain = quad(1.0, Some("wall.png"), Surface::default());
        plain.surface = None;
        plain
    }];
    let bytes = write_glb(&model(parts), &ExportOptions::default());
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let blob = gltf.blob.clone();
    let tangents: Vec<Option<Vec<[f32; 4]>>> = gltf
        .meshes()
        .flat_map(|m| m.primitives().collect::<Vec<_>>())
        .map(|p| {
            let reader = p.reader(|_| blob.as_deref());
            reader.read_tangents().map(Iterator::collect)
        })
        .collect();
    // u runs along +x; glTF's v (1 − v) grows towards +z, and the floor faces up, so
    // normal × tangent = y × x = −z points against it: w = −1.
    assert_eq!(tangents, [Some(vec![[1.0, 0.0, 0.0, -1.0]; 4]), None]);
}

/// A surface with a normal and an occlusion map, the colour map and those two placed by
/// CGA map transforms (`material.colormap.su` and the others).
fn transformed_surface() -> Surface {
    let mut transforms = [MapTransform::IDENTITY; 10];
    transforms[0] = MapTransform {
        su: 2.0,
        sv: 0.5,
        tu: 0.25,
        tv: 0.125,
        rw: 90.0,
    };
    transforms[5].su = 3.0;
    transforms[7].tv = 0.5;
    Surface {
        maps: Maps {
            normal: image("normal.png"),
            occlusion: image("ao.png"),
            ..Maps::default()
        },
        transforms,
        ..Surface::default()
    }
}

#[test]
fn map_transforms_become_khr_texture_transforms_in_gltf_uv_space() {
    let bytes = write_glb(
        &model(vec![quad(0.0, Some("wall.png"), transformed_surface())]),
        &ExportOptions::default(),
    );
    let (json, _) = split_glb(&bytes);
    assert_eq!(json["extensionsUsed"], json!(["KHR_texture_transform"]));
    let material = &json["materials"][0];
    // The colour map: scaled (2, 0.5), turned a quarter, moved (0.25, 0.125) with v up; in
    // glTF's v-down space the offset is (tu − sv, 1 − tv) = (−0.25, 0.875).
    assert_eq!(
        material["pbrMetallicRoughness"]["baseColorTexture"],
        json!({
            "index": 0,
            "texCoord": 0,
            "extensions": { "KHR_texture_transform": {
                "offset": [-0.25, 0.875],
                "rotation": std::f64::consts::FRAC_PI_2,
                "scale": [2.0, 0.5],
            }},
        })
    );
    // A scale of u alone needs no offset; a shift of v up by 0.5 is one down by 0.5.
    assert_eq!(
        material["normalTexture"],
        json!({
            "index": 1,
            "scale": 1.0,
            "texCoord": 0,
            "extensions": { "KHR_texture_transform": { "scale": [3.0, 1.0] } },
        })
    );
    assert_eq!(
        material["occlusionTexture"],
        json!({
            "index": 2,
            "strength": 1.0,
            "texCoord": 0,
            "extensions": { "KHR_texture_transform": { "offset": [0.0, -0.5] } },
        })
    );
    // Read back through the gltf crate, as a viewer would.
    gltf::Gltf::from_slice(&bytes).unwrap();
}

#[test]
fn untransformed_maps_use_no_extension_and_transforms_keep_materials_apart() {
    let parts = vec![
        quad(0.0, Some("wall.png"), Surface::default()),
        quad(1.0, Some("wall.png"), transformed_surface()),
    ];
    let (json, _) = split_glb(&write_glb(&model(parts), &ExportOptions::default()));
    assert_eq!(json["materials"].as_array().unwrap().len(), 2);
    assert_eq!(
        json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"],
        json!({ "index": 0, "texCoord": 0 })
    );
    let (json, _) = split_glb(&write_glb(
        &model(vec![quad(0.0, Some("wall.png"), Surface::default())]),
        &ExportOptions::default(),
    ));
    assert!(json.get("extensionsUsed").is_none(), "{json}");
}

#[test]
fn mtl_scales_and_moves_maps_and_leaves_turned_ones_as_they_lie() {
    let mut surface = transformed_surface();
    surface.maps.specular = image("spec.png");
    surface.transforms[3] = MapTransform {
        su: 0.5,
        tu: 0.25,
        tv: -1.0,
        ..MapTransform::IDENTITY
    };
    let (_, mtl) = write_obj(
        &model(vec![quad(0.0, Some("wall.png"), surface)]),
        &ExportOptions::default(),
        "m.mtl",
    );
    let maps: Vec<&str> = mtl.lines().filter(|l| l.contains(".png")).collect();
    assert_eq!(
        maps,
        [
            "map_Kd wall.png",
            "map_Ks -s 0.5 1 1 -o 0.25 -1 0 spec.png",
            "norm -s 3 1 1 normal.png",
        ]
    );
}
