//! Coplanar merge: flat rectangles of one primitive that share a whole edge and the same normal
//! become one rectangle. A facade split into floors and tiles is mostly such rectangles (the
//! wall strips between windows stack from floor to floor), and each merge saves two triangles
//! and, after vertex sharing, about two vertices. The merged rectangle covers exactly the two it
//! replaces, with the same normal and material, so nothing visible changes; only the corners in
//! the middle of the merged edge go (a neighbour that had a corner there now meets a straight
//! edge, as CGA's own splits already make neighbours of different sizes meet).

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::aligned;

/// A flat rectangle: its corners in loop order (counter-clockwise seen from the side its normal
/// points to) and its unit normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Rectangle {
    pub(crate) corners: [[f32; 3]; 4],
    pub(crate) normal: [f32; 3],
}

/// How far from a true rectangle a quad may be, relative to its size: well below what a
/// renderer resolves, well above f32 rounding of corners computed in f64.
const TOLERANCE: f64 = 1e-5;

impl Rectangle {
    /// The quad as a rectangle, its corners turned to wind counter-clockwise about `normal`;
    /// `None` when the quad is not a rectangle (within [`TOLERANCE`]).
    pub(crate) fn new(corners: [[f32; 3]; 4], normal: [f32; 3]) -> Option<Self> {
        let [a, b, c, d] = corners.map(wide);
        let (ab, ad) = (b - a, d - a);
        // Squared lengths throughout: no square roots for the millions of leaves of a city.
        let (ab2, ad2) = (ab.length_squared(), ad.length_squared());
        let tolerance2 = TOLERANCE * TOLERANCE;
        let parallelogram = (a + c - b - d).length_squared() <= tolerance2 * ab2.max(ad2);
        let dot = ab.dot(ad);
        let square_corner = dot * dot <= tolerance2 * ab2 * ad2;
        if ab2 == 0.0 || ad2 == 0.0 || !parallelogram || !square_corner {
            return None;
        }
        let corners = if ab.cross(ad).dot(wide(normal)) >= 0.0 {
            corners
        } else {
            let [a, b, c, d] = corners;
            [a, d, c, b]
        };
        Some(Self { corners, normal })
    }

    /// The directed edge from corner `k` to the next.
    fn edge(&self, k: usize) -> Edge {
        Edge::new(self.corners[k], self.corners[(k + 1) % 4])
    }
}

/// A directed edge by the exact bits of its ends.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Edge([u32; 6]);

impl Edge {
    fn new(from: [f32; 3], to: [f32; 3]) -> Self {
        let [a, b, c] = from.map(f32::to_bits);
        let [d, e, f] = to.map(f32::to_bits);
        Self([a, b, c, d, e, f])
    }

    /// The same edge walked the other way, as the neighbour across it has it.
    fn reversed(self) -> Self {
        let [a, b, c, d, e, f] = self.0;
        Self([d, e, f, a, b, c])
    }
}

fn wide(p: [f32; 3]) -> shapegram_geom::DVec3 {
    shapegram_geom::DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
}

/// Merges rectangles that share a whole edge (same ends, walked in opposite directions) and
/// have the same normal bit for bit, until no two do; returns the rectangles left, each grown
/// from the first of its pieces in input order. Deterministic: the result depends only on the
/// input order.
pub(crate) fn merge(rectangles: &[Rectangle]) -> Vec<Rectangle> {
    // Plane by plane (a facade, a roof), so that each pass's edge map stays small enough to
    // live in the cache: one map over a city's millions of edges spends its time in misses.
    let mut plane_of: FxHashMap<([u32; 3], i64), usize> = FxHashMap::default();
    let mut planes: Vec<Vec<Rectangle>> = Vec::new();
    for rectangle in rectangles {
        let plane = *plane_of.entry(plane_key(rectangle)).or_insert_with(|| {
            planes.push(Vec::new());
            planes.len() - 1
        });
        planes[plane].push(*rectangle);
    }
    // Planes merge on their own, on as many threads as there are; each plane's result is the
    // same on any of them, and the results are kept in plane order.
    let per_plane: Vec<Vec<Rectangle>> = planes
        .par_iter()
        .map_init(FxHashMap::default, |owner, plane| merge_plane(plane, owner))
        .collect();
    // Sized once: grown by doubling, a city's list is copied many times.
    let mut merged = Vec::with_capacity(per_plane.iter().map(Vec::len).sum());
    for plane in per_plane {
        merged.extend(plane);
    }
    merged
}

/// The plane a rectangle lies in: its normal, bit for bit, and its distance from the origin
/// to a tenth of a millimetre. Rectangles of one plane that round apart are only not merged.
fn plane_key(rectangle: &Rectangle) -> ([u32; 3], i64) {
    let distance = wide(rectangle.normal).dot(wide(rectangle.corners[0]));
    (
        rectangle.normal.map(f32::to_bits),
        (distance * 1e4).round() as i64,
    )
}

/// [`merge`] for the rectangles of one plane; `owner` is scratch space for the edge map.
fn merge_plane(rectangles: &[Rectangle], owner: &mut FxHashMap<Edge, u32>) -> Vec<Rectangle> {
    if let Some(merged) = aligned::merge(rectangles) {
        return merged;
    }
    let merged = pass(rectangles, owner);
    // A pass finds neighbours by the edges the rectangles had at its start: strips it made
    // side by side meet along edges only a second pass knows. Further passes find little
    // (strips of strips) and each costs as much as the second.
    if merged.len() < rectangles.len() {
        pass(&merged, owner)
    } else {
        merged
    }
}

/// One round of merges over the edges `rectangles` have.
fn pass(rectangles: &[Rectangle], owner: &mut FxHashMap<Edge, u32>) -> Vec<Rectangle> {
    owner.clear();
    for (i, rectangle) in rectangles.iter().enumerate() {
        for k in 0..4 {
            owner.entry(rectangle.edge(k)).or_insert(i as u32);
        }
    }
    let mut alive = vec![true; rectangles.len()];
    let mut merged = Vec::new();
    for seed in 0..rectangles.len() {
        if !alive[seed] {
            continue;
        }
        alive[seed] = false;
        let mut grown = rectangles[seed];
        // A merge changes two sides, whose neighbours may now match: go round until none does.
        let mut changed = true;
        while changed {
            changed = false;
            for k in 0..4 {
                while let Some(other) = neighbour(&grown, k, owner, &alive, rectangles) {
                    alive[other] = false;
                    absorb(&mut grown, k, &rectangles[other]);
                    changed = true;
                }
            }
        }
        merged.push(grown);
    }
    merged
}

/// The rectangle still unmerged across `grown`'s edge `k`, with the same normal.
fn neighbour(
    grown: &Rectangle,
    k: usize,
    owner: &FxHashMap<Edge, u32>,
    alive: &[bool],
    rectangles: &[Rectangle],
) -> Option<usize> {
    let other = *owner.get(&grown.edge(k).reversed())? as usize;
    (alive[other] && rectangles[other].normal == grown.normal).then_some(other)
}

/// Grows `grown` across its edge `k` over `other`, which has that edge reversed: the edge's
/// two corners move to `other`'s far corners, so the far edge becomes edge `k`.
fn absorb(grown: &mut Rectangle, k: usize, other: &Rectangle) {
    let shared = grown.edge(k).reversed();
    let j = (0..4)
        .find(|&j| other.edge(j) == shared)
        .expect("the neighbour has the shared edge");
    // other: j = grown's k+1, j+1 = grown's k, j+2 lies beyond k, j+3 beyond k+1.
    grown.corners[k] = other.corners[(j + 2) % 4];
    grown.corners[(k + 1) % 4] = other.corners[(j + 3) % 4];
}

#[cfg(test)]
mod tests {
    use super::*;

    const UP: [f32; 3] = [0.0, 0.0, 1.0];

    /// The unit square at (x, y) in the z = 0 plane, facing +z.
    fn square(x: f32, y: f32) -> Rectangle {
        let corners = [
            [x, y, 0.0],
            [x + 1.0, y, 0.0],
            [x + 1.0, y + 1.0, 0.0],
            [x, y + 1.0, 0.0],
        ];
        Rectangle::new(corners, UP).unwrap()
    }

    #[test]
    fn a_column_of_squares_becomes_one_rectangle() {
        let column: Vec<Rectangle> = (0..5).map(|y| square(0.0, y as f32)).collect();
        let merged = merge(&column);
        assert_eq!(merged.len(), 1);
        let mut corners = merged[0].corners.to_vec();
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            corners,
            [
                [0.0, 0.0, 0.0],
                [0.0, 5.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 5.0, 0.0]
            ]
        );
    }

    #[test]
    fn a_grid_merges_into_one_and_an_l_shape_into_two() {
        let grid: Vec<Rectangle> = (0..9)
            .map(|i| square((i % 3) as f32, (i / 3) as f32))
            .collect();
        assert_eq!(merge(&grid).len(), 1);
        let l_shape = [square(0.0, 0.0), square(1.0, 0.0), square(0.0, 1.0)];
        assert_eq!(merge(&l_shape).len(), 2);
    }

    #[test]
    fn other_normals_partial_edges_and_non_rectangles_stay_apart() {
        let mut facing_down = square(1.0, 0.0);
        facing_down.normal = [0.0, 0.0, -1.0];
        assert_eq!(merge(&[square(0.0, 0.0), facing_down]).len(), 2);
        // Half an edge shared: the union is no rectangle.
        assert_eq!(merge(&[square(0.0, 0.0), square(1.0, 0.5)]).len(), 2);
        let skewed = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.5, 1.0, 0.0],
            [0.5, 1.0, 0.0],
        ];
        assert_eq!(Rectangle::new(skewed, UP), None);
    }

    #[test]
    fn clockwise_corners_are_turned_to_face_the_normal() {
        let clockwise = [
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
        ];
        let turned = Rectangle::new(clockwise, UP).unwrap();
        assert_eq!(turned.corners[1], [1.0, 0.0, 0.0]);
    }
}
