//! CGA `translate(abs | rel, scope | pivot | object | world, x, y, z)` and
//! `rotate(abs | rel, …, xAngle, yAngle, zAngle)`: the scope moved or turned about its origin in
//! a chosen frame, the geometry with it. Shapegram keeps no pivot apart from the scope, so
//! `pivot` is the scope's frame.

use shapegram_geom::{DAffine3, DMat3, DQuat, DVec3};

use super::Fallible;
use super::machine::Engine;
use super::texturing::follow_geometry;
use crate::ops::CoordSystem;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Engine<'_> {
    /// `translate(…)`: the scope's origin set to a position in the frame (`abs`) or moved by a
    /// vector along its axes (`rel`).
    pub(super) fn translate_in(
        &mut self,
        state: &mut State,
        absolute: bool,
        system: CoordSystem,
        values: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let v = self.vector(values, state, args)?;
        let (origin, axes) = self.frame(state, system);
        let before = state.scope;
        state.scope.origin = if absolute { origin } else { before.origin } + axes * v;
        follow_geometry(state, &before, DAffine3::IDENTITY);
        Ok(())
    }

    /// `rotate(…)`: the scope turned about its origin, to angles about the frame's axes (`abs`,
    /// x then y then z, each about the axes the ones before turned) or by them (`rel`).
    pub(super) fn rotate_in(
        &mut self,
        state: &mut State,
        absolute: bool,
        system: CoordSystem,
        values: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let r = self.vector(values, state, args)? * (std::f64::consts::PI / 180.0);
        let turn = DMat3::from_quat(
            DQuat::from_rotation_x(r.x) * DQuat::from_rotation_y(r.y) * DQuat::from_rotation_z(r.z),
        );
        let (_, axes) = self.frame(state, system);
        let before = state.scope;
        state.scope.axes = if absolute {
            axes * turn
        } else {
            axes * turn * axes.transpose() * before.axes
        };
        follow_geometry(state, &before, DAffine3::IDENTITY);
        Ok(())
    }

    /// The origin and axes of a frame for this shape.
    fn frame(&self, state: &State, system: CoordSystem) -> (DVec3, DMat3) {
        match system {
            CoordSystem::Scope => (state.scope.origin, state.scope.axes),
            CoordSystem::Object => (self.ev.initial_origin, self.ev.object_axes),
            CoordSystem::World => (DVec3::ZERO, DMat3::IDENTITY),
        }
    }
}
