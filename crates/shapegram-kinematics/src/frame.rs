//! Rigid frames: a rotation and a translation, composed and inverted exactly enough that a
//! frame times its inverse is the identity to rounding.

use glam::{DAffine3, DMat3, DQuat, DVec3};

/// A rigid transformation: rotate by `rotation`, then move by `translation`. Also a coordinate
/// frame: `translation` is its origin and `rotation` turns the model axes into its axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Unit quaternion.
    pub rotation: DQuat,
    /// Translation, in metres.
    pub translation: DVec3,
}

impl Default for Frame {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Frame {
    /// No rotation, no translation.
    pub const IDENTITY: Self = Self {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A frame from its origin and orthonormal, right-handed axes (the columns of `axes`).
    #[inline]
    pub fn from_axes(origin: DVec3, axes: DMat3) -> Self {
        Self {
            rotation: DQuat::from_mat3(&axes).normalize(),
            translation: origin,
        }
    }

    /// A pure translation.
    pub fn from_translation(translation: DVec3) -> Self {
        Self {
            rotation: DQuat::IDENTITY,
            translation,
        }
    }

    /// A pure rotation.
    pub fn from_rotation(rotation: DQuat) -> Self {
        Self {
            rotation,
            translation: DVec3::ZERO,
        }
    }

    /// `self · other`: first `other`, then `self`.
    #[inline]
    pub fn mul(&self, other: &Frame) -> Frame {
        Frame {
            rotation: (self.rotation * other.rotation).normalize(),
            translation: self.transform_point(other.translation),
        }
    }

    /// The inverse transformation.
    #[inline]
    pub fn inverse(&self) -> Frame {
        let rotation = self.rotation.conjugate();
        Frame {
            rotation,
            translation: -(rotation * self.translation),
        }
    }

    /// A point moved by the transformation.
    #[inline]
    pub fn transform_point(&self, point: DVec3) -> DVec3 {
        self.rotation * point + self.translation
    }

    /// A direction turned by the rotation.
    #[inline]
    pub fn transform_vector(&self, vector: DVec3) -> DVec3 {
        self.rotation * vector
    }

    /// As an affine transformation.
    pub fn to_affine(&self) -> DAffine3 {
        DAffine3::from_rotation_translation(self.rotation, self.translation)
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.rotation.is_finite() && self.translation.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_times_its_inverse_is_the_identity() {
        let f = Frame {
            rotation: DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0),
            translation: DVec3::new(4.0, -2.0, 7.5),
        };
        let p = DVec3::new(1.0, 2.0, 3.0);
        let back = f.inverse().mul(&f).transform_point(p);
        assert!((back - p).length() < 1e-12, "{back}");
        assert!((f.to_affine().transform_point3(p) - f.transform_point(p)).length() < 1e-12);
    }

    #[test]
    fn frames_compose_right_to_left() {
        let turn = Frame::from_rotation(DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2));
        let shift = Frame::from_translation(DVec3::X);
        // Shift first, then turn: (1, 0, 0) goes to (2, 0, 0) and turns to (0, 0, −2).
        let p = turn.mul(&shift).transform_point(DVec3::X);
        assert!((p - DVec3::new(0.0, 0.0, -2.0)).length() < 1e-12, "{p}");
    }
}
