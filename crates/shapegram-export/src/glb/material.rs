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

use shapegram_geom::{AlphaMode, Color, MapTransform, Part, Surface, Texture};

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

/// A material drawn with texture `index` (`texture`) as its base colour, placed by
/// `transform`: blended when the image has alpha.
pub(super) fn textured(
    material: &mut json::Material,
    index: usize,
    texture: &Texture,
    transform: MapTransform,
) {
    material.pbr_metallic_roughness.base_color_texture = Some(info(index, transform));
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
    let placed = |set: usize| {
        let transform = surface.transforms[set];
        move |i: usize| info(i, transform)
    };
    let pbr = &mut material.pbr_metallic_roughness;
    if let Some(metallic) = finish.metallic {
        pbr.metallic_factor = json::material::StrengthFactor(metallic);
    }
    if let Some(roughness) = finish.roughness {
        pbr.roughness_factor = json::material::StrengthFactor(roughness);
    }
    // glTF reads roughness from G and metalness from B of one texture, as CGA reads its two
    // maps; when both are set to different images, the roughness map is written.
    pbr.metallic_roughness_texture = match layer(&maps.roughness) {
        Some(i) => Some(placed(8)(i)),
        None => layer(&maps.metallic).map(placed(9)),
    };
    let emissive_map = layer(&maps.emissive);
    material.emissive_texture = emissive_map.map(placed(6));
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
        extensions: transformed(surface.transforms[5]),
        extras: Default::default(),
    });
    material.occlusion_texture = layer(&maps.occlusion).map(|i| json::material::OcclusionTexture {
        index: json::Index::new(i as u32),
        strength: json::material::StrengthFactor(1.0),
        tex_coord: 0,
        extensions: transformed(surface.transforms[7]),
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

/// A reference to texture `index` through `TEXCOORD_0`, placed by `transform`.
fn info(index: usize, transform: MapTransform) -> json::texture::Info {
    json::texture::Info {
        index: json::Index::new(index as u32),
        tex_coord: 0,
        extensions: transformed(transform),
        extras: Default::default(),
    }
}

/// The extensions of a texture reference placed by `transform`: none for the identity, else
/// `KHR_texture_transform` (see [`khr_texture_transform`]).
fn transformed<E: Default + HasOthers>(transform: MapTransform) -> Option<E> {
    let value = khr_texture_transform(transform)?;
    let mut extensions = E::default();
    extensions
        .others()
        .insert(TEXTURE_TRANSFORM.to_owned(), value);
    Some(extensions)
}

/// The name of glTF's extension for texture transforms, which a GLB using one lists in
/// `extensionsUsed`.
pub(super) const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";

/// The `KHR_texture_transform` of a CGA map transform; `None` for the identity.
///
/// CGA turns and moves uvs with v up; glTF's uvs run down (`TEXCOORD_0` holds `1 − v`), and
/// glTF's transform is `offset + R(rotation) · scale · uv` with R turning the other way in
/// that space. Writing CGA's transform `T` as glTF's `F ∘ T ∘ F`, with `F(u, v) = (u, 1 − v)`,
/// gives the same scale, the same angle (in radians) and the offset
/// `(tu − sin(rw) · sv, 1 − tv − cos(rw) · sv)`.
pub(super) fn khr_texture_transform(transform: MapTransform) -> Option<serde_json::Value> {
    if transform.is_identity() {
        return None;
    }
    let MapTransform { su, sv, tu, tv, rw } = transform;
    let (sin, cos) = transform.turn();
    let mut value = serde_json::Map::new();
    let offset = [tu - sin * sv, 1.0 - tv - cos * sv];
    if offset != [0.0, 0.0] {
        value.insert("offset".into(), serde_json::json!(offset));
    }
    if rw != 0.0 {
        value.insert("rotation".into(), serde_json::json!(rw.to_radians()));
    }
    if (su, sv) != (1.0, 1.0) {
        value.insert("scale".into(), serde_json::json!([su, sv]));
    }
    Some(serde_json::Value::Object(value))
}

/// Whether any texture reference of `materials` has a `KHR_texture_transform`.
pub(super) fn uses_texture_transform(materials: &[json::Material]) -> bool {
    let has = |others: &serde_json::Map<String, serde_json::Value>| {
        others.contains_key(TEXTURE_TRANSFORM)
    };
    materials.iter().any(|m| {
        let pbr = &m.pbr_metallic_roughness;
        let infos = [
            &pbr.base_color_texture,
            &pbr.metallic_roughness_texture,
            &m.emissive_texture,
        ];
        infos
            .into_iter()
            .flatten()
            .any(|i| i.extensions.as_ref().is_some_and(|e| has(&e.others)))
            || m.normal_texture
                .as_ref()
                .and_then(|t| t.extensions.as_ref())
                .is_some_and(|e| has(&e.others))
            || m.occlusion_texture
                .as_ref()
                .and_then(|t| t.extensions.as_ref())
                .is_some_and(|e| has(&e.others))
    })
}

/// The extensions of a texture reference, which can hold one more.
trait HasOthers {
    /// The extensions gltf-json has no type for.
    fn others(&mut self) -> &mut serde_json::Map<String, serde_json::Value>;
}

impl HasOthers for json::extensions::texture::Info {
    fn others(&mut self) -> &mut serde_json::Map<String, serde_json::Value> {
        &mut self.others
    }
}

impl HasOthers for json::extensions::material::NormalTexture {
    fn others(&mut self) -> &mut serde_json::Map<String, serde_json::Value> {
        &mut self.others
    }
}

impl HasOthers for json::extensions::material::OcclusionTexture {
    fn others(&mut self) -> &mut serde_json::Map<String, serde_json::Value> {
        &mut self.others
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// glTF's transform of a uv as `KHR_texture_transform` defines it: `offset + R · scale ·
    /// uv`, where R's columns are `(cos, −sin)` and `(sin, cos)`.
    fn gltf_apply(value: &serde_json::Value, uv: [f64; 2]) -> [f64; 2] {
        let pair = |key: &str, default: f64| {
            value.get(key).map_or([default; 2], |v| {
                [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()]
            })
        };
        let (offset, scale) = (pair("offset", 0.0), pair("scale", 1.0));
        let (sin, cos) = value
            .get("rotation")
            .map_or(0.0, |r| r.as_f64().unwrap())
            .sin_cos();
        let (x, y) = (scale[0] * uv[0], scale[1] * uv[1]);
        [offset[0] + cos * x + sin * y, offset[1] - sin * x + cos * y]
    }

    #[test]
    fn gltf_draws_every_point_where_cga_does() {
        let flip = |[u, v]: [f64; 2]| [u, 1.0 - v];
        for transform in [
            MapTransform {
                su: 2.0,
                sv: -0.5,
                tu: 0.3,
                tv: 0.7,
                rw: 30.0,
            },
            MapTransform {
                rw: -135.0,
                sv: 3.0,
                ..MapTransform::IDENTITY
            },
            MapTransform {
                tu: -1.0,
                ..MapTransform::IDENTITY
            },
        ] {
            let value = khr_texture_transform(transform).unwrap();
            for uv in [[0.0, 0.0], [1.0, 0.0], [0.25, 0.75], [-2.0, 5.0]] {
                // A vertex's TEXCOORD_0 is its CGA uv flipped; glTF transforms that, and must
                // land on CGA's transformed uv, flipped.
                let gltf = gltf_apply(&value, flip(uv));
                let cga = flip(transform.apply(uv));
                assert!(
                    (gltf[0] - cga[0]).abs() < 1e-12 && (gltf[1] - cga[1]).abs() < 1e-12,
                    "{transform:?} at {uv:?}: {gltf:?} vs {cga:?}"
                );
            }
        }
        assert_eq!(khr_texture_transform(MapTransform::IDENTITY), None);
    }
}
