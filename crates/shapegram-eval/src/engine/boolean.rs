//! `union`, `subtract`, `intersect` and `inline`: operands derived at once, each from a copy
//! of the shape, their leaves merged back into the shape (see [`crate::booleans`] for the
//! geometry).
//!
//! The shapes an operand derives are shapes of the derivation (they count against the limits
//! and appear in the tree) but never leaves of the model: their geometry goes into the shape.

use std::sync::Arc;

use shapegram_geom::{Color, Mesh, Scope};
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::{Engine, Work};
use crate::asset_look::{AssetLook, AssetMaterial, NO_MATERIAL, WornAsset};
use crate::booleans::{BooleanOp, Combined, Operand, WELD, combine};
use crate::error::DeriveError;
use crate::ops::InlineMode;
use crate::program::CStmt;
use crate::shape::{Geometry, State};
use crate::texturing::Texturing;
use crate::value::Value;

impl<'p> Engine<'p> {
    /// `union`, `subtract`, `intersect`: the result replaces the shape's geometry, in the scope
    /// of the target (the first operand) and with its attributes and material.
    pub(super) fn boolean(
        &mut self,
        state: &mut State,
        kind: BooleanOp,
        operands: &'p [Option<Vec<CStmt>>; 2],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let mut derived = Vec::with_capacity(2);
        for operand in operands {
            derived.push(match operand {
                Some(stmts) => Some(self.derive_now(stmts, state, span, args)?),
                None => None,
            });
        }
        let target = derived[0].as_ref().and_then(|leaves| leaves.first());
        let frame = target.map_or(state.scope, |leaf| leaf.scope);
        let b_look = match &derived[1] {
            Some(leaves) => leaves.first().map(Look::of),
            None => Some(Look::of(state)),
        };
        let operand = |leaves: &Option<Vec<State>>| match leaves {
            Some(leaves) => Operand::new(&meshes_in(leaves, &frame)),
            None => Operand::new(&meshes_in(std::slice::from_ref(state), &frame)),
        };
        let Combined { mesh, from_b } = guarded(span, || {
            let (a, b) = (operand(&derived[0]), operand(&derived[1]));
            combine(kind, &a, &b)
        })?;
        if let Some(target) = target {
            state.attrs = target.attrs.clone();
            take_look(state, target);
        }
        state.scope = frame;
        if let Some(b_look) = b_look
            && from_b.contains(&true)
        {
            wear_both(state, &mesh, &from_b, b_look);
        }
        state.geometry = geometry(mesh);
        Ok(())
    }

    /// `inline(mode) { ops }`: the leaves of the operations replace the shape's geometry, in
    /// its own scope; the material is the first leaf's, the other attributes stay the shape's.
    pub(super) fn inline(
        &mut self,
        state: &mut State,
        mode: InlineMode,
        body: &'p [CStmt],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let leaves = self.derive_now(body, state, span, args)?;
        let parts = meshes_in(&leaves, &state.scope);
        let mesh = match mode {
            InlineMode::Unify => guarded(span, || Operand::new(&parts).into_mesh())?,
            InlineMode::Append | InlineMode::Recompose => {
                let mut mesh = Mesh::new();
                for part in &parts {
                    mesh.append(part);
                }
                match mode {
                    InlineMode::Recompose => mesh.welded(WELD),
                    _ => mesh,
                }
            }
        };
        if let Some(first) = leaves.first() {
            take_look(state, first);
        }
        state.geometry = geometry(mesh);
        Ok(())
    }

    /// Derives `stmts` on a copy of the shape to the end, depth first, and returns the leaves
    /// in order.
    fn derive_now(
        &mut self,
        stmts: &'p [CStmt],
        state: &mut State,
        span: Span,
        args: &[Value],
    ) -> Fallible<Vec<State>> {
        let mut copy = state.spawn();
        // Leaves wait on the stack rather than going to the model.
        let base = std::mem::replace(&mut self.base, usize::MAX);
        let leaves = self.derive_copy(stmts, &mut copy, span, args);
        self.base = base;
        leaves
    }

    fn derive_copy(
        &mut self,
        stmts: &'p [CStmt],
        copy: &mut State,
        span: Span,
        args: &[Value],
    ) -> Fallible<Vec<State>> {
        let mut stack = Vec::new();
        self.run_stmts(stmts, copy, args, &mut stack)?;
        stack.reverse();
        let mut leaves = Vec::new();
        while let Some(work) = stack.pop() {
            match work {
                Work::Leaf(leaf) => leaves.push(*leaf),
                Work::Rewrite(task) => {
                    let base = stack.len();
                    let parked = self.parked.len();
                    self.apply(task, &mut stack)?;
                    // A rule asking about other shapes waits for the second phase, too late
                    // for an operand that is needed now.
                    if self.parked.len() > parked {
                        return Err(DeriveError::at(
                            "an operand derived here reaches a rule that asks about other shapes (occlusion, snapping), which cannot be derived at once",
                            span,
                        )
                        .with_hint("move the context query out of the operand's rules"));
                    }
                    stack[base..].reverse();
                }
            }
        }
        Ok(leaves)
    }
}

/// The meshes of shapes, in the local coordinates of `frame`.
fn meshes_in(shapes: &[State], frame: &Scope) -> Vec<Mesh> {
    let to_frame = frame.world_to_local();
    shapes
        .iter()
        .filter_map(|shape| {
            let mut mesh = shape.geometry.world_mesh(&shape.scope)?;
            mesh.transform(&to_frame);
            Some(mesh)
        })
        .collect()
}

/// Runs the mesh Boolean, turning a panic of the crate (a bug there, which its docs ask to be
/// reported) into an error at the operation rather than the end of the derivation.
fn guarded<T>(span: Span, boolean: impl FnOnce() -> T) -> Fallible<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(boolean)).map_err(|_| {
        DeriveError::at("the mesh Boolean failed on these operands", span)
            .with_hint("a bug of the mesh Boolean (manifold-rust): please report the grammar")
    })
}

/// The colour and material of a shape.
struct Look {
    color: Color,
    material: Option<Arc<str>>,
    textured: bool,
}

impl Look {
    fn of(state: &State) -> Self {
        Self {
            color: state.color,
            material: state.material.clone(),
            textured: state.texturing.as_deref().is_some_and(dresses),
        }
    }
}

/// Whether a texturing puts images or an asset's own materials on the faces; uvs alone (a
/// primitive cube's) change nothing of a face's look.
fn dresses(texturing: &Texturing) -> bool {
    texturing.maps.iter().any(Option::is_some)
        || texturing
            .asset
            .as_ref()
            .is_some_and(|asset| asset.look.has_materials())
}

/// The faces of operand B keep B's colour and material where they differ from the target's:
/// the result wears them as an asset's look (see [`crate::asset_look`]), B's faces with B's
/// material (named `bool.B` when B has no name), the others with the shape's own, and the
/// shape's colour stops overriding them (as CityEngine writes conflicting materials to the
/// faces). Textured operands keep the target's texturing alone.
fn wear_both(state: &mut State, mesh: &Mesh, from_b: &[bool], b: Look) {
    let same = b.color == state.color && b.material == state.material;
    if same || b.textured || state.texturing.as_deref().is_some_and(dresses) {
        return;
    }
    let material = AssetMaterial {
        name: Some(b.material.unwrap_or_else(|| Arc::from("bool.B"))),
        color: b.color,
        texture: None,
        surface: None,
    };
    let faces = from_b
        .iter()
        .map(|&is_b| if is_b { 0 } else { NO_MATERIAL })
        .collect();
    let look = AssetLook::of_faces(mesh.clone(), faces, vec![material]);
    let placed = state.scope.local_to_world();
    state.texturing = Some(Arc::new(Texturing {
        asset: Some(WornAsset::new(Arc::new(look), placed)),
        ..Texturing::default()
    }));
    state.painted = false;
}

/// The shape takes the colour and material of `from`.
fn take_look(state: &mut State, from: &State) {
    state.color = from.color;
    state.painted = from.painted;
    state.material = from.material.clone();
    state.texturing = from.texturing.clone();
}

fn geometry(mesh: Mesh) -> Geometry {
    match mesh.is_empty() {
        true => Geometry::Empty,
        false => Geometry::mesh(mesh),
    }
}
