//! The deformations of the Michelangelo paper: `taper`, `twist` and `shear` along a scope axis
//! (the geometry's work is in [`shapegram_geom::deform`]). A box becomes a mesh; the scope stays
//! as it is, though the deformed geometry may leave it (as CGA's geometry may leave its scope).
//! Implicit solids can be sheared (an affine map), not tapered or twisted.

use std::sync::Arc;

use shapegram_geom::{DAffine3, DMat3, DVec3, deform};
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::Engine;
use crate::error::DeriveError;
use crate::ops::DeformKind;
use crate::program::CExpr;
use crate::shape::{Geometry, State, moved};
use crate::tags::FaceTags;
use crate::value::Value;

impl Engine<'_> {
    /// `taper(axis, factor)`, `twist(axis, degrees)` or `shear(axis, toward, amount)` on the
    /// shape's geometry.
    pub(super) fn deform(
        &mut self,
        state: &mut State,
        kind: DeformKind,
        axis: usize,
        amount: &CExpr,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let value = self.ev.number(amount, state, args)?;
        if kind == DeformKind::Taper && value < 0.0 {
            return Err(DeriveError::at(
                format!(
                    "taper factor {value}: expected a number of at least 0 (0 draws the far end \
                     into a point, 1 changes nothing)"
                ),
                amount.span,
            ));
        }
        let changes = match kind {
            DeformKind::Taper => value != 1.0,
            DeformKind::Twist | DeformKind::Shear { .. } => value != 0.0,
        };
        if !changes {
            return Ok(());
        }
        let size = state.scope.size;
        let name = kind.name();
        if let Geometry::Implicit(implicit) = &state.geometry {
            let DeformKind::Shear { toward } = kind else {
                return Err(DeriveError::at(
                    format!("`{name}` cannot deform this shape: deformation of implicit solids is not supported"),
                    span,
                )
                .with_hint("deform the shape before it becomes implicit; `shear`, an affine map, works on solids"));
            };
            let map = shear_map(size, axis, toward, value);
            state.geometry = state.geometry.with_solid(moved(&implicit.solid, map));
            return Ok(());
        }
        let Some(mesh) = state.geometry.local_mesh(size) else {
            // No geometry, or a box flat in more than one axis: nothing to deform.
            return Ok(());
        };
        let deformed = match kind {
            DeformKind::Taper => deform::taper(&mesh, size, axis, value),
            DeformKind::Twist => deform::twist(&mesh, size, axis, value),
            DeformKind::Shear { toward } => deform::shear(&mesh, size, axis, toward, value),
        };
        let Some(deformed) = deformed else {
            // The arguments were checked above and by the compiler, and numbers are finite: the
            // deformation took the geometry beyond the range of numbers.
            return Err(DeriveError::at(
                format!("`{name}` by {value} takes the geometry out of the range of numbers"),
                amount.span,
            ));
        };
        let tags: Option<Arc<Vec<FaceTags>>> = state.geometry.tags().map(|tags| {
            deformed
                .sources
                .iter()
                // Sliced faces have new corners: edge tags do not follow them.
                .map(|&s| {
                    tags.get(s as usize)
                        .map_or_else(FaceTags::default, |t| FaceTags {
                            edges: None,
                            ..t.clone()
                        })
                })
                .collect::<Vec<_>>()
                .into()
        });
        state.geometry = Geometry::Mesh(Arc::new(deformed.mesh), tags);
        Ok(())
    }
}

/// The shear of a scope of size `size` as an affine map: `p[toward] += amount · p[axis] /
/// size[axis]` (nothing when the scope has no extent along `axis`).
fn shear_map(size: DVec3, axis: usize, toward: usize, amount: f64) -> DAffine3 {
    let mut columns = DMat3::IDENTITY.to_cols_array_2d();
    if size[axis] > 0.0 {
        columns[axis][toward] = amount / size[axis];
    }
    DAffine3::from_mat3(DMat3::from_cols_array_2d(&columns))
}
