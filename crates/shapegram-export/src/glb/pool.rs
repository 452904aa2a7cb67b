//! A vertex pool: the bare primitives of a mesh (flat triangles with positions only: no normals,
//! uvs, tangents or joints) share their vertices across materials. glTF lets primitives of a
//! mesh name the same POSITION accessor, so a window pane of glass uses the corners of the wall
//! around it instead of four of its own, and a city's glass costs little more than its indices.
//!
//! The pool is cut into pieces of fewer than 65,535 vertices (u16 indices) along a Z-order
//! curve through the triangles' centres, so that neighbours, of whatever material, mostly land
//! in the same piece. Within a piece each material's triangles are put in vertex-cache order
//! and the vertices in order of first use. Deterministic: the result depends on the data only,
//! not on the threads that make the curve's keys, sort them and order the pieces.

use rayon::prelude::*;

use super::compact::Vertices;

/// One piece of a pool: its vertices and, per member primitive with triangles among them, the
/// member's index and those triangles (indices into the piece's vertices).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Piece {
    pub(crate) positions: Vec<[f32; 3]>,
    pub(crate) members: Vec<(usize, Vec<u32>)>,
}

/// The triangles of `members` (positions and indices only) over shared vertices, cut into
/// pieces of at most `limit` vertices each.
pub(crate) fn pool(members: &[Vertices], limit: usize) -> Vec<Piece> {
    let (positions, indices, owner) = shared(members);
    let unique = positions.len();

    let order = z_order(&positions, &indices, &owner);
    drop((indices, owner));
    // Triangles over the same three corners (a leaf's front and back) follow one another, as
    // their centres are one point: the run of triangles at the current centre, sorted corners.
    let mut run: (u64, Vec<[u32; 3]>) = (u64::MAX, Vec::new());
    let mut cutter = Cutter {
        slots: [vec![u32::MAX; unique], vec![u32::MAX; unique]],
        used: Vec::new(),
        lists: vec![Vec::new(); members.len()],
        cuts: Vec::new(),
    };
    for Ordered {
        key,
        triangle,
        owner,
        ..
    } in order
    {
        let mut corners = triangle;
        corners.sort_unstable();
        if run.0 != key {
            run.0 = key;
            run.1.clear();
        }
        // Readers that keep one face per set of corners (Blender) would drop the second of
        // two such triangles: the second takes corners of another layer, shared only with
        // other second ones; a third has corners of its own.
        let layer = run.1.iter().filter(|&&c| c == corners).count();
        run.1.push(corners);
        let new = match layer {
            0 | 1 => triangle
                .iter()
                .filter(|&&v| cutter.slots[layer][v as usize] == u32::MAX)
                .count(),
            _ => 3,
        };
        if cutter.used.len() + new > limit {
            cutter.cut();
        }
        let list = owner as usize;
        for v in triangle {
            let index = match cutter.slots.get_mut(layer) {
                Some(slots) if slots[v as usize] != u32::MAX => slots[v as usize],
                slots => {
                    let index = cutter.used.len() as u32;
                    cutter.used.push(v);
                    if let Some(slots) = slots {
                        slots[v as usize] = index;
                    }
                    index
                }
            };
            cutter.lists[list].push(index);
        }
    }
    if !cutter.used.is_empty() {
        cutter.cut();
    }
    // Pieces are independent from here on: ordered on as many threads as there are, each
    // piece's result the same on any number of them.
    cutter
        .cuts
        .into_par_iter()
        .map(|cut| cut.finish(&positions))
        .collect()
}

/// The members' vertices shared where their positions agree bit for bit, numbered in order of
/// first use by the members' triangles (as meshoptimizer's vertex remap numbers them); the
/// triangles over them; and the member each triangle comes from. Each member's positions are
/// looked up where they lie, rather than copied into one list for meshoptimizer first.
///
/// Equal positions are found by sorting rather than by a hash map: a city's millions of
/// vertices make a map larger than the caches, and each lookup a miss, where a sort (on
/// rayon's threads) walks memory in order.
fn shared(members: &[Vertices]) -> (Vec<[f32; 3]>, Vec<u32>, Vec<u32>) {
    let total: usize = members.iter().map(|m| m.indices.len()).sum();
    let mut indices = Vec::with_capacity(total);
    let mut owner = Vec::with_capacity(total / 3);
    // Each member's vertices in order of first use over all members (the "use" of a vertex),
    // and the triangles over those uses.
    let corners: usize = members.iter().map(Vertices::len).sum();
    let mut uses: Vec<[f32; 3]> = Vec::with_capacity(corners);
    let mut slots = Vec::new();
    for (m, member) in members.iter().enumerate() {
        slots.clear();
        slots.resize(member.len(), u32::MAX);
        for &v in &member.indices {
            let slot = &mut slots[v as usize];
            if *slot == u32::MAX {
                *slot = uses.len() as u32;
                uses.push(member.positions[v as usize]);
            }
            indices.push(*slot);
        }
        owner.extend(std::iter::repeat_n(m as u32, member.indices.len() / 3));
    }
    // Uses by position bits, then by order of use: a run of one position starts at its first
    // use. Every key is distinct, so the order is the same on any number of threads.
    let mut keys: Vec<u128> = uses
        .par_iter()
        .enumerate()
        .map(|(u, p)| {
            let [x, y, z] = p.map(|c| u128::from(c.to_bits()));
            x << 96 | y << 64 | z << 32 | u as u128
        })
        .collect();
    keys.par_sort_unstable();
    // Each use's first use of its position.
    let mut number = vec![0u32; uses.len()];
    for run in keys.chunk_by(|a, b| a >> 32 == b >> 32) {
        let first = run[0] as u32;
        for &key in run {
            number[key as u32 as usize] = first;
        }
    }
    drop(keys);
    // Numbers in order of first use: a use after its position's first takes that one's number,
    // already made.
    let mut positions = Vec::new();
    for u in 0..number.len() {
        let first = number[u] as usize;
        number[u] = if first == u {
            positions.push(uses[u]);
            positions.len() as u32 - 1
        } else {
            number[first]
        };
    }
    for index in &mut indices {
        *index = number[*index as usize];
    }
    (positions, indices, owner)
}

/// The pieces cut so far and the one being filled.
struct Cutter {
    /// Each pool vertex's index in the piece being filled (`u32::MAX`: not in it), for the
    /// first triangle over a set of corners and for the second.
    slots: [Vec<u32>; 2],
    /// The pool vertices of the piece being filled, in order of first use (a vertex twice when
    /// a twin triangle has its own copy).
    used: Vec<u32>,
    /// Per member, its triangles in the piece being filled.
    lists: Vec<Vec<u32>>,
    cuts: Vec<Cut>,
}

impl Cutter {
    /// Ends the piece being filled, to be ordered later (see [`Cut::finish`]).
    fn cut(&mut self) {
        for &v in &self.used {
            for slots in &mut self.slots {
                slots[v as usize] = u32::MAX;
            }
        }
        let members = self
            .lists
            .iter_mut()
            .enumerate()
            .filter(|(_, list)| !list.is_empty())
            .map(|(m, list)| (m, std::mem::take(list)))
            .collect();
        self.cuts.push(Cut {
            used: std::mem::take(&mut self.used),
            members,
        });
    }
}

/// A piece as cut: its pool vertices in order of first use and, per member with triangles in
/// it, the member's index and those triangles (indices into `used`).
struct Cut {
    used: Vec<u32>,
    members: Vec<(usize, Vec<u32>)>,
}

impl Cut {
    /// The piece: each member's triangles in vertex-cache order, the vertices in order of
    /// first use over all of them.
    fn finish(self, positions: &[[f32; 3]]) -> Piece {
        let count = self.used.len();
        let mut members: Vec<(usize, Vec<u32>)> = self
            .members
            .into_iter()
            .map(|(m, list)| (m, meshopt::optimize_vertex_cache_fifo(&list, count, 16)))
            .collect();
        let all: Vec<u32> = members
            .iter()
            .flat_map(|(_, l)| l.iter().copied())
            .collect();
        let remap = meshopt::optimize_vertex_fetch_remap(&all, count);
        let positions: Vec<[f32; 3]> = self.used.iter().map(|&v| positions[v as usize]).collect();
        let positions = meshopt::remap_vertex_buffer(&positions, count, &remap);
        for (_, list) in &mut members {
            *list = meshopt::remap_index_buffer(Some(list), count, &remap);
        }
        Piece { positions, members }
    }
}

/// A triangle in Z-order: its key, its number (which orders ties), its corners and the member
/// it comes from. The corners and member travel with the key so that the walk in Z-order reads
/// them in order rather than looking them up all over the pool.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Ordered {
    key: u64,
    number: u32,
    triangle: [u32; 3],
    owner: u32,
}

/// The triangles in the order of their centres along a Z-order (Morton) curve over the
/// positions' bounds, ties in triangle order.
fn z_order(positions: &[[f32; 3]], indices: &[u32], owner: &[u32]) -> Vec<Ordered> {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    // 21 bits per axis fill a u64's 63; cubic cells, so that a thin layout (a street) is
    // walked along its length rather than across it.
    let cells = f64::from((1u32 << 21) - 1);
    let extent = (0..3)
        .map(|k| f64::from(max[k]) - f64::from(min[k]))
        .fold(0.0, f64::max);
    let scale = if extent > 0.0 { cells / extent } else { 0.0 };
    // On as many threads as there are: each key depends on its triangle alone, and the
    // triangle's number makes every key distinct, so the sorted order is the same on any number.
    let mut keyed: Vec<Ordered> = indices
        .par_chunks_exact(3)
        .zip(owner)
        .enumerate()
        .map(|(t, (triangle, &owner))| {
            // Summed in the order of the corners' indices, so that a triangle and its back
            // (the same corners in another order) get one key.
            let mut corners = [triangle[0], triangle[1], triangle[2]];
            corners.sort_unstable();
            let cell: [u64; 3] = std::array::from_fn(|k| {
                let sum: f64 = corners
                    .iter()
                    .map(|&v| f64::from(positions[v as usize][k]))
                    .sum();
                ((sum / 3.0 - f64::from(min[k])) * scale).clamp(0.0, cells) as u64
            });
            Ordered {
                key: spread(cell[0]) | spread(cell[1]) << 1 | spread(cell[2]) << 2,
                number: t as u32,
                triangle: [triangle[0], triangle[1], triangle[2]],
                owner,
            }
        })
        .collect();
    keyed.par_sort_unstable();
    keyed
}

/// The low 21 bits of `x` spread out to every third bit.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use rustc_hash::FxHashMap;

    use super::*;

    /// A unit square at (x, y) in the plane z = 0, as four vertices and two triangles.
    fn square(x: f32, y: f32) -> Vertices<'static> {
        Vertices {
            positions: vec![
                [x, y, 0.0],
                [x + 1.0, y, 0.0],
                [x + 1.0, y + 1.0, 0.0],
                [x, y + 1.0, 0.0],
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Vertices::default()
        }
    }

    /// Each member's triangles as positions, in the order the pieces hold them.
    fn triangles(pieces: &[Piece], member: usize) -> Vec<[[f32; 3]; 3]> {
        let mut found = Vec::new();
        for piece in pieces {
            for (m, list) in &piece.members {
                if *m == member {
                    let corners = list.chunks_exact(3);
                    found
                        .extend(corners.map(|t| [0, 1, 2].map(|k| piece.positions[t[k] as usize])));
                }
            }
        }
        found.sort_by(|a, b| a.partial_cmp(b).unwrap());
        found
    }

    /// `shared` as it was with a hash map, the numbering the sort must reproduce.
    fn shared_by_map(members: &[Vertices]) -> (Vec<[f32; 3]>, Vec<u32>, Vec<u32>) {
        let (mut positions, mut indices, mut owner) = (Vec::new(), Vec::new(), Vec::new());
        let mut number: FxHashMap<[u32; 3], u32> = FxHashMap::default();
        for (m, member) in members.iter().enumerate() {
            let mut slots = vec![u32::MAX; member.len()];
            for &v in &member.indices {
                let slot = &mut slots[v as usize];
                if *slot == u32::MAX {
                    let position = member.positions[v as usize];
                    *slot = *number.entry(position.map(f32::to_bits)).or_insert_with(|| {
                        positions.push(position);
                        positions.len() as u32 - 1
                    });
                }
                indices.push(*slot);
            }
            owner.extend(std::iter::repeat_n(m as u32, member.indices.len() / 3));
        }
        (positions, indices, owner)
    }

    #[test]
    fn shared_numbers_vertices_in_order_of_first_use_as_a_map_does() {
        // Members over a few coordinates of both signs (0.0 and -0.0 apart, as their bits
        // are), each with vertices it lists twice and vertices it never uses.
        let values = [-2.0f32, -0.0, 0.0, 0.5, 1.0, 3.0];
        let mut state = 7u32;
        let mut next = || {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            state >> 16
        };
        let members: Vec<Vertices> = (0..6)
            .map(|_| {
                let positions: Vec<[f32; 3]> = (0..200)
                    .map(|_| [0; 3].map(|_| values[next() as usize % values.len()]))
                    .collect();
                let indices = (0..300).map(|_| next() % 150).collect();
                Vertices {
                    positions,
                    indices,
                    ..Vertices::default()
                }
            })
            .collect();
        let (positions, indices, owner) = shared(&members);
        assert!(
            positions.len() < members.len() * 150,
            "members share vertices"
        );
        assert_eq!((positions, indices, owner), shared_by_map(&members));
    }

    #[test]
    fn members_share_the_corners_where_they_meet() {
        // A pane between two wall squares: 8 corners in all, not 12.
        let members = [square(0.0, 0.0), square(1.0, 0.0), square(2.0, 0.0)];
        let walls = Vertices {
            positions: [&members[0], &members[2]]
                .iter()
                .flat_map(|m| m.positions.clone())
                .collect(),
            indices: vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7],
            ..Vertices::default()
        };
        let pane = members[1].clone();
        let pieces = pool(&[walls.clone(), pane.clone()], 100);
        assert_eq!(pieces.len(), 1);
        assert_eq!(pieces[0].positions.len(), 8);
        assert_eq!(pieces[0].members.len(), 2);
        for (member, original) in [walls, pane].iter().enumerate() {
            let want: Vec<[[f32; 3]; 3]> = original
                .indices
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| original.positions[t[k] as usize]))
                .collect();
            let got = triangles(&pieces, member);
            assert_eq!(got.len(), want.len());
            // Cache order may start a triangle at another corner, never turn it over.
            for triangle in &got {
                let rotations = [0, 1, 2].map(|r| [0, 1, 2].map(|k| triangle[(k + r) % 3]));
                assert!(rotations.iter().any(|r| want.contains(r)), "{triangle:?}");
            }
        }
    }

    #[test]
    fn a_large_pool_is_cut_into_pieces_that_keep_every_triangle() {
        // A strip of 100 squares of two materials, pieces of at most 20 vertices.
        let members: Vec<Vertices> = (0..2)
            .map(|m| {
                let mut all = Vertices::default();
                for i in (m..100).step_by(2) {
                    let base = all.positions.len() as u32;
                    let s = square(i as f32, 0.0);
                    all.positions.extend(s.positions);
                    all.indices.extend(s.indices.iter().map(|&v| base + v));
                }
                all
            })
            .collect();
        let pieces = pool(&members, 20);
        assert!(pieces.len() > 1);
        assert!(pieces.iter().all(|p| p.positions.len() <= 20));
        for m in 0..2 {
            assert_eq!(triangles(&pieces, m).len(), 100);
        }
        // 202 corners in the strip, and a few repeated where pieces meet.
        let vertices: usize = pieces.iter().map(|p| p.positions.len()).sum();
        assert!(
            (202..202 + 2 * pieces.len()).contains(&vertices),
            "{vertices}"
        );
        assert_eq!(pool(&members, 20), pieces);
    }

    #[test]
    fn a_face_and_its_back_keep_corners_of_their_own() {
        let front = square(0.0, 0.0);
        let back = Vertices {
            indices: vec![0, 2, 1, 0, 3, 2],
            ..front.clone()
        };
        let pieces = pool(&[front, back], 100);
        assert_eq!(pieces[0].positions.len(), 8);
        let corners = |m: usize| {
            let mut used: Vec<u32> = pieces[0].members[m].1.clone();
            used.sort_unstable();
            used.dedup();
            used
        };
        assert!(corners(0).iter().all(|v| !corners(1).contains(v)));
    }

    #[test]
    fn spread_interleaves_bits() {
        assert_eq!(spread(0b1011), 0b1_000_001_001);
        assert_eq!(spread(0x1f_ffff), 0x1249_2492_4924_9249);
    }
}
