//! Axis-aligned bounding boxes.

use crate::{DVec3, RELATIVE_EPSILON};

/// An axis-aligned bounding box, `min <= max` on every axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: DVec3,
    /// The corner with the largest coordinates.
    pub max: DVec3,
}

impl Aabb {
    /// The box spanned by two corners, in any order.
    pub fn new(a: DVec3, b: DVec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box holding every point, or `None` for no points.
    pub fn from_points(points: impl IntoIterator<Item = DVec3>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = it.next()?;
        Some(it.fold(Self::new(first, first), |b, p| b.including(p)))
    }

    /// This box grown to include `p`.
    pub fn including(self, p: DVec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box holding both boxes.
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Extent along each axis.
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// The centre point.
    pub fn center(&self) -> DVec3 {
        (self.min + self.max) * 0.5
    }

    /// Length of the diagonal.
    pub fn diagonal(&self) -> f64 {
        self.size().length()
    }

    /// The distance below which two points of geometry this size count as the same point.
    pub fn tolerance(&self) -> f64 {
        RELATIVE_EPSILON * self.diagonal().max(1.0)
    }

    /// Whether `p` lies inside the box or within `eps` of it.
    pub fn contains(&self, p: DVec3, eps: f64) -> bool {
        p.cmpge(self.min - eps).all() && p.cmple(self.max + eps).all()
    }
}
