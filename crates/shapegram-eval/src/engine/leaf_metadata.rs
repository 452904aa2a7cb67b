//! What each leaf is, for readers of the written model ([`super::ModelOptions::metadata`]):
//! its rule, its derivation path and its attributes, read from the derivation tree, with the
//! goals, tags and named attributes of goal grammars.

use shapegram_geom::{MetaValue, Metadata};

use super::{Leaf, TreeNode, meta_value};
use crate::goals::LeafSemantics;

/// Describes leaves from the derivation tree (which may be empty: then a leaf has its rule
/// alone).
pub(super) struct LeafDescriber<'a> {
    tree: &'a [TreeNode],
    attr_names: &'a [String],
    /// Each tree node's position among the children of its parent (for an initial shape, the
    /// lot's index).
    positions: Vec<u32>,
}

impl<'a> LeafDescriber<'a> {
    /// A describer over `tree`, whose nodes hold attribute values in the order of
    /// `attr_names`.
    pub(super) fn new(tree: &'a [TreeNode], attr_names: &'a [String]) -> Self {
        // Nodes come parents first, children in the order they were made.
        let mut made = vec![0u32; tree.len()];
        let positions = tree
            .iter()
            .map(|node| match node.parent {
                Some(parent) => {
                    let count = &mut made[parent as usize];
                    *count += 1;
                    *count - 1
                }
                None => node.lot,
            })
            .collect();
        Self {
            tree,
            attr_names,
            positions,
        }
    }

    /// The leaf's metadata: rule, path and attributes, and the semantics of a goal grammar's
    /// leaf (whose named attributes win over grammar attributes of the same name).
    pub(super) fn describe(&self, leaf: &Leaf, semantics: Option<&LeafSemantics>) -> Metadata {
        let node = leaf
            .node
            .map(|n| n as usize)
            .filter(|&n| n < self.tree.len());
        let mut attributes: Vec<(String, MetaValue)> = Vec::new();
        let names = |list: &[std::sync::Arc<str>]| list.iter().map(|s| s.to_string()).collect();
        let (goals, tags) = match semantics {
            Some(semantics) => {
                attributes.extend(
                    semantics
                        .attributes
                        .iter()
                        .map(|(name, value)| (name.to_string(), meta_value(value))),
                );
                (names(&semantics.goals), names(&semantics.tags))
            }
            None => (Vec::new(), Vec::new()),
        };
        if let Some(node) = node {
            for (name, value) in self.attr_names.iter().zip(self.tree[node].attrs.iter()) {
                if !attributes.iter().any(|(known, _)| known == name) {
                    attributes.push((name.clone(), meta_value(value)));
                }
            }
        }
        attributes.sort_by(|a, b| a.0.cmp(&b.0));
        Metadata {
            rule: Some(leaf.name.to_string()),
            path: node.map(|n| self.path(n)),
            leaves: None,
            goals,
            tags,
            attributes,
        }
    }

    /// `Lot[0]/Mass[0]/Facade[2]`: the symbol of each shape from the initial shape down to
    /// `node`, each with its position among its parent's children (the lot's index first).
    fn path(&self, node: usize) -> String {
        let mut steps = Vec::new();
        let mut at = Some(node);
        while let Some(n) = at {
            steps.push(n);
            at = self.tree[n].parent.map(|p| p as usize);
        }
        let mut path = String::new();
        for &n in steps.iter().rev() {
            if !path.is_empty() {
                path.push('/');
            }
            path.push_str(&self.tree[n].name);
            path.push('[');
            path.push_str(&self.positions[n].to_string());
            path.push(']');
        }
        path
    }
}

/// Per-part metadata ([`super::MetadataScope::Part`]): each part's rule, its leaves' count and
/// the attributes all of them agree on, gathered leaf by leaf.
#[derive(Default)]
pub(super) struct PartSummaries {
    /// By part: the summary so far and the last leaf counted in it.
    parts: Vec<Option<(Metadata, usize)>>,
}

impl PartSummaries {
    /// Counts leaf `leaf`, described by `description`, in part `part`.
    pub(super) fn add(&mut self, part: usize, leaf: usize, description: &Metadata) {
        if self.parts.len() <= part {
            self.parts.resize(part + 1, None);
        }
        match &mut self.parts[part] {
            None => {
                self.parts[part] = Some((
                    Metadata {
                        path: None,
                        leaves: Some(1),
                        ..description.clone()
                    },
                    leaf,
                ));
            }
            // A leaf drawn in several materials of one part counts once.
            Some((_, last)) if *last == leaf => {}
            Some((summary, last)) => {
                *last = leaf;
                summary.leaves = summary.leaves.map(|n| n + 1);
                summary
                    .attributes
                    .retain(|attribute| description.attributes.contains(attribute));
            }
        }
    }

    /// Gives each part that holds leaves its summary.
    pub(super) fn finish(self, parts: &mut [shapegram_geom::Part]) {
        for (part, summary) in parts.iter_mut().zip(self.parts) {
            if let Some((summary, _)) = summary {
                part.metadata = Some(std::sync::Arc::new(summary));
            }
        }
    }
}
