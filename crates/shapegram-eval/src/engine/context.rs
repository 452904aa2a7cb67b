//! The engine's side of context-sensitive rules (the queries themselves are in
//! [`crate::context`]): in phase 1, `label` and `comp` record occluders and `snap` records snap
//! planes; in phase 2, `split(…, snap)` asks where the snap planes are.

use std::sync::Arc;

use shapegram_geom::Mesh;

use super::Fallible;
use super::machine::{Engine, Phase};
use crate::context::{Occluder, snap_planes};
use crate::program::CExpr;
use crate::shape::State;
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
            let planes = snap_planes(&state.scope, axes, tag.transpose()?, self.ev.lot);
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
        if let Some(occluder) = Occluder::new(scope, geometry, world, symbol, label, lot, parent) {
            state.occluder = self.occluders.len() as u32;
            self.occluders.push(occluder);
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
        Ok(match self.ev.context {
            Some(context) => {
                context.snap_positions(&state.scope, axis, self.ev.lot, tag.as_deref())
            }
            None => Vec::new(),
        })
    }
}
