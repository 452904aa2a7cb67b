//! Plane cuts of polygons and meshes, with capping of closed solids.
//!
//! A cut classifies every vertex against the plane (within a tolerance scaled to the mesh, so
//! vertices on the plane are reused rather than duplicated), clips each face to each side, and, when
//! the input was closed, closes every part with cap faces built from the loops the cut left open.
//! Caps may be non-convex and may have holes (a cut through a tube gives a ring); a cap with holes
//! is triangulated. New vertices are shared between neighbouring faces, so closed input gives
//! watertight parts.

use rustc_hash::FxHashMap as HashMap;

use crate::{
    DVec3, Mesh, Plane,
    mesh::newell,
    triangulate::{Triangulator, plane_basis},
};

/// Cuts a mesh by one plane into the part on its negative side and the part on its positive side
/// (either may be empty). Closed input gives closed parts.
pub fn split(mesh: &Mesh, plane: &Plane) -> (Mesh, Mesh) {
    let mut parts = split_slabs(mesh, plane.normal, &[plane.offset]).into_iter();
    let below = parts.next().unwrap_or_default();
    let above = parts.next().unwrap_or_default();
    (below, above)
}

/// Cuts a mesh by the parallel planes `normal · p = offsets[k]` in one pass and returns the
/// `offsets.len() + 1` slabs in order along `normal` (empty meshes where a slab holds nothing).
/// Offsets are sorted first; `normal` need not be unit length. Closed input gives closed slabs.
///
/// Degenerate input cuts nothing rather than losing geometry: with a zero or non-finite normal the
/// whole mesh is the first slab, and a NaN offset counts as +∞.
pub fn split_slabs(mesh: &Mesh, normal: DVec3, offsets: &[f64]) -> Vec<Mesh> {
    let Some((normal, offsets)) = unit_planes(normal, offsets) else {
        let mut slabs = vec![Mesh::new(); offsets.len() + 1];
        slabs[0] = mesh.clone();
        return slabs;
    };
    let Some(bounds) = mesh.bounds() else {
        return vec![Mesh::new(); offsets.len() + 1];
    };
    let closed = !mesh.is_empty() && mesh.boundary_edges().is_empty();
    let mut cutter = Cutter {
        positions: mesh.positions().to_vec(),
        normal,
        offsets: &offsets,
        eps: bounds.tolerance(),
        crossings: HashMap::default(),
        seams: false,
    };
    let mut slabs: Vec<Vec<Vec<u32>>> = vec![Vec::new(); offsets.len() + 1];
    let mut cut: Vec<Vec<Vec<u32>>> = vec![Vec::new(); offsets.len() + 1];
    for face in mesh.faces() {
        cutter.distribute(face, &mut cut);
        for (slab, pieces) in slabs.iter_mut().zip(&mut cut) {
            for mut piece in pieces.drain(..) {
                cutter.keep_first_edge(face, &mut piece);
                slab.push(piece);
            }
        }
    }
    slabs
        .iter()
        .enumerate()
        .map(|(i, faces)| {
            let mut part = Mesh::from_faces(cutter.positions.clone(), faces);
            if closed {
                cutter.cap(&mut part, i);
            }
            part.compacted()
        })
        .collect()
}

/// Cuts every face of a mesh where it crosses the parallel planes `normal · p = offsets[k]`,
/// keeping the pieces together in one mesh: the surface stays the same, nothing is capped, and the
/// new vertices on a face's edges are shared with the face on the other side of the edge, so a
/// watertight mesh stays watertight. Input vertices keep their indices (new ones come after them).
/// Also returns, for each face of the result, the input face it is a piece of.
///
/// Degenerate planes (a zero or non-finite normal) cut nothing, as in [`split_slabs`]; planes
/// within a few times the mesh's tolerance of one another cut as one.
pub fn slice_faces(mesh: &Mesh, normal: DVec3, offsets: &[f64]) -> (Mesh, Vec<u32>) {
    let whole = || (mesh.clone(), (0..mesh.face_count() as u32).collect());
    let Some((normal, mut offsets)) = unit_planes(normal, offsets) else {
        return whole();
    };
    let Some(bounds) = mesh.bounds() else {
        return whole();
    };
    let eps = bounds.tolerance();
    // Planes so close that a vertex could lie on two of them cut as one: the first.
    offsets.dedup_by(|next, kept| *next - *kept <= 4.0 * eps);
    let mut cutter = Cutter {
        positions: mesh.positions().to_vec(),
        normal,
        offsets: &offsets,
        eps,
        crossings: HashMap::default(),
        seams: true,
    };
    let mut slabs: Vec<Vec<Vec<u32>>> = vec![Vec::new(); offsets.len() + 1];
    let mut faces = Vec::with_capacity(mesh.face_count());
    let mut sources = Vec::with_capacity(mesh.face_count());
    for (f, face) in mesh.faces().enumerate() {
        cutter.distribute(face, &mut slabs);
        for mut piece in slabs.iter_mut().flat_map(|slab| slab.drain(..)) {
            // The piece that holds the face's first corner starts with it, as the face did: a
            // face the planes miss keeps its loop as it was.
            if let Some(at) = piece.iter().position(|&v| v == face[0]) {
                piece.rotate_left(at);
            }
            faces.push(piece);
            sources.push(f as u32);
        }
    }
    (Mesh::from_faces(cutter.positions, faces), sources)
}

/// The planes of a cut with a unit normal: the offsets divided by the normal's length and
/// sorted, a NaN offset as +∞; `None` for a zero or non-finite normal.
fn unit_planes(normal: DVec3, offsets: &[f64]) -> Option<(DVec3, Vec<f64>)> {
    let length = normal.length();
    if !(length > 0.0 && length.is_finite()) {
        return None;
    }
    let mut offsets: Vec<f64> = offsets
        .iter()
        .map(|o| {
            if o.is_nan() {
                f64::INFINITY
            } else {
                o / length
            }
        })
        .collect();
    offsets.sort_by(f64::total_cmp);
    Some((normal / length, offsets))
}

/// Cuts one planar polygon by a plane and returns the pieces on the negative and on the positive
/// side. A non-convex polygon may give several pieces on one side.
pub fn split_polygon(points: &[DVec3], plane: &Plane) -> (Vec<Vec<DVec3>>, Vec<Vec<DVec3>>) {
    let (below, above) = split(&Mesh::from_polygon(points), plane);
    let loops = |m: &Mesh| {
        (0..m.face_count())
            .map(|f| m.face_points(f).collect())
            .collect()
    };
    (loops(&below), loops(&above))
}

/// State of one multi-plane cut: the growing vertex pool and the cache of edge crossings.
struct Cutter<'a> {
    positions: Vec<DVec3>,
    normal: DVec3,
    offsets: &'a [f64],
    eps: f64,
    /// New vertex on edge `(min, max)` at plane `k`, shared by the two faces along the edge.
    crossings: HashMap<(u32, u32, usize), u32>,
    /// Whether a piece's edge along a cut line keeps the face's corners that lie on it, so that
    /// the pieces on either side of the line meet edge to edge (slicing; a capped part leaves
    /// them to its cap).
    seams: bool,
}

/// A maximal run of consecutive face corners strictly inside the half-space being kept, with the
/// points where the boundary enters and leaves it.
struct Run {
    entry: u32,
    first: u32,
    body: std::ops::Range<usize>,
    last: u32,
    exit: u32,
}

impl Cutter<'_> {
    /// Signed distance of vertex `v` from plane `k`, snapped to exactly zero within tolerance.
    fn distance(&self, v: u32, k: usize) -> f64 {
        let d = self.normal.dot(self.positions[v as usize]) - self.offsets[k];
        if d.abs() <= self.eps { 0.0 } else { d }
    }

    /// Rotates a piece of `face` so that its first edge runs as the face's first edge did, as
    /// CityEngine's pieces keep it (a component's x axis follows its first edge): from the
    /// face's first corner when the piece has it, or else along the piece's edge closest in
    /// direction to the face's first edge (the cut edge across a wall's floor strip, not a
    /// side of it).
    fn keep_first_edge(&self, face: &[u32], piece: &mut [u32]) {
        if let Some(at) = piece.iter().position(|&v| v == face[0]) {
            piece.rotate_left(at);
            return;
        }
        let at = |v: u32| self.positions[v as usize];
        let Some(first) = (at(face[1]) - at(face[0])).try_normalize() else {
            return;
        };
        let n = piece.len();
        let alignment = |i: usize| {
            (at(piece[(i + 1) % n]) - at(piece[i]))
                .try_normalize()
                .map_or(f64::NEG_INFINITY, |d| d.dot(first))
        };
        // The first of the best within rounding, so near-ties keep the loop as it was.
        let best = (0..n).map(alignment).fold(f64::NEG_INFINITY, f64::max);
        if let Some(start) = (0..n).find(|&i| alignment(i) >= best - 1e-9) {
            piece.rotate_left(start);
        }
    }

    /// Sends the pieces of one face to the slabs they fall in.
    fn distribute(&mut self, face: &[u32], slabs: &mut [Vec<Vec<u32>>]) {
        let heights: Vec<f64> = face
            .iter()
            .map(|&v| self.normal.dot(self.positions[v as usize]))
            .collect();
        let lo = heights.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut pieces = vec![face.to_vec()];
        for k in 0..self.offsets.len() {
            let offset = self.offsets[k];
            if offset < lo - self.eps {
                continue;
            }
            if offset > hi + self.eps {
                slabs[k].append(&mut pieces);
                return;
            }
            if hi - offset <= self.eps && offset - lo <= self.eps {
                // The face lies in the plane: it belongs to the side its normal faces away from.
                let normal = newell(face.iter().map(|&v| self.positions[v as usize]));
                let slab = if normal.dot(self.normal) > 0.0 {
                    k
                } else {
                    k + 1
                };
                slabs[slab].append(&mut pieces);
                return;
            }
            let mut above = Vec::new();
            for piece in &pieces {
                slabs[k].extend(self.clip(piece, k, 1.0));
                above.extend(self.clip(piece, k, -1.0));
            }
            pieces = above;
            if pieces.is_empty() {
                return;
            }
        }
        slabs[self.offsets.len()].append(&mut pieces);
    }

    /// The vertex where edge `a → b` crosses plane `k`; one of the two when it lies on the plane.
    fn crossing(&mut self, a: u32, b: u32, k: usize) -> u32 {
        let (da, db) = (self.distance(a, k), self.distance(b, k));
        if da == 0.0 {
            return a;
        }
        if db == 0.0 {
            return b;
        }
        // Always interpolate from the lower index, so both faces along the edge compute the same
        // point bit for bit (and share it through the cache anyway).
        let (p, q, dp, dq) = if a < b {
            (a, b, da, db)
        } else {
            (b, a, db, da)
        };
        if let Some(&v) = self.crossings.get(&(p, q, k)) {
            return v;
        }
        let (pp, pq) = (self.positions[p as usize], self.positions[q as usize]);
        let point = pp + (pq - pp) * (dp / (dp - dq));
        self.positions.push(point);
        let v = (self.positions.len() - 1) as u32;
        self.crossings.insert((p, q, k), v);
        v
    }

    /// Clips a face loop to the half-space where `side · distance < 0` of plane `k`. Corners on the
    /// plane count as outside, so each inside run is bounded by two crossings; several runs (a
    /// non-convex face) are joined along the cut line into as many simple pieces as needed.
    fn clip(&mut self, face: &[u32], k: usize, side: f64) -> Vec<Vec<u32>> {
        let n = face.len();
        let inside: Vec<bool> = face
            .iter()
            .map(|&v| side * self.distance(v, k) < 0.0)
            .collect();
        let Some(start) = (0..n).find(|&i| inside[i] && !inside[(i + n - 1) % n]) else {
            return if inside[0] {
                vec![face.to_vec()]
            } else {
                Vec::new()
            };
        };
        // Rotate so the loop starts with a run; then every run is a contiguous index range.
        let rotated: Vec<u32> = (0..n).map(|i| face[(start + i) % n]).collect();
        let inside: Vec<bool> = (0..n).map(|i| inside[(start + i) % n]).collect();
        let mut runs = Vec::new();
        let mut i = 0;
        while i < n {
            if !inside[i] {
                i += 1;
                continue;
            }
            let begin = i;
            while i < n && inside[i] {
                i += 1;
            }
            let before = rotated[(begin + n - 1) % n];
            let after = rotated[i % n];
            runs.push(Run {
                entry: self.crossing(before, rotated[begin], k),
                first: rotated[begin],
                body: begin..i,
                last: rotated[i - 1],
                exit: self.crossing(rotated[i - 1], after, k),
            });
        }
        let successor = if runs.len() == 1 {
            vec![0]
        } else {
            self.pair_runs(face, &runs, k)
                .unwrap_or_else(|| (1..=runs.len()).map(|r| r % runs.len()).collect())
        };
        let mut pieces = Vec::new();
        let mut visited = vec![false; runs.len()];
        for r0 in 0..runs.len() {
            let mut piece = Vec::new();
            let mut r = r0;
            while !visited[r] {
                visited[r] = true;
                let run = &runs[r];
                piece.push(run.entry);
                piece.extend_from_slice(&rotated[run.body.clone()]);
                piece.push(run.exit);
                r = successor[r];
                if self.seams {
                    self.push_corners_between(&mut piece, face, k, run.exit, runs[r].entry);
                }
            }
            dedup_loop(&mut piece);
            if piece.len() >= 3 {
                pieces.push(piece);
            }
        }
        pieces
    }

    /// Pushes the corners of `face` that lie on plane `k` strictly between `from` and `to` (on
    /// the segment between them), in order from `from`.
    fn push_corners_between(
        &self,
        piece: &mut Vec<u32>,
        face: &[u32],
        k: usize,
        from: u32,
        to: u32,
    ) {
        let (a, b) = (self.positions[from as usize], self.positions[to as usize]);
        let ab = b - a;
        let length2 = ab.length_squared();
        if length2 == 0.0 {
            return;
        }
        let mut between: Vec<(f64, u32)> = face
            .iter()
            .filter(|&&v| v != from && v != to && self.distance(v, k) == 0.0)
            .filter_map(|&v| {
                let p = self.positions[v as usize];
                let s = (p - a).dot(ab) / length2;
                let off = (p - (a + ab * s)).length();
                (s > 0.0 && s < 1.0 && off <= self.eps).then_some((s, v))
            })
            .collect();
        between.sort_by(|x, y| x.0.total_cmp(&y.0));
        piece.extend(between.into_iter().map(|(_, v)| v));
    }

    /// For a face whose inside part is made of several runs, decides which run follows which
    /// along the cut line: sorting the crossings along the line and pairing them two by two gives
    /// the stretches of the line inside the face. Crossings at the same point are ordered by the
    /// direction of the edge that reaches them, as if the plane were moved a hair into the kept
    /// side. Returns `None` when the crossings do not alternate (self-intersecting input).
    fn pair_runs(&self, face: &[u32], runs: &[Run], k: usize) -> Option<Vec<usize>> {
        let face_normal = newell(face.iter().map(|&v| self.positions[v as usize]));
        let line = self.normal.cross(face_normal);
        let key = |at: u32, inner: u32| {
            let p = self.positions[at as usize];
            let q = self.positions[inner as usize];
            let depth = self.distance(inner, k).abs();
            (line.dot(p), line.dot(q - p) / depth)
        };
        let mut ends: Vec<(f64, f64, usize, bool)> = Vec::with_capacity(2 * runs.len());
        for (r, run) in runs.iter().enumerate() {
            let (t, s) = key(run.entry, run.first);
            ends.push((t, s, r, false));
            let (t, s) = key(run.exit, run.last);
            ends.push((t, s, r, true));
        }
        ends.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut successor = vec![usize::MAX; runs.len()];
        for pair in ends.chunks_exact(2) {
            match (pair[0], pair[1]) {
                ((_, _, from, true), (_, _, to, false))
                | ((_, _, to, false), (_, _, from, true)) => {
                    successor[from] = to;
                }
                _ => return None,
            }
        }
        Some(successor)
    }

    /// Closes the open loops a cut left in slab `slab` of a closed mesh with cap faces.
    fn cap(&self, part: &mut Mesh, slab: usize) {
        let open = part.boundary_edges();
        if open.is_empty() {
            return;
        }
        // Each open edge lies on the plane below the slab (k = slab − 1) or above it (k = slab).
        let mut by_plane: [Vec<(u32, u32)>; 2] = [Vec::new(), Vec::new()];
        for (a, b) in open {
            let h = self.normal.dot(self.positions[a as usize]);
            let upper = slab < self.offsets.len()
                && (slab == 0
                    || (h - self.offsets[slab]).abs() < (h - self.offsets[slab - 1]).abs());
            // Caps run against the open edges.
            by_plane[usize::from(upper)].push((b, a));
        }
        for (upper, edges) in by_plane.iter().enumerate() {
            let cap_normal = if upper == 1 {
                self.normal
            } else {
                -self.normal
            };
            let loops = chain_loops(edges, &self.positions, cap_normal);
            add_cap_faces(part, &loops, &self.positions, cap_normal);
        }
    }
}

/// Removes repeated consecutive vertices, including between the last and the first.
fn dedup_loop(face: &mut Vec<u32>) {
    face.dedup();
    while face.len() > 1 && face.first() == face.last() {
        face.pop();
    }
}

/// Links directed edges into closed loops. Where several edges leave one vertex (two cap regions
/// touching at a corner) the loop takes the sharpest left turn, which keeps each loop simple for
/// loops counter-clockwise about `normal`. Chains that do not close are dropped.
fn chain_loops(edges: &[(u32, u32)], positions: &[DVec3], normal: DVec3) -> Vec<Vec<u32>> {
    let mut leaving: HashMap<u32, Vec<usize>> = HashMap::default();
    for (i, &(a, _)) in edges.iter().enumerate() {
        leaving.entry(a).or_default().push(i);
    }
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for e0 in 0..edges.len() {
        if used[e0] {
            continue;
        }
        used[e0] = true;
        let (start, mut at) = edges[e0];
        let mut prev = start;
        let mut loop_ = vec![start];
        let closed = loop {
            if at == start {
                break true;
            }
            loop_.push(at);
            let incoming = positions[at as usize] - positions[prev as usize];
            let next = leaving.get(&at).and_then(|candidates| {
                candidates
                    .iter()
                    .copied()
                    .filter(|&e| !used[e])
                    .max_by(|&e, &f| {
                        let turn = |e: usize| {
                            let out = positions[edges[e].1 as usize] - positions[at as usize];
                            ccw_angle(-incoming, out, normal)
                        };
                        turn(e).total_cmp(&turn(f))
                    })
            });
            let Some(e) = next else { break false };
            used[e] = true;
            prev = at;
            at = edges[e].1;
        };
        if closed && loop_.len() >= 3 {
            loops.push(loop_);
        }
    }
    loops
}

/// Counter-clockwise angle about `normal` from `from` to `to`, in `[0, 2π)`.
fn ccw_angle(from: DVec3, to: DVec3, normal: DVec3) -> f64 {
    let a = normal.dot(from.cross(to)).atan2(from.dot(to));
    if a < 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

/// Adds cap loops to a part: loops counter-clockwise about `normal` are outer boundaries, the
/// others holes; an outer loop without holes becomes one face, one with holes is triangulated.
fn add_cap_faces(part: &mut Mesh, loops: &[Vec<u32>], positions: &[DVec3], normal: DVec3) {
    let (u, v) = plane_basis(normal);
    let flat = |i: u32| {
        let p = positions[i as usize];
        glam::DVec2::new(p.dot(u), p.dot(v))
    };
    let area = |l: &Vec<u32>| newell(l.iter().map(|&i| positions[i as usize])).dot(normal) * 0.5;
    let (outer, holes): (Vec<&Vec<u32>>, Vec<&Vec<u32>>) = loops
        .iter()
        .filter(|l| area(l).abs() > 0.0)
        .partition(|l| area(l) > 0.0);
    let mut holes_of: Vec<Vec<&Vec<u32>>> = vec![Vec::new(); outer.len()];
    for hole in holes {
        // A hole may touch its outline at a vertex (a cut through a corner of a tube's inner
        // wall), so probe with a hole vertex that is not on the outline.
        let inside = |o: &Vec<u32>| {
            let polygon: Vec<glam::DVec2> = o.iter().map(|&i| flat(i)).collect();
            hole.iter()
                .find(|v| !o.contains(v))
                .is_some_and(|&v| contains(&polygon, flat(v)))
        };
        let host = outer
            .iter()
            .enumerate()
            .filter(|(_, o)| inside(o))
            .min_by(|a, b| area(a.1).total_cmp(&area(b.1)))
            .map(|(i, _)| i);
        if let Some(i) = host {
            holes_of[i].push(hole);
        }
    }
    let mut triangulator = Triangulator::new();
    for (o, holes) in outer.iter().zip(&holes_of) {
        if holes.is_empty() {
            part.add_face(o);
            continue;
        }
        let mut ids: Vec<u32> = o.to_vec();
        let mut starts = Vec::new();
        for h in holes {
            starts.push(ids.len());
            ids.extend_from_slice(h);
        }
        let points: Vec<DVec3> = ids.iter().map(|&i| positions[i as usize]).collect();
        for t in triangulator.triangulate(&points, &starts) {
            part.add_face(&t.map(|i| ids[i as usize]));
        }
    }
}

/// Even–odd point-in-polygon test in 2D.
fn contains(polygon: &[glam::DVec2], p: glam::DVec2) -> bool {
    let mut inside = false;
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}
