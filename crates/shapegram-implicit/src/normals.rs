//! Vertex normals of a meshed solid from the field's gradient: smooth where the surface is, and
//! crisp across the creases that CSG makes, where averaging the faces around a vertex would
//! round them off.

use glam::DVec3;
use rayon::prelude::*;
use shapegram_geom::Mesh;

use crate::solid::Solid;
use crate::tape::Tape;

/// Vertices whose gradients one evaluation of the tape works out.
const CHUNK: usize = 256;

/// A unit outward normal per vertex of `mesh` (a mesh of `solid`): the field's gradient by
/// central differences over `step` (about half a grid cell suits marching cubes), negated since
/// the field grows inwards. Where the gradient vanishes or is not finite, the vertex takes the
/// area-weighted normal of its faces.
pub fn surface_normals(solid: &Solid, mesh: &Mesh, step: f64) -> Vec<DVec3> {
    let tape = Tape::new(solid);
    let h = step.abs().max(f64::MIN_POSITIVE);
    let mut normals: Vec<DVec3> = mesh
        .positions()
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| gradients(&tape, chunk, h))
        .collect();
    if normals.contains(&DVec3::ZERO) {
        let fallback = mesh.vertex_normals();
        for (n, f) in normals.iter_mut().zip(fallback) {
            if *n == DVec3::ZERO {
                *n = f;
            }
        }
    }
    normals
}

/// The negated, normalised gradients at `points` (zero where there is none to normalise).
fn gradients(tape: &Tape, points: &[DVec3], h: f64) -> Vec<DVec3> {
    let n = points.len();
    let (mut xs, mut ys, mut zs) = (vec![0.0; 6 * n], vec![0.0; 6 * n], vec![0.0; 6 * n]);
    for (i, &p) in points.iter().enumerate() {
        for (k, axis) in DVec3::AXES.iter().enumerate() {
            for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                let q = p + *axis * (sign * h);
                let at = 6 * i + 2 * k + s;
                (xs[at], ys[at], zs[at]) = (q.x, q.y, q.z);
            }
        }
    }
    // The mesher emits vertices block by block, so a chunk lies close together: the tape
    // pruned to the ball around it gives the same values for less work.
    let centre = points.iter().copied().sum::<DVec3>() / n.max(1) as f64;
    let radius = points
        .iter()
        .map(|p| p.distance(centre))
        .fold(0.0, f64::max)
        + 2.0 * h;
    // The whole tape is only evaluated at the centre: room for one point is enough.
    let local = tape.pruned(&mut tape.workspace(1), centre, radius);
    let mut ws = local.workspace(6 * n);
    let mut values = vec![0.0; 6 * n];
    local.eval(&mut ws, &xs, &ys, &zs, &mut values);
    values
        .chunks_exact(6)
        .map(|v| {
            let gradient = DVec3::new(v[0] - v[1], v[2] - v[3], v[4] - v[5]);
            let normal = -gradient.normalize_or_zero();
            if normal.is_finite() {
                normal
            } else {
                DVec3::ZERO
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MeshOptions, mesh};

    #[test]
    fn a_cube_keeps_its_face_normals_up_to_the_crease() {
        let cube = Solid::cuboid(DVec3::splat(2.0)).unwrap();
        let h = 0.1;
        let meshed = mesh(&cube, &MeshOptions::with_cell_size(h)).unwrap().mesh;
        let normals = surface_normals(&cube, &meshed, h / 2.0);
        assert_eq!(normals.len(), meshed.vertex_count());
        let mut on_faces = 0;
        for (p, n) in meshed.positions().iter().zip(&normals) {
            assert!((n.length() - 1.0).abs() < 1e-9);
            // Away from the edges, the face's own normal exactly; averaging faces would tilt
            // the normals of vertices next to the bevel.
            let a = p.abs();
            let near_edges = a.to_array().iter().filter(|&&c| c > 0.8).count();
            if a.max_element() > 0.99 && near_edges == 1 {
                let axis = a.max_position();
                let mut expected = DVec3::ZERO;
                expected[axis] = p[axis].signum();
                assert!((*n - expected).length() < 1e-9, "{p}: {n}");
                on_faces += 1;
            }
        }
        assert!(on_faces > 1000, "{on_faces}");
    }

    #[test]
    fn a_sphere_has_radial_normals() {
        let ball = Solid::sphere(1.0).unwrap();
        let meshed = mesh(&ball, &MeshOptions::with_cell_size(0.05))
            .unwrap()
            .mesh;
        let normals = surface_normals(&ball, &meshed, 0.025);
        for (p, n) in meshed.positions().iter().zip(&normals) {
            assert!(n.dot(p.normalize()) > 0.9999, "{p}: {n}");
        }
    }
}
