//! What a shape carries for texturing, as CGA has it: up to ten projections set up in world
//! space (`setupProjection`), up to ten uv sets (`projectUV`, edited by `tileUV` and friends)
//! and the texture layers of its material (`texture`, `set(material.colormap, …)`), with the
//! material's other attributes (`set(material.metallic, …)` and the rest of [`FinishAttr`]).
//!
//! A projection is affine in world position, and so is every uv set made from one, edited in uv
//! space, or carried along when `t`, `r`, `s`, `center` or `mirror` move the geometry: a uv set
//! is therefore kept as an affine map of world position (see [`UvMap`]), not per vertex, and a
//! leaf's uvs are that map evaluated at its vertices. Splits, component splits and extrusions
//! leave geometry where it is, so they need nothing.

use std::sync::Arc;

use shapegram_geom::{DAffine3, DVec2, DVec3, Finish, MapTransform, Maps, Surface, Texture};

use crate::asset_look::WornAsset;

/// The layer of the colour map, the one layer whose image is read and exported.
pub const COLORMAP: usize = 0;

/// The layer of the opacity map, which `texture()` sets to an image with alpha.
pub const OPACITYMAP: usize = 4;

/// How many uv sets and texture layers a shape has.
pub const UV_SETS: usize = 10;

/// The texture layer of each uv set, as `material.<layer>` names it: the layer of set `i` is
/// textured through uv set `i`.
pub const LAYERS: [&str; UV_SETS] = [
    "colormap",
    "bumpmap",
    "dirtmap",
    "specularmap",
    "opacitymap",
    "normalmap",
    "emissivemap",
    "occlusionmap",
    "roughnessmap",
    "metallicmap",
];

/// The layer an attribute `material.<name>` sets, with CGA's deprecated aliases.
pub fn layer(name: &str) -> Option<usize> {
    let name = match name {
        "map3" => "specularmap",
        "map4" => "opacitymap",
        "map5" => "normalmap",
        other => other,
    };
    LAYERS.iter().position(|l| *l == name)
}

/// A material attribute that `set(material.<name>, value)` sets, besides colour, opacity, name
/// and texture layers (see [`Finish`] for their meanings).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FinishAttr {
    /// `metallic`.
    Metallic,
    /// `roughness`.
    Roughness,
    /// A channel (0 red, 1 green, 2 blue) of `emissive`.
    Emissive(usize),
    /// A channel of `specular`.
    Specular(usize),
    /// A channel of `ambient`.
    Ambient(usize),
    /// `shininess`.
    Shininess,
    /// `reflectivity`.
    Reflectivity,
    /// `bumpValue` (and its old name `bump`).
    BumpValue,
    /// `opacitymap.mode`.
    AlphaMode,
    /// `opacitymap.cutoff`.
    AlphaCutoff,
    /// `doubleSided`.
    DoubleSided,
    /// A number of how a layer's image lies on its uvs (`colormap.su`, …, `metallicmap.rw`):
    /// the layer, as its uv set, and which number.
    Transform(usize, TransformPart),
}

/// One of the numbers of a [`MapTransform`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransformPart {
    /// `su`.
    Su,
    /// `sv`.
    Sv,
    /// `tu`.
    Tu,
    /// `tv`.
    Tv,
    /// `rw`.
    Rw,
}

impl TransformPart {
    /// The part CGA names `name` (`su`, `sv`, `tu`, `tv` or `rw`).
    fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "su" => Self::Su,
            "sv" => Self::Sv,
            "tu" => Self::Tu,
            "tv" => Self::Tv,
            "rw" => Self::Rw,
            _ => return None,
        })
    }

    /// Sets the part of `transform` to `n`.
    pub fn set(self, transform: &mut MapTransform, n: f64) {
        let slot = match self {
            Self::Su => &mut transform.su,
            Self::Sv => &mut transform.sv,
            Self::Tu => &mut transform.tu,
            Self::Tv => &mut transform.tv,
            Self::Rw => &mut transform.rw,
        };
        *slot = n;
    }
}

impl FinishAttr {
    /// The attribute `material.<name>` names, if it is one.
    pub fn from_name(name: &str) -> Option<Self> {
        let channel = |c: &str| ["r", "g", "b"].iter().position(|x| *x == c);
        Some(match name {
            "metallic" => Self::Metallic,
            "roughness" => Self::Roughness,
            "shininess" => Self::Shininess,
            "reflectivity" => Self::Reflectivity,
            "bumpValue" | "bump" => Self::BumpValue,
            "opacitymap.mode" => Self::AlphaMode,
            "opacitymap.cutoff" => Self::AlphaCutoff,
            "doubleSided" => Self::DoubleSided,
            _ => {
                let (colour, c) = name.split_once('.')?;
                if let (Some(layer), Some(part)) = (layer(colour), TransformPart::from_name(c)) {
                    return Some(Self::Transform(layer, part));
                }
                let c = channel(c)?;
                match colour {
                    "emissive" => Self::Emissive(c),
                    "specular" => Self::Specular(c),
                    "ambient" => Self::Ambient(c),
                    _ => return None,
                }
            }
        })
    }

    /// Sets the attribute to a number, clamped to its range (shininess 0 to 128, bumpValue as
    /// given but finite in f32, the others 0 to 1); `None` if it takes no number.
    pub fn set_number(self, finish: &mut Finish, n: f64) -> Option<()> {
        let unit = n.clamp(0.0, 1.0) as f32;
        let channel = |colour: &mut Option<[f32; 3]>, c: usize| {
            colour.get_or_insert([0.0; 3])[c] = unit;
        };
        match self {
            Self::Metallic => finish.metallic = Some(unit),
            Self::Roughness => finish.roughness = Some(unit),
            Self::Reflectivity => finish.reflectivity = Some(unit),
            Self::AlphaCutoff => finish.alpha_cutoff = Some(unit),
            Self::Shininess => finish.shininess = Some(n.clamp(0.0, 128.0) as f32),
            Self::BumpValue => finish.bump_value = Some((n as f32).clamp(f32::MIN, f32::MAX)),
            Self::Emissive(c) => channel(&mut finish.emissive, c),
            Self::Specular(c) => channel(&mut finish.specular, c),
            Self::Ambient(c) => channel(&mut finish.ambient, c),
            Self::AlphaMode | Self::DoubleSided | Self::Transform(..) => return None,
        }
        Some(())
    }
}

/// u and v as affine functions of a world position: `u = u.xyz · p + u.w`, likewise v.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvMap {
    /// The coefficients of u.
    pub u: [f64; 4],
    /// The coefficients of v.
    pub v: [f64; 4],
}

impl UvMap {
    /// The uv at world position `p`.
    pub fn at(&self, p: DVec3) -> DVec2 {
        let row = |r: &[f64; 4]| r[0] * p.x + r[1] * p.y + r[2] * p.z + r[3];
        DVec2::new(row(&self.u), row(&self.v))
    }

    /// A planar projection: `u = ((p − o)·(U + k W) − a) / w`, `v = ((p − o)·V − b) / h`.
    pub fn projection(frame: &ProjectionFrame, width: f64, height: f64, offset: DVec2) -> Self {
        let along_u = frame.u + frame.w * frame.uw_factor;
        let row = |axis: DVec3, shift: f64, size: f64| {
            let a = axis / size;
            [a.x, a.y, a.z, (-axis.dot(frame.origin) - shift) / size]
        };
        Self {
            u: row(along_u, offset.x, width),
            v: row(frame.v, offset.y, height),
        }
    }

    /// The map after the geometry it textures moved by `motion` (world to world): every vertex
    /// keeps the uv it had.
    pub fn moved(&self, motion: &DAffine3) -> Self {
        let back = motion.inverse();
        let row = |r: &[f64; 4]| {
            let gradient = DVec3::new(r[0], r[1], r[2]);
            let turned = back.matrix3.transpose() * gradient;
            [
                turned.x,
                turned.y,
                turned.z,
                gradient.dot(back.translation) + r[3],
            ]
        };
        Self {
            u: row(&self.u),
            v: row(&self.v),
        }
    }

    /// The map followed by an affine change of the uvs: `(u, v) → (m00 u + m01 v + t0, m10 u +
    /// m11 v + t1)`.
    pub fn then(&self, m: [[f64; 2]; 2], t: DVec2) -> Self {
        let mix = |a: f64, b: f64| std::array::from_fn(|i| a * self.u[i] + b * self.v[i]);
        let mut u: [f64; 4] = mix(m[0][0], m[0][1]);
        let mut v: [f64; 4] = mix(m[1][0], m[1][1]);
        u[3] += t.x;
        v[3] += t.y;
        Self { u, v }
    }

    /// How far u and v grow per metre at most: the length of each one's world gradient.
    pub fn rates(&self) -> DVec2 {
        let length = |r: &[f64; 4]| DVec3::new(r[0], r[1], r[2]).length();
        DVec2::new(length(&self.u), length(&self.v))
    }
}

/// Where a projection is set up: its origin and axes in world space, and how much u advances
/// along the third axis (the uwFactor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectionFrame {
    /// The projection's origin.
    pub origin: DVec3,
    /// The axis u runs along (unit).
    pub u: DVec3,
    /// The axis v runs along (unit).
    pub v: DVec3,
    /// `u × v`.
    pub w: DVec3,
    /// How much u advances per metre along `w`, relative to along `u`.
    pub uw_factor: f64,
}

/// A shape's texturing state (shared between a shape and its children until one changes it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Texturing {
    /// The projection of each uv set, frozen in world space when it was set up.
    pub projections: [Option<UvMap>; UV_SETS],
    /// Each uv set of the geometry, if it has one.
    pub uvs: [Option<UvMap>; UV_SETS],
    /// The texture of each layer (see [`LAYERS`]): the path the grammar gave, with the image
    /// read.
    pub maps: [Option<Arc<Texture>>; UV_SETS],
    /// The material's other attributes the grammar set.
    pub finish: Finish,
    /// How each layer's image lies on its uvs (`material.<layer>.su` and the others).
    pub transforms: [MapTransform; UV_SETS],
    /// The materials and uvs of the asset the shape holds, when `i()` inserted one that has
    /// any (see [`crate::asset_look`]).
    pub asset: Option<WornAsset>,
}

impl Texturing {
    /// Whether any uv set is present: only then does moving the geometry concern it.
    pub fn has_uvs(&self) -> bool {
        self.uvs.iter().any(Option::is_some)
    }

    /// The uvs exported with the shape's texture layers: uv set 0, as CityEngine's exporters
    /// write it for every layer; `None` when no layer has a texture or there is no set 0.
    pub fn drawn_uvs(&self) -> Option<&UvMap> {
        self.maps.iter().any(Option::is_some).then_some(())?;
        self.uvs[0].as_ref()
    }

    /// The material attributes and layers besides the colour map, as a part carries them (the
    /// layers only when `drawn`, that is with uvs to place them); `None` when there are none.
    pub fn surface(&self, drawn: bool) -> Option<Surface> {
        let mut maps = Maps::default();
        if drawn {
            for (set, texture) in self.maps.iter().enumerate().skip(1) {
                if let Some(layer) = maps.layer_mut(set) {
                    layer.clone_from(texture);
                }
            }
        }
        let transforms = if drawn {
            self.transforms
        } else {
            Default::default()
        };
        let turned = transforms.iter().any(|t| !t.is_identity());
        (!self.finish.is_unset() || !maps.is_empty() || turned).then_some(Surface {
            finish: self.finish,
            maps,
            transforms,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::{DMat3, DQuat};

    fn facade_frame(k: f64) -> ProjectionFrame {
        ProjectionFrame {
            origin: DVec3::new(1.0, 2.0, 3.0),
            u: DVec3::X,
            v: DVec3::Y,
            w: DVec3::Z,
            uw_factor: k,
        }
    }

    #[test]
    fn a_projection_measures_from_its_origin_in_texture_sizes_minus_its_offset() {
        let map = UvMap::projection(&facade_frame(0.0), 5.0, 2.0, DVec2::new(1.0, -1.0));
        let uv = map.at(DVec3::new(11.0, 6.0, 3.0));
        assert!((uv - DVec2::new((10.0 - 1.0) / 5.0, (4.0 + 1.0) / 2.0)).length() < 1e-12);
        let reveal = UvMap::projection(&facade_frame(1.0), 5.0, 2.0, DVec2::ZERO);
        // Along w, u advances as fast as along u: 1/5 per metre.
        let step = reveal.at(DVec3::new(1.0, 2.0, 4.0)) - reveal.at(DVec3::new(1.0, 2.0, 3.0));
        assert!((step.x - 0.2).abs() < 1e-12 && step.y.abs() < 1e-12);
    }

    #[test]
    fn a_moved_map_gives_every_moved_vertex_its_old_uv() {
        let map = UvMap::projection(&facade_frame(0.5), 3.0, 4.0, DVec2::new(0.2, 0.7));
        let motion = DAffine3::from_mat3_translation(
            DMat3::from_quat(DQuat::from_rotation_y(0.7))
                * DMat3::from_diagonal(DVec3::new(2.0, 1.0, 0.5)),
            DVec3::new(-4.0, 1.0, 9.0),
        );
        let moved = map.moved(&motion);
        for p in [
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::new(-5.0, 0.5, 7.0),
        ] {
            let d = moved.at(motion.transform_point3(p)) - map.at(p);
            assert!(d.length() < 1e-12, "{d}");
        }
    }

    #[test]
    fn then_applies_the_uv_change_after_the_map() {
        let map = UvMap::projection(&facade_frame(0.0), 1.0, 1.0, DVec2::ZERO);
        let p = DVec3::new(3.0, 5.0, 0.0);
        let turned = map.then([[0.0, -1.0], [1.0, 0.0]], DVec2::new(10.0, 20.0));
        let uv = map.at(p);
        assert_eq!(turned.at(p), DVec2::new(-uv.y + 10.0, uv.x + 20.0));
    }

    #[test]
    fn finish_attributes_by_name_and_their_ranges() {
        assert_eq!(
            FinishAttr::from_name("metallic"),
            Some(FinishAttr::Metallic)
        );
        assert_eq!(
            FinishAttr::from_name("specular.g"),
            Some(FinishAttr::Specular(1))
        );
        assert_eq!(FinishAttr::from_name("bump"), Some(FinishAttr::BumpValue));
        assert_eq!(
            FinishAttr::from_name("opacitymap.cutoff"),
            Some(FinishAttr::AlphaCutoff)
        );
        assert_eq!(FinishAttr::from_name("specular.a"), None);
        assert_eq!(
            FinishAttr::from_name("colormap.su"),
            Some(FinishAttr::Transform(0, TransformPart::Su))
        );
        assert_eq!(
            FinishAttr::from_name("map5.rw"),
            Some(FinishAttr::Transform(5, TransformPart::Rw))
        );
        assert_eq!(
            FinishAttr::from_name("metallicmap.tv"),
            Some(FinishAttr::Transform(9, TransformPart::Tv))
        );
        assert_eq!(FinishAttr::from_name("colormap.r"), None);
        assert_eq!(FinishAttr::from_name("colormap.sw"), None);
        assert_eq!(FinishAttr::from_name("colormap"), None);
        let mut finish = Finish::default();
        FinishAttr::Emissive(2)
            .set_number(&mut finish, 0.25)
            .unwrap();
        FinishAttr::Shininess
            .set_number(&mut finish, 300.0)
            .unwrap();
        FinishAttr::Roughness.set_number(&mut finish, -1.0).unwrap();
        FinishAttr::BumpValue
            .set_number(&mut finish, -1e300)
            .unwrap();
        assert_eq!(finish.bump_value, Some(f32::MIN));
        assert_eq!(finish.emissive, Some([0.0, 0.0, 0.25]));
        assert_eq!(finish.shininess, Some(128.0));
        assert_eq!(finish.roughness, Some(0.0));
        assert!(FinishAttr::AlphaMode.set_number(&mut finish, 1.0).is_none());
    }

    #[test]
    fn layers_and_their_deprecated_names() {
        assert_eq!(layer("colormap"), Some(0));
        assert_eq!(layer("dirtmap"), Some(2));
        assert_eq!(layer("map4"), Some(4));
        assert_eq!(layer("metallicmap"), Some(9));
        assert_eq!(layer("colour"), None);
    }
}
