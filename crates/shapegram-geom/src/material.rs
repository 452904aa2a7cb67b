//! Material attributes beyond a part's colour, colour map and name: CGA's `material.*`
//! scalars and colours ([`Finish`]) and its texture layers other than the colour map
//! ([`Maps`]), together a part's [`Surface`].
//!
//! Every attribute of a [`Finish`] is `None` until a grammar sets it, as CityEngine counts only
//! the material attributes set in CGA; exporters then write their own defaults, so a model that
//! sets none is written exactly as before these attributes existed.

use std::sync::Arc;

use crate::Texture;

/// How a material's alpha is used (CGA `material.opacitymap.mode`, glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AlphaMode {
    /// Alpha blends the surface with what lies behind it (CGA's default, `"blend"`).
    Blend,
    /// Alpha below the cutoff cuts the surface away, the rest is opaque (`"mask"`).
    Mask,
    /// Alpha is ignored (`"opaque"`).
    Opaque,
}

impl AlphaMode {
    /// The mode CGA names `name` (`"blend"`, `"mask"` or `"opaque"`).
    pub fn from_cga(name: &str) -> Option<Self> {
        match name {
            "blend" => Some(Self::Blend),
            "mask" => Some(Self::Mask),
            "opaque" => Some(Self::Opaque),
            _ => None,
        }
    }
}

/// The material attributes a grammar set besides colour, opacity and name (`None`: not set).
/// Colours are sRGB, as written in grammars, each channel in `0..=1`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Finish {
    /// `material.metallic`, 0 (dielectric) to 1 (metal); CGA's default is 0.
    pub metallic: Option<f32>,
    /// `material.roughness`, 0 (polished) to 1 (matte); CGA's default is 1.
    pub roughness: Option<f32>,
    /// `material.emissive.r/g/b`: light the surface gives off; CGA's default is black.
    pub emissive: Option<[f32; 3]>,
    /// `material.specular.r/g/b`: the colour of highlights; CGA's default is black.
    pub specular: Option<[f32; 3]>,
    /// `material.ambient.r/g/b`; CGA's default is black.
    pub ambient: Option<[f32; 3]>,
    /// `material.shininess`, the Phong exponent, 0 to 128; CGA's default is 1.
    pub shininess: Option<f32>,
    /// `material.reflectivity`, 0 to 1.
    pub reflectivity: Option<f32>,
    /// `material.bumpValue`, how strongly the bump map bumps; CGA's default is 1.
    pub bump_value: Option<f32>,
    /// `material.opacitymap.mode`; CGA's default is blend.
    pub alpha_mode: Option<AlphaMode>,
    /// `material.opacitymap.cutoff`, the alpha below which a masked surface is cut away;
    /// CGA's default is 0.5.
    pub alpha_cutoff: Option<f32>,
    /// `material.doubleSided`; CGA's default is true.
    pub double_sided: Option<bool>,
}

/// One value per attribute of a [`Finish`], equal exactly when the attributes are (bit for
/// bit), for telling materials apart in hash maps.
pub type FinishKey = [Option<u32>; 17];

impl Finish {
    /// Whether no attribute is set.
    pub fn is_unset(&self) -> bool {
        *self == Self::default()
    }

    /// The attributes as a [`FinishKey`].
    pub fn key(&self) -> FinishKey {
        let one = |v: Option<f32>| v.map(f32::to_bits);
        let channel = |v: Option<[f32; 3]>, i: usize| v.map(|c| c[i].to_bits());
        [
            one(self.metallic),
            one(self.roughness),
            channel(self.emissive, 0),
            channel(self.emissive, 1),
            channel(self.emissive, 2),
            channel(self.specular, 0),
            channel(self.specular, 1),
            channel(self.specular, 2),
            channel(self.ambient, 0),
            channel(self.ambient, 1),
            channel(self.ambient, 2),
            one(self.shininess),
            one(self.reflectivity),
            one(self.bump_value),
            self.alpha_mode.map(|m| m as u32),
            one(self.alpha_cutoff),
            self.double_sided.map(u32::from),
        ]
    }
}

/// A material's texture layers besides the colour map (which is [`crate::Part::texture`]), by
/// CGA's names; all drawn through the part's uvs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Maps {
    /// `material.bumpmap`: heights, read as luminance.
    pub bump: Option<Arc<Texture>>,
    /// `material.dirtmap`: multiplies the colour in CityEngine's own viewer.
    pub dirt: Option<Arc<Texture>>,
    /// `material.specularmap`: the colour of highlights.
    pub specular: Option<Arc<Texture>>,
    /// `material.opacitymap`: alpha (`texture()` sets it to a colour map with alpha).
    pub opacity: Option<Arc<Texture>>,
    /// `material.normalmap`: tangent-space normals.
    pub normal: Option<Arc<Texture>>,
    /// `material.emissivemap`: light given off.
    pub emissive: Option<Arc<Texture>>,
    /// `material.occlusionmap`: ambient occlusion, in the red channel.
    pub occlusion: Option<Arc<Texture>>,
    /// `material.roughnessmap`: roughness, in the green channel.
    pub roughness: Option<Arc<Texture>>,
    /// `material.metallicmap`: metalness, in the blue channel.
    pub metallic: Option<Arc<Texture>>,
}

impl Maps {
    /// The layers in CGA's uv-set order (bump map first), each with its `material.*` name.
    pub fn layers(&self) -> [(&'static str, Option<&Arc<Texture>>); 9] {
        [
            ("bumpmap", self.bump.as_ref()),
            ("dirtmap", self.dirt.as_ref()),
            ("specularmap", self.specular.as_ref()),
            ("opacitymap", self.opacity.as_ref()),
            ("normalmap", self.normal.as_ref()),
            ("emissivemap", self.emissive.as_ref()),
            ("occlusionmap", self.occlusion.as_ref()),
            ("roughnessmap", self.roughness.as_ref()),
            ("metallicmap", self.metallic.as_ref()),
        ]
    }

    /// The layer of CGA uv set `set` (1 to 9), to fill.
    pub fn layer_mut(&mut self, set: usize) -> Option<&mut Option<Arc<Texture>>> {
        Some(match set {
            1 => &mut self.bump,
            2 => &mut self.dirt,
            3 => &mut self.specular,
            4 => &mut self.opacity,
            5 => &mut self.normal,
            6 => &mut self.emissive,
            7 => &mut self.occlusion,
            8 => &mut self.roughness,
            9 => &mut self.metallic,
            _ => return None,
        })
    }

    /// The layer of CGA uv set `set` (1 to 9).
    pub fn layer(&self, set: usize) -> Option<&Option<Arc<Texture>>> {
        Some(match set {
            1 => &self.bump,
            2 => &self.dirt,
            3 => &self.specular,
            4 => &self.opacity,
            5 => &self.normal,
            6 => &self.emissive,
            7 => &self.occlusion,
            8 => &self.roughness,
            9 => &self.metallic,
            _ => return None,
        })
    }

    /// Whether no layer has a texture.
    pub fn is_empty(&self) -> bool {
        self.layers().iter().all(|(_, t)| t.is_none())
    }
}

/// How a texture layer's image lies on its uvs (CGA's `material.<layer>.su/sv/tu/tv/rw`): a
/// uv is scaled, turned `rw` degrees counter-clockwise about (0, 0), then moved:
/// `(u, v) → (tu, tv) + R(rw) · (su · u, sv · v)`, in CGA's uv space (v up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapTransform {
    /// `su`: the scale of u.
    pub su: f64,
    /// `sv`: the scale of v.
    pub sv: f64,
    /// `tu`: the shift of u.
    pub tu: f64,
    /// `tv`: the shift of v.
    pub tv: f64,
    /// `rw`: the turn in degrees, counter-clockwise.
    pub rw: f64,
}

impl Default for MapTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl MapTransform {
    /// No change, CGA's default.
    pub const IDENTITY: Self = Self {
        su: 1.0,
        sv: 1.0,
        tu: 0.0,
        tv: 0.0,
        rw: 0.0,
    };

    /// Whether the transform changes nothing.
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// The sine and cosine of `rw`, exact at whole quarter turns (so that a map turned by 90°
    /// is written with exact numbers).
    pub fn turn(&self) -> (f64, f64) {
        let quarters = self.rw / 90.0;
        if quarters.fract() == 0.0 && quarters.is_finite() {
            match quarters.rem_euclid(4.0) as u8 {
                0 => (0.0, 1.0),
                1 => (1.0, 0.0),
                2 => (0.0, -1.0),
                _ => (-1.0, 0.0),
            }
        } else {
            self.rw.to_radians().sin_cos()
        }
    }

    /// The uv `uv` transformed.
    pub fn apply(&self, uv: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.turn();
        let (x, y) = (self.su * uv[0], self.sv * uv[1]);
        [self.tu + c * x - s * y, self.tv + s * x + c * y]
    }

    /// The five numbers' bits, for telling transforms apart in hash maps.
    pub fn key(&self) -> [u64; 5] {
        [self.su, self.sv, self.tu, self.tv, self.rw].map(f64::to_bits)
    }
}

/// What a part's material has besides colour, colour map and name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Surface {
    /// The attributes set.
    pub finish: Finish,
    /// The texture layers set.
    pub maps: Maps,
    /// How each layer's image lies on the uvs, by CGA's uv set (0 the colour map, then the
    /// layers of [`Maps`]).
    pub transforms: [MapTransform; 10],
}

/// What tells two surfaces apart: their attributes, their layers' paths and how each layer
/// lies on the uvs.
pub type SurfaceKey = (FinishKey, [Option<Arc<str>>; 9], [[u64; 5]; 10]);

impl Surface {
    /// The surface as a [`SurfaceKey`].
    pub fn key(&self) -> SurfaceKey {
        let paths = self.maps.layers().map(|(_, t)| t.map(|t| t.path.clone()));
        (self.finish.key(), paths, self.transforms.map(|t| t.key()))
    }

    /// `self` laid over `under`, attribute by attribute and layer by layer: what `self` sets
    /// wins, the rest comes from `under` (a shape's material over an inserted asset's, as CGA
    /// has it).
    pub fn over(&self, under: &Surface) -> Surface {
        let (a, b) = (&self.finish, &under.finish);
        let finish = Finish {
            metallic: a.metallic.or(b.metallic),
            roughness: a.roughness.or(b.roughness),
            emissive: a.emissive.or(b.emissive),
            specular: a.specular.or(b.specular),
            ambient: a.ambient.or(b.ambient),
            shininess: a.shininess.or(b.shininess),
            reflectivity: a.reflectivity.or(b.reflectivity),
            bump_value: a.bump_value.or(b.bump_value),
            alpha_mode: a.alpha_mode.or(b.alpha_mode),
            alpha_cutoff: a.alpha_cutoff.or(b.alpha_cutoff),
            double_sided: a.double_sided.or(b.double_sided),
        };
        let mut maps = self.maps.clone();
        for set in 1..=9 {
            if let (Some(mine), Some(theirs)) = (maps.layer_mut(set), under.maps.layer(set))
                && mine.is_none()
            {
                mine.clone_from(theirs);
            }
        }
        let transforms = std::array::from_fn(|set| {
            let mine = self.transforms[set];
            if mine.is_identity() {
                under.transforms[set]
            } else {
                mine
            }
        });
        Surface {
            finish,
            maps,
            transforms,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_surface_over_another_wins_where_it_sets_something() {
        let texture = |path: &str| {
            Some(Arc::new(Texture {
                path: path.into(),
                image: None,
            }))
        };
        let turned = MapTransform {
            rw: 30.0,
            ..MapTransform::IDENTITY
        };
        let shape = Surface {
            finish: Finish {
                shininess: Some(40.0),
                ..Finish::default()
            },
            maps: Maps {
                bump: texture("shape-bump.png"),
                ..Maps::default()
            },
            transforms: std::array::from_fn(|set| match set {
                1 => turned,
                _ => MapTransform::IDENTITY,
            }),
        };
        let asset = Surface {
            finish: Finish {
                shininess: Some(10.0),
                specular: Some([0.5, 0.25, 0.0]),
                ..Finish::default()
            },
            maps: Maps {
                bump: texture("asset-bump.png"),
                specular: texture("asset-spec.png"),
                ..Maps::default()
            },
            transforms: std::array::from_fn(|set| MapTransform {
                su: set as f64 + 1.0,
                ..MapTransform::IDENTITY
            }),
        };
        let both = shape.over(&asset);
        assert_eq!(both.finish.shininess, Some(40.0));
        assert_eq!(both.finish.specular, Some([0.5, 0.25, 0.0]));
        assert_eq!(both.maps.bump.unwrap().path.as_ref(), "shape-bump.png");
        assert_eq!(both.maps.specular.unwrap().path.as_ref(), "asset-spec.png");
        assert!(both.maps.normal.is_none());
        assert_eq!(both.transforms[1], turned);
        assert_eq!(both.transforms[3].su, 4.0);
    }

    #[test]
    fn a_map_transform_scales_then_turns_counter_clockwise_then_moves() {
        let t = MapTransform {
            su: 2.0,
            sv: 3.0,
            tu: 0.5,
            tv: -1.0,
            rw: 90.0,
        };
        // (1, 1) scaled is (2, 3); a quarter turn makes it (-3, 2); moved, (-2.5, 1).
        assert_eq!(t.apply([1.0, 1.0]), [-2.5, 1.0]);
        assert_eq!(MapTransform { rw: -90.0, ..t }.turn(), (-1.0, 0.0));
        assert_eq!(MapTransform { rw: 540.0, ..t }.turn(), (0.0, -1.0));
        let (s, c) = MapTransform { rw: 30.0, ..t }.turn();
        assert!((s - 0.5).abs() < 1e-15 && (c - 0.75f64.sqrt()).abs() < 1e-15);
        assert!(MapTransform::default().is_identity());
        assert_ne!(t.key(), MapTransform::IDENTITY.key());
    }

    #[test]
    fn keys_tell_every_attribute_apart() {
        let base = Finish::default();
        assert!(base.is_unset());
        let variants = [
            Finish {
                metallic: Some(0.0),
                ..base
            },
            Finish {
                roughness: Some(0.0),
                ..base
            },
            Finish {
                emissive: Some([0.0, 0.0, 0.0]),
                ..base
            },
            Finish {
                specular: Some([0.0, 0.0, 0.5]),
                ..base
            },
            Finish {
                alpha_mode: Some(AlphaMode::Blend),
                ..base
            },
            Finish {
                alpha_mode: Some(AlphaMode::Mask),
                ..base
            },
            Finish {
                double_sided: Some(false),
                ..base
            },
        ];
        let mut keys: Vec<FinishKey> = variants.iter().map(Finish::key).collect();
        keys.push(base.key());
        let count = keys.len();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), count);
    }

    #[test]
    fn alpha_modes_by_their_cga_names() {
        assert_eq!(AlphaMode::from_cga("mask"), Some(AlphaMode::Mask));
        assert_eq!(AlphaMode::from_cga("blend"), Some(AlphaMode::Blend));
        assert_eq!(AlphaMode::from_cga("opaque"), Some(AlphaMode::Opaque));
        assert_eq!(AlphaMode::from_cga("Mask"), None);
    }

    #[test]
    fn layers_follow_the_uv_sets() {
        let mut maps = Maps::default();
        assert!(maps.is_empty());
        let normal = Arc::new(Texture {
            path: "n.png".into(),
            image: None,
        });
        *maps.layer_mut(5).unwrap() = Some(normal.clone());
        assert!(maps.layer_mut(0).is_none() && maps.layer_mut(10).is_none());
        assert_eq!(maps.layers()[4], ("normalmap", Some(&normal)));
        assert!(!maps.is_empty());
    }
}
