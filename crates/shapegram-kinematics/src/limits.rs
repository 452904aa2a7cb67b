//! Joint limits and poses: per-axis ranges of rotation (degrees) and translation (metres), and
//! a current pose clamped into them.

use std::fmt;

use glam::{DQuat, DVec3};

use crate::Frame;

/// An axis of a joint's frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The joint's x axis.
    X,
    /// The joint's y axis.
    Y,
    /// The joint's z axis.
    Z,
}

impl Axis {
    /// The three axes in order.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    /// The lower-case name: `x`, `y` or `z`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// A closed interval `min..=max`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Range {
    /// Lower end.
    pub min: f64,
    /// Upper end.
    pub max: f64,
}

impl Range {
    /// `min..=max`.
    pub const fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// Whether the range allows any movement.
    #[inline]
    pub fn is_free(&self) -> bool {
        self.min < self.max
    }
}

/// Per-axis limits of a joint; the default locks every axis (all ranges 0..=0), as the paper's
/// joints are locked until a limitation rule frees them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Limits {
    /// Rotation about the joint's x, y and z axes, in degrees.
    pub rotation: [Range; 3],
    /// Translation along the joint's x, y and z axes, in metres.
    pub translation: [Range; 3],
}

impl Limits {
    /// Checks that every end is finite and no range is reversed.
    pub fn validate(&self) -> Result<(), KinematicError> {
        for (kind, ranges) in [
            ("rotation", &self.rotation),
            ("translation", &self.translation),
        ] {
            for (axis, range) in Axis::ALL.into_iter().zip(ranges) {
                if !(range.min.is_finite() && range.max.is_finite()) {
                    return Err(KinematicError::NotFinite {
                        what: format!("the {kind} limit about {}", axis.name()),
                    });
                }
                if range.min > range.max {
                    return Err(KinematicError::ReversedRange {
                        what: format!("the {kind} limit about {}", axis.name()),
                        range: *range,
                    });
                }
            }
        }
        Ok(())
    }

    /// Whether any axis may move.
    pub fn is_free(&self) -> bool {
        self.rotation
            .iter()
            .chain(&self.translation)
            .any(Range::is_free)
    }

    /// Checks that `pose` is finite and within the limits (the first component outside them is
    /// the error).
    pub fn admit(&self, pose: &Pose) -> Result<(), KinematicError> {
        pose.validate()?;
        if self.contains(pose) {
            return Ok(());
        }
        let (_, clamped) = self.clamp(pose);
        match clamped.first() {
            None => Ok(()),
            Some(&clamped) => {
                let ranges = if clamped.rotation {
                    &self.rotation
                } else {
                    &self.translation
                };
                Err(KinematicError::OutsideLimits {
                    clamped,
                    range: ranges[clamped.axis as usize],
                })
            }
        }
    }

    /// Whether every component of `pose` lies within its range (the usual case, checked
    /// before anything is clamped).
    #[inline]
    fn contains(&self, pose: &Pose) -> bool {
        let within = |v: DVec3, ranges: &[Range; 3]| {
            (0..3).all(|i| ranges[i].min <= v[i] && v[i] <= ranges[i].max)
        };
        within(pose.rotation, &self.rotation) && within(pose.translation, &self.translation)
    }

    /// `pose` with every component brought into its range, and what had to be moved.
    pub fn clamp(&self, pose: &Pose) -> (Pose, Vec<Clamped>) {
        if self.contains(pose) {
            return (*pose, Vec::new());
        }
        let mut clamped = Vec::new();
        let mut fit = |requested: DVec3, ranges: &[Range; 3], rotation: bool| {
            let mut value = requested;
            for (i, axis) in Axis::ALL.into_iter().enumerate() {
                let range = ranges[i];
                let limit = requested[i].clamp(range.min, range.max);
                if limit != requested[i] {
                    clamped.push(Clamped {
                        axis,
                        rotation,
                        requested: requested[i],
                        limit,
                    });
                    value[i] = limit;
                }
            }
            value
        };
        let rotation = fit(pose.rotation, &self.rotation, true);
        let translation = fit(pose.translation, &self.translation, false);
        (
            Pose {
                rotation,
                translation,
            },
            clamped,
        )
    }
}

/// The current pose of a joint, relative to its rest frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// Rotation about the joint's x, then y, then z axis (fixed axes, Blender's `XYZ` Euler
    /// order), in degrees.
    pub rotation: DVec3,
    /// Translation along the joint's axes, in metres, applied before the rotation.
    pub translation: DVec3,
}

impl Pose {
    /// Whether the pose is the rest pose.
    #[inline]
    pub fn is_rest(&self) -> bool {
        self.rotation == DVec3::ZERO && self.translation == DVec3::ZERO
    }

    /// The pose as a transformation in the joint's frame: translate, then rotate about x, y, z.
    pub fn frame(&self) -> Frame {
        let [x, y, z] = self.rotation.to_array().map(f64::to_radians);
        let rotation =
            DQuat::from_rotation_z(z) * DQuat::from_rotation_y(y) * DQuat::from_rotation_x(x);
        Frame::from_translation(self.translation).mul(&Frame::from_rotation(rotation))
    }

    /// Checks that every component is finite.
    pub fn validate(&self) -> Result<(), KinematicError> {
        if self.rotation.is_finite() && self.translation.is_finite() {
            Ok(())
        } else {
            Err(KinematicError::NotFinite {
                what: "the pose".to_string(),
            })
        }
    }
}

/// A pose component that was outside its limits and was set to the nearest limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clamped {
    /// The axis.
    pub axis: Axis,
    /// A rotation (degrees) rather than a translation (metres).
    pub rotation: bool,
    /// What was asked for.
    pub requested: f64,
    /// What was set.
    pub limit: f64,
}

impl Clamped {
    /// `the rotation about y of 120°`, and the unit for further values.
    fn describe(&self) -> (String, &'static str) {
        let (kind, unit) = if self.rotation {
            ("rotation about", "°")
        } else {
            ("translation along", " m")
        };
        let what = format!(
            "the {kind} {} of {}{unit}",
            self.axis.name(),
            self.requested
        );
        (what, unit)
    }
}

impl fmt::Display for Clamped {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (what, unit) = self.describe();
        write!(
            f,
            "{what} is outside the joint's limits; clamped to {}{unit}",
            self.limit
        )
    }
}

/// Why a kinematic operation was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum KinematicError {
    /// A value is NaN or infinite.
    NotFinite {
        /// What the value is.
        what: String,
    },
    /// A range whose minimum exceeds its maximum.
    ReversedRange {
        /// What the range is.
        what: String,
        /// The range.
        range: Range,
    },
    /// A parallel split of a section without a parent (it would make a second root).
    ParallelAtRoot,
    /// A parallel split of a section with children (they would need several parents).
    ParallelWithChildren,
    /// A pose component outside the joint's limits.
    OutsideLimits {
        /// The component, and the limit it would be clamped to.
        clamped: Clamped,
        /// The range of that axis.
        range: Range,
    },
}

impl fmt::Display for KinematicError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFinite { what } => write!(f, "{what} is not a finite number"),
            Self::ReversedRange { what, range } => write!(
                f,
                "{what} runs from {} to {}: the minimum must not exceed the maximum",
                range.min, range.max
            ),
            Self::ParallelAtRoot => f.write_str(
                "a parallel split needs a shape with a kinematic parent, and this shape is the skeleton's root: split sequentially, or split a child",
            ),
            Self::OutsideLimits { clamped, range } => {
                let (what, unit) = clamped.describe();
                write!(
                    f,
                    "{what} is outside the joint's limits ({}{unit} to {}{unit})",
                    range.min, range.max
                )
            }
            Self::ParallelWithChildren => f.write_str(
                "a parallel split needs a shape without kinematic children, and this shape has some: split sequentially",
            ),
        }
    }
}

impl std::error::Error for KinematicError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_limits_lock_every_axis_and_clamp_to_zero() {
        let pose = Pose {
            rotation: DVec3::new(10.0, 0.0, -5.0),
            translation: DVec3::ZERO,
        };
        let (rest, clamped) = Limits::default().clamp(&pose);
        assert!(rest.is_rest());
        assert_eq!(clamped.len(), 2);
        assert_eq!(
            clamped[0].to_string(),
            "the rotation about x of 10° is outside the joint's limits; clamped to 0°"
        );
    }

    #[test]
    fn reversed_and_infinite_limits_are_errors() {
        let mut limits = Limits::default();
        limits.rotation[1] = Range::new(30.0, -30.0);
        assert_eq!(
            limits.validate().unwrap_err().to_string(),
            "the rotation limit about y runs from 30 to -30: the minimum must not exceed the maximum"
        );
        limits.rotation[1] = Range::new(f64::NEG_INFINITY, 0.0);
        assert_eq!(
            limits.validate().unwrap_err().to_string(),
            "the rotation limit about y is not a finite number"
        );
    }

    #[test]
    fn a_pose_translates_then_rotates_x_before_z() {
        let pose = Pose {
            rotation: DVec3::new(90.0, 0.0, 90.0),
            translation: DVec3::new(0.0, 0.0, 1.0),
        };
        // y turns to z about x, then z turns... z is the rotation axis of the second turn: stays.
        let p = pose.frame().transform_point(DVec3::Y);
        assert!((p - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12, "{p}");
        // x stays under the x turn, then turns to y about z.
        let q = pose.frame().transform_vector(DVec3::X);
        assert!((q - DVec3::Y).length() < 1e-12, "{q}");
    }
}
