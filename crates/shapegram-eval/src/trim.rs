//! Trim planes (CGA `comp(f)`, `set(trim.horizontal | trim.vertical, …)`): a face component
//! gets a plane at each edge it shares with another face, through the edge and the bisector of
//! the two faces' normals, and what `i()` and `primitive…()` insert in it or below it is cut
//! there — a cornice inserted a little longer than its facade ends on the mitre at the corner.

use std::sync::{Arc, OnceLock};

use rustc_hash::FxHashMap;

use shapegram_geom::plane::Plane;
use shapegram_geom::split::split_polygon;
use shapegram_geom::{DVec3, Mesh};

/// A trim plane, in world space: geometry on its negative side is kept.
#[derive(Clone, Debug, PartialEq)]
pub struct TrimPlane {
    plane: Plane,
    /// The edge it was made at; the plane only cuts what lies along it.
    edge: (DVec3, DVec3),
    /// Whether the edge makes less than 40° with the horizontal.
    horizontal: bool,
}

/// A shape's trim planes and which kinds of them cut.
#[derive(Clone, Debug, Default)]
pub struct Trim {
    /// The face of a component split the shape came from, whose planes are worked out the
    /// first time something is inserted below it: most faces never need them.
    face: Option<(Arc<Faces>, u32)>,
    /// `trim.horizontal`: planes at edges within 40° of the horizontal cut (off by default).
    pub horizontal: bool,
    /// `trim.vertical`: the other planes cut (on unless set off).
    vertical_off: bool,
}

/// The faces of one component split (world space) and, once asked for, their trim planes.
#[derive(Debug)]
pub struct Faces {
    mesh: Mesh,
    planes: OnceLock<Vec<Vec<TrimPlane>>>,
}

impl Faces {
    /// The faces of a mesh (world space), their planes not worked out yet.
    pub fn new(mesh: Mesh) -> Arc<Self> {
        Arc::new(Self {
            mesh,
            planes: OnceLock::new(),
        })
    }
}

/// Edges at most this steep (degrees) make horizontal planes.
const HORIZONTAL_DEGREES: f64 = 40.0;

impl Trim {
    /// `trim.vertical`: whether planes at steep edges cut.
    pub fn vertical(&self) -> bool {
        !self.vertical_off
    }

    /// Sets `trim.vertical`.
    pub fn set_vertical(&mut self, on: bool) {
        self.vertical_off = !on;
    }

    /// These settings with the planes of face `face` of `faces` instead of the shape's (or
    /// none).
    pub fn with_face(&self, face: Option<(&Arc<Faces>, usize)>) -> Self {
        Self {
            face: face.map(|(faces, f)| (Arc::clone(faces), f as u32)),
            ..self.clone()
        }
    }

    /// The shape's planes.
    fn planes(&self) -> &[TrimPlane] {
        match &self.face {
            Some((faces, f)) => faces
                .planes
                .get_or_init(|| face_planes(&faces.mesh))
                .get(*f as usize)
                .map_or(&[], Vec::as_slice),
            None => &[],
        }
    }

    fn enabled(&self, plane: &TrimPlane) -> bool {
        if plane.horizontal {
            self.horizontal
        } else {
            self.vertical()
        }
    }

    /// Whether any plane would cut (the shape has planes of a kind that is on).
    pub fn cuts(&self) -> bool {
        self.face.is_some() && self.planes().iter().any(|p| self.enabled(p))
    }

    /// `mesh` (world space) cut by every enabled plane, without closing the cuts; `None` when
    /// no plane cuts it. A plane only cuts faces whose centres lie along its edge, give or take
    /// `reach`: on a face that is not convex, the plane of one notch would otherwise cut a far
    /// part of it.
    pub fn cut(&self, mesh: &Mesh, reach: f64) -> Option<Mesh> {
        let mut current: Option<Mesh> = None;
        for p in self.planes().iter().filter(|p| self.enabled(p)) {
            let source = current.as_ref().unwrap_or(mesh);
            let (a, b) = p.edge;
            let length = (b - a).length();
            let direction = (b - a) / length;
            // The faces it cuts: along its edge, with a corner beyond it. Most inserts (a window
            // in the middle of a facade) have none, and are not copied.
            let hits: Vec<bool> = (0..source.face_count())
                .map(|f| {
                    let t = (source.face_centroid(f) - a).dot(direction);
                    !(t < -reach || t > length + reach)
                        && source
                            .face_points(f)
                            .any(|q| p.plane.signed_distance(q) > 0.0)
                })
                .collect();
            if !hits.contains(&true) {
                continue;
            }
            let mut next = Mesh::new();
            for (f, &hit) in hits.iter().enumerate() {
                let points: Vec<DVec3> = source.face_points(f).collect();
                if hit {
                    for piece in split_polygon(&points, &p.plane).0 {
                        add_polygon(&mut next, &piece);
                    }
                } else {
                    add_polygon(&mut next, &points);
                }
            }
            current = Some(next);
        }
        current
    }
}

/// A corner on the grid that tells coinciding points apart.
type Corner = [u64; 3];

/// An edge's ends and the faces along it.
type SharedEdge = (DVec3, DVec3, Vec<usize>);

fn add_polygon(mesh: &mut Mesh, points: &[DVec3]) {
    let ids: Vec<u32> = points.iter().map(|&q| mesh.add_vertex(q)).collect();
    mesh.add_face(&ids);
}

/// The trim planes of each face of `mesh` (world space), by face: one at every edge the face
/// shares with another face, through the edge and the bisector of the two outward normals,
/// keeping the face's side (a mitre at convex and reflex corners alike; a straight cut between
/// coplanar faces).
pub fn face_planes(mesh: &Mesh) -> Vec<Vec<TrimPlane>> {
    let size = mesh
        .bounds()
        .map_or(1.0, |b| b.size().max_element().max(1.0));
    // Faces meet where their corners coincide: points are compared on a fine grid.
    let grid = 1e-9 * size;
    let key = |p: DVec3| p.to_array().map(|x| ((x / grid).round() + 0.0).to_bits());
    let mut edges: FxHashMap<(Corner, Corner), SharedEdge> = FxHashMap::default();
    for f in 0..mesh.face_count() {
        let points: Vec<DVec3> = mesh.face_points(f).collect();
        for (i, &a) in points.iter().enumerate() {
            let b = points[(i + 1) % points.len()];
            let (ka, kb) = (key(a), key(b));
            if ka == kb {
                continue;
            }
            let (k, ends) = if ka < kb {
                ((ka, kb), (a, b))
            } else {
                ((kb, ka), (b, a))
            };
            edges
                .entry(k)
                .or_insert_with(|| (ends.0, ends.1, Vec::new()))
                .2
                .push(f);
        }
    }
    let normals: Vec<DVec3> = (0..mesh.face_count())
        .map(|f| mesh.face_normal(f).normalize_or_zero())
        .collect();
    let mut planes = vec![Vec::new(); mesh.face_count()];
    // In the order of the edges' first appearance, so that planes come out the same each time.
    let mut ordered: Vec<_> = edges.into_values().collect();
    ordered.sort_by_key(|(_, _, faces)| faces[0]);
    for (a, b, faces) in ordered {
        let direction = (b - a).normalize_or_zero();
        for &f in &faces {
            for &g in faces.iter().filter(|&&g| g != f) {
                let normal = direction.cross(normals[f] + normals[g]).normalize_or_zero();
                if normal == DVec3::ZERO {
                    continue;
                }
                let mut plane = Plane::from_point_normal(a, normal);
                if plane.signed_distance(mesh.face_centroid(f)) > 0.0 {
                    plane = plane.flipped();
                }
                planes[f].push(TrimPlane {
                    plane,
                    edge: (a, b),
                    horizontal: direction.y.abs().asin().to_degrees() < HORIZONTAL_DEGREES,
                });
            }
        }
    }
    planes
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::primitives;

    #[test]
    fn the_faces_of_a_box_cut_on_their_mitres() {
        let cube = primitives::cuboid(DVec3::new(4.0, 3.0, 4.0));
        let planes = face_planes(&cube);
        assert_eq!(planes.len(), 6);
        // Each face meets four others: two vertical corner edges and two horizontal ones (on a
        // side face), or four horizontal ones (top and bottom).
        for p in &planes {
            assert_eq!(p.len(), 4);
        }
        let vertical: usize = planes.iter().flatten().filter(|p| !p.horizontal).count();
        assert_eq!(vertical, 8);
        // A beam along the front face (z = 4), 2 m longer on each side, ends on the 45° mitres.
        let front = (0..cube.face_count())
            .find(|&f| cube.face_normal(f).z > 0.5)
            .unwrap();
        let faces = Faces::new(cube.clone());
        let trim = Trim::default().with_face(Some((&faces, front)));
        let mut beam = primitives::cuboid(DVec3::new(8.0, 0.5, 0.5));
        beam.transform(&shapegram_geom::DAffine3::from_translation(DVec3::new(
            -2.0, 1.0, 4.0,
        )));
        let cut = trim
            .cut(&beam, 1.0)
            .expect("the beam reaches past both corners");
        let bounds = cut.bounds().unwrap();
        // The mitres x = 4 - (z - 4)... keep x between -(z - 4) and 4 + (z - 4): at most 0.5 out.
        assert!((bounds.min.x + 0.5).abs() < 1e-9, "{:?}", bounds);
        assert!((bounds.max.x - 4.5).abs() < 1e-9, "{:?}", bounds);
        // No caps: the cut faces are open, so there are fewer faces than a closed beam's.
        assert!(cut.face_count() <= beam.face_count());
        // Horizontal planes do not cut unless asked to.
        let mut tall = primitives::cuboid(DVec3::new(1.0, 6.0, 0.5));
        tall.transform(&shapegram_geom::DAffine3::from_translation(DVec3::new(
            1.0, -1.0, 4.0,
        )));
        assert!(trim.cut(&tall, 1.0).is_none());
        let both = Trim {
            horizontal: true,
            ..trim.clone()
        };
        let cut = both.cut(&tall, 1.0).unwrap().bounds().unwrap();
        assert!(cut.min.y > -1.0 + 1e-9 && cut.max.y < 5.0 - 1e-9, "{cut:?}");
    }
}
