//! Splitting a convex polyhedron by a plane into two closed convex parts (thesis 3.1.6).
//!
//! Vertices lying on the plane are reused by both parts; every edge whose ends lie strictly on
//! opposite sides gets one new vertex, which records how it was made (the edge's two vertices and
//! the interpolation coefficient), so that a rule can rebuild it on any instance of the shape.

use std::fmt;

use rustc_hash::FxHashMap;
use shapegram_geom::DVec3;

use crate::polyhedron::{Index, Polyhedron, PolyhedronError};

/// Relative tolerance, times the bounding diagonal, within which a vertex counts as on the plane.
pub const PLANE_EPSILON: f64 = 1e-9;

/// A cutting plane: a point on it and a normal (any length but zero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutPlane {
    /// A point on the plane.
    pub point: DVec3,
    /// The normal; the part on the side it points to is the second part of a cut.
    pub normal: DVec3,
}

impl CutPlane {
    /// The plane through `point` with `normal`.
    pub fn new(point: DVec3, normal: DVec3) -> Self {
        Self { point, normal }
    }

    /// The plane through three points, its normal by the right-hand rule (a → b → c
    /// counter-clockwise seen from the side the normal points to); `None` when they are
    /// (nearly) collinear or not finite.
    pub fn through(a: DVec3, b: DVec3, c: DVec3) -> Option<Self> {
        let normal = (b - a).cross(c - a);
        let scale = (b - a).length().max((c - a).length()).max((c - b).length());
        let ok = normal.is_finite() && normal.length() > 1e-9 * scale * scale;
        ok.then(|| Self::new(a, normal.normalize()))
    }

    /// Signed distance of `p` along the normalised normal.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.normal.normalize().dot(p - self.point)
    }
}

/// Where a vertex of a cut part comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VertexSource {
    /// A vertex of the cut shape, by index.
    Vertex(Index),
    /// A new vertex on the edge between two vertices of the cut shape: `from + t (to − from)`.
    Edge {
        /// The first end (the lower index).
        from: Index,
        /// The second end.
        to: Index,
        /// Interpolation coefficient, strictly between 0 and 1.
        t: f64,
    },
}

/// One part of a cut: the polyhedron, where each of its vertices comes from, and which of its
/// faces lies on the cutting plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The closed convex part.
    pub shape: Polyhedron,
    /// One entry per vertex of `shape`.
    pub sources: Vec<VertexSource>,
    /// The face on the cutting plane (the cap).
    pub cap: Index,
    /// For each face of `shape`, the face of the cut shape it is a piece of; `None` for the cap.
    pub face_sources: Vec<Option<Index>>,
}

/// The two parts of a cut: `below` lies on the side opposite the normal, `above` on the side it
/// points to.
#[derive(Clone, Debug, PartialEq)]
pub struct Cut {
    /// The part behind the plane.
    pub below: Part,
    /// The part in front of the plane.
    pub above: Part,
}

/// Why a plane does not cut a shape in two.
#[derive(Clone, Debug, PartialEq)]
pub enum CutError {
    /// The plane's point or normal is not finite, or the normal is zero.
    BadPlane,
    /// The whole shape lies on one side of the plane (it misses the shape, touches it at a
    /// vertex or an edge, or runs through one of its faces): cutting would leave one part empty.
    Miss,
    /// The parts would be degenerate (slivers thinner than the tolerance).
    Degenerate(PolyhedronError),
}

impl fmt::Display for CutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadPlane => write!(
                f,
                "the cutting plane needs a finite point and a non-zero normal"
            ),
            Self::Miss => write!(
                f,
                "the cutting plane does not pass through the shape's interior (it misses the shape, \
                 touches it or runs along a face)"
            ),
            Self::Degenerate(e) => write!(f, "the cut would leave a degenerate part: {e}"),
        }
    }
}

impl std::error::Error for CutError {}

/// Cuts `shape` by `plane` into two closed convex parts.
pub fn cut(shape: &Polyhedron, plane: &CutPlane) -> Result<Cut, CutError> {
    if !plane.point.is_finite() || !plane.normal.is_finite() || plane.normal == DVec3::ZERO {
        return Err(CutError::BadPlane);
    }
    let normal = plane.normal.normalize();
    if !normal.is_finite() {
        return Err(CutError::BadPlane);
    }
    let eps = PLANE_EPSILON * shape.diagonal();
    let distance: Vec<f64> = shape
        .positions()
        .iter()
        .map(|&p| normal.dot(p - plane.point))
        .collect();
    let side: Vec<i8> = distance
        .iter()
        .map(|&d| {
            if d > eps {
                1
            } else if d < -eps {
                -1
            } else {
                0
            }
        })
        .collect();
    if !side.contains(&1) || !side.contains(&-1) {
        return Err(CutError::Miss);
    }
    let new_vertices = crossing_vertices(shape, &side, &distance);
    let below = build_part(shape, &side, &new_vertices, -1)?;
    let above = build_part(shape, &side, &new_vertices, 1)?;
    Ok(Cut { below, above })
}

/// One new vertex per edge with ends strictly on opposite sides, keyed by the edge (lower index
/// first), in order of first meeting (faces in order, corners in loop order).
fn crossing_vertices(
    shape: &Polyhedron,
    side: &[i8],
    distance: &[f64],
) -> FxHashMap<(Index, Index), (usize, f64)> {
    let mut found = FxHashMap::default();
    for h in 0..shape.half_edge_count() as Index {
        let (a, b) = (shape.origin(h), shape.destination(h));
        if side[a as usize] * side[b as usize] < 0 && a < b {
            let t = distance[a as usize] / (distance[a as usize] - distance[b as usize]);
            let n = found.len();
            found.insert((a, b), (n, t));
        }
    }
    found
}

/// The part on side `keep` (−1 or 1): clipped faces plus the cap.
fn build_part(
    shape: &Polyhedron,
    side: &[i8],
    crossings: &FxHashMap<(Index, Index), (usize, f64)>,
    keep: i8,
) -> Result<Part, CutError> {
    // Source index space: the shape's vertices, then the crossing vertices.
    let n = shape.vertex_count();
    let mut faces: Vec<Vec<usize>> = Vec::new();
    let mut face_sources = Vec::new();
    for f in 0..shape.face_count() {
        let mut polygon = Vec::new();
        for h in shape.face_half_edges(f) {
            let (a, b) = (shape.origin(h), shape.destination(h));
            if side[a as usize] == keep || side[a as usize] == 0 {
                polygon.push(a as usize);
            }
            if side[a as usize] * side[b as usize] < 0 {
                polygon.push(n + crossings[&(a.min(b), a.max(b))].0);
            }
        }
        if polygon.len() >= 3 {
            faces.push(polygon);
            face_sources.push(Some(f));
        }
    }
    let cap = cap_loop(&faces).ok_or_else(|| {
        CutError::Degenerate(PolyhedronError::Geometry(
            "the cut face is not a single loop".into(),
        ))
    })?;
    faces.push(cap);
    face_sources.push(None);

    let mut ordered_crossings = vec![((0, 0), 0.0); crossings.len()];
    for (&edge, &(k, t)) in crossings {
        ordered_crossings[k] = (edge, t);
    }
    let mut local = vec![Index::MAX; n + crossings.len()];
    let mut positions = Vec::new();
    let mut sources = Vec::new();
    for face in &faces {
        for &v in face {
            if local[v] != Index::MAX {
                continue;
            }
            local[v] = positions.len() as Index;
            if v < n {
                positions.push(shape.position(v as Index));
                sources.push(VertexSource::Vertex(v as Index));
            } else {
                let ((from, to), t) = ordered_crossings[v - n];
                let (p, q) = (shape.position(from), shape.position(to));
                positions.push(p + (q - p) * t);
                sources.push(VertexSource::Edge { from, to, t });
            }
        }
    }
    let loops: Vec<Vec<Index>> = faces
        .iter()
        .map(|face| face.iter().map(|&v| local[v]).collect())
        .collect();
    let shape = Polyhedron::from_faces(positions, &loops).map_err(CutError::Degenerate)?;
    Ok(Part {
        shape,
        sources,
        cap: (loops.len() - 1) as Index,
        face_sources,
    })
}

/// The loop closing the open surface made by `faces`: the reverse of its boundary edges, chained
/// from the boundary edge with the lowest start; `None` unless they form exactly one loop.
fn cap_loop(faces: &[Vec<usize>]) -> Option<Vec<usize>> {
    let mut directed = FxHashMap::default();
    for face in faces {
        for (k, &a) in face.iter().enumerate() {
            directed.insert((a, face[(k + 1) % face.len()]), ());
        }
    }
    // Boundary edge a → b of the surface becomes cap edge b → a.
    let mut cap_next: FxHashMap<usize, usize> = FxHashMap::default();
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) && cap_next.insert(b, a).is_some() {
            return None;
        }
    }
    let start = *cap_next.keys().min()?;
    let mut loop_ = vec![start];
    let mut current = cap_next[&start];
    while current != start {
        if loop_.len() > cap_next.len() {
            return None;
        }
        loop_.push(current);
        current = *cap_next.get(&current)?;
    }
    (loop_.len() == cap_next.len() && loop_.len() >= 3).then_some(loop_)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Polyhedron {
        Polyhedron::cuboid(DVec3::ZERO, DVec3::ONE).unwrap()
    }

    fn volume_sum(cut: &Cut) -> f64 {
        cut.below.shape.volume() + cut.above.shape.volume()
    }

    #[test]
    fn a_cut_through_the_middle_makes_two_boxes_with_four_new_vertices() {
        let cut = cut(&cube(), &CutPlane::new(DVec3::splat(0.5), DVec3::Y)).unwrap();
        for part in [&cut.below, &cut.above] {
            assert_eq!(part.shape.vertex_count(), 8);
            assert_eq!(part.shape.face_count(), 6);
            assert!((part.shape.volume() - 0.5).abs() < 1e-12);
            let new = part
                .sources
                .iter()
                .filter(|s| matches!(s, VertexSource::Edge { t, .. } if *t == 0.5))
                .count();
            assert_eq!(new, 4);
            assert_eq!(part.shape.face_normal(part.cap).y.abs(), 1.0);
            assert_eq!(part.face_sources.len(), 6);
            assert_eq!(part.face_sources[part.cap as usize], None);
            for (f, source) in part.face_sources.iter().enumerate() {
                if let Some(g) = source {
                    assert_eq!(part.shape.face_normal(f as Index), cube().face_normal(*g));
                }
            }
        }
        assert_eq!(cut.below.shape.face_normal(cut.below.cap), DVec3::Y);
        assert_eq!(cut.above.shape.face_normal(cut.above.cap), -DVec3::Y);
        assert!(cut.above.shape.positions().iter().all(|p| p.y >= 0.5));
    }

    #[test]
    fn a_diagonal_cut_reuses_the_vertices_on_the_plane() {
        // Through the edges 0–2 and 5–7: two triangular prisms and no new vertex.
        let plane = CutPlane::new(DVec3::ZERO, DVec3::new(1.0, 0.0, -1.0));
        let cut = cut(&cube(), &plane).unwrap();
        for part in [&cut.below, &cut.above] {
            assert_eq!(part.shape.vertex_count(), 6);
            assert_eq!(part.shape.face_count(), 5);
            assert!(
                part.sources
                    .iter()
                    .all(|s| matches!(s, VertexSource::Vertex(_)))
            );
        }
        assert!((volume_sum(&cut) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_corner_cut_makes_a_tetrahedron() {
        let plane = CutPlane::new(DVec3::new(0.25, 0.0, 0.0), DVec3::new(1.0, 1.0, 1.0));
        let cut = cut(&cube(), &plane).unwrap();
        assert_eq!(cut.below.shape.vertex_count(), 4);
        assert_eq!(cut.below.shape.face_count(), 4);
        assert_eq!(cut.above.shape.face_count(), 7);
        assert!((cut.below.shape.volume() - 0.25f64.powi(3) / 6.0).abs() < 1e-12);
        assert!((volume_sum(&cut) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn planes_that_miss_or_run_along_a_face_are_errors() {
        let shape = cube();
        let miss = CutPlane::new(DVec3::splat(2.0), DVec3::Y);
        assert_eq!(cut(&shape, &miss), Err(CutError::Miss));
        let along_face = CutPlane::new(DVec3::ZERO, DVec3::Y);
        assert_eq!(cut(&shape, &along_face), Err(CutError::Miss));
        let touching_corner = CutPlane::new(DVec3::ZERO, DVec3::ONE);
        assert_eq!(cut(&shape, &touching_corner), Err(CutError::Miss));
        let zero = CutPlane::new(DVec3::ZERO, DVec3::ZERO);
        assert_eq!(cut(&shape, &zero), Err(CutError::BadPlane));
        let nan = CutPlane::new(DVec3::NAN, DVec3::Y);
        assert_eq!(cut(&shape, &nan), Err(CutError::BadPlane));
        assert!(CutError::Miss.to_string().contains("does not pass through"));
    }

    #[test]
    fn three_collinear_points_make_no_plane() {
        assert_eq!(
            CutPlane::through(DVec3::ZERO, DVec3::X, DVec3::X * 2.0),
            None
        );
        let plane = CutPlane::through(DVec3::ZERO, DVec3::X, DVec3::Z).unwrap();
        assert_eq!(plane.normal, -DVec3::Y);
    }

    #[test]
    fn new_vertices_are_rebuilt_from_their_sources() {
        let shape = cube();
        let plane = CutPlane::new(DVec3::new(0.3, 0.2, 0.1), DVec3::new(0.2, 1.0, 0.4));
        let cut = cut(&shape, &plane).unwrap();
        for part in [&cut.below, &cut.above] {
            for (v, source) in part.sources.iter().enumerate() {
                let rebuilt = match *source {
                    VertexSource::Vertex(i) => shape.position(i),
                    VertexSource::Edge { from, to, t } => {
                        assert!(from < to && t > 0.0 && t < 1.0);
                        shape.position(from).lerp(shape.position(to), t)
                    }
                };
                assert_eq!(rebuilt, part.shape.position(v as Index));
            }
        }
    }

    mod properties {
        use proptest::prelude::*;

        use super::*;

        fn unit_vector() -> impl Strategy<Value = DVec3> {
            (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
                .prop_filter("not too short", |(x, y, z)| x * x + y * y + z * z > 0.01)
                .prop_map(|(x, y, z)| DVec3::new(x, y, z).normalize())
        }

        proptest! {
            #[test]
            fn cuts_preserve_volume_and_give_closed_convex_parts(
                size in (0.5..4.0f64, 0.5..4.0f64, 0.5..4.0f64),
                point in (0.05..0.95f64, 0.05..0.95f64, 0.05..0.95f64),
                normal in unit_vector(),
                second in unit_vector(),
            ) {
                let size = DVec3::new(size.0, size.1, size.2);
                let shape = Polyhedron::cuboid(DVec3::new(-1.0, 2.0, 0.5), size).unwrap();
                let point = DVec3::new(-1.0, 2.0, 0.5) + DVec3::new(point.0, point.1, point.2) * size;
                let first = cut(&shape, &CutPlane::new(point, normal)).unwrap();
                prop_assert!((volume_sum(&first) - shape.volume()).abs() < 1e-9);
                // Cut the larger part again through its centre: parts of parts stay valid
                // (from_faces checked closedness and convexity).
                let part = if first.below.shape.volume() > first.above.shape.volume() {
                    &first.below.shape
                } else {
                    &first.above.shape
                };
                if let Ok(again) = cut(part, &CutPlane::new(part.center(), second)) {
                    prop_assert!((volume_sum(&again) - part.volume()).abs() < 1e-9);
                    let faces = again.below.shape.face_count() as i64;
                    let vertices = again.below.shape.vertex_count() as i64;
                    prop_assert!(faces >= 4 && vertices >= 4);
                }
            }
        }
    }
}
