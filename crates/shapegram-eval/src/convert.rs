//! CGA's `convert`: positions and orientations between the scope's frame and the world.
//!
//! Shapegram's shapes have no pivot or object frame apart from the world: the scope's position
//! and rotation (`scope.tx`, `scope.rx`, …) are world coordinates. So `pivot` and `object`
//! name the world frame here.

use shapegram_geom::{DMat3, DQuat, DVec3, Scope};

/// A coordinate system `convert` converts between.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CoordinateSystem {
    Scope,
    World,
}

impl CoordinateSystem {
    /// The frame a `convert` argument names.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "scope" => Some(Self::Scope),
            "world" | "pivot" | "object" => Some(Self::World),
            _ => None,
        }
    }
}

/// A position (`orient` false) or Euler angles in degrees, intrinsic x-y-z as `r()` turns and
/// `scope.rx` reads (`orient` true), given in `from` and returned in `to`.
pub(crate) fn convert(
    scope: &Scope,
    from: CoordinateSystem,
    to: CoordinateSystem,
    orient: bool,
    v: DVec3,
) -> DVec3 {
    if from == to {
        return v;
    }
    let to_world = from == CoordinateSystem::Scope;
    if orient {
        let rotation = DMat3::from_quat(DQuat::from_euler(
            glam::EulerRot::XYZ,
            v.x.to_radians(),
            v.y.to_radians(),
            v.z.to_radians(),
        ));
        let turned = if to_world {
            scope.axes * rotation
        } else {
            scope.axes.transpose() * rotation
        };
        let (x, y, z) = DQuat::from_mat3(&turned).to_euler(glam::EulerRot::XYZ);
        return DVec3::new(x.to_degrees(), y.to_degrees(), z.to_degrees());
    }
    if to_world {
        scope.origin + scope.axes * v
    } else {
        scope.axes.transpose() * (v - scope.origin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        a.abs_diff_eq(b, 1e-9)
    }

    #[test]
    fn positions_and_angles_go_between_a_turned_scope_and_the_world() {
        // A scope at (10, 0, 5) turned 90° about y: its x axis points along −z.
        let axes = DMat3::from_rotation_y(std::f64::consts::FRAC_PI_2);
        let scope = Scope::new(DVec3::new(10.0, 0.0, 5.0), axes, DVec3::ONE);
        let world = convert(
            &scope,
            CoordinateSystem::Scope,
            CoordinateSystem::World,
            false,
            DVec3::new(2.0, 1.0, 0.0),
        );
        assert!(close(world, DVec3::new(10.0, 1.0, 3.0)), "{world}");
        let back = convert(
            &scope,
            CoordinateSystem::World,
            CoordinateSystem::Scope,
            false,
            world,
        );
        assert!(close(back, DVec3::new(2.0, 1.0, 0.0)), "{back}");
        let angles = convert(
            &scope,
            CoordinateSystem::Scope,
            CoordinateSystem::World,
            true,
            DVec3::ZERO,
        );
        assert!(close(angles, DVec3::new(0.0, 90.0, 0.0)), "{angles}");
        let angles = convert(
            &scope,
            CoordinateSystem::World,
            CoordinateSystem::Scope,
            true,
            DVec3::new(0.0, 90.0, 0.0),
        );
        assert!(close(angles, DVec3::ZERO), "{angles}");
        let same = convert(
            &scope,
            CoordinateSystem::World,
            CoordinateSystem::World,
            false,
            DVec3::ONE,
        );
        assert_eq!(same, DVec3::ONE);
    }
}
