//! The tags operations give what they build, as CityEngine names them: `extrude.bottom`,
//! `extrude.side.outer`, `extrude.top`; `roof.bottom`, `roof.side` (gable ends) or
//! `roof.side.outer` (the walls of shed and ridge roofs), `roof.top`; `taper.bottom`,
//! `taper.side`; `envelope.bottom`, `envelope.side.base`, `envelope.side.slope`,
//! `envelope.top`.
//!
//! Faces built on a face keep its tags, those of an operation's own family excepted (an
//! operation's tags last until it runs again); faces that rise from an edge take the edge's
//! tags too. Shapegram's faces have no holes, so nothing is tagged `….side.inner`.
//!
//! Only grammars that read or write tags get any ([`crate::program::Program`]'s `tagged`):
//! the others keep their boxes and their output.

use shapegram_geom::{DVec3, Mesh};

use crate::tags::{FaceTags, TagQuery, TagSet, edge_tags};

/// The names a face built from one with `inherited` tags takes: those, without the ones of the
/// family `family` (`"roof"`), and `tag`.
pub(super) fn renamed(inherited: &TagSet, family: &str, tag: &str) -> TagSet {
    inherited
        .without(&TagQuery::parse(family))
        .union(&TagSet::of(tag))
}

/// The tags of the faces of a prism that `extrude` built over a face carrying `source`: face
/// 0 and 1 are the two ends (`flipped` when face 1 is the original), face `2 + i` rises from
/// the face's edge `i`.
pub(super) fn extruded(prism: &Mesh, source: &FaceTags, flipped: bool) -> Vec<FaceTags> {
    let n = prism.face(1).len();
    let (bottom, top) = if flipped { (1, 0) } else { (0, 1) };
    (0..prism.face_count())
        .map(|f| {
            let names = |tag| renamed(&source.names, "extrude", tag);
            if f == bottom || f == top {
                let tag = if f == bottom {
                    "extrude.bottom"
                } else {
                    "extrude.top"
                };
                // Face 0 runs the source's loop backwards.
                let edges = if f == 0 {
                    source.reversed(n).edges
                } else {
                    source.edges.clone()
                };
                return FaceTags {
                    names: names(tag),
                    edges,
                    ..FaceTags::default()
                };
            }
            let edge = source.edge(f - 2);
            FaceTags {
                names: names("extrude.side.outer").union(edge),
                edges: edge_tags(4, |k| if k == 0 { edge.clone() } else { TagSet::EMPTY }),
                ..FaceTags::default()
            }
        })
        .collect()
}

/// How a built face sits against the face it was built on (normal `up`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Facing {
    /// Looking down, against `up`.
    Down,
    /// Upright.
    Upright,
    /// Looking up along `up`, level.
    Level,
    /// Sloping.
    Slope,
}

/// How face `f` of `mesh` (world space) sits against `up`.
pub(super) fn facing(mesh: &Mesh, f: usize, up: DVec3) -> Facing {
    let d = mesh.face_normal(f).dot(up);
    if d < -0.999_999 {
        Facing::Down
    } else if d.abs() < 1e-6 {
        Facing::Upright
    } else if d > 0.999_999 {
        Facing::Level
    } else {
        Facing::Slope
    }
}

/// Tags for every face of `built` (world space), made on a face carrying `source` whose
/// normal is `up`: each face named by `name` from how it sits, in the family `family`.
pub(super) fn by_facing(
    built: &Mesh,
    source: &FaceTags,
    up: DVec3,
    family: &str,
    name: impl Fn(Facing) -> &'static str,
) -> Vec<FaceTags> {
    (0..built.face_count())
        .map(|f| FaceTags::with_names(renamed(&source.names, family, name(facing(built, f, up)))))
        .collect()
}
