//! The edge tags of a setback's pieces, as CityEngine gives them: on a strip (and on the
//! outline of shapeL/U/O) the edge that moved is `setback.front`, the new edge along the
//! remainder `setback.back`, the others `setback.side`; on the remainder the edges of the old
//! outline are `setback.remainder` and the new ones `setback.back`. Pieces keep the tags of
//! the face they were cut from, and edges along the old outline its edges' tags (but for an
//! earlier setback's, which the new ones replace).

use shapegram_geom::{DVec3, Mesh};

use crate::tags::{FaceTags, TagQuery, TagSet, edge_tags, lies_in, on_segment};

/// A face of the shape a setback cut: its edges, whether each moved, and its tags.
struct CutFace {
    corners: Vec<DVec3>,
    moved: Vec<bool>,
    tags: FaceTags,
}

/// What tells the edges of a setback's pieces apart.
pub(super) struct SetbackEdges {
    faces: Vec<CutFace>,
    /// The edges of the remainder's polygons.
    inner: Vec<(DVec3, DVec3)>,
    tolerance: f64,
}

impl SetbackEdges {
    /// The edges of the setback of `world`'s faces, whose edges moved where `moved` says (by
    /// face, by edge), carrying `tags` (by face), leaving the remainder `rest`.
    pub fn new(
        world: &Mesh,
        moved: Vec<Vec<bool>>,
        tags: impl Fn(usize) -> FaceTags,
        rest: &[Vec<DVec3>],
    ) -> Self {
        let size = world
            .bounds()
            .map_or(1.0, |b| b.size().max_element())
            .max(f64::MIN_POSITIVE);
        let faces = moved
            .into_iter()
            .enumerate()
            .map(|(f, moved)| CutFace {
                corners: world.face_points(f).collect(),
                moved,
                tags: tags(f),
            })
            .collect();
        let inner = rest
            .iter()
            .flat_map(|p| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])))
            .collect();
        Self {
            faces,
            inner,
            tolerance: 1e-7 * size,
        }
    }

    /// The tags of a piece (a strip or the outline's, or with `remainder` the remainder's).
    pub fn tags(&self, polygon: &[DVec3], remainder: bool) -> FaceTags {
        let centre = polygon.iter().sum::<DVec3>() / polygon.len().max(1) as f64;
        let Some(face) = self
            .faces
            .iter()
            .find(|f| lies_in(&f.corners, centre, self.tolerance))
        else {
            return FaceTags::default();
        };
        let n = polygon.len();
        let edges = edge_tags(n, |i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            let middle = 0.5 * (a + b);
            let count = face.corners.len();
            let old = (0..count).find(|&k| {
                on_segment(
                    middle,
                    face.corners[k],
                    face.corners[(k + 1) % count],
                    self.tolerance,
                )
            });
            let name = match old {
                Some(_) if remainder => "setback.remainder",
                Some(k) if face.moved[k] => "setback.front",
                Some(_) => "setback.side",
                None if remainder => "setback.back",
                None if self
                    .inner
                    .iter()
                    .any(|&(p, q)| on_segment(middle, p, q, self.tolerance)) =>
                {
                    "setback.back"
                }
                None => "setback.side",
            };
            // A setback's edge tags replace those of an earlier one.
            let kept = face.tags.edge(old.unwrap_or(usize::MAX));
            kept.without(&TagQuery::parse("setback"))
                .union(&TagSet::of(name))
        });
        FaceTags {
            names: face.tags.names.clone(),
            edges,
            ..FaceTags::default()
        }
    }
}
