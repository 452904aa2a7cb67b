//! CGA `comp(f | e | fe | v | fv | m | g | h) { selector : … }`: the faces, edges, face
//! edges, vertices, face vertices, materials or asset groups of the shape, each a new shape
//! with a scope of its own, going to the first entry whose selector takes it (or, with
//! `selector = …`, all of an entry's in one shape). Faces keep their tags. Shapegram's faces
//! have no holes, so `comp(h)` takes nothing.

use shapegram_geom::{DVec3, Mesh, Scope, component};
use shapegram_syntax::Span;

use super::Fallible;
use super::implicit::no_solid;
use super::machine::{Engine, Phase, Work};
use super::roof_edges::RoofEdges;
use crate::face_sets::{asset_groups, material_groups};
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
            CompKind::Faces | CompKind::Materials | CompKind::Groups => component::faces(&world),
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
        // Material and group components are sets of faces: a selector takes one when it takes
        // one of its faces (or, for conditions and indices, the set itself).
        let sets = match kind {
            CompKind::Materials => Some(material_groups(state, &world)),
            CompKind::Groups => Some(asset_groups(state, &world)),
            _ => None,
        };
        let sets = sets.map(|sets| {
            sets.into_iter()
                .map(|(_, faces)| {
                    (0..components.len())
                        .filter(|&c| faces.contains(&components[c].source))
                        .collect::<Vec<usize>>()
                })
                .filter(|members| !members.is_empty())
                .collect::<Vec<_>>()
        });
        let kind = if sets.is_some() {
            CompKind::Faces
        } else {
            kind
        };
        let judge = Judge {
            kind,
            components: &components,
            tags: tags.as_deref().map(Vec::as_slice),
            index: wants(asks_tags)
                .then(|| TagIndex::new(&world, tags.as_deref().map(Vec::as_slice))),
            roof: (kind == CompKind::Edges && wants(asks_roof))
                .then(|| RoofEdges::new(&world, &components, state.scope.axes.y_axis)),
            frames: self.ev.frames(&scope),
        };
        if let Some(sets) = &sets {
            return self.comp_sets(state, &judge, sets, entries, span, args, out);
        }
        let mut assigned: Vec<Vec<usize>> = vec![Vec::new(); entries.len()];
        let mut made = 0;
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
        for (entry, chosen) in entries.iter().zip(&assigned) {
            if chosen.is_empty() {
                continue;
            }
            if entry.merge {
                let child = merged_shape(state, &judge, chosen);
                self.derive_component(state, child, (entry, (0, 1), &mut made), span, args, out)?;
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

    /// `comp(m)` and `comp(g)`: each set of faces (`sets`, by their components) goes to the
    /// first entry whose selector takes it, a shape of its own or (with `=`) merged with the
    /// entry's others.
    #[allow(clippy::too_many_arguments)]
    fn comp_sets(
        &mut self,
        state: &mut State,
        judge: &Judge,
        sets: &[Vec<usize>],
        entries: &'p [CompEntry],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let mut assigned: Vec<Vec<usize>> = vec![Vec::new(); entries.len()];
        for (g, members) in sets.iter().enumerate() {
            let mut probe = None;
            for (e, entry) in entries.iter().enumerate() {
                let unit = (g, members.as_slice());
                if self.takes_set(&entry.selector, judge, unit, (state, &mut probe), args)? {
                    assigned[e].push(g);
                    break;
                }
            }
        }
        let mut made = 0;
        for (entry, chosen) in entries.iter().zip(&assigned) {
            let shapes: Vec<Vec<usize>> = if entry.merge {
                vec![chosen.iter().flat_map(|&g| sets[g].clone()).collect()]
            } else {
                chosen.iter().map(|&g| sets[g].clone()).collect()
            };
            let total = shapes.len() as u32;
            for (i, faces) in shapes.iter().enumerate().filter(|(_, f)| !f.is_empty()) {
                let child = merged_shape(state, judge, faces);
                let at = (entry, (i as u32, total), &mut made);
                self.derive_component(state, child, at, span, args, out)?;
            }
        }
        Ok(())
    }

    /// Derives the shape of merged components (`merged_shape`) with an entry's body, as
    /// component `position` of its entry (`made` counts the component shapes made so far).
    fn derive_component(
        &mut self,
        state: &mut State,
        (scope, geometry): (Scope, Geometry),
        (entry, position, made): (&'p CompEntry, (u32, u32), &mut u64),
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let mut child = state.spawn();
        child.comp = position;
        child.comp_sel = entry.selector.code();
        // Merged components get no trim planes.
        child.trim = state.trim.with_face(None);
        child.scope = scope;
        self.hang_component(state, &mut child, &entry.body, made);
        child.geometry = geometry;
        self.admit(&mut child, span)?;
        self.run_stmts(&entry.body, &mut child, args, out)
    }

    /// Whether a selector takes set `g` of components (`members`, material components): an
    /// index or a condition by the set, any other selector when it takes one of the members.
    fn takes_set(
        &mut self,
        selector: &CompSelector,
        judge: &Judge,
        (g, members): (usize, &[usize]),
        (state, probe): (&State, &mut Option<State>),
        args: &[Value],
    ) -> Fallible<bool> {
        let set = |probe: &mut Option<State>| {
            probe
                .get_or_insert_with(|| {
                    let mut shape = state.clone();
                    (shape.scope, shape.geometry) = merged_shape(state, judge, members);
                    shape
                })
                .clone()
        };
        let unit = (g, members);
        Ok(match selector {
            CompSelector::Not(s) => !self.takes_set(s, judge, unit, (state, probe), args)?,
            CompSelector::And(a, b) => {
                self.takes_set(a, judge, unit, (state, probe), args)?
                    && self.takes_set(b, judge, unit, (state, probe), args)?
            }
            CompSelector::Or(a, b) => {
                self.takes_set(a, judge, unit, (state, probe), args)?
                    || self.takes_set(b, judge, unit, (state, probe), args)?
            }
            CompSelector::Index(i) => *i == g,
            CompSelector::Test(condition) => self.ev.condition(condition, &mut set(probe), args)?,
            CompSelector::TaggedBy(query, around) => {
                let query = TagQuery::parse(&self.ev.string(query, &mut set(probe), args)?);
                members
                    .iter()
                    .any(|&c| is_tagged(judge, c, &query, *around))
            }
            other => members.iter().any(|&c| selects(other, judge, c)),
        })
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
        CompKind::Faces | CompKind::Materials | CompKind::Groups => {
            index.face(comp.source, query, around)
        }
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

/// The scope and geometry of face components merged into one shape: the scope in the first
/// face's frame, fitted around them; the faces keep their tags.
fn merged_shape(state: &State, judge: &Judge, faces: &[usize]) -> (Scope, Geometry) {
    let mut merged = Mesh::new();
    let mut tags = Vec::new();
    for &c in faces {
        merged.append(&Mesh::from_polygon(&judge.components[c].points));
        tags.push(carried(judge, c));
    }
    let axes = faces
        .first()
        .map_or(state.scope.axes, |&c| judge.components[c].scope.axes);
    let scope = Scope::fit(axes, merged.positions().iter().copied());
    merged.transform(&scope.world_to_local());
    let geometry = if judge.kind == CompKind::Faces {
        Geometry::tagged_mesh(merged, tags)
    } else {
        Geometry::mesh(merged)
    };
    (scope, geometry)
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
