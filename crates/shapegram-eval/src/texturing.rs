//! What a shape carries for texturing, as CGA has it: up to ten projections set up in world
//! space (`setupProjection`), up to ten uv sets (`projectUV`, edited by `tileUV` and friends)
//! and the texture layers of its material (`texture`, `set(material.colormap, …)`).
//!
//! A projection is affine in world position, and so is every uv set made from one, edited in uv
//! space, or carried along when `t`, `r`, `s`, `center` or `mirror` move the geometry: a uv set
//! is therefore kept as an affine map of world position (see [`UvMap`]), not per vertex, and a
//! leaf's uvs are that map evaluated at its vertices. Splits, component splits and extrusions
//! leave geometry where it is, so they need nothing.

use std::sync::Arc;

use shapegram_geom::{DAffine3, DVec2, DVec3, Texture};

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
    /// read for the colour map.
    pub maps: [Option<Arc<Texture>>; UV_SETS],
}

impl Texturing {
    /// Whether any uv set is present: only then does moving the geometry concern it.
    pub fn has_uvs(&self) -> bool {
        self.uvs.iter().any(Option::is_some)
    }

    /// The uv set a texture layer is drawn with: its own, else set 0 (as CityEngine's
    /// exporters fall back), else none.
    pub fn uvs_of_layer(&self, layer: usize) -> Option<&UvMap> {
        self.uvs.get(layer)?.as_ref().or(self.uvs[0].as_ref())
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
    fn layers_and_their_deprecated_names() {
        assert_eq!(layer("colormap"), Some(0));
        assert_eq!(layer("dirtmap"), Some(2));
        assert_eq!(layer("map4"), Some(4));
        assert_eq!(layer("metallicmap"), Some(9));
        assert_eq!(layer("colour"), None);
    }
}
