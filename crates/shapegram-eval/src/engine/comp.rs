//! CGA `comp(f | e | fe | v | fv | h) { selector : … }`: the faces, edges, face edges,
//! vertices or face vertices of the shape, each a new shape with a scope of its own, going to
//! the first entry whose selector takes it (or, with `selector = …`, all of an entry's in one
//! shape). Faces keep their tags. Shapegram's faces have no holes, so `comp(h)` takes nothing.

use shapegram_geom::{DVec3, Mesh, Scope, component};
use shapegram_syntax::Span;

use super::Fallible;
use super::implicit::no_solid;
use super::machine::{Engine, Phase, Work};
use super::roof_edges::RoofEdges;
use crate::ops::{CompEntry, CompKind, CompSelector};
use crate::selectors::Frames;
use crate::shape::{Geometry, State, fills_box};
use crate::tags::{Around, FaceTags, OffsetPart, TagIndex, TagQuery};
use crate::trim::Faces;
use crate::value::Value;

/// What selectors read about the components of one component split.
struct Judge<'a> {
    kind: CompKind,
    components: &'a [component::Component],
    tags: Option<&'a [FaceTags]>,
    /// The components' tags, when a selector asks for tags.
    index: Option<TagIndex>,
    /// The roof edges, when a selector asks for them.
    roof: Option<RoofEdges>,
    frames: Frames<'a>,
}

impl Judge<'_> {
    /// What face `f` carries.
    fn face(&self, f: usize) -> Option<&FaceTags> {
        self.tags.and_then(|t| t.get(f))
    }
}

impl<'p> Engine<'p> {
    /// Splits the shape into its components and derives each with its entry's body; faces
    /// become flat shapes (boxes where they are rectangles without tags), edges and vertices
    /// shapes without geometry.
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
            CompKind::FaceVertices => component::face_vertices(&world),
            CompKind::Holes => Vec::new(),
        };
        let wants = |f: fn(&CompSelector) -> bool| entries.iter().any(|e| f(&e.selector));
        let scope = state.scope;
        let tags = match &state.geometry {
            Geometry::Mesh(_, tags) => tags.clone(),
            _ => None,
        };
        let judge = Judge {
            kind,
            components: &components,
            tags: tags.as_deref(),
            index: wants(asks_tags).then(|| TagIndex::new(&world, tags.as_deref())),
            roof: (kind == CompKind::Edges && wants(asks_roof))
                .then(|| RoofEdges::new(&world, &components, state.scope.axes.y_axis)),
            frames: self.ev.frames(&scope),
        };
        let mut assigned: Vec<Vec<usize>> = vec![Vec::new(); entries.len()];
        for c in 0..components.len() {
            let mut probe = None;
            for (e, entry) in entries.iter().enumerate() {
                if self.takes(&entry.selector, &judge, c, (state, &mut probe), args)? {
                    assigned[e].push(c);
                    break;
                }
            }
        }
        // The faces' trim planes, at the edges each shares with the others, for what is
        // inserted below them.
        let faces = (kind == CompKind::Faces).then(|| Faces::new(world));
        let mut made = 0;
        for (entry, chosen) in entries.iter().zip(&assigned) {
            if chosen.is_empty() {
                continue;
            }
            if entry.merge {
                let mut merged = Mesh::new();
                let mut tags = Vec::new();
                for &c in chosen {
                    merged.append(&Mesh::from_polygon(&components[c].points));
                    tags.push(carried(&judge, c));
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
                child.geometry = if kind == CompKind::Faces {
                    Geometry::tagged_mesh(merged, tags)
                } else {
                    Geometry::mesh(merged)
                };
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
                continue;
            }
            for (i, &c) in chosen.iter().enumerate() {
                let comp = match (&entry.selector, &judge.roof) {
                    (CompSelector::Roof(_), Some(roof)) => roof.oriented(&components[c], c),
                    _ => components[c].clone(),
                };
                let mut child = state.spawn();
                child.comp = (i as u32, chosen.len() as u32);
                child.comp_sel = entry.selector.code();
                child.scope = comp.scope;
                if let Some(faces) = &faces {
                    child.trim = state.trim.with_face(Some((faces, comp.source)));
                }
                self.hang_component(state, &mut child, &entry.body, &mut made);
                child.geometry = component_geometry(&judge, &comp, c);
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
            }
        }
        Ok(())
    }

    /// Whether a selector takes component `c`. Conditions are evaluated on the component's
    /// shape, made once (in `probe`) from the parent's `state`.
    fn takes(
        &mut self,
        selector: &CompSelector,
        judge: &Judge,
        c: usize,
        (state, probe): (&State, &mut Option<State>),
        args: &[Value],
    ) -> Fallible<bool> {
        Ok(match selector {
            CompSelector::Not(s) => !self.takes(s, judge, c, (state, probe), args)?,
            CompSelector::And(a, b) => {
                self.takes(a, judge, c, (state, probe), args)?
                    && self.takes(b, judge, c, (state, probe), args)?
            }
            CompSelector::Or(a, b) => {
                self.takes(a, judge, c, (state, probe), args)?
                    || self.takes(b, judge, c, (state, probe), args)?
            }
            CompSelector::Test(condition) => {
                let shape = probe.get_or_insert_with(|| component_shape(state, judge, c));
                self.ev.condition(condition, shape, args)?
            }
            CompSelector::TaggedBy(query, around) => {
                let shape = probe.get_or_insert_with(|| component_shape(state, judge, c));
                let query = TagQuery::parse(&self.ev.string(query, shape, args)?);
                is_tagged(judge, c, &query, *around)
            }
            other => selects(other, judge, c),
        })
    }
}

/// Whether the tag query matches component `c` (or, by `around`, its edges or vertices).
fn is_tagged(judge: &Judge, c: usize, query: &TagQuery, around: Around) -> bool {
    let comp = &judge.components[c];
    judge.index.as_ref().is_some_and(|index| match judge.kind {
        CompKind::Faces => index.face(comp.source, query, around),
        CompKind::Edges | CompKind::FaceEdges => {
            index.edge(comp.points[0], comp.points[1], query, around)
        }
        CompKind::Vertices | CompKind::FaceVertices => index.vertex(comp.points[0], query),
        CompKind::Holes => false,
    })
}

/// The shape of component `c` made from its parent's `state`, for conditions to read.
fn component_shape(state: &State, judge: &Judge, c: usize) -> State {
    let comp = &judge.components[c];
    let mut shape = state.clone();
    shape.scope = comp.scope;
    shape.geometry = component_geometry(judge, comp, c);
    shape.comp = (c as u32, judge.components.len() as u32);
    shape
}

/// Whether a selector or a part of it asks for tags.
fn asks_tags(selector: &CompSelector) -> bool {
    match selector {
        CompSelector::Tagged(..) | CompSelector::TaggedBy(..) => true,
        CompSelector::Not(s) => asks_tags(s),
        CompSelector::And(a, b) | CompSelector::Or(a, b) => asks_tags(a) || asks_tags(b),
        _ => false,
    }
}

/// Whether a selector or a part of it asks for roof edges.
fn asks_roof(selector: &CompSelector) -> bool {
    match selector {
        CompSelector::Roof(_) => true,
        CompSelector::Not(s) => asks_roof(s),
        CompSelector::And(a, b) | CompSelector::Or(a, b) => asks_roof(a) || asks_roof(b),
        _ => false,
    }
}

/// The tags a face component takes into its own shape: its face's, without the part of an
/// `offset` (which `comp` reads, not passes on).
fn carried(judge: &Judge, c: usize) -> FaceTags {
    judge
        .face(judge.components[c].source)
        .map_or_else(FaceTags::default, |t| FaceTags {
            part: OffsetPart::None,
            ..t.clone()
        })
}

/// The geometry of a component's own shape: a face's polygon (a box where it is a rectangle
/// without tags), nothing for the others.
fn component_geometry(judge: &Judge, comp: &component::Component, c: usize) -> Geometry {
    if judge.kind != CompKind::Faces {
        return Geometry::Empty;
    }
    let local: Vec<DVec3> = comp
        .points
        .iter()
        .map(|&p| comp.scope.to_local(p))
        .collect();
    let tags = carried(judge, c);
    if tags.is_plain() && fills_box(&local, comp.scope.size) {
        Geometry::Box
    } else {
        Geometry::tagged_mesh(Mesh::from_polygon(&local), vec![tags])
    }
}

/// Whether a selector that needs no component shape takes component `c`: faces by their
/// normal, face edges and face vertices by their direction out of the face, edges by their
/// scope's y axis (for the slope selectors only); tags and roof edges from the judge.
fn selects(selector: &CompSelector, judge: &Judge, c: usize) -> bool {
    let comp = &judge.components[c];
    let kind = judge.kind;
    let part = judge.face(comp.source).map_or(OffsetPart::None, |t| t.part);
    match (selector, kind) {
        (CompSelector::All, _) => true,
        (CompSelector::Index(i), _) => *i == c,
        (CompSelector::Inside, CompKind::Faces) => part == OffsetPart::Inside,
        (CompSelector::Border, CompKind::Faces) => part == OffsetPart::Border,
        (CompSelector::Tagged(query, around), _) => is_tagged(judge, c, query, *around),
        (CompSelector::Roof(edge), CompKind::Edges) => judge
            .roof
            .as_ref()
            .is_some_and(|r| r.kind(c) == Some(*edge)),
        (
            CompSelector::Vertical
            | CompSelector::Horizontal
            | CompSelector::Aslant
            | CompSelector::Nutant,
            CompKind::Edges,
        ) => selector
            .takes_direction(comp.scope.axes.y_axis, c, &judge.frames)
            .unwrap_or(false),
        (_, CompKind::Faces | CompKind::FaceEdges | CompKind::FaceVertices) => selector
            .takes_direction(comp.normal, c, &judge.frames)
            .unwrap_or(false),
        _ => false,
    }
}
