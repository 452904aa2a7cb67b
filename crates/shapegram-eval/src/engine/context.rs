//! The engine's side of context-sensitive rules (the queries themselves are in
//! [`crate::context`]): in phase 1, `label` and `comp` record occluders and `snap` records snap
//! planes; in phase 2, `split(…, snap)` asks where the snap planes are.

use std::sync::Arc;

use shapegram_geom::{Mesh, Scope};

use super::Fallible;
use super::machine::{Engine, Phase};
use crate::context::{Occluder, posed_scope, snap_planes};
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::value::Value;

impl Engine<'_> {
    /// `label("name")` (or `tag`): the shape becomes an occluder with that name, in phase 1.
    pub(super) fn label(
        &mut self,
        state: &mut State,
        name: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let name = self.ev.string(name, state, args)?;
        if self.phase == Phase::Gather {
            self.occlude(state, Some(name), None);
        }
        Ok(())
    }

    /// `snap(axes [, "tag"])`: snap planes across the given scope axes, at both ends of the
    /// scope, recorded in phase 1.
    pub(super) fn snap(
        &mut self,
        state: &mut State,
        axes: [bool; 3],
        tag: Option<&CExpr>,
        args: &[Value],
    ) -> Fallible<()> {
        if self.phase == Phase::Gather {
            let tag = tag.map(|t| self.ev.string(t, state, args));
            let (lot, section) = (self.ev.lot, state.section);
            let planes = snap_planes(&state.scope, axes, tag.transpose()?, lot, section);
            self.snaps.extend(planes);
        }
        Ok(())
    }

    /// Records the shape as an occluder (when its geometry is a closed solid); its descendants
    /// will not see it in their queries.
    pub(super) fn occlude(
        &mut self,
        state: &mut State,
        label: Option<Arc<str>>,
        world: Option<&Mesh>,
    ) {
        let (scope, geometry, symbol) = (&state.scope, &state.geometry, state.symbol);
        let (lot, parent) = (self.ev.lot, state.occluder);
        let occluder = Occluder::new(scope, geometry, world, symbol, label, lot, parent);
        if let Some(occluder) = self.posable(occluder, state.section, scope, geometry) {
            state.occluder = self.occluders.len() as u32;
            self.occluders.push(occluder);
        }
    }

    /// An occluder of a shape hanging from `section`, made posable when the grammar builds a
    /// skeleton: phase 2 sees it where the pose puts it.
    pub(super) fn posable(
        &self,
        occluder: Option<Occluder>,
        section: u32,
        scope: &Scope,
        geometry: &Geometry,
    ) -> Option<Occluder> {
        match &self.skeleton {
            Some(_) => Some(occluder?.hanging_from(section, scope, geometry)),
            None => occluder,
        }
    }

    /// Where a snapping split of the shape along `axis` moves its boundaries to.
    pub(super) fn snap_positions(
        &mut self,
        state: &mut State,
        axis: usize,
        tag: Option<&CExpr>,
        args: &[Value],
    ) -> Fallible<Vec<f64>> {
        let tag = tag.map(|t| self.ev.string(t, state, args)).transpose()?;
        // Positions along the axis do not change when the scope is posed; the planes are
        // placed by the pose, so the scope is too.
        let scope = match self.ev.motions.get(state.section as usize) {
            Some(motion) => posed_scope(&state.scope, motion),
            None => state.scope,
        };
        Ok(match self.ev.context {
            Some(context) => context.snap_positions(&scope, axis, self.ev.lot, tag.as_deref()),
            None => Vec::new(),
        })
    }
}
