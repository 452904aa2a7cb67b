//! CGA `comp(f | e | fe | v) { selector : … }`: the faces, edges, face edges or vertices of the
//! shape, each a new shape with a scope of its own, going to the first entry whose selector
//! takes it (or, with `selector = …`, all of an entry's in one shape).

use shapegram_geom::{DVec3, Mesh, Scope, component};
use shapegram_syntax::Span;

use super::Fallible;
use super::implicit::no_solid;
use super::machine::{Engine, Phase, Work};
use crate::ops::{CompEntry, CompKind, CompSelector};
use crate::selectors::Frames;
use crate::shape::{FaceTag, Geometry, State, fills_box};
use crate::trim::Faces;
use crate::value::Value;

impl<'p> Engine<'p> {
    /// Splits the shape into its components and derives each with its entry's body; faces
    /// become flat shapes (boxes where they are rectangles), edges and vertices shapes without
    /// geometry.
    pub(super) fn comp(
        &mut self,
        state: &mut State,
        kind: CompKind,
        entries: &'p [CompEntry],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        no_solid(state, "comp", span)?;
        let Some(world) = state.geometry.world_mesh(&state.scope) else {
            return Ok(());
        };
        if self.phase == Phase::Gather {
            self.occlude(state, None, Some(&world));
        }
        let components = match kind {
            CompKind::Faces => component::faces(&world),
            CompKind::Edges => component::edges(&world),
            CompKind::FaceEdges => component::face_edges(&world),
            CompKind::Vertices => component::vertices(&world),
        };
        // The faces' trim planes, at the edges each shares with the others, for what is
        // inserted below them.
        let faces = (kind == CompKind::Faces).then(|| Faces::new(world));
        let tags = state.geometry.tags();
        let frames = self.ev.frames(&state.scope);
        let mut assigned: Vec<Vec<usize>> = vec![Vec::new(); entries.len()];
        for (c, comp) in components.iter().enumerate() {
            let tag = tags
                .and_then(|t| t.get(comp.source))
                .copied()
                .unwrap_or(FaceTag::None);
            if let Some(e) = entries
                .iter()
                .position(|e| selects(&e.selector, comp, c, tag, &frames, kind))
            {
                assigned[e].push(c);
            }
        }
        let mut made = 0;
        for (entry, chosen) in entries.iter().zip(&assigned) {
            if chosen.is_empty() {
                continue;
            }
            if entry.merge {
                let mut merged = Mesh::new();
                for &c in chosen {
                    merged.append(&Mesh::from_polygon(&components[c].points));
                }
                let mut child = state.spawn();
                child.comp = (0, 1);
                child.comp_sel = entry.selector.code();
                // Faces merged with `=` get no trim planes.
                child.trim = state.trim.with_face(None);
                child.scope = Scope::fit(
                    components[chosen[0]].scope.axes,
                    merged.positions().iter().copied(),
                );
                self.hang_component(state, &mut child, &entry.body, &mut made);
                merged.transform(&child.scope.world_to_local());
                child.geometry = Geometry::mesh(merged);
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
                continue;
            }
            for (i, &c) in chosen.iter().enumerate() {
                let comp = &components[c];
                let mut child = state.spawn();
                child.comp = (i as u32, chosen.len() as u32);
                child.comp_sel = entry.selector.code();
                child.scope = comp.scope;
                if let Some(faces) = &faces {
                    child.trim = state.trim.with_face(Some((faces, comp.source)));
                }
                self.hang_component(state, &mut child, &entry.body, &mut made);
                child.geometry = match kind {
                    CompKind::Faces => {
                        let local: Vec<DVec3> = comp
                            .points
                            .iter()
                            .map(|&p| comp.scope.to_local(p))
                            .collect();
                        if fills_box(&local, comp.scope.size) {
                            Geometry::Box
                        } else {
                            Geometry::mesh(Mesh::from_polygon(&local))
                        }
                    }
                    CompKind::Edges | CompKind::FaceEdges | CompKind::Vertices => Geometry::Empty,
                };
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
            }
        }
        Ok(())
    }
}

/// Whether an entry's selector takes a component: faces by their normal, face edges by their
/// direction out of the face, edges by their scope's y axis (for the slope selectors only).
fn selects(
    selector: &CompSelector,
    comp: &component::Component,
    index: usize,
    tag: FaceTag,
    frames: &Frames,
    kind: CompKind,
) -> bool {
    match (selector, kind) {
        (CompSelector::All, _) => true,
        (CompSelector::Index(i), _) => *i == index,
        (CompSelector::Inside, CompKind::Faces) => tag == FaceTag::Inside,
        (CompSelector::Border, CompKind::Faces) => tag == FaceTag::Border,
        (
            CompSelector::Vertical
            | CompSelector::Horizontal
            | CompSelector::Aslant
            | CompSelector::Nutant,
            CompKind::Edges,
        ) => selector
            .takes_direction(comp.scope.axes.y_axis, index, frames)
            .unwrap_or(false),
        (_, CompKind::Faces | CompKind::FaceEdges) => selector
            .takes_direction(comp.normal, index, frames)
            .unwrap_or(false),
        _ => false,
    }
}
