//! What each leaf is, for readers of the written model ([`super::ModelOptions::metadata`]):
//! its rule, its derivation path, its attributes and the reports made on its way from the lot,
//! read from the derivation tree, with the goals, tags and named attributes of goal grammars;
//! and what each lot is: its rule, attributes, leaf count and all the reports made deriving it.

use std::sync::Arc;

use shapegram_geom::{MetaValue, Metadata};

use super::{Derivation, Leaf, TreeNode, meta_value};
use crate::goals::LeafSemantics;
use crate::reports::summarise_reports;
use crate::value::Value;

/// Describes leaves from the derivation tree (which may be empty: then a leaf has its rule
/// alone).
pub(super) struct LeafDescriber<'a> {
    tree: &'a [TreeNode],
    /// The names of leaves' symbols ([`Derivation::names`]).
    names: &'a [Arc<str>],
    attr_names: &'a [String],
    /// Each tree node's position among the children of its parent (for an initial shape, the
    /// lot's index).
    positions: Vec<u32>,
    reports: &'a [(String, Value)],
    /// The reports made on each tree node, as indices into `reports`: node `n`'s are
    /// `report_order[report_starts[n]..report_starts[n + 1]]`, in the order they were made.
    report_starts: Vec<u32>,
    report_order: Vec<u32>,
    /// Each lot's metadata, by lot index (`None` for an index no tree node has).
    lots: Vec<Option<Arc<Metadata>>>,
    /// The path of the last leaf described, and the tree node of each of its steps with the
    /// path's length up to that step.
    last_path: String,
    last_steps: Vec<(u32, usize)>,
}

impl<'a> LeafDescriber<'a> {
    /// A describer over the tree of `derivation`, whose nodes hold attribute values in the
    /// order of `attr_names`; a lot's path starts with its number in `numbers` (by its index
    /// among the derivation's lots), or with that index where `numbers` has none.
    pub(super) fn new(
        derivation: &'a Derivation,
        attr_names: &'a [String],
        numbers: &[u32],
    ) -> Self {
        let tree = derivation.tree.as_slice();
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
                None => numbers.get(node.lot as usize).copied().unwrap_or(node.lot),
            })
            .collect();
        // Report nodes are complete exactly when the tree was kept.
        let report_nodes = if derivation.report_nodes.len() == derivation.reports.len() {
            derivation.report_nodes.as_slice()
        } else {
            &[]
        };
        let mut report_starts = vec![0u32; tree.len() + 1];
        for &node in report_nodes {
            if let Some(start) = report_starts.get_mut(node as usize + 1) {
                *start += 1;
            }
        }
        for n in 1..report_starts.len() {
            report_starts[n] += report_starts[n - 1];
        }
        let mut next = report_starts.clone();
        let mut report_order = vec![0u32; *report_starts.last().unwrap_or(&0) as usize];
        for (i, &node) in report_nodes.iter().enumerate() {
            if let Some(slot) = next.get_mut(node as usize) {
                report_order[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
        let mut describer = Self {
            tree,
            names: &derivation.names,
            attr_names,
            positions,
            reports: &derivation.reports,
            report_starts,
            report_order,
            lots: Vec::new(),
            last_path: String::new(),
            last_steps: Vec::new(),
        };
        describer.lots = describer.lots(derivation, report_nodes);
        describer
    }

    /// Each lot's metadata, by lot index (`None` for an index no tree node has).
    pub(super) fn into_lots(self) -> Vec<Option<Arc<Metadata>>> {
        self.lots
    }

    /// Every lot's metadata: its initial shape's rule, path and attributes, how many leaves it
    /// derived and the summary of every report made deriving it (on shapes that became
    /// leaves or not).
    fn lots(&self, derivation: &Derivation, report_nodes: &[u32]) -> Vec<Option<Arc<Metadata>>> {
        let count = self
            .tree
            .iter()
            .map(|n| n.lot as usize + 1)
            .max()
            .unwrap_or(0);
        let mut leaves = vec![0u32; count];
        for leaf in &derivation.leaves {
            if let Some(n) = leaves.get_mut(leaf.lot as usize) {
                *n += 1;
            }
        }
        let mut reports: Vec<Vec<(String, Value)>> = vec![Vec::new(); count];
        for (report, &node) in self.reports.iter().zip(report_nodes) {
            if let Some(node) = self.tree.get(node as usize) {
                reports[node.lot as usize].push(report.clone());
            }
        }
        let mut lots = vec![None; count];
        for (n, node) in self.tree.iter().enumerate() {
            if node.parent.is_some() {
                continue;
            }
            let lot = node.lot as usize;
            let mut metadata = self.node_metadata(n, &reports[lot]);
            metadata.leaves = Some(leaves[lot]);
            lots[lot] = Some(Arc::new(metadata));
        }
        lots
    }

    /// Tree node `node` as metadata: its symbol, path and attributes, with `reports`
    /// summarised.
    fn node_metadata(&self, node: usize, reports: &[(String, Value)]) -> Metadata {
        let mut attributes: Vec<(String, MetaValue)> = self
            .attr_names
            .iter()
            .zip(self.tree[node].attrs.iter())
            .map(|(name, value)| (name.clone(), meta_value(value)))
            .collect();
        attributes.sort_by(|a, b| a.0.cmp(&b.0));
        Metadata {
            rule: Some(self.tree[node].name.to_string()),
            path: Some(self.path(node)),
            attributes,
            reports: Some(summary(reports)),
            ..Metadata::default()
        }
    }

    /// The leaf's metadata: rule, path, attributes, the reports made on its shape and its
    /// ancestors, its lot, and the semantics of a goal grammar's leaf (whose named attributes
    /// win over grammar attributes of the same name).
    pub(super) fn describe(&mut self, leaf: &Leaf, semantics: Option<&LeafSemantics>) -> Metadata {
        let node = leaf
            .node()
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
            rule: Some(self.names[leaf.name.0 as usize].to_string()),
            path: node.map(|n| self.leaf_path(n)),
            leaves: None,
            goals,
            tags,
            attributes,
            reports: node.map(|n| summary(&self.path_reports(n))),
            lot: node.and_then(|_| self.lots.get(leaf.lot as usize).cloned().flatten()),
        }
    }

    /// The reports made on `node` and its ancestors, from the initial shape down (what PRT's
    /// leaf reporting strategy gives a leaf).
    fn path_reports(&self, node: usize) -> Vec<(String, Value)> {
        let mut steps = Vec::new();
        let mut at = Some(node);
        while let Some(n) = at {
            steps.push(n);
            at = self.tree[n].parent.map(|p| p as usize);
        }
        let starts = &self.report_starts;
        steps
            .iter()
            .rev()
            .flat_map(|&n| &self.report_order[starts[n] as usize..starts[n + 1] as usize])
            .map(|&i| self.reports[i as usize].clone())
            .collect()
    }

    /// [`Self::path`] of a leaf's node, built on the part of the last leaf's path that the
    /// two share: leaves come in derivation order, so that is most of it.
    fn leaf_path(&mut self, node: usize) -> String {
        // The node's ancestors below the deepest one on the last path, from the node up.
        let mut below = Vec::new();
        let mut kept = 0;
        let mut at = Some(node as u32);
        while let Some(n) = at {
            if let Some(k) = self.last_steps.iter().rposition(|&(m, _)| m == n) {
                kept = k + 1;
                break;
            }
            below.push(n);
            at = self.tree[n as usize].parent;
        }
        self.last_steps.truncate(kept);
        let mut path = std::mem::take(&mut self.last_path);
        path.truncate(self.last_steps.last().map_or(0, |&(_, end)| end));
        for &n in below.iter().rev() {
            if !path.is_empty() {
                path.push('/');
            }
            self.push_step(&mut path, n as usize);
            self.last_steps.push((n, path.len()));
        }
        self.last_path = path;
        self.last_path.clone()
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
            self.push_step(&mut path, n);
        }
        path
    }

    /// Appends `Name[k]`, node `n`'s step of a path.
    fn push_step(&self, path: &mut String, n: usize) {
        use std::fmt::Write;
        write!(path, "{}[{}]", self.tree[n].name, self.positions[n]).expect("a String takes text");
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
                        reports: None,
                        lot: None,
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

/// Reports summarised as metadata values (see [`summarise_reports`]).
fn summary(reports: &[(String, Value)]) -> Vec<(String, MetaValue)> {
    summarise_reports(reports)
        .into_iter()
        .map(|(key, value)| (key, meta_value(&value)))
        .collect()
}

#[cfg(test)]
mod tests {
    use shapegram_geom::DVec2;

    use super::*;
    use crate::{DeriveOptions, InitialShape, Program};

    #[test]
    fn leaf_paths_built_on_the_last_path_are_the_paths_from_the_root() {
        let source = shapegram_syntax::SourceFile::new(
            "t.cga",
            "Lot --> extrude(9) comp(f) { side : Facade | top : Roof. }\n\
             Facade --> split(y) { ~3 : Floor }*\n\
             Floor --> split(x) { ~1 : Tile }*\n\
             Tile --> split(x) { 0.2 : Wall. | ~1 : Window. | 0.2 : Wall. }",
        );
        let program = Program::compile(&shapegram_syntax::parse(&source).grammar)
            .0
            .expect("compiles");
        let lots: Vec<InitialShape> = [0.0, 30.0]
            .map(|x| {
                let corners = [(x, 0.0), (x + 10.0, 0.0), (x + 10.0, 20.0), (x, 20.0)];
                InitialShape::from_xz(&corners.map(|(x, z)| DVec2::new(x, z))).unwrap()
            })
            .to_vec();
        let options = DeriveOptions {
            keep_tree: true,
            ..DeriveOptions::default()
        };
        let derivation = crate::derive(&program, &lots, &options).expect("derives");
        let leaves = &derivation.leaves;
        assert!(leaves.len() > 100, "{} leaves", leaves.len());
        // In leaf order (neighbours in turn), then backwards, skipping (paths that share less).
        let mut describer = LeafDescriber::new(&derivation, &[], &[]);
        let order = (0..leaves.len()).chain((0..leaves.len()).rev().step_by(3));
        for i in order {
            let node = leaves[i].node().expect("the tree was kept") as usize;
            let path = describer.describe(&leaves[i], None).path.expect("a path");
            assert_eq!(path, describer.path(node));
            assert!(
                path.starts_with(&format!("Lot[{}]/", leaves[i].lot)),
                "{path}"
            );
        }
    }
}
