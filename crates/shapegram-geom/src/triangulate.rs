//! Triangulation of planar polygons, convex or not.

use earcut::Earcut;

use crate::{DVec2, DVec3, Mesh, mesh::newell};

/// Reusable triangulator: keeps its buffers between calls.
#[derive(Default)]
pub struct Triangulator {
    earcut: Earcut<f64>,
    flat: Vec<[f64; 2]>,
    out: Vec<u32>,
}

impl Triangulator {
    /// A triangulator with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Triangulates a planar loop with optional holes, given as 3D points. The outer loop is
    /// `points[..hole_starts[0]]` (or all points), hole `k` starts at `hole_starts[k]`.
    /// Returned triangles index into `points` and wind like the outer loop.
    pub fn triangulate(&mut self, points: &[DVec3], hole_starts: &[usize]) -> Vec<[u32; 3]> {
        let outer_len = hole_starts.first().copied().unwrap_or(points.len());
        let n = points.len();
        if outer_len < 3 {
            return Vec::new();
        }
        if n == 3 && hole_starts.is_empty() {
            return vec![[0, 1, 2]];
        }
        let normal = newell(points[..outer_len].iter().copied()).normalize_or_zero();
        if hole_starts.is_empty() && is_convex(points) {
            let hub = fan_hub(points);
            let at = |i: usize| ((hub + i) % n) as u32;
            let mut fan: Vec<[u32; 3]> = (1..n - 1).map(|i| [at(0), at(i), at(i + 1)]).collect();
            // The test is on the sine of the angle at the hub, so the thin but real triangles of
            // a finely divided circle count as proper.
            let proper = |t: &[u32; 3]| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                let (ab, ac) = (b - a, c - a);
                ab.cross(ac).length() > 1e-12 * ab.length() * ac.length()
            };
            if fan.iter().all(proper) || normal == DVec3::ZERO {
                fan.retain(proper);
                return fan;
            }
            // Corners on a straight line give fan triangles of zero area; dropping them alone
            // would leave those corners in the middle of other triangles' edges.
            self.flatten(points, normal);
            let flat: Vec<DVec2> = self.flat.iter().map(|f| DVec2::new(f[0], f[1])).collect();
            make_conforming(&mut fan, &flat);
            return fan;
        }
        if normal == DVec3::ZERO {
            return Vec::new();
        }
        self.flatten(points, normal);
        let holes: Vec<u32> = hole_starts.iter().map(|&h| h as u32).collect();
        self.earcut.earcut_slice(&self.flat, &holes, &mut self.out);
        let flat: Vec<DVec2> = self.flat.iter().map(|f| DVec2::new(f[0], f[1])).collect();
        // Earcut winds all its triangles one way, either way; make them agree with the outer
        // loop. Decided once for all: the sign of a zero-area triangle is noise.
        let twice_area = |t: &[u32]| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| flat[i as usize]);
            (b - a).perp_dot(c - a)
        };
        let reversed = self.out.chunks_exact(3).map(twice_area).sum::<f64>() < 0.0;
        let mut triangles: Vec<[u32; 3]> = self
            .out
            .chunks_exact(3)
            .map(|t| {
                if reversed {
                    [t[0], t[2], t[1]]
                } else {
                    [t[0], t[1], t[2]]
                }
            })
            .collect();
        make_conforming(&mut triangles, &flat);
        widen_needles(&mut triangles, &flat);
        triangles
    }

    /// Fills `flat` with the points in plane coordinates about the unit `normal`.
    fn flatten(&mut self, points: &[DVec3], normal: DVec3) {
        let (u, v) = plane_basis(normal);
        let origin = points[0];
        self.flat.clear();
        self.flat.extend(points.iter().map(|&p| {
            let d = p - origin;
            [d.dot(u), d.dot(v)]
        }));
    }
}

/// The corner of a convex polygon to fan it from: the one whose thinnest triangle is the widest,
/// so that corners almost on a line (a footprint's kink of a few millimetres) do not become a
/// needle of the fan when another corner gives them room. The first corner stays the hub unless
/// another makes the thinnest triangle at least twice as wide (rectangles fan as they always did).
/// Polygons of more than 16 corners (fine circles, whose triangles are alike from any corner) fan
/// from the first.
fn fan_hub(points: &[DVec3]) -> usize {
    const MOST_CORNERS: usize = 16;
    let n = points.len();
    if n <= 3 || n > MOST_CORNERS {
        return 0;
    }
    let thinnest = |hub: usize| {
        (1..n - 1)
            .map(|i| {
                let a = points[hub];
                let (b, c) = (points[(hub + i) % n], points[(hub + i + 1) % n]);
                (b - a).cross(c - a).length_squared()
            })
            .fold(f64::INFINITY, f64::min)
    };
    // Squared cross products: twice as wide is four times as much.
    let mut best = (0, thinnest(0));
    for hub in 1..n {
        let area = thinnest(hub);
        if area > 4.0 * best.1 {
            best = (hub, area);
        }
    }
    best.0
}

/// Makes earcut's triangles conforming and free of zero-area triangles. Where a polygon has
/// corners on a straight line (along a roof ridge, a stepped footprint, a cap through a straight
/// wall) earcut may fill the straight angle at a corner with a zero-area triangle while a triangle
/// on the other side runs straight past that corner, drop the corner altogether, or leave two
/// triangles whose edges overlap along the line. Dropping the slivers and splitting every triangle
/// whose edge passes through a corner at that corner keeps the triangles covering the polygon and
/// makes them share whole edges again, each with area. The scan is O(triangles · corners); a
/// self-intersecting polygon may be left partly unrepaired rather than repaired forever.
fn make_conforming(triangles: &mut Vec<[u32; 3]>, flat: &[DVec2]) {
    // `c` within 10⁻¹² · |ab| of the line through `a` and `b`. A triangle is a sliver when a corner
    // is that close to its longest edge, the same test that finds corners on edges below.
    let on_line = |a: DVec2, b: DVec2, c: DVec2| {
        (b - a).perp_dot(c - a).abs() <= 1e-12 * a.distance_squared(b)
    };
    let sliver = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| flat[i as usize]);
        let longest = [(a, b, c), (b, c, a), (c, a, b)]
            .into_iter()
            .max_by(|x, y| {
                x.0.distance_squared(x.1)
                    .total_cmp(&y.0.distance_squared(y.1))
            });
        longest.is_none_or(|(p, q, r)| on_line(p, q, r))
    };
    triangles.retain(|t| !sliver(t));
    // For a simple polygon each split removes one corner from the inside of an edge, a few
    // splits per corner at most. A polygon that crosses itself can keep producing new corner-edge
    // contacts, so the splits are bounded: past the budget the triangles stay as they are.
    let mut budget = 16 * flat.len() + 64;
    let mut k = 0;
    while k < triangles.len() && budget > 0 {
        let t = triangles[k];
        let split = (0..3).find_map(|e| {
            let (p, q) = (t[e], t[(e + 1) % 3]);
            let (a, b) = (flat[p as usize], flat[q as usize]);
            (0..flat.len() as u32).find_map(|v| {
                let c = flat[v as usize];
                let along = (c - a).dot(b - a);
                (!t.contains(&v)
                    && along > 0.0
                    && along < a.distance_squared(b)
                    && on_line(a, b, c))
                .then_some((e, v))
            })
        });
        match split {
            Some((e, v)) => {
                let (p, q, r) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                triangles[k] = [p, v, r];
                triangles.push([v, q, r]);
                budget -= 1;
            }
            None => k += 1,
        }
    }
}

/// Flips inner edges while that makes the smaller of the two triangles on them larger. Ear
/// clipping may cut a needle off a nearly straight corner although the polygon allows triangles
/// with area there; flipping the needle's inner edge removes it. The polygon's own edges are
/// never flipped. Every flip raises the sorted list of triangle areas, so flips cannot cycle.
fn widen_needles(triangles: &mut [[u32; 3]], flat: &[DVec2]) {
    let mut owner: rustc_hash::FxHashMap<(u32, u32), usize> = rustc_hash::FxHashMap::default();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            owner.insert((tri[k], tri[(k + 1) % 3]), t);
        }
    }
    let mut pending: Vec<(u32, u32)> = owner.keys().copied().filter(|(x, y)| x < y).collect();
    let p = |i: u32| flat[i as usize];
    let twice_area = |a: u32, b: u32, c: u32| (p(b) - p(a)).perp_dot(p(c) - p(a));
    while let Some((x, y)) = pending.pop() {
        let (Some(&t1), Some(&t2)) = (owner.get(&(x, y)), owner.get(&(y, x))) else {
            continue;
        };
        let third = |t: [u32; 3]| t.into_iter().find(|&v| v != x && v != y);
        let (Some(a), Some(b)) = (third(triangles[t1]), third(triangles[t2])) else {
            continue;
        };
        // t1 = x y a and t2 = y x b, counter-clockwise; the flip gives x b a and b y a.
        let before = twice_area(x, y, a).min(twice_area(y, x, b));
        let after = twice_area(x, b, a).min(twice_area(b, y, a));
        if after <= before * (1.0 + 1e-9) || after <= 0.0 {
            continue;
        }
        for tri in [triangles[t1], triangles[t2]] {
            for k in 0..3 {
                owner.remove(&(tri[k], tri[(k + 1) % 3]));
            }
        }
        triangles[t1] = [x, b, a];
        triangles[t2] = [b, y, a];
        for t in [t1, t2] {
            let tri = triangles[t];
            for k in 0..3 {
                owner.insert((tri[k], tri[(k + 1) % 3]), t);
            }
        }
        pending.extend([(x, b), (b, y), (y, a), (a, x)]);
    }
}

/// Two unit vectors spanning the plane with the given unit normal, so that `(u, v, normal)` is
/// right-handed.
pub fn plane_basis(normal: DVec3) -> (DVec3, DVec3) {
    let u = normal.any_orthonormal_vector();
    (u, normal.cross(u))
}

/// Whether a planar loop is convex (no reflex corner; collinear corners allowed).
pub fn is_convex(points: &[DVec3]) -> bool {
    is_convex_about(points, newell(points.iter().copied()))
}

/// [`is_convex`] for a caller that has the polygon's Newell normal already.
// Inlined into the exporters, which test every quad of a tube (millions); the corners wrap
// around without a division (`% n`), which cost more than the arithmetic. A plain loop: as
// an iterator's `all` the test stayed out of line, called per quad.
#[inline]
pub fn is_convex_about(points: &[DVec3], normal: DVec3) -> bool {
    let n = points.len();
    let next = |i: usize| if i + 1 == n { 0 } else { i + 1 };
    for i in 0..n {
        let a = points[i];
        let b = points[next(i)];
        let c = points[next(next(i))];
        if !turns_convex(b - a, c - b, normal, || c - a) {
            return false;
        }
    }
    true
}

/// [`is_convex_about`] of the quad `a b c d`, with the same result for every input (the same
/// arithmetic), each edge computed once: the exporters test every side face of a tube.
#[inline(always)]
pub fn is_convex_quad(a: DVec3, b: DVec3, c: DVec3, d: DVec3, normal: DVec3) -> bool {
    // Written out corner by corner, without arrays: those went through the stack.
    let (ab, bc, cd, da) = (b - a, c - b, d - c, a - d);
    turns_convex(ab, bc, normal, || c - a)
        && turns_convex(bc, cd, normal, || d - b)
        && turns_convex(cd, da, normal, || a - c)
        && turns_convex(da, ab, normal, || b - d)
}

/// Whether a loop turns convexly (or stays straight) at a corner from edge `ab` to edge `bc`,
/// about `normal`; `ac` gives the corner's chord, needed only where the turn is negative.
#[inline(always)]
fn turns_convex(ab: DVec3, bc: DVec3, normal: DVec3, ac: impl FnOnce() -> DVec3) -> bool {
    // turn ≥ -1e-12 · |normal| · |c - a|, squared to spare two square roots.
    let turn = ab.cross(bc).dot(normal);
    turn >= 0.0 || turn * turn <= 1e-24 * normal.length_squared() * ac().length_squared()
}

impl Mesh {
    /// Triangles covering every face, indexing this mesh's vertices, in face order.
    pub fn triangulate(&self) -> Vec<[u32; 3]> {
        let mut triangulator = Triangulator::new();
        let mut points = Vec::new();
        let mut triangles = Vec::with_capacity(self.face_count() * 2);
        for face in self.faces() {
            points.clear();
            points.extend(face.iter().map(|&v| self.position(v)));
            triangles.extend(
                triangulator
                    .triangulate(&points, &[])
                    .into_iter()
                    .map(|t| t.map(|i| face[i as usize])),
            );
        }
        triangles
    }

    /// Number of triangles of [`Mesh::triangulate`] whose area is below `min_area`.
    pub fn degenerate_triangle_count(&self, min_area: f64) -> usize {
        self.triangulate()
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| self.position(i));
                0.5 * (b - a).cross(c - a).length() < min_area
            })
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_quad_test_agrees_with_the_general_one() {
        // Squares bent out of plane, pushed in at a corner and made slivers, with a
        // generator of our own: the convex, the reflex and the nearly straight must agree.
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut random = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut convex, mut reflex) = (0, 0);
        for k in 0..20_000 {
            let scale = [1.0, 1e-6, 1e-13, 1e7][k % 4];
            let mut quad = [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ];
            for p in &mut quad {
                *p += scale * DVec3::new(random(), random(), random());
            }
            if k % 7 == 0 {
                // A corner on the line of its neighbours, give or take rounding.
                quad[1] = (quad[0] + quad[2]) * 0.5;
            }
            let normal = newell(quad.iter().copied());
            let expected = is_convex_about(&quad, normal);
            let [a, b, c, d] = quad;
            assert_eq!(is_convex_quad(a, b, c, d, normal), expected, "{quad:?}");
            if expected {
                convex += 1;
            } else {
                reflex += 1;
            }
        }
        assert!(
            convex > 1000 && reflex > 1000,
            "{convex} convex, {reflex} reflex"
        );
        // A corner dented inwards by about the tolerance (1e-12 of the chord past it), at
        // each of the four: only the right chord gives the general test's answer.
        let mut dents = [0; 2];
        for k in 0..4000 {
            let mut quad = [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ];
            for p in &mut quad {
                *p += 1e-3 * DVec3::new(random(), random(), 0.0);
            }
            let j = k % 4;
            let (before, after) = (quad[(j + 3) % 4], quad[(j + 1) % 4]);
            let middle = (before + after) * 0.5;
            let centre = quad.iter().copied().sum::<DVec3>() * 0.25;
            let depth = 1e-12 * (before - after).length() * (1.0 + 1.5 * random());
            quad[j] = middle + (centre - middle).normalize() * depth;
            let normal = newell(quad.iter().copied());
            let expected = is_convex_about(&quad, normal);
            let [a, b, c, d] = quad;
            assert_eq!(is_convex_quad(a, b, c, d, normal), expected, "{quad:?}");
            dents[usize::from(expected)] += 1;
        }
        assert!(dents.iter().all(|&n| n > 500), "{dents:?}");
        let broken = [DVec3::ZERO, DVec3::X, DVec3::NAN, DVec3::Y];
        let normal = newell(broken.iter().copied());
        assert_eq!(
            is_convex_quad(broken[0], broken[1], broken[2], broken[3], normal),
            is_convex_about(&broken, normal)
        );
    }

    #[test]
    fn convexity_checks_the_corners_that_wrap_around() {
        let square = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        assert!(is_convex(&square));
        // A dart whose reflex corner is the last one: only the triples (2, 3, 0) and (3, 0, 1),
        // which wrap around the loop, see it.
        let mut dart = square;
        dart[3] = DVec3::new(0.8, 0.2, 0.0);
        assert!(!is_convex(&dart));
        for start in 0..4 {
            let mut turned = dart;
            turned.rotate_left(start);
            assert!(!is_convex(&turned), "starting at corner {start}");
        }
        assert!(is_convex(&square[..3]));
        assert!(is_convex(&square[..1]));
    }
}
