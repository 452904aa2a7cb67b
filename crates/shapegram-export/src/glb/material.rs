//! glTF materials: the palette's colours, colour maps and surfaces (CGA's `material.*`, see
//! [`shapegram_geom::material`]) as PBR metallic-roughness materials, every texture drawn
//! through `TEXCOORD_0`.
//!
//! What glTF has no place for stays out: the bump, dirt and specular maps, the specular,
//! ambient, shininess and reflectivity attributes, and an opacity map other than the colour
//! map's own alpha (glTF reads alpha from the base colour texture only).

use gltf_json as json;
use json::validation::Checked::Valid;
use std::sync::Arc;

use shapegram_geom::{AlphaMode, Color, Part, Surface, Texture};

use crate::flat::{drawable, texture_uvs};

/// The material of a colour (linear RGBA) named `name`: opaque unless the colour is not,
/// single-sided, not metallic and matte, as procedural models are mostly buildings and props.
pub(super) fn material(rgba: [f32; 4], name: String) -> json::Material {
    json::Material {
        name: Some(name),
        alpha_mode: Valid(if rgba[3] < 1.0 {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        double_sided: false,
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor(rgba),
            metallic_factor: json::material::StrengthFactor(0.0),
            roughness_factor: json::material::StrengthFactor(0.9),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// A material drawn with texture `index` (`texture`) as its base colour: blended when the
/// image has alpha.
pub(super) fn textured(material: &mut json::Material, index: usize, texture: &Texture) {
    material.pbr_metallic_roughness.base_color_texture = Some(info(index));
    if texture.has_alpha() {
        material.alpha_mode = Valid(json::material::AlphaMode::Blend);
    }
}

/// The surface's attributes and layers written into a material; `index` gives the texture of
/// each drawn image.
pub(super) fn with_surface(
    material: &mut json::Material,
    surface: &Surface,
    index: impl Fn(&Texture) -> Option<usize>,
) {
    let (finish, maps) = (&surface.finish, &surface.maps);
    let layer = |map: &Option<Arc<Texture>>| map.as_deref().and_then(&index);
    let pbr = &mut material.pbr_metallic_roughness;
    if let Some(metallic) = finish.metallic {
        pbr.metallic_factor = json::material::StrengthFactor(metallic);
    }
    if let Some(roughness) = finish.roughness {
        pbr.roughness_factor = json::material::StrengthFactor(roughness);
    }
    // glTF reads roughness from G and metalness from B of one texture, as CGA reads its two
    // maps; when both are set to different images, the roughness map is written.
    pbr.metallic_roughness_texture = layer(&maps.roughness).or(layer(&maps.metallic)).map(info);
    let emissive_map = layer(&maps.emissive);
    material.emissive_texture = emissive_map.map(info);
    if let Some([r, g, b]) = finish.emissive {
        let [r, g, b, _] = Color::rgb(r, g, b).to_linear();
        material.emissive_factor = json::material::EmissiveFactor([r, g, b]);
    } else if emissive_map.is_some() {
        // The map alone shows as it is (glTF multiplies it by a factor of black by default).
        material.emissive_factor = json::material::EmissiveFactor([1.0; 3]);
    }
    material.normal_texture = layer(&maps.normal).map(|i| json::material::NormalTexture {
        index: json::Index::new(i as u32),
        scale: 1.0,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    material.occlusion_texture = layer(&maps.occlusion).map(|i| json::material::OcclusionTexture {
        index: json::Index::new(i as u32),
        strength: json::material::StrengthFactor(1.0),
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    if let Some(mode) = finish.alpha_mode {
        material.alpha_mode = Valid(match mode {
            AlphaMode::Blend => json::material::AlphaMode::Blend,
            AlphaMode::Mask => json::material::AlphaMode::Mask,
            AlphaMode::Opaque => json::material::AlphaMode::Opaque,
        });
        material.alpha_cutoff = (mode == AlphaMode::Mask)
            .then(|| json::material::AlphaCutoff(finish.alpha_cutoff.unwrap_or(0.5)));
    }
    if let Some(double_sided) = finish.double_sided {
        material.double_sided = double_sided;
    }
}

/// The textures glTF draws a part with, those with images, when it has uvs: the colour map,
/// then the normal, emissive, occlusion and metallic-roughness maps (the roughness map, else
/// the metallic map).
pub(super) fn gltf_textures(part: &Part) -> impl Iterator<Item = &Arc<Texture>> {
    let maps = part.surface.as_ref().map(|s| &s.maps);
    let layers = maps.into_iter().flat_map(|m| {
        [
            m.normal.as_ref(),
            m.emissive.as_ref(),
            m.occlusion.as_ref(),
            m.roughness.as_ref().or(m.metallic.as_ref()),
        ]
    });
    let textured = texture_uvs(part).is_some();
    part.texture
        .iter()
        .chain(layers.flatten())
        .filter(move |t| textured && drawable(t))
}

/// A reference to texture `index` through `TEXCOORD_0`.
fn info(index: usize) -> json::texture::Info {
    json::texture::Info {
        index: json::Index::new(index as u32),
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    }
}
