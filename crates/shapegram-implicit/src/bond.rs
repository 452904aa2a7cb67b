//! Bonds and labels (Definitions 4 and 5 of the SG+M paper).

use glam::{DAffine3, DVec3};

/// How close two unit directions must be to count as equal or opposite.
const DIRECTION_TOLERANCE: f64 = 1e-9;

/// A bond `B = (P, D)`: a point where a shape can be joined and the direction it faces. A zero
/// direction means "any direction": such a bond labels with every other bond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bond {
    /// Where the shapes meet.
    pub point: DVec3,
    /// The outward direction, unit length or zero.
    pub dir: DVec3,
}

impl Bond {
    /// A bond at `point` facing `dir` (normalised; zero stays zero).
    pub fn new(point: DVec3, dir: DVec3) -> Self {
        Self {
            point,
            dir: dir.normalize_or_zero(),
        }
    }

    /// Whether the bond has no direction and so matches any bond.
    pub fn is_free(&self) -> bool {
        self.dir == DVec3::ZERO
    }

    /// Whether two bonds can form a label (eq. 8) once their points are brought together: their
    /// directions are opposite, or one of them has none.
    pub fn labels_with(&self, other: &Bond) -> bool {
        self.is_free()
            || other.is_free()
            || (self.dir + other.dir).length_squared() < DIRECTION_TOLERANCE
    }

    /// The bond carried by an affine map: the point mapped, the direction mapped as a normal
    /// (by the inverse transpose) so it keeps facing out of the mapped solid.
    pub fn transformed(&self, map: &DAffine3) -> Self {
        let normal_map = map.matrix3.inverse().transpose();
        // Rounding leaves traces like 1e-16 in components that should be zero; clear them so
        // quarter turns keep axis directions exact and labels compare exactly.
        let dir = (normal_map * self.dir).normalize_or_zero();
        let dir = DVec3::select(dir.abs().cmplt(DVec3::splat(1e-12)), DVec3::ZERO, dir);
        Self::new(map.transform_point3(self.point), dir)
    }
}

/// A label (Definition 5): which bond of the base and which bond of the new shape were joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Label {
    /// Index of the base's bond.
    pub base: usize,
    /// Index of the new shape's bond.
    pub shape: usize,
}

/// The first bond of `shape_bonds` that labels with `base`, preferring a directed bond exactly
/// opposite to `base` over a free one (a free bond on either side matches anything).
pub fn matching_bond(base: &Bond, shape_bonds: &[Bond]) -> Option<usize> {
    let directed = shape_bonds
        .iter()
        .position(|b| !b.is_free() && !base.is_free() && base.labels_with(b));
    directed.or_else(|| shape_bonds.iter().position(|b| base.labels_with(b)))
}
