//! The primitive solids, centred at the origin with y up, and their fields.
//!
//! Every field here is the negated signed distance (or, for the cone and the pyramid, the negated
//! maximum of the distances to their bounding planes): positive inside, zero on the surface,
//! negative outside, and 1-Lipschitz, which is what lets the mesher skip empty space.

use glam::DVec3;

use crate::bond::Bond;
use crate::error::{Result, positive};

/// A primitive solid in its local frame: centred at the origin, axis of revolution along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// A ball of this radius.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// A cuboid with these full side lengths along x, y, z.
    Cuboid {
        /// Side lengths.
        size: DVec3,
    },
    /// A cylinder around the y axis.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Height along y.
        height: f64,
    },
    /// A cone around the y axis: base disc at `y = -height/2`, apex at `y = +height/2`.
    Cone {
        /// Base radius.
        radius: f64,
        /// Height along y.
        height: f64,
    },
    /// A pyramid on a `size.x` × `size.z` rectangle at `y = -size.y/2`, apex at `y = +size.y/2`.
    Pyramid {
        /// Base sides along x and z, height along y.
        size: DVec3,
    },
    /// A ring torus lying in the xz-plane.
    Torus {
        /// Distance from the centre to the middle of the tube.
        major: f64,
        /// Radius of the tube (less than `major`).
        minor: f64,
    },
    /// A capsule around the y axis: a cylinder of `length` capped with half-balls.
    Capsule {
        /// Radius.
        radius: f64,
        /// Distance between the centres of the two caps (may be 0: a ball).
        length: f64,
    },
}

impl Primitive {
    /// Checks the parameters: sizes finite and positive, the torus tube thinner than its ring.
    pub fn validate(&self) -> Result<Self> {
        match *self {
            Self::Sphere { radius } => {
                positive("sphere radius", radius)?;
            }
            Self::Cuboid { size } | Self::Pyramid { size } => {
                let name = self.name();
                positive(&format!("{name} size x"), size.x)?;
                positive(&format!("{name} size y"), size.y)?;
                positive(&format!("{name} size z"), size.z)?;
            }
            Self::Cylinder { radius, height } | Self::Cone { radius, height } => {
                let name = self.name();
                positive(&format!("{name} radius"), radius)?;
                positive(&format!("{name} height"), height)?;
            }
            Self::Torus { major, minor } => {
                positive("torus major radius", major)?;
                positive("torus minor radius", minor)?;
                if minor >= major {
                    return Err(crate::ImplicitError::new(format!(
                        "invalid torus: the minor radius {minor} must be less than the major \
                         radius {major}"
                    )));
                }
            }
            Self::Capsule { radius, length } => {
                positive("capsule radius", radius)?;
                if !(length.is_finite() && length >= 0.0) {
                    return Err(crate::ImplicitError::new(format!(
                        "invalid capsule length {length}: expected a finite number of at least 0"
                    )));
                }
            }
        }
        Ok(*self)
    }

    /// The lowercase name used in messages and in the text form.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Sphere { .. } => "sphere",
            Self::Cuboid { .. } => "box",
            Self::Cylinder { .. } => "cylinder",
            Self::Cone { .. } => "cone",
            Self::Pyramid { .. } => "pyramid",
            Self::Torus { .. } => "torus",
            Self::Capsule { .. } => "capsule",
        }
    }

    /// Half the extent of the bounding box along each axis (the box is centred at the origin).
    pub fn half_extent(&self) -> DVec3 {
        match *self {
            Self::Sphere { radius } => DVec3::splat(radius),
            Self::Cuboid { size } | Self::Pyramid { size } => size * 0.5,
            Self::Cylinder { radius, height } | Self::Cone { radius, height } => {
                DVec3::new(radius, height * 0.5, radius)
            }
            Self::Torus { major, minor } => DVec3::new(major + minor, minor, major + minor),
            Self::Capsule { radius, length } => DVec3::new(radius, length * 0.5 + radius, radius),
        }
    }

    /// How fast, per unit `c`, the box holding `{f > −c}` grows past [`Self::half_extent`] along
    /// each axis. The exact distances grow by `c` (rate 1). The cone's and the pyramid's fields
    /// are distances to their planes, which fall behind the true distance past the apex and the
    /// base rim: `{f > −c}` is the solid with every plane moved out by `c`, whose apex rises by
    /// `c / sin` of the side's slope from the axis and whose base widens by more than `c`.
    pub(crate) fn level_rate(&self) -> DVec3 {
        match *self {
            Self::Cone { radius, height } => {
                let norm = radius.hypot(height);
                let side = (norm + radius) / height;
                DVec3::new(side, norm / radius, side)
            }
            Self::Pyramid { size } => {
                let (a, h, c) = (size.x * 0.5, size.y, size.z * 0.5);
                let (na, nc) = (a.hypot(h), c.hypot(h));
                DVec3::new((na + a) / h, (na / a).min(nc / c), (nc + c) / h)
            }
            _ => DVec3::ONE,
        }
    }

    /// The field at one point: positive inside, zero on the surface, negative outside.
    pub fn value(&self, p: DVec3) -> f64 {
        let mut out = [0.0];
        self.values(&[p.x], &[p.y], &[p.z], &mut out);
        out[0]
    }

    /// The field at many points at once (coordinates in separate slices, all of `out`'s length).
    pub fn values(&self, xs: &[f64], ys: &[f64], zs: &[f64], out: &mut [f64]) {
        let n = out.len();
        let (xs, ys, zs) = (&xs[..n], &ys[..n], &zs[..n]);
        match *self {
            Self::Sphere { radius } => {
                for i in 0..n {
                    out[i] = radius - (xs[i] * xs[i] + ys[i] * ys[i] + zs[i] * zs[i]).sqrt();
                }
            }
            Self::Cuboid { size } => {
                let b = size * 0.5;
                for i in 0..n {
                    let (qx, qy, qz) = (xs[i].abs() - b.x, ys[i].abs() - b.y, zs[i].abs() - b.z);
                    let (ox, oy, oz) = (qx.max(0.0), qy.max(0.0), qz.max(0.0));
                    let outside = (ox * ox + oy * oy + oz * oz).sqrt();
                    out[i] = -(outside + qx.max(qy).max(qz).min(0.0));
                }
            }
            Self::Cylinder { radius, height } => {
                let half = height * 0.5;
                for i in 0..n {
                    let dr = (xs[i] * xs[i] + zs[i] * zs[i]).sqrt() - radius;
                    let dy = ys[i].abs() - half;
                    let (or, oy) = (dr.max(0.0), dy.max(0.0));
                    out[i] = -((or * or + oy * oy).sqrt() + dr.max(dy).min(0.0));
                }
            }
            Self::Cone { radius, height } => {
                let half = height * 0.5;
                let norm = radius.hypot(height);
                let (nr, ny) = (height / norm, radius / norm);
                for i in 0..n {
                    let rho = (xs[i] * xs[i] + zs[i] * zs[i]).sqrt();
                    let side = rho * nr + (ys[i] - half) * ny;
                    out[i] = -side.max(-half - ys[i]);
                }
            }
            Self::Pyramid { size } => {
                let (a, half, c) = (size.x * 0.5, size.y * 0.5, size.z * 0.5);
                let (na, nc) = (a.hypot(size.y), c.hypot(size.y));
                let (ax, ay) = (size.y / na, a / na);
                let (cz, cy) = (size.y / nc, c / nc);
                for i in 0..n {
                    let up = ys[i] - half;
                    let side_x = xs[i].abs() * ax + up * ay;
                    let side_z = zs[i].abs() * cz + up * cy;
                    out[i] = -side_x.max(side_z).max(-half - ys[i]);
                }
            }
            Self::Torus { major, minor } => {
                for i in 0..n {
                    let ring = (xs[i] * xs[i] + zs[i] * zs[i]).sqrt() - major;
                    out[i] = minor - (ring * ring + ys[i] * ys[i]).sqrt();
                }
            }
            Self::Capsule { radius, length } => {
                let half = length * 0.5;
                for i in 0..n {
                    let dy = ys[i] - ys[i].clamp(-half, half);
                    out[i] = radius - (xs[i] * xs[i] + dy * dy + zs[i] * zs[i]).sqrt();
                }
            }
        }
    }

    /// The bonds (Definition 4) in the local frame: the centre with no direction, then points on
    /// the surface where the axes leave the solid (−x, +x, −y, +y, −z, +z), each facing outward.
    /// For the cuboid these are the face centres of the paper's Figure 6; for the cone and the
    /// pyramid the ±y bonds are the base centre and the apex, and the side bonds sit at mid-height;
    /// the torus's ±y bonds sit on top of and under the tube at `x = major`.
    pub fn bonds(&self) -> Vec<Bond> {
        let mut bonds = vec![Bond::new(DVec3::ZERO, DVec3::ZERO)];
        let h = self.half_extent();
        let side = match *self {
            // Half-way up a cone or pyramid the side is half as far out as at the base.
            Self::Cone { .. } | Self::Pyramid { .. } => DVec3::new(h.x * 0.5, 0.0, h.z * 0.5),
            _ => h,
        };
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let dir = DVec3::AXES[axis] * sign;
                let reach = if axis == 1 { h.y } else { side[axis] };
                let mut point = dir * reach;
                if let Self::Torus { major, .. } = *self {
                    // The axis crosses the hole: the ±y bonds sit on top of the tube instead.
                    if axis == 1 {
                        point.x = major;
                    }
                }
                bonds.push(Bond::new(point, dir));
            }
        }
        bonds
    }
}
