//! Oriented planes.

use crate::DVec3;

/// The plane of points `p` with `normal · p = offset`; `normal` has unit length.
///
/// The positive side is the half-space the normal points into.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal.
    pub normal: DVec3,
    /// Signed distance of the plane from the world origin along `normal`.
    pub offset: f64,
}

impl Plane {
    /// The plane through `point` with the given normal (normalised here; must not be zero).
    pub fn from_point_normal(point: DVec3, normal: DVec3) -> Self {
        let normal = normal.normalize();
        Self {
            normal,
            offset: normal.dot(point),
        }
    }

    /// Signed distance of `p` from the plane: positive on the side the normal points to.
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    /// The same plane facing the other way.
    pub fn flipped(&self) -> Self {
        Self {
            normal: -self.normal,
            offset: -self.offset,
        }
    }

    /// The orthogonal projection of `p` onto the plane.
    pub fn project(&self, p: DVec3) -> DVec3 {
        p - self.normal * self.signed_distance(p)
    }
}
