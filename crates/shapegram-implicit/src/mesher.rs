//! Sparse, parallel marching cubes.
//!
//! The field is sampled on a regular grid padded by 1.5 cells around the solid's bounds, and the
//! outermost samples always count as outside, so every surface comes out closed. The grid is
//! split recursively into regions; a region whose centre value exceeds its half-diagonal in
//! magnitude cannot hold the surface (the field is 1-Lipschitz) and is skipped whole, so the work
//! follows the surface, not the volume. Regions of at most `block` cells per side that may hold
//! surface are meshed in parallel, each with the compiled [`Tape`], and joined in a fixed order:
//! the output is the same whatever the thread count.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use shapegram_geom::Mesh;

use crate::error::{ImplicitError, Result, positive};
use crate::solid::Solid;
use crate::table::{CENTRE, cases, edge_corners};
use crate::tape::{Tape, Workspace};

/// Vertices are kept at least this fraction of a cell away from grid corners, so no triangle of
/// a cell can collapse: its corners lie on distinct cell edges, strictly inside them.
const CORNER_CLEARANCE: f64 = 1e-3;

/// Default limit on the number of grid cells (about 2048³).
pub const DEFAULT_MAX_CELLS: u64 = 1 << 33;
/// Default limit on the number of output triangles.
pub const DEFAULT_MAX_TRIANGLES: usize = 20_000_000;

/// How to mesh a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    /// Edge length of a grid cell (the paper's `C_E`).
    pub cell_size: f64,
    /// Side of the blocks meshed as one unit of work, in cells (2 to 32).
    pub block: usize,
    /// The grid may have at most this many cells.
    pub max_cells: u64,
    /// The mesh may have at most this many triangles.
    pub max_triangles: usize,
    /// Meshing stops with an error when it is still at work at this time.
    pub deadline: Option<Instant>,
}

impl MeshOptions {
    /// Options with cells of edge `cell_size` and the default block size and limits.
    pub fn with_cell_size(cell_size: f64) -> Self {
        Self {
            cell_size,
            block: 8,
            max_cells: DEFAULT_MAX_CELLS,
            max_triangles: DEFAULT_MAX_TRIANGLES,
            deadline: None,
        }
    }

    /// Options whose grid has `cells` cells along the longest side of `solid`'s bounds.
    pub fn cells_along_longest(solid: &Solid, cells: usize) -> Self {
        let longest = solid
            .bounds()
            .map_or(1.0, |b| b.size().max_element())
            .max(f64::MIN_POSITIVE);
        Self::with_cell_size(longest / cells.max(1) as f64)
    }
}

/// The sampling grid: samples at `origin + cell_size · (i, j, k)` for `i` in `0..=cells[0]`, ….
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Position of sample `(0, 0, 0)`.
    pub origin: DVec3,
    /// Edge length of a cell.
    pub cell_size: f64,
    /// Number of cells along each axis.
    pub cells: [usize; 3],
}

impl Grid {
    /// Total number of cells.
    pub fn cell_count(&self) -> u64 {
        self.cells.iter().map(|&c| c as u64).product()
    }

    /// Position of sample `(i, j, k)`; every block computes it the same way, so shared vertices
    /// come out bit-identical.
    fn sample(&self, i: usize, j: usize, k: usize) -> DVec3 {
        DVec3::new(
            self.origin.x + self.cell_size * i as f64,
            self.origin.y + self.cell_size * j as f64,
            self.origin.z + self.cell_size * k as f64,
        )
    }

    fn sample_index(&self, s: [usize; 3]) -> u64 {
        let n = self.cells.map(|c| c as u64 + 1);
        s[0] as u64 + n[0] * (s[1] as u64 + n[1] * s[2] as u64)
    }
}

/// A meshed solid with what the mesher learnt on the way.
#[derive(Clone, Debug)]
pub struct Meshing {
    /// Triangles with shared vertices, counter-clockwise seen from outside.
    pub mesh: Mesh,
    /// The grid that was sampled.
    pub grid: Grid,
    /// Cells whose eight corners are all inside (eq. 10's `N_C`).
    pub inside_cells: u64,
    /// Field samples actually evaluated (the rest were skipped as empty or full).
    pub evaluated_samples: u64,
    /// Blocks meshed densely.
    pub surface_blocks: usize,
}

impl Meshing {
    /// Volume by voxel count, eq. (10): `N_C · C_E³`.
    pub fn voxel_volume(&self) -> f64 {
        self.inside_cells as f64 * self.grid.cell_size.powi(3)
    }
}

/// A box of cells `lo..hi` (exclusive) on each axis.
#[derive(Clone, Copy, Debug)]
struct Region {
    lo: [usize; 3],
    hi: [usize; 3],
}

impl Region {
    fn cells(&self) -> u64 {
        (0..3).map(|a| (self.hi[a] - self.lo[a]) as u64).product()
    }
}

/// What one block contributed.
#[derive(Debug, Default)]
struct BlockMesh {
    positions: Vec<DVec3>,
    /// Global edge key of vertices on the block's boundary (shared with neighbours), else
    /// `u64::MAX`.
    keys: Vec<u64>,
    triangles: Vec<[u32; 3]>,
    inside_cells: u64,
}

/// Meshes `solid`; see the module documentation.
pub fn mesh(solid: &Solid, options: &MeshOptions) -> Result<Meshing> {
    mesh_with_progress(solid, options, &|_, _| {})
}

/// Like [`mesh`], calling `progress(done, total)` as blocks are finished (from any thread).
pub fn mesh_with_progress(
    solid: &Solid,
    options: &MeshOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Meshing> {
    mesh_until(solid, options, progress, &|| false)
}

/// Like [`mesh_with_progress`], giving up with a "cancelled" error once `stop()` says so:
/// it is asked before each block, so a host can cancel meshing from another thread.
pub fn mesh_until(
    solid: &Solid,
    options: &MeshOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Result<Meshing> {
    let h = positive("cell size", options.cell_size)?;
    if !(2..=32).contains(&options.block) {
        return Err(ImplicitError::new(format!(
            "invalid block size {}: expected 2 to 32 cells",
            options.block
        )));
    }
    let Some(bounds) = solid.bounds() else {
        return Ok(Meshing {
            mesh: Mesh::new(),
            grid: Grid {
                origin: DVec3::ZERO,
                cell_size: h,
                cells: [0; 3],
            },
            inside_cells: 0,
            evaluated_samples: 0,
            surface_blocks: 0,
        });
    };
    let grid = grid_for(bounds.min, bounds.size(), h, options.max_cells)?;
    let tape = Arc::new(Tape::new(solid));
    let mut classifier = Classifier {
        ws: tape.workspace(1),
        grid: &grid,
        block: options.block,
        leaves: Vec::new(),
        inside_cells: 0,
    };
    let root = Region {
        lo: [0; 3],
        hi: grid.cells,
    };
    classifier.classify(root, &tape);
    let Classifier {
        leaves,
        mut inside_cells,
        ..
    } = classifier;
    let capacity = (options.block + 1).pow(3);
    let done = AtomicUsize::new(0);
    let triangles = AtomicUsize::new(0);
    let over_limit = AtomicBool::new(false);
    let late = AtomicBool::new(false);
    let stopped = AtomicBool::new(false);
    let blocks: Vec<BlockMesh> = leaves
        .par_iter()
        .map_init(
            || (tape.workspace(capacity), Scratch::new(capacity)),
            |(ws, scratch), leaf| {
                if over_limit.load(Ordering::Relaxed)
                    || late.load(Ordering::Relaxed)
                    || stopped.load(Ordering::Relaxed)
                {
                    return BlockMesh::default();
                }
                if stop() {
                    stopped.store(true, Ordering::Relaxed);
                    return BlockMesh::default();
                }
                if options.deadline.is_some_and(|d| Instant::now() > d) {
                    late.store(true, Ordering::Relaxed);
                    return BlockMesh::default();
                }
                let block = mesh_block(&leaf.tape, ws, scratch, &grid, &leaf.region);
                let total = triangles.fetch_add(block.triangles.len(), Ordering::Relaxed)
                    + block.triangles.len();
                if total > options.max_triangles {
                    over_limit.store(true, Ordering::Relaxed);
                }
                progress(done.fetch_add(1, Ordering::Relaxed) + 1, leaves.len());
                block
            },
        )
        .collect();
    if stopped.load(Ordering::Relaxed) {
        return Err(ImplicitError::new("meshing was cancelled"));
    }
    if over_limit.load(Ordering::Relaxed) {
        return Err(ImplicitError::new(format!(
            "the mesh would have more than {} triangles: use larger cells (a lower level of detail)",
            options.max_triangles
        )));
    }
    if late.load(Ordering::Relaxed) {
        return Err(ImplicitError::new(
            "meshing took longer than the time allowed: use larger cells (a lower level of detail)",
        ));
    }
    let evaluated_samples = leaves
        .iter()
        .map(|Leaf { region: r, .. }| {
            (0..3)
                .map(|a| (r.hi[a] - r.lo[a] + 1) as u64)
                .product::<u64>()
        })
        .sum();
    inside_cells += blocks.iter().map(|b| b.inside_cells).sum::<u64>();
    Ok(Meshing {
        mesh: join(&blocks),
        grid,
        inside_cells,
        evaluated_samples,
        surface_blocks: leaves.len(),
    })
}

/// How far from the origin, in cells, a grid may reach: there a coordinate's rounding error is
/// still below 2⁻¹⁶ of a cell (a double has 52 fraction bits). Further out, neighbouring samples
/// would round to the same point and the mesh would silently collapse.
const MAX_REACH_CELLS: f64 = (1u64 << 36) as f64;

/// The padded grid over a box at `min` of extent `size`.
fn grid_for(min: DVec3, size: DVec3, h: f64, max_cells: u64) -> Result<Grid> {
    let padding = 1.5 * h;
    let cells = size.to_array().map(|s| (s / h).ceil() + 3.0);
    let total: f64 = cells.iter().product();
    if !total.is_finite() || total > max_cells as f64 {
        // Integers up to 10¹⁵ in full, larger ones (a solid of size 10³⁰⁰) in scientific form.
        let count = |c: f64| {
            if c < 1e15 {
                format!("{c}")
            } else {
                format!("{c:.3e}")
            }
        };
        return Err(ImplicitError::new(format!(
            "a grid of {} × {} × {} cells exceeds the limit of {max_cells} cells: use larger \
             cells (a lower level of detail)",
            count(cells[0]),
            count(cells[1]),
            count(cells[2])
        )));
    }
    let reach = min.abs().max((min + size).abs()).max_element() + padding;
    if reach / h > MAX_REACH_CELLS {
        return Err(ImplicitError::new(format!(
            "the solid reaches {reach:.3e} units from the origin, too far for cells of {h}: \
             coordinates there are not precise enough; move it nearer the origin or use larger \
             cells"
        )));
    }
    Ok(Grid {
        origin: min - padding,
        cell_size: h,
        cells: cells.map(|c| c as usize),
    })
}

/// A block that may hold surface, with the tape pruned to the region it was split from.
struct Leaf {
    region: Region,
    tape: Arc<Tape>,
}

/// Sorts regions into skipped space and leaf blocks.
struct Classifier<'a> {
    /// Scratch for single-point evaluations of the tape and its pruned copies.
    ws: Workspace,
    grid: &'a Grid,
    block: usize,
    /// Blocks that may hold surface, in a fixed depth-first order.
    leaves: Vec<Leaf>,
    /// Cells of regions found wholly inside.
    inside_cells: u64,
}

impl Classifier<'_> {
    /// Sorts `region`, where `tape` (pruned for an enclosing region) gives the field.
    fn classify(&mut self, region: Region, tape: &Arc<Tape>) {
        let grid = self.grid;
        let h = grid.cell_size;
        let lo = grid.sample(region.lo[0], region.lo[1], region.lo[2]);
        let hi = grid.sample(region.hi[0], region.hi[1], region.hi[2]);
        let centre = (lo + hi) * 0.5;
        // A little slack covers rounding in the field and in the sample positions.
        let reach = (hi - lo).length() * 0.5 * (1.0 + 1e-9) + h * 1e-6;
        let v = tape.value(&mut self.ws, centre);
        if v < -reach {
            return;
        }
        let on_border = (0..3).any(|a| region.lo[a] == 0 || region.hi[a] == grid.cells[a]);
        if v > reach && !on_border {
            self.inside_cells += region.cells();
            return;
        }
        let block = self.block;
        let sizes = [0, 1, 2].map(|a| region.hi[a] - region.lo[a]);
        if sizes.iter().all(|&s| s <= block) {
            self.leaves.push(Leaf {
                region,
                tape: tape.clone(),
            });
            return;
        }
        // The children see only what can matter in this region: far parts of a large solid
        // drop out on the way down.
        let tape = Arc::new(tape.pruned(&mut self.ws, centre, reach));
        // Split long axes at a multiple of the block size so leaves are whole blocks where
        // possible.
        let ranges = |a: usize| {
            if sizes[a] <= block {
                vec![(region.lo[a], region.hi[a])]
            } else {
                let m = region.lo[a] + sizes[a].div_ceil(block) / 2 * block;
                vec![(region.lo[a], m), (m, region.hi[a])]
            }
        };
        let (xs, ys, zs) = (ranges(0), ranges(1), ranges(2));
        for &(z0, z1) in &zs {
            for &(y0, y1) in &ys {
                for &(x0, x1) in &xs {
                    let child = Region {
                        lo: [x0, y0, z0],
                        hi: [x1, y1, z1],
                    };
                    self.classify(child, &tape);
                }
            }
        }
    }
}

/// Per-thread buffers for one block.
struct Scratch {
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    values: Vec<f64>,
    edge_vertex: Vec<u32>,
}

impl Scratch {
    fn new(capacity: usize) -> Self {
        Self {
            xs: vec![0.0; capacity],
            ys: vec![0.0; capacity],
            zs: vec![0.0; capacity],
            values: vec![0.0; capacity],
            edge_vertex: vec![u32::MAX; capacity * 3],
        }
    }
}

/// Marching cubes over one block.
fn mesh_block(
    tape: &Tape,
    ws: &mut Workspace,
    scratch: &mut Scratch,
    grid: &Grid,
    region: &Region,
) -> BlockMesh {
    let h = grid.cell_size;
    let size = [0, 1, 2].map(|a| region.hi[a] - region.lo[a]);
    let n = size.map(|s| s + 1);
    let count = n[0] * n[1] * n[2];
    let local = |i: usize, j: usize, k: usize| i + n[0] * (j + n[1] * k);
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let p = grid.sample(region.lo[0] + i, region.lo[1] + j, region.lo[2] + k);
                let s = local(i, j, k);
                (scratch.xs[s], scratch.ys[s], scratch.zs[s]) = (p.x, p.y, p.z);
            }
        }
    }
    let values = &mut scratch.values[..count];
    let lo = grid.sample(region.lo[0], region.lo[1], region.lo[2]);
    let hi = grid.sample(region.hi[0], region.hi[1], region.hi[2]);
    let reach = (hi - lo).length() * 0.5 * (1.0 + 1e-9) + h * 1e-6;
    let tape = tape.pruned(ws, (lo + hi) * 0.5, reach);
    tape.eval(
        ws,
        &scratch.xs[..count],
        &scratch.ys[..count],
        &scratch.zs[..count],
        values,
    );
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let g = [region.lo[0] + i, region.lo[1] + j, region.lo[2] + k];
                let border = (0..3).any(|a| g[a] == 0 || g[a] == grid.cells[a]);
                let v = &mut values[local(i, j, k)];
                // The outer layer is outside so surfaces close; NaN never reaches a vertex.
                if border || v.is_nan() {
                    *v = -h;
                }
            }
        }
    }
    let edge_vertex = &mut scratch.edge_vertex[..count * 3];
    edge_vertex.fill(u32::MAX);
    let block = BlockGrid {
        grid,
        region,
        size,
        n,
        stride: [1, n[0], n[0] * n[1]],
    };
    let table = cases();
    let mut out = BlockMesh::default();
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                let base = local(i, j, k);
                let corner = |c: usize| block.corner(base, c);
                let pattern = (0..8).fold(0usize, |acc, c| {
                    acc | usize::from(values[corner(c)] > 0.0) << c
                });
                if pattern == 255 {
                    out.inside_cells += 1;
                    continue;
                }
                let case = &table[pattern];
                // Rings fanned around a centre get one vertex there, private to this cell.
                let mut centres = [u32::MAX; 4];
                for (r, centre) in centres
                    .iter_mut()
                    .enumerate()
                    .take(case.ring_count as usize)
                {
                    let ring = &case.rings[r][..case.ring_len[r] as usize];
                    let uses_centre = case.triangles[..case.count as usize]
                        .iter()
                        .any(|t| t[0] == CENTRE + r as u8);
                    if uses_centre {
                        let sum: DVec3 = ring
                            .iter()
                            .map(|&e| {
                                let v =
                                    block.vertex(values, edge_vertex, &mut out, base, e as usize);
                                out.positions[v as usize]
                            })
                            .sum();
                        *centre = out.positions.len() as u32;
                        out.positions.push(sum / ring.len() as f64);
                        out.keys.push(u64::MAX);
                    }
                }
                for tri in &case.triangles[..case.count as usize] {
                    let corners = tri.map(|e| {
                        if e >= CENTRE {
                            centres[(e - CENTRE) as usize]
                        } else {
                            block.vertex(values, edge_vertex, &mut out, base, e as usize)
                        }
                    });
                    out.triangles.push(corners);
                }
            }
        }
    }
    out
}

/// Where a block sits in the grid, and how its samples are laid out.
struct BlockGrid<'a> {
    grid: &'a Grid,
    region: &'a Region,
    /// Cells along each axis.
    size: [usize; 3],
    /// Samples along each axis.
    n: [usize; 3],
    /// Index steps between neighbouring samples along each axis.
    stride: [usize; 3],
}

impl BlockGrid<'_> {
    /// Sample index of corner `c` of the cell whose first corner is sample `base`.
    fn corner(&self, base: usize, c: usize) -> usize {
        base + (c & 1) * self.stride[0]
            + (c >> 1 & 1) * self.stride[1]
            + (c >> 2 & 1) * self.stride[2]
    }

    /// The vertex on edge `e` of the cell at sample `base`, made on first use: linear
    /// interpolation of the field, kept clear of the edge's ends.
    fn vertex(
        &self,
        values: &[f64],
        edge_vertex: &mut [u32],
        out: &mut BlockMesh,
        base: usize,
        e: usize,
    ) -> u32 {
        let axis = e / 4;
        let start = self.corner(base, edge_corners(e).0);
        let slot = start * 3 + axis;
        if edge_vertex[slot] != u32::MAX {
            return edge_vertex[slot];
        }
        let index = out.positions.len() as u32;
        edge_vertex[slot] = index;
        let (va, vb) = (values[start], values[start + self.stride[axis]]);
        let t = (va / (va - vb)).clamp(CORNER_CLEARANCE, 1.0 - CORNER_CLEARANCE);
        let n = self.n;
        let s = [start % n[0], start / n[0] % n[1], start / (n[0] * n[1])];
        let g = [0, 1, 2].map(|a| self.region.lo[a] + s[a]);
        let mut p = self.grid.sample(g[0], g[1], g[2]);
        p[axis] += t * self.grid.cell_size;
        let on_boundary = (0..3).any(|a| a != axis && (s[a] == 0 || s[a] == self.size[a]));
        out.positions.push(p);
        out.keys.push(if on_boundary {
            self.grid.sample_index(g) * 3 + axis as u64
        } else {
            u64::MAX
        });
        index
    }
}

/// Concatenates the blocks in order, merging the vertices they share.
fn join(blocks: &[BlockMesh]) -> Mesh {
    let vertices: usize = blocks.iter().map(|b| b.positions.len()).sum();
    let mut positions = Vec::with_capacity(vertices);
    let mut shared: FxHashMap<u64, u32> = FxHashMap::default();
    let mut triangles = Vec::with_capacity(blocks.iter().map(|b| b.triangles.len()).sum());
    let mut remap = Vec::new();
    for block in blocks {
        remap.clear();
        for (&p, &key) in block.positions.iter().zip(&block.keys) {
            let index = if key == u64::MAX {
                positions.push(p);
                positions.len() as u32 - 1
            } else {
                *shared.entry(key).or_insert_with(|| {
                    positions.push(p);
                    positions.len() as u32 - 1
                })
            };
            remap.push(index);
        }
        triangles.extend(block.triangles.iter().map(|t| t.map(|v| remap[v as usize])));
    }
    Mesh::from_faces(positions, triangles)
}
