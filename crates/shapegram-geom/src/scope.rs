//! Scopes: the oriented boxes every grammar operation works in.

use crate::{Aabb, DAffine3, DMat3, DQuat, DVec3};

/// An oriented box: an origin corner, orthonormal axes and a size along each axis.
///
/// Axes are right-handed except after a mirroring scale (a negative `s(…)` in a grammar), which
/// flips one axis; geometry placed in a mirrored scope is mirrored, with its faces turned so that
/// they still face outward.
///
/// Local coordinates `(x, y, z)` with `0 <= x <= size.x` (and so on) cover the box; `y` is "up"
/// for a scope made by extruding a footprint, as in CGA.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scope {
    /// The corner at local `(0, 0, 0)`, in world coordinates.
    pub origin: DVec3,
    /// Columns are the unit x, y and z axes of the scope in world coordinates (determinant ±1).
    pub axes: DMat3,
    /// Extent along each axis; a size of zero marks a flat (2D) or degenerate scope.
    pub size: DVec3,
}

/// Which point a rotation of a scope turns around.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pivot {
    /// The scope's origin corner.
    Origin,
    /// The scope's centre.
    Center,
}

impl Default for Scope {
    /// The unit-less scope at the world origin with world axes and zero size.
    fn default() -> Self {
        Self::axis_aligned(DVec3::ZERO, DVec3::ZERO)
    }
}

impl Scope {
    /// A scope with the given axes (columns; they should be orthonormal and right-handed).
    pub fn new(origin: DVec3, axes: DMat3, size: DVec3) -> Self {
        Self { origin, axes, size }
    }

    /// A scope with world-aligned axes.
    pub fn axis_aligned(origin: DVec3, size: DVec3) -> Self {
        Self::new(origin, DMat3::IDENTITY, size)
    }

    /// The world-aligned scope covering a bounding box.
    pub fn from_aabb(bounds: &Aabb) -> Self {
        Self::axis_aligned(bounds.min, bounds.size())
    }

    /// The tightest scope with the given axes around a set of world points (zero size for none).
    /// This is the alignment helper behind CGA's `alignScopeToAxes` and component scopes.
    pub fn fit(axes: DMat3, points: impl IntoIterator<Item = DVec3>) -> Self {
        let inverse = axes.transpose();
        match Aabb::from_points(points.into_iter().map(|p| inverse * p)) {
            Some(local) => Self::new(axes * local.min, axes, local.size()),
            None => Self::new(DVec3::ZERO, axes, DVec3::ZERO),
        }
    }

    /// The unit x axis in world coordinates.
    pub fn x_axis(&self) -> DVec3 {
        self.axes.x_axis
    }

    /// The unit y axis in world coordinates.
    pub fn y_axis(&self) -> DVec3 {
        self.axes.y_axis
    }

    /// The unit z axis in world coordinates.
    pub fn z_axis(&self) -> DVec3 {
        self.axes.z_axis
    }

    /// A scope-local point in world coordinates.
    pub fn to_world(&self, local: DVec3) -> DVec3 {
        self.origin + self.axes * local
    }

    /// A world point in scope-local coordinates.
    pub fn to_local(&self, world: DVec3) -> DVec3 {
        self.axes.transpose() * (world - self.origin)
    }

    /// A scope-local direction in world coordinates.
    pub fn direction_to_world(&self, local: DVec3) -> DVec3 {
        self.axes * local
    }

    /// A world direction in scope-local coordinates.
    pub fn direction_to_local(&self, world: DVec3) -> DVec3 {
        self.axes.transpose() * world
    }

    /// The map from scope-local to world coordinates (no scaling: local units are world units).
    pub fn local_to_world(&self) -> DAffine3 {
        DAffine3::from_mat3_translation(self.axes, self.origin)
    }

    /// The map from world to scope-local coordinates.
    pub fn world_to_local(&self) -> DAffine3 {
        self.local_to_world().inverse()
    }

    /// The map taking the unit cube `[0, 1]³` onto this scope's box, for fitting assets.
    pub fn unit_cube_to_world(&self) -> DAffine3 {
        self.local_to_world() * DAffine3::from_scale(self.size)
    }

    /// The centre of the box in world coordinates.
    pub fn center(&self) -> DVec3 {
        self.to_world(self.size * 0.5)
    }

    /// The eight corners in world coordinates, ordered by local (x, y, z) bits: index
    /// `x + 2y + 4z`.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|i| {
            let bit = |b: usize| if i & b != 0 { 1.0 } else { 0.0 };
            self.to_world(self.size * DVec3::new(bit(1), bit(2), bit(4)))
        })
    }

    /// World bounds of the box.
    pub fn aabb(&self) -> Aabb {
        Aabb::from_points(self.corners()).expect("a scope has corners")
    }

    /// Volume of the box.
    pub fn volume(&self) -> f64 {
        self.size.x * self.size.y * self.size.z
    }

    /// Moves the origin by a vector given in scope-local axes (CGA `t`).
    #[inline]
    pub fn translate(&mut self, local: DVec3) {
        self.origin += self.axes * local;
    }

    /// Moves the origin by a world-space vector.
    pub fn translate_world(&mut self, world: DVec3) {
        self.origin += world;
    }

    /// Rotates the scope by a rotation given in its own local frame, about `pivot`.
    pub fn rotate_local(&mut self, rotation: DQuat, pivot: Pivot) {
        let pivot_world = match pivot {
            Pivot::Origin => self.origin,
            Pivot::Center => self.center(),
        };
        let world_rotation = DMat3::from_quat(rotation);
        // A rotation expressed in local axes is A·R·Aᵀ in world axes.
        let turn = self.axes * world_rotation * self.axes.transpose();
        self.axes = orthonormalize(turn * self.axes);
        self.origin = pivot_world + turn * (self.origin - pivot_world);
    }

    /// Rotates about the scope's own x, then y, then z axes by angles in degrees, about `pivot`
    /// (CGA `r(x, y, z)` and `rotate`).
    pub fn rotate_euler_degrees(&mut self, degrees: DVec3, pivot: Pivot) {
        let r = degrees * (std::f64::consts::PI / 180.0);
        let rotation = DQuat::from_rotation_x(r.x) * DQuat::from_rotation_y(r.y);
        // Intrinsic x-y-z: each later rotation turns about the already-rotated axes.
        self.rotate_local(rotation * DQuat::from_rotation_z(r.z), pivot);
    }

    /// Rotates about a world axis through a world point (angle in degrees).
    pub fn rotate_world(&mut self, axis: DVec3, degrees: f64, pivot: DVec3) {
        let turn = DMat3::from_axis_angle(axis.normalize(), degrees.to_radians());
        self.axes = orthonormalize(turn * self.axes);
        self.origin = pivot + turn * (self.origin - pivot);
    }

    /// Sets the size (CGA `s`); the origin corner stays where it is.
    pub fn set_size(&mut self, size: DVec3) {
        self.size = size;
    }

    /// Multiplies the size per axis about `pivot` (the centre stays fixed for `Pivot::Center`).
    pub fn scale(&mut self, factors: DVec3, pivot: Pivot) {
        let new_size = self.size * factors;
        if pivot == Pivot::Center {
            self.translate((self.size - new_size) * 0.5);
        }
        self.size = new_size;
    }

    /// Moves the scope so that its centre lies on the given centre, on the selected local axes
    /// only (CGA `center(xz)` and friends).
    pub fn center_on(&mut self, center: DVec3, axes: [bool; 3]) {
        let delta = self.direction_to_local(center - self.center());
        let mask = DVec3::new(
            f64::from(u8::from(axes[0])),
            f64::from(u8::from(axes[1])),
            f64::from(u8::from(axes[2])),
        );
        self.translate(delta * mask);
    }

    /// The world-aligned scope around this box's corners.
    pub fn aligned_to_world(&self) -> Self {
        Self::fit(DMat3::IDENTITY, self.corners())
    }

    /// Whether a world point lies in the box, within `eps`.
    pub fn contains(&self, world: DVec3, eps: f64) -> bool {
        let p = self.to_local(world);
        p.cmpge(DVec3::splat(-eps)).all() && p.cmple(self.size + eps).all()
    }
}

/// Re-orthonormalises a nearly orthonormal frame (Gram–Schmidt, keeping x, then y), so that long
/// chains of rotations do not drift. A mirrored (left-handed) frame stays mirrored.
fn orthonormalize(m: DMat3) -> DMat3 {
    let x = m.x_axis.normalize();
    let y = (m.y_axis - x * x.dot(m.y_axis)).normalize();
    let z = x.cross(y);
    DMat3::from_cols(x, y, if m.determinant() < 0.0 { -z } else { z })
}
