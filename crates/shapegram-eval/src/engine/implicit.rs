//! Implicit solids in shapes: `implicit(kind)` and `implicit("file.cave")` make the shape a
//! solid, and `csg("group", …)` makes its solid a member of a CSG group (each group is combined
//! and meshed when the derivation is done, see [`crate::solids`]). Operations that need faces
//! refuse solids with [`no_solid`].

use std::sync::Arc;

use shapegram_geom::{DAffine3, DVec3};
use shapegram_implicit::Solid;
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::Engine;
use crate::error::DeriveError;
use crate::ops::{CsgKind, ImplicitKind};
use crate::program::CExpr;
use crate::shape::{Csg, Geometry, Implicit, State};
use crate::value::Value;

impl Engine<'_> {
    /// `implicit("file.cave")`: the solid of the implicit grammar at the path, stretched to
    /// the scope (see [`implicit_in_scope`]).
    pub(super) fn implicit_file(
        &mut self,
        state: &mut State,
        path: &CExpr,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let file = self.ev.string(path, state, args)?;
        let solid = self.grammar_solid(&file, path.span)?;
        implicit_in_scope(state, &solid, &file, span)
    }

    /// `csg("group", union | subtract | intersect [, fillet])` and `csg("group", morph,
    /// amount)`: the group's name and the amount evaluated, then [`join_group`].
    pub(super) fn csg(
        &mut self,
        state: &mut State,
        kind: CsgKind,
        group: &CExpr,
        amount: Option<&CExpr>,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let group = match self.ev.eval(group, state, args)? {
            Value::Str(name) => name,
            v => {
                return Err(DeriveError::at(
                    format!(
                        "expected a group name (a string), found a {}",
                        v.type_name()
                    ),
                    group.span,
                ));
            }
        };
        let amount = match amount {
            Some(e) => Some((self.ev.number(e, state, args)?, e.span)),
            None => None,
        };
        join_group(state, kind, group, amount, span)
    }

    /// The solid of the implicit grammar at `path`.
    fn grammar_solid(&self, path: &str, span: Span) -> Fallible<Solid> {
        let Some(loader) = &self.options.assets else {
            return Err(DeriveError::at(
                format!("cannot run `{path}`: no asset folder is set"),
                span,
            ));
        };
        loader
            .solid(path)
            .map_err(|why| DeriveError::at(format!("cannot run `{path}`: {why}"), span))
    }
}

/// An error for operations that need faces on a shape that holds an implicit solid.
pub(super) fn no_solid(state: &State, op: &str, span: Span) -> Fallible<()> {
    if !matches!(state.geometry, Geometry::Implicit(_)) {
        return Ok(());
    }
    Err(DeriveError::at(
        format!("{op} needs faces, but an implicit solid has none until the model is made"),
        span,
    )
    .with_hint("split the shape into parts first, then make the parts implicit"))
}

/// `implicit(kind)`: the shape becomes the solid `kind` filling its scope.
pub(super) fn implicit(state: &mut State, kind: ImplicitKind, span: Span) -> Fallible<()> {
    let size = state.scope.size;
    if !size.cmpgt(DVec3::ZERO).all() {
        return Err(DeriveError::at(
            format!(
                "implicit({}) needs a scope with volume, but its size is {} × {} × {}",
                kind.name(),
                size.x,
                size.y,
                size.z
            ),
            span,
        )
        .with_hint("extrude the shape first, or give it a size with `s(…)`"));
    }
    let solid = crate::solids::fitted(kind, size)
        .map_err(|e| DeriveError::at(format!("implicit({}): {e}", kind.name()), span))?;
    set_solid(state, solid, span);
    Ok(())
}

/// Makes the shape's geometry `solid`, in no group, made by the operation at `span`.
fn set_solid(state: &mut State, solid: Solid, span: Span) {
    let csg = None;
    state.geometry = Geometry::Implicit(Arc::new(Implicit { solid, csg, span }));
}

/// `implicit("file.cave")`: the shape becomes `solid` with its bounds stretched to the scope,
/// which must have volume.
fn implicit_in_scope(state: &mut State, solid: &Solid, file: &str, span: Span) -> Fallible<()> {
    let size = state.scope.size;
    let bounds = solid.bounds().filter(|b| b.size().cmpgt(DVec3::ZERO).all());
    let (true, Some(bounds)) = (size.cmpgt(DVec3::ZERO).all(), bounds) else {
        return Err(DeriveError::at(
            format!(
                "implicit(\"{file}\") needs a scope with volume and a grammar that makes a solid"
            ),
            span,
        ));
    };
    let map = DAffine3::from_scale(size / bounds.size()) * DAffine3::from_translation(-bounds.min);
    let solid = solid
        .transform(&map)
        .map_err(|e| DeriveError::at(format!("implicit(\"{file}\"): {}", e.message()), span))?;
    set_solid(state, solid, span);
    Ok(())
}

/// `csg("group", union)` and friends: the shape's solid (a box becomes one) joins `group`.
fn join_group(
    state: &mut State,
    kind: CsgKind,
    group: Arc<str>,
    amount: Option<(f64, Span)>,
    span: Span,
) -> Fallible<()> {
    let name = kind.name();
    let value = match amount {
        None => 0.0,
        Some((a, at)) if kind == CsgKind::Morph && !(0.0..=1.0).contains(&a) => {
            return Err(DeriveError::at(
                format!(
                    "morph amount {a}: expected 0 (the group as it is) to 1 (the member added)"
                ),
                at,
            ));
        }
        Some((k, at)) if !(k.is_finite() && k >= 0.0) => {
            return Err(DeriveError::at(
                format!("fillet radius {k}: expected a finite number of at least 0"),
                at,
            ));
        }
        Some((a, _)) => a,
    };
    let op = kind.op(value);
    let solid = match &state.geometry {
        Geometry::Implicit(implicit) => implicit.solid.clone(),
        Geometry::Box if state.scope.size.cmpgt(DVec3::ZERO).all() => {
            crate::solids::fitted(ImplicitKind::Box, state.scope.size)
                .map_err(|e| DeriveError::at(format!("csg(\"{group}\", {name}): {e}"), span))?
        }
        _ => {
            return Err(DeriveError::at(
                format!("csg(\"{group}\", {name}) needs an implicit solid or a box with volume"),
                span,
            )
            .with_hint(
                "polygon meshes are not solids: fill the scope with one first, e.g. `implicit(box)`",
            ));
        }
    };
    let csg = Some(Csg { group, op, span });
    state.geometry = Geometry::Implicit(Arc::new(Implicit { solid, csg, span }));
    Ok(())
}
