//! CGA's component tags: names on the faces and edges of a shape's geometry (`extrude.top`,
//! `roof.side`, `setback.front`, or the grammar's own through `tag(…)`), the queries that match
//! them (`"roof"`, `"?.side"`, `"envelope.*.inner"`), and how they follow the geometry through
//! cuts.
//!
//! A tag is a dot-separated hierarchy of subtags. A query matches a tag when its subtags match
//! the tag's first subtags: `"roof"` matches `roof.side.outer`; `?` stands for exactly one
//! subtag, `*` for one or more.
//!
//! Faces carry their tags and the tags of each of their edges ([`FaceTags`]); an edge shared by
//! two faces has the tags either gives it. Shapegram keeps no vertex tags.

use std::sync::Arc;

use rustc_hash::FxHashMap;
use shapegram_geom::{DVec3, Mesh};

/// The tags of one component: names, sorted, each once.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct TagSet(Option<Arc<[Arc<str>]>>);

impl TagSet {
    /// No tags.
    pub const EMPTY: Self = Self(None);

    /// The one tag `name`, without the wildcard characters `?` and `*` (none when nothing is
    /// left of it).
    pub fn of(name: &str) -> Self {
        let clean: String = name.chars().filter(|c| !matches!(c, '?' | '*')).collect();
        if clean.is_empty() {
            return Self::EMPTY;
        }
        Self(Some(Arc::from([Arc::from(clean.as_str())])))
    }

    /// Whether there are no tags.
    pub fn is_empty(&self) -> bool {
        self.0.is_none()
    }

    /// The names, sorted.
    pub fn names(&self) -> impl Iterator<Item = &Arc<str>> {
        self.0.iter().flat_map(|n| n.iter())
    }

    /// The tags of both sets.
    pub fn union(&self, other: &TagSet) -> TagSet {
        match (&self.0, &other.0) {
            (_, None) => self.clone(),
            (None, _) => other.clone(),
            (Some(a), Some(b)) => {
                let mut all: Vec<Arc<str>> = a.iter().chain(b.iter()).cloned().collect();
                all.sort();
                all.dedup();
                Self(Some(all.into()))
            }
        }
    }

    /// The tags the query does not match.
    pub fn without(&self, query: &TagQuery) -> TagSet {
        let kept: Vec<Arc<str>> = self
            .names()
            .filter(|n| !query.matches(n))
            .cloned()
            .collect();
        Self((!kept.is_empty()).then(|| kept.into()))
    }

    /// Whether the query matches one of the tags.
    pub fn matches(&self, query: &TagQuery) -> bool {
        self.names().any(|n| query.matches(n))
    }
}

/// One subtag of a query.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Subtag {
    Name(Box<str>),
    /// `?`: exactly one subtag.
    One,
    /// `*`: one or more subtags.
    Many,
}

/// A tag query (`"roof.side"`, `"?.top"`); the empty query matches every tag.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TagQuery(Vec<Subtag>);

impl TagQuery {
    /// The query written as `text`.
    pub fn parse(text: &str) -> Self {
        if text.is_empty() {
            return Self(Vec::new());
        }
        Self(
            text.split('.')
                .map(|s| match s {
                    "?" => Subtag::One,
                    "*" => Subtag::Many,
                    _ => Subtag::Name(s.into()),
                })
                .collect(),
        )
    }

    /// Whether the query matches the tag `name`.
    pub fn matches(&self, name: &str) -> bool {
        let parts: Vec<&str> = name.split('.').collect();
        prefix_matches(&self.0, &parts)
    }
}

/// Whether the query's subtags match the first subtags of a tag.
fn prefix_matches(query: &[Subtag], tag: &[&str]) -> bool {
    let Some((first, rest)) = query.split_first() else {
        return true;
    };
    match first {
        Subtag::Name(n) => tag.first() == Some(&&**n) && prefix_matches(rest, &tag[1..]),
        Subtag::One => !tag.is_empty() && prefix_matches(rest, &tag[1..]),
        Subtag::Many => (1..=tag.len()).any(|k| prefix_matches(rest, &tag[k..])),
    }
}

/// Which part of an `offset` a face is, for the `inside` and `border` selectors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OffsetPart {
    /// Not made by `offset`.
    #[default]
    None,
    /// The inset polygon.
    Inside,
    /// The ring between the outline and the inset polygon.
    Border,
}

/// What a face carries besides its corners: its part of an `offset`, its tags and its edges',
/// and the group of an inserted asset it belongs to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceTags {
    /// The face's part of an `offset`.
    pub part: OffsetPart,
    /// The group of an inserted asset the face belongs to (`comp(g)`).
    pub group: Option<Arc<str>>,
    /// The face's tags.
    pub names: TagSet,
    /// The tags of each edge, from corner `i` to corner `i + 1`; `None` when no edge has any.
    pub edges: Option<Arc<[TagSet]>>,
}

impl FaceTags {
    /// A face tagged `name`.
    pub fn named(name: &str) -> Self {
        Self {
            names: TagSet::of(name),
            ..Self::default()
        }
    }

    /// A face with the tags of `names` and no part or edge tags.
    pub fn with_names(names: TagSet) -> Self {
        Self {
            names,
            ..Self::default()
        }
    }

    /// The tags of edge `i`.
    pub fn edge(&self, i: usize) -> &TagSet {
        self.edges
            .as_ref()
            .and_then(|e| e.get(i))
            .unwrap_or(&TagSet::EMPTY)
    }

    /// The face's tags with `names` added.
    pub fn tagged(&self, names: &TagSet) -> Self {
        Self {
            names: self.names.union(names),
            ..self.clone()
        }
    }

    /// These tags for the face's loop of `n` corners reversed: edge `k` of the reversed loop is
    /// edge `n − 2 − k` of the old one.
    pub fn reversed(&self, n: usize) -> Self {
        let edges = self.edges.as_ref().map(|_| {
            (0..n)
                .map(|k| self.edge((2 * n - 2 - k) % n).clone())
                .collect()
        });
        Self {
            edges,
            ..self.clone()
        }
    }

    /// Whether the face carries nothing.
    pub fn is_plain(&self) -> bool {
        *self == Self::default()
    }
}

/// The group of each face of an asset's parts merged in order (as
/// [`crate::asset_look::AssetLook::from_parts`] merges them): each part's name; `None`
/// without parts.
pub fn face_groups(parts: &[shapegram_geom::Part]) -> Option<Arc<[Arc<str>]>> {
    if parts.is_empty() {
        return None;
    }
    let mut groups = Vec::new();
    for part in parts {
        let name: Arc<str> = Arc::from(part.name.as_str());
        groups.extend(std::iter::repeat_n(name, part.mesh.face_count()));
    }
    Some(groups.into())
}

/// Edge tags for a loop of `n` corners from a function of the edge index; `None` when no edge
/// gets any.
pub fn edge_tags(n: usize, tags: impl Fn(usize) -> TagSet) -> Option<Arc<[TagSet]>> {
    let all: Vec<TagSet> = (0..n).map(tags).collect();
    all.iter().any(|t| !t.is_empty()).then(|| all.into())
}

/// The tags of the faces of `to`, pieces of the faces of `from` (in the same coordinates) cut
/// or copied from them: each face takes the part and tags of the face of `from` it lies on, and
/// each of its edges the tags of the edge of that face it lies along. Faces on none of `from`'s
/// (the caps of a cut) get none. `None` when nothing carries a tag.
pub fn carry(from: &Mesh, tags: &[FaceTags], to: &Mesh) -> Option<Arc<Vec<FaceTags>>> {
    let size = from
        .bounds()
        .map_or(1.0, |b| b.size().max_element())
        .max(f64::MIN_POSITIVE);
    let tolerance = 1e-7 * size;
    let carried: Vec<FaceTags> = (0..to.face_count())
        .map(|f| {
            let points: Vec<DVec3> = to.face_points(f).collect();
            let normal = to.face_normal(f);
            let Some(g) = source_face(from, &points, normal, tolerance) else {
                return FaceTags::default();
            };
            let source = &tags.get(g).cloned().unwrap_or_default();
            let edges = source.edges.as_ref().and_then(|_| {
                let corners: Vec<DVec3> = from.face_points(g).collect();
                edge_tags(points.len(), |i| {
                    let mid = 0.5 * (points[i] + points[(i + 1) % points.len()]);
                    (0..corners.len())
                        .find(|&k| {
                            on_segment(mid, corners[k], corners[(k + 1) % corners.len()], tolerance)
                        })
                        .map_or(TagSet::EMPTY, |k| source.edge(k).clone())
                })
            });
            FaceTags {
                edges,
                ..source.clone()
            }
        })
        .collect();
    carried
        .iter()
        .any(|t| !t.is_plain())
        .then(|| carried.into())
}

/// The face of `mesh` a polygon lies on: facing the same way, in the same plane, holding the
/// polygon's centre.
fn source_face(mesh: &Mesh, points: &[DVec3], normal: DVec3, tolerance: f64) -> Option<usize> {
    let centre = points.iter().sum::<DVec3>() / points.len().max(1) as f64;
    (0..mesh.face_count()).find(|&g| {
        let n = mesh.face_normal(g);
        let corners: Vec<DVec3> = mesh.face_points(g).collect();
        n.dot(normal) > 0.999
            && (centre - corners[0]).dot(n).abs() <= tolerance
            && holds(&corners, n, centre, tolerance)
    })
}

/// Whether `p` lies in the planar polygon `corners` (on its outline included).
pub fn lies_in(corners: &[DVec3], p: DVec3, tolerance: f64) -> bool {
    let n = shapegram_geom::mesh::newell(corners.iter().copied()).normalize_or_zero();
    corners
        .first()
        .is_some_and(|&c| (p - c).dot(n).abs() <= tolerance)
        && holds(corners, n, p, tolerance)
}

/// Whether the planar polygon `corners` (normal `n`) holds `p`, on its outline included.
fn holds(corners: &[DVec3], n: DVec3, p: DVec3, tolerance: f64) -> bool {
    let count = corners.len();
    if (0..count).any(|k| on_segment(p, corners[k], corners[(k + 1) % count], tolerance)) {
        return true;
    }
    // Even-odd crossings in the plane, dropping the normal's largest axis.
    let drop = n.abs().max_position();
    let flat = |v: DVec3| {
        let (a, b) = ((drop + 1) % 3, (drop + 2) % 3);
        (v[a], v[b])
    };
    let (px, py) = flat(p);
    let mut inside = false;
    for k in 0..count {
        let (ax, ay) = flat(corners[k]);
        let (bx, by) = flat(corners[(k + 1) % count]);
        if (ay > py) != (by > py) && px < ax + (py - ay) / (by - ay) * (bx - ax) {
            inside = !inside;
        }
    }
    inside
}

/// Whether `p` lies on the segment from `a` to `b`, within `tolerance`.
pub fn on_segment(p: DVec3, a: DVec3, b: DVec3, tolerance: f64) -> bool {
    let d = b - a;
    let length2 = d.length_squared();
    if length2 == 0.0 {
        return p.distance(a) <= tolerance;
    }
    let t = ((p - a).dot(d) / length2).clamp(0.0, 1.0);
    p.distance(a + d * t) <= tolerance
}

/// A corner's key: its exact position.
type Corner = [u64; 3];

fn corner(p: DVec3) -> Corner {
    // `+ 0.0` turns −0 into 0, so both signs of zero meet.
    p.to_array().map(|x| (x + 0.0).to_bits())
}

fn edge_key(a: DVec3, b: DVec3) -> (Corner, Corner) {
    let (a, b) = (corner(a), corner(b));
    if a <= b { (a, b) } else { (b, a) }
}

/// Which components a tag query looks at: the component itself, or the edges or vertices
/// around it (`isTagged(q, e)`, `isTagged(q, v)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Around {
    /// The component itself.
    Itself,
    /// Its edges.
    Edges,
    /// Its vertices.
    Vertices,
}

/// The tags of every component of a mesh, as `isTagged` reads them: a face has its own tags,
/// an edge its own and those of the faces beside it, a vertex those of the edges (and so the
/// faces) around it.
pub struct TagIndex {
    faces: Vec<TagSet>,
    face_corners: Vec<Vec<DVec3>>,
    edges: FxHashMap<(Corner, Corner), TagSet>,
    vertices: FxHashMap<Corner, TagSet>,
}

impl TagIndex {
    /// The index of `mesh`'s tags (`tags` per face, or none).
    pub fn new(mesh: &Mesh, tags: Option<&[FaceTags]>) -> Self {
        let mut index = Self {
            faces: Vec::with_capacity(mesh.face_count()),
            face_corners: Vec::with_capacity(mesh.face_count()),
            edges: FxHashMap::default(),
            vertices: FxHashMap::default(),
        };
        for f in 0..mesh.face_count() {
            let face = tags.and_then(|t| t.get(f)).cloned().unwrap_or_default();
            let corners: Vec<DVec3> = mesh.face_points(f).collect();
            for (i, &a) in corners.iter().enumerate() {
                let b = corners[(i + 1) % corners.len()];
                let own = face.edge(i).union(&face.names);
                let entry = index.edges.entry(edge_key(a, b)).or_default();
                *entry = entry.union(&own);
            }
            index.faces.push(face.names);
            index.face_corners.push(corners);
        }
        for ((a, b), tags) in &index.edges {
            for end in [a, b] {
                let entry = index.vertices.entry(*end).or_default();
                *entry = entry.union(tags);
            }
        }
        index
    }

    /// Whether the query matches face `f` (or, by `around`, one of its edges or vertices).
    pub fn face(&self, f: usize, query: &TagQuery, around: Around) -> bool {
        let corners = self.face_corners.get(f).map_or(&[][..], Vec::as_slice);
        match around {
            Around::Itself => self.faces.get(f).is_some_and(|t| t.matches(query)),
            Around::Edges => (0..corners.len())
                .any(|i| self.edge(corners[i], corners[(i + 1) % corners.len()], query, around)),
            Around::Vertices => corners.iter().any(|&p| self.vertex(p, query)),
        }
    }

    /// Whether the query matches the edge from `a` to `b` (or, with [`Around::Vertices`], one
    /// of its ends).
    pub fn edge(&self, a: DVec3, b: DVec3, query: &TagQuery, around: Around) -> bool {
        match around {
            Around::Vertices => self.vertex(a, query) || self.vertex(b, query),
            _ => self
                .edges
                .get(&edge_key(a, b))
                .is_some_and(|t| t.matches(query)),
        }
    }

    /// Whether the query matches the vertex at `p`.
    pub fn vertex(&self, p: DVec3, query: &TagQuery) -> bool {
        self.vertices
            .get(&corner(p))
            .is_some_and(|t| t.matches(query))
    }
}

/// Which components of a geometry `tag`, `deleteTags`, `geometry.tags` and `geometry.hasTags`
/// act on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TagTarget {
    /// Faces and edges (`all`; `auto` for `tag`, which tags the faces).
    All,
    /// Faces.
    Faces,
    /// Edges.
    Edges,
    /// Vertices: Shapegram keeps no vertex tags.
    Vertices,
}

impl TagTarget {
    /// The target a word names (`all`, `auto`, `faces`, `edges`, `vertices`).
    pub fn named(word: &str) -> Option<Self> {
        Some(match word {
            "all" | "auto" => Self::All,
            "faces" => Self::Faces,
            "edges" => Self::Edges,
            "vertices" => Self::Vertices,
            _ => return None,
        })
    }
}

/// The tags of a geometry's `target` components that `query` matches, sorted, each once.
pub fn collect(tags: Option<&[FaceTags]>, query: &TagQuery, target: TagTarget) -> Vec<Arc<str>> {
    let mut names: Vec<Arc<str>> = Vec::new();
    for face in tags.unwrap_or(&[]) {
        if matches!(target, TagTarget::All | TagTarget::Faces) {
            names.extend(face.names.names().cloned());
        }
        if matches!(target, TagTarget::All | TagTarget::Edges) {
            for edge in face.edges.iter().flat_map(|e| e.iter()) {
                names.extend(edge.names().cloned());
            }
        }
    }
    names.retain(|n| query.matches(n));
    names.sort();
    names.dedup();
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_match_hierarchies_and_wildcards() {
        let q = |s: &str| TagQuery::parse(s);
        assert!(q("roof").matches("roof.side.outer"));
        assert!(q("roof.side").matches("roof.side"));
        assert!(!q("roof.side").matches("roof.sides"));
        assert!(!q("roof.side.outer").matches("roof.side"));
        assert!(q("?.top").matches("roof.top"));
        assert!(!q("?.top").matches("a.b.top"));
        assert!(q("a.*.left").matches("a.b.c.left"));
        assert!(!q("a.*.left").matches("a.left"));
        assert!(q("").matches("anything"));
    }

    #[test]
    fn sets_stay_sorted_and_lose_wildcards() {
        let set = TagSet::of("b")
            .union(&TagSet::of("a*"))
            .union(&TagSet::of("b"));
        let names: Vec<&str> = set.names().map(|n| &**n).collect();
        assert_eq!(names, ["a", "b"]);
        assert!(TagSet::of("?*").is_empty());
        assert!(
            set.without(&TagQuery::parse("a"))
                .matches(&TagQuery::parse("b"))
        );
        assert!(set.without(&TagQuery::parse("")).is_empty());
    }

    #[test]
    fn reversed_loops_keep_each_edge_its_tags() {
        let tags = FaceTags {
            edges: edge_tags(4, |i| TagSet::of(&i.to_string())),
            ..FaceTags::default()
        };
        // Corners 0 1 2 3 reversed are 3 2 1 0: edge 0 (3 → 2) was edge 2.
        let reversed = tags.reversed(4);
        let names: Vec<String> = (0..4)
            .map(|k| reversed.edge(k).names().next().unwrap().to_string())
            .collect();
        assert_eq!(names, ["2", "1", "0", "3"]);
    }

    #[test]
    fn pieces_take_the_tags_of_the_face_and_edges_under_them() {
        let square = Mesh::from_polygon(&[
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
        ]);
        let tags = [FaceTags {
            names: TagSet::of("wall"),
            edges: edge_tags(4, |i| {
                if i == 0 {
                    TagSet::of("foot")
                } else {
                    TagSet::EMPTY
                }
            }),
            ..FaceTags::default()
        }];
        // The left half, and a cap standing across it.
        let piece = Mesh::from_faces(
            vec![
                DVec3::ZERO,
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 2.0, 0.0),
                DVec3::new(0.0, 2.0, 0.0),
                DVec3::new(1.0, 0.0, 1.0),
            ],
            [vec![0u32, 1, 2, 3], vec![1, 4, 2]],
        );
        let carried = carry(&square, &tags, &piece).unwrap();
        assert_eq!(carried[0].names, TagSet::of("wall"));
        assert_eq!(carried[0].edge(0), &TagSet::of("foot"));
        assert!(carried[0].edge(1).is_empty());
        assert!(carried[1].is_plain());
    }
}
