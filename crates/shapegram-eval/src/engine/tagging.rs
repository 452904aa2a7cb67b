//! CGA `tag(name [, components])` and `deleteTags([query [, components]])`: tags added to or
//! removed from the faces or edges of the shape's geometry (see [`crate::tags`]).

use super::Fallible;
use super::machine::Engine;
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::tags::{FaceTags, TagQuery, TagSet, TagTarget, edge_tags};
use crate::value::Value;

impl Engine<'_> {
    /// `tag`: every face (`auto`, `faces`) or every edge (`edges`) gets the tag; a box becomes
    /// the mesh of its faces to carry it. Shapegram keeps no vertex tags.
    pub(super) fn tag(
        &mut self,
        state: &mut State,
        name: &CExpr,
        target: TagTarget,
        args: &[Value],
    ) -> Fallible<()> {
        let name = self.ev.string(name, state, args)?;
        let added = TagSet::of(&name);
        if added.is_empty() || target == TagTarget::Vertices {
            return Ok(());
        }
        retag(state, |face, corners| match target {
            TagTarget::Edges => FaceTags {
                edges: edge_tags(corners, |i| face.edge(i).union(&added)),
                ..face.clone()
            },
            _ => face.tagged(&added),
        });
        Ok(())
    }

    /// `deleteTags`: the tags the query matches (all without one) go from the faces and edges
    /// (`all`), the faces or the edges.
    pub(super) fn delete_tags(
        &mut self,
        state: &mut State,
        query: Option<&CExpr>,
        target: TagTarget,
        args: &[Value],
    ) -> Fallible<()> {
        let query = match query {
            Some(q) => TagQuery::parse(&self.ev.string(q, state, args)?),
            None => TagQuery::parse(""),
        };
        if state.geometry.tags().is_none() {
            return Ok(());
        }
        let faces = matches!(target, TagTarget::All | TagTarget::Faces);
        let edges = matches!(target, TagTarget::All | TagTarget::Edges);
        retag(state, |face, corners| FaceTags {
            part: face.part,
            group: face.group.clone(),
            names: if faces {
                face.names.without(&query)
            } else {
                face.names.clone()
            },
            edges: if edges {
                edge_tags(corners, |i| face.edge(i).without(&query))
            } else {
                face.edges.clone()
            },
        });
        Ok(())
    }
}

/// Gives each face of a shape's polygon geometry the tags `change` makes of its old ones (and
/// its corner count); solids and shapes without geometry stay as they are.
fn retag(state: &mut State, change: impl Fn(&FaceTags, usize) -> FaceTags) {
    if let Geometry::Implicit(_) | Geometry::Empty = state.geometry {
        return;
    }
    let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
        return;
    };
    let old = state.geometry.tags();
    let tags = (0..mesh.face_count())
        .map(|f| {
            let face = old.and_then(|t| t.get(f)).cloned().unwrap_or_default();
            change(&face, mesh.face(f).len())
        })
        .collect();
    state.geometry = Geometry::tagged_mesh(mesh, tags);
}
