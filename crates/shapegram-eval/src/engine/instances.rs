//! Leaves that repeat a shape, found while the model is built: each candidate leaf's geometry is
//! brought into a normal frame (its box onto the unit box, axis by axis, in its scope's
//! orientation), and leaves whose pieces agree there share a prototype.
//!
//! The comparison is by content, not by the identity of an inserted mesh, so that every way a
//! grammar repeats a shape counts: the same asset inserted again (a file is loaded once, but
//! each `i()` fits its own copy into the scope), a built-in primitive (made anew each time),
//! and equal terminals. A leaf whose inserted asset was cut has other faces, so it is no
//! instance of the asset, as CGA's `geometry.isInstanced` says.

use rustc_hash::FxHashMap;
use shapegram_geom::{DAffine3, DVec3, Instance, InstanceSetKey};

use super::Leaf;
use crate::asset_look::Piece;
use crate::shape::Geometry;

/// Which leaves may become instances.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InstanceCandidates {
    /// None: every leaf is merged into its part as before.
    #[default]
    None,
    /// Leaves holding a mesh (inserted assets, round primitives, anything an operation turned
    /// into polygons); plain boxes and quads stay with their parts, where merging serves them
    /// better.
    Meshes,
    /// Mesh leaves and box leaves (walls, floors, `primitiveCube()`), each box an instance of
    /// the unit box (or of a unit quad) scaled to its size.
    All,
}

/// The bytes a GPU instance costs (translation, rotation, scale as f32) and the JSON an
/// instanced mesh adds, roughly, as the GLB writer counts them.
const INSTANCE_BYTES: usize = 40;
const SET_BYTES: usize = 600;

/// Which pieces of which leaves are instances, by leaf and piece in model order: a piece is
/// one when its prototype is used at least twice in its material and, with `smaller_only`,
/// when drawing the copies from one mesh takes fewer bytes than writing each (the others stay
/// merged with their rule's part, so the model is then the one without instancing).
/// `leaves` gives each leaf's frame and pieces (`None` when it cannot be an instance).
pub(super) fn assign(
    leaves: impl Iterator<Item = Option<(DAffine3, Vec<Piece>)>>,
    smaller_only: bool,
) -> Vec<Vec<Option<Instance>>> {
    let mut prototypes = Prototypes::default();
    let mut uses: FxHashMap<InstanceSetKey, (usize, usize)> = FxHashMap::default();
    let mut keys: Vec<Vec<Option<InstanceSetKey>>> = Vec::new();
    let mut assigned: Vec<Vec<Option<Instance>>> = Vec::new();
    for leaf in leaves {
        let (frame, pieces) = leaf.unwrap_or_default();
        let mut leaf_keys = Vec::with_capacity(pieces.len());
        let mut leaf_instances = Vec::with_capacity(pieces.len());
        for piece in &pieces {
            let instance = prototypes.instance(frame, piece);
            let key = instance.map(|i| {
                InstanceSetKey::new(
                    i.prototype,
                    piece.color,
                    piece.colormap.as_deref(),
                    piece.material.as_ref(),
                    piece.surface.as_deref(),
                )
            });
            if let Some(key) = &key {
                let mesh = &piece.mesh;
                let corners = mesh.indices_len();
                let triangles = corners.saturating_sub(2 * mesh.face_count());
                let entry = uses.entry(key.clone()).or_insert((0, 0));
                entry.0 += 1;
                entry.1 = corners * 24 + triangles * 6;
            }
            leaf_keys.push(key);
            leaf_instances.push(instance);
        }
        keys.push(leaf_keys);
        assigned.push(leaf_instances);
    }
    let worth = |key: &InstanceSetKey| {
        let (copies, bytes) = uses[key];
        copies > 1
            && (!smaller_only || copies * bytes > bytes + SET_BYTES + copies * INSTANCE_BYTES)
    };
    for (leaf_keys, leaf_instances) in keys.iter().zip(&mut assigned) {
        for (key, instance) in leaf_keys.iter().zip(leaf_instances) {
            if key.as_ref().is_some_and(|k| !worth(k)) {
                *instance = None;
            }
        }
    }
    assigned
}

/// Normal-frame coordinates are kept on a grid of 2⁻²⁴ of the leaf's box: far finer than f32
/// resolves in the written file, coarse enough that rounding in fitting does not part copies.
const POSITION_GRID: f64 = (1u64 << 24) as f64;
/// uvs are compared on a grid of 2⁻²⁰, finer than any texture's texel.
const UV_GRID: f64 = (1u64 << 20) as f64;

/// A piece's geometry in its leaf's normal frame, as compared between leaves.
#[derive(Hash, PartialEq, Eq)]
struct Shape {
    /// Each face's corner count followed by its corners.
    faces: Vec<u32>,
    points: Vec<[i64; 3]>,
    uvs: Vec<[i64; 2]>,
}

/// The prototypes of one model, numbered in order of first use.
#[derive(Default)]
pub(super) struct Prototypes {
    ids: FxHashMap<Shape, u32>,
}

impl Prototypes {
    /// The map from a leaf's normal frame to the world, when the leaf may be an instance:
    /// a candidate with a box that has extent and a scope that is not mirrored.
    pub(super) fn frame(leaf: &Leaf, candidates: InstanceCandidates) -> Option<DAffine3> {
        let (min, size) = match (&leaf.geometry, candidates) {
            (_, InstanceCandidates::None) => return None,
            (Geometry::Mesh(mesh, _), _) => {
                let bounds = mesh.bounds()?;
                (bounds.min, bounds.size())
            }
            (Geometry::Box, InstanceCandidates::All) => (DVec3::ZERO, leaf.scope.size),
            _ => return None,
        };
        // An axis without extent keeps its unit: the prototype is flat there too.
        let scale = DVec3::from_array(size.to_array().map(|s| if s > 0.0 { s } else { 1.0 }));
        let frame = leaf.scope.local_to_world()
            * DAffine3::from_translation(min)
            * DAffine3::from_scale(scale);
        let determinant = frame.matrix3.determinant();
        (determinant.is_finite() && determinant > 0.0 && frame.translation.is_finite())
            .then_some(frame)
    }

    /// The piece as an instance of the prototype it shares its geometry with in `frame` (a
    /// new prototype when no earlier piece had it); `None` for a piece without faces.
    fn instance(&mut self, frame: DAffine3, piece: &Piece) -> Option<Instance> {
        let mesh = &piece.mesh;
        if mesh.face_count() == 0 {
            return None;
        }
        let to_frame = frame.inverse();
        let mut faces = Vec::with_capacity(mesh.face_count() + mesh.indices_len());
        for face in mesh.faces() {
            faces.push(face.len() as u32);
            faces.extend_from_slice(face);
        }
        let points = mesh
            .positions()
            .iter()
            .map(|&p| {
                let q = to_frame.transform_point3(p) * POSITION_GRID;
                q.round().to_array().map(|x| x as i64)
            })
            .collect();
        let uvs = piece.uvs.as_deref().map_or_else(Vec::new, |uvs| {
            uvs.iter()
                .map(|uv| [uv.x, uv.y].map(|x| (x * UV_GRID).round() as i64))
                .collect()
        });
        let next = self.ids.len() as u32;
        let prototype = *self.ids.entry(Shape { faces, points, uvs }).or_insert(next);
        Some(Instance {
            prototype,
            transform: frame,
        })
    }
}
