//! Visual debugging (§4.3 of "Procedural Skeletons"): the model of the derivation as it stood
//! at any node of the derivation tree, posed like the finished model. The tree keeps each
//! shape's birth snapshot (its scope and section when it was made) in the order shapes were
//! made, which is all it takes.

use shapegram_geom::{Bone, Color, Model, Part, Scope};
use shapegram_kinematics::SectionId;

use crate::engine::{Derivation, Leaf};
use crate::error::DeriveError;
use crate::shape::Geometry;

impl Derivation {
    /// The model of the shapes that existed right after tree node `node` was made: the
    /// *frontier* of the nodes `0..=node`, those without a child among them. A part per shape,
    /// in node order, named after its symbol and bound to its section so that exporters pose
    /// it (the skeletons are the finished ones: by Theorem 4.9 of the paper a joint's state at
    /// a shape's birth is its final one). Each shape is shown as
    ///
    /// - its leaf geometry, when it ended as a leaf with geometry (an implicit solid meshed on
    ///   its own, not combined with its CSG group);
    /// - else its scope box at birth, in the colour of uncoloured shapes, when it was rewritten
    ///   after `node` (a flat scope is a rectangle; a scope flat in two axes shows nothing);
    /// - else not at all: it ended without geometry (`NIL`, or an edge or vertex of a
    ///   component split with nothing inserted). The tree does not say when such a shape
    ///   ended, and leaving it out makes the state at the last node the model's own leaves.
    ///
    /// The tree numbers lots one after another (with context rules: every lot's first phase,
    /// then every lot's second), so a lot not started by `node` is not there yet and one
    /// finished before it is there whole. Needs [`DeriveOptions::keep_tree`]; an error
    /// without a tree or for a node past the last one.
    ///
    /// [`DeriveOptions::keep_tree`]: crate::DeriveOptions::keep_tree
    pub fn model_at_node(&self, node: usize) -> Result<Model, DeriveError> {
        if self.tree.is_empty() {
            return Err(DeriveError::general("the derivation kept no tree")
                .with_hint("derive with `DeriveOptions::keep_tree` set"));
        }
        if node >= self.tree.len() {
            let last = self.tree.len() - 1;
            return Err(DeriveError::general(format!(
                "there is no node {node}: the derivation tree has {} nodes (0 to {last})",
                self.tree.len()
            )));
        }
        // Parents come before their children, so the first child met is the earliest one.
        let mut first_child = vec![u32::MAX; self.tree.len()];
        for (i, n) in self.tree.iter().enumerate() {
            if let Some(p) = n.parent {
                let slot = &mut first_child[p as usize];
                *slot = (*slot).min(i as u32);
            }
        }
        // The leaves of each shape made by `node`, in node order (a shape may leave several).
        let mut leaves: Vec<(u32, usize)> = self
            .leaves
            .iter()
            .enumerate()
            .filter_map(|(i, leaf)| leaf.node().filter(|&k| k as usize <= node).map(|k| (k, i)))
            .collect();
        leaves.sort_unstable();
        let mut leaves = leaves.into_iter().peekable();

        let skeleton_of = |lot: u32| {
            self.skeletons
                .iter()
                .position(|(l, _)| *l == lot)
                .map(|i| i as u32)
        };
        let bone = |lot: u32, section: u32| {
            skeleton_of(lot).map(|skeleton| Bone {
                skeleton,
                section: SectionId(section),
            })
        };
        let mut parts = Vec::new();
        for (k, shape) in self.tree.iter().enumerate().take(node + 1) {
            let frontier = first_child[k] as usize > node;
            let mut ended_as_leaf = false;
            while let Some((_, i)) = leaves.next_if(|&(n, _)| n as usize == k) {
                ended_as_leaf = true;
                let leaf = &self.leaves[i];
                if frontier {
                    parts.extend(leaf_part(self, leaf, bone(leaf.lot, leaf.section())));
                }
            }
            let rewritten_later = first_child[k] != u32::MAX;
            if frontier && rewritten_later && !ended_as_leaf {
                let bone = bone(shape.lot, shape.section);
                parts.extend(box_part(&shape.name, &shape.scope, bone));
            }
        }
        Ok(Model {
            parts,
            lines: Vec::new(),
            skeletons: self.skeletons.iter().map(|(_, s)| s.clone()).collect(),
        })
    }
}

/// A leaf as a part of its own (`None` without geometry).
fn leaf_part(derivation: &Derivation, leaf: &Leaf, bone: Option<Bone>) -> Option<Part> {
    Some(Part {
        texture: None,
        uvs: Vec::new(),
        name: derivation.name(leaf.name).to_string(),
        color: derivation.color(leaf),
        mesh: leaf.world_mesh()?,
        normals: Vec::new(),
        bone,
        metadata: None,
        material: leaf.material().cloned(),
        surface: None,
        instance: None,
    })
}

/// A shape still to be rewritten, as its scope box at birth in the colour of uncoloured shapes
/// (`None` for a scope flat in more than one axis).
fn box_part(name: &str, scope: &Scope, bone: Option<Bone>) -> Option<Part> {
    Some(Part {
        texture: None,
        uvs: Vec::new(),
        name: name.to_owned(),
        color: Color::default(),
        mesh: Geometry::Box.world_mesh(scope)?,
        normals: Vec::new(),
        bone,
        metadata: None,
        material: None,
        surface: None,
        instance: None,
    })
}
