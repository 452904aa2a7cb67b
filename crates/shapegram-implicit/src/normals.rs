//! Vertex normals of a meshed solid from the field's gradient: smooth where the surface is, and
//! crisp across the creases that CSG makes, where averaging the faces around a vertex would
//! round them off.
//!
//! The vertices are sorted along a Morton curve and split recursively into spatially tight
//! groups, the tape being pruned on the way down (as the mesher prunes it over its regions), so
//! each group is evaluated with the few primitives near it, not with the whole cave.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec3;
use rayon::prelude::*;
use shapegram_geom::{Aabb, Mesh};

use crate::solid::Solid;
use crate::tape::{Tape, Workspace};

/// Most vertices in a group, evaluated with one pruned tape.
const CHUNK: usize = 256;

/// Most vertices whose samples one evaluation of the tape takes: a workspace holds a value per
/// sample for every value live at once, so a small one stays in cache.
const PIECE: usize = 64;

/// Bits of a Morton key per axis (three make 63 bits).
const MORTON_BITS: u32 = 21;

/// A unit outward normal per vertex of `mesh` (a mesh of `solid`): the field's gradient by
/// central differences over `step` (about half a grid cell suits marching cubes), negated since
/// the field grows inwards. Where the gradient vanishes or is not finite, the vertex takes the
/// area-weighted normal of its faces. The result does not depend on the number of threads.
pub fn surface_normals(solid: &Solid, mesh: &Mesh, step: f64) -> Vec<DVec3> {
    surface_normals_with_progress(solid, mesh, step, &|_, _| {})
}

/// Like [`surface_normals`], calling `progress(done, total)` as groups of vertices are finished
/// (from any thread).
pub fn surface_normals_with_progress(
    solid: &Solid,
    mesh: &Mesh,
    step: f64,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Vec<DVec3> {
    let positions = mesh.positions();
    let Some(bounds) = Aabb::from_points(positions.iter().copied()) else {
        return Vec::new();
    };
    let h = step.abs().max(f64::MIN_POSITIVE);
    let tape = Arc::new(Tape::new(solid));
    let (keys, order) = morton_order(positions, &bounds);
    // In curve order, so that the runs below read contiguous memory.
    let points: Vec<DVec3> = order.par_iter().map(|&v| positions[v as usize]).collect();
    let mut splitter = Splitter {
        ws: tape.workspace(1),
        keys: &keys,
        points: &points,
        h,
        groups: Vec::new(),
    };
    splitter.split(0, points.len(), &tape, 3 * MORTON_BITS);
    let groups = splitter.groups;
    let done = AtomicUsize::new(0);
    // A workspace grows to fit the largest tape it prunes (one sample per value of it), so each
    // is shared by a few runs of groups per thread.
    let batch = groups.len().div_ceil(4 * rayon::current_num_threads());
    let per_group: Vec<Vec<DVec3>> = groups
        .par_iter()
        .with_min_len(batch)
        .map_init(
            || (tape.workspace(6 * PIECE), Samples::default()),
            |(ws, samples), group| {
                let run = &points[group.start..group.end];
                let normals = gradients(&group.tape, ws, samples, run, h);
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, groups.len());
                normals
            },
        )
        .collect();
    let mut normals = vec![DVec3::ZERO; positions.len()];
    for (&v, n) in order.iter().zip(per_group.into_iter().flatten()) {
        normals[v as usize] = n;
    }
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

/// The Morton keys of `positions`, sorted, and the vertex of each: vertices close along the
/// curve are close in space, and those in any cell of the curve's octree are a run of the list.
/// The key quantises positions over their bounding box; ties are broken by index, so the order
/// is one and the same whatever the thread count.
fn morton_order(positions: &[DVec3], bounds: &Aabb) -> (Vec<u64>, Vec<u32>) {
    let (lo, extent) = (bounds.min, bounds.size().max_element());
    let scale = if extent > 0.0 && extent.is_finite() {
        f64::from((1u32 << MORTON_BITS) - 1) / extent
    } else {
        0.0
    };
    let mut keyed: Vec<(u64, u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(v, &p)| {
            // Float-to-integer casts saturate (NaN gives 0): any position gets a key.
            let q = ((p - lo) * scale).to_array().map(|c| c as u32);
            let key = spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2;
            (key, v as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().unzip()
}

/// The low 21 bits of `x` moved to every third bit.
fn spread(x: u32) -> u64 {
    let mut x = u64::from(x) & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

/// A run of the vertices in curve order, with the tape pruned for a ball around an enclosing
/// run.
struct Group {
    start: usize,
    end: usize,
    tape: Arc<Tape>,
}

/// Splits the sorted vertices into groups of at most [`CHUNK`].
struct Splitter<'a> {
    /// Scratch for single-point evaluations of the tape and its pruned copies.
    ws: Workspace,
    /// Morton keys and positions of the vertices in curve order.
    keys: &'a [u64],
    points: &'a [DVec3],
    h: f64,
    /// The groups in list order.
    groups: Vec<Group>,
}

impl Splitter<'_> {
    /// Splits the run `start..end`, where `tape` gives the field around the cell of the curve's
    /// octree whose keys agree above bit `pruned_at` (63: the whole bounding box).
    fn split(&mut self, start: usize, end: usize, tape: &Arc<Tape>, pruned_at: u32) {
        if end - start <= CHUNK {
            self.groups.push(Group {
                start,
                end,
                tape: tape.clone(),
            });
            return;
        }
        let run = &self.keys[start..end];
        let differing = run[0] ^ run[run.len() - 1];
        if differing == 0 {
            // Vertices in one spot: nothing to split them by but their count.
            let middle = start + run.len() / 2;
            self.split(start, middle, tape, pruned_at);
            self.split(middle, end, tape, pruned_at);
            return;
        }
        // The run fills a cell of the octree; split it where the first bit in which its keys
        // differ changes.
        let bit = u64::BITS - 1 - differing.leading_zeros();
        let middle = start + run.partition_point(|&k| k >> bit & 1 == 0);
        // Each bit halves the cell along one axis. Pruning costs about as much as the tape it
        // starts from is long, so, as the mesher's octree does, it waits until the cell has
        // halved along all three.
        if pruned_at - bit >= 3 {
            let (centre, radius) = ball(&self.points[start..end], self.h);
            let tape = Arc::new(tape.pruned(&mut self.ws, centre, radius));
            self.split(start, middle, &tape, bit);
            self.split(middle, end, &tape, bit);
        } else {
            self.split(start, middle, tape, pruned_at);
            self.split(middle, end, tape, pruned_at);
        }
    }
}

/// A ball holding every sample the central differences take around `points`, with room to
/// spare for rounding.
fn ball(points: &[DVec3], h: f64) -> (DVec3, f64) {
    Aabb::from_points(points.iter().copied()).map_or((DVec3::ZERO, 2.0 * h), |b| {
        (b.center(), b.diagonal() * 0.5 + 2.0 * h)
    })
}

/// Per-thread buffers for one group's samples.
#[derive(Default)]
struct Samples {
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    values: Vec<f64>,
}

/// The negated, normalised gradients at `points` (zero where there is none to normalise), with
/// `tape` giving the field around them.
fn gradients(
    tape: &Tape,
    ws: &mut Workspace,
    samples: &mut Samples,
    points: &[DVec3],
    h: f64,
) -> Vec<DVec3> {
    // The group lies close together: the tape pruned to the ball around it gives the same
    // values for less work.
    let (centre, radius) = ball(points, h);
    let local = tape.pruned(ws, centre, radius);
    let Samples { xs, ys, zs, values } = samples;
    let mut normals = Vec::with_capacity(points.len());
    for piece in points.chunks(PIECE) {
        for buffer in [&mut *xs, &mut *ys, &mut *zs, &mut *values] {
            buffer.resize(6 * piece.len(), 0.0);
        }
        for (i, &p) in piece.iter().enumerate() {
            for (k, axis) in DVec3::AXES.iter().enumerate() {
                for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                    let q = p + *axis * (sign * h);
                    let at = 6 * i + 2 * k + s;
                    (xs[at], ys[at], zs[at]) = (q.x, q.y, q.z);
                }
            }
        }
        local.eval(ws, xs, ys, zs, values);
        normals.extend(values.chunks_exact(6).map(|v| {
            let gradient = DVec3::new(v[0] - v[1], v[2] - v[3], v[4] - v[5]);
            let normal = -gradient.normalize_or_zero();
            if normal.is_finite() {
                normal
            } else {
                DVec3::ZERO
            }
        }));
    }
    normals
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

    #[test]
    fn morton_keys_interleave_the_axes() {
        assert_eq!(spread(0b101), 0b1_000_001);
        assert_eq!(spread(0x1f_ffff), 0x1249_2492_4924_9249);
        for x in [1u32, 2, 0x15_5555, 0x1f_fffe, 0x12_3456] {
            let naive = (0..MORTON_BITS).fold(0u64, |k, b| k | u64::from(x >> b & 1) << (3 * b));
            assert_eq!(spread(x), naive, "{x:#x}");
        }
    }

    #[test]
    fn vertices_in_one_spot_are_split_by_count() {
        // More vertices than a group holds, all with one key.
        let ball = Solid::sphere(1.0).unwrap();
        let p = DVec3::new(0.6, 0.0, 0.8);
        let mesh = Mesh::from_faces(vec![p; 3 * CHUNK + 5], Vec::<[u32; 3]>::new());
        let normals = surface_normals(&ball, &mesh, 1e-4);
        assert_eq!(normals.len(), 3 * CHUNK + 5);
        for n in normals {
            assert!((n - p).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn a_vanishing_gradient_takes_the_face_normal() {
        // At a ball's centre the central differences cancel.
        let ball = Solid::sphere(1.0).unwrap();
        let positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        let mesh = Mesh::from_faces(positions, [[0u32, 1, 2]]);
        let normals = surface_normals(&ball, &mesh, 0.01);
        assert_eq!(normals[0], DVec3::Z);
        assert!((normals[1] - DVec3::X).length() < 1e-4, "{}", normals[1]);
        assert!((normals[2] - DVec3::Y).length() < 1e-4, "{}", normals[2]);
        assert!(surface_normals(&ball, &Mesh::new(), 0.01).is_empty());
    }
}
