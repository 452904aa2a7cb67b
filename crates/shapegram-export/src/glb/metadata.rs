//! Metadata in GLB: a part's [`Metadata`] as its node's extras, and a node per lot above the
//! nodes of the lot's leaves, carrying the lot's own metadata (rule, attributes, leaf count,
//! reports). `docs/export.md` documents the keys.

use std::collections::HashMap;

use gltf_json as json;
use shapegram_geom::{MetaValue, Metadata};

/// A part's metadata as node extras: `{"shapegram": {"rule": …, "path": …, "leaves": n,
/// "goals": […], "tags": […], "attributes": {name: value}, "reports": {key: value}}}`
/// (`rule`, `path`, `leaves` and `reports` when known).
pub(super) fn metadata_extras(metadata: &Metadata) -> Box<json::extras::RawValue> {
    let object = |entries: &[(String, MetaValue)]| -> serde_json::Map<String, serde_json::Value> {
        entries
            .iter()
            .map(|(name, value)| {
                let value = match value {
                    MetaValue::Number(n) => serde_json::json!(n),
                    MetaValue::Text(t) => serde_json::json!(t),
                    MetaValue::Bool(b) => serde_json::json!(b),
                };
                (name.clone(), value)
            })
            .collect()
    };
    let mut fields = serde_json::Map::new();
    if let Some(rule) = &metadata.rule {
        fields.insert("rule".to_owned(), rule.clone().into());
    }
    if let Some(path) = &metadata.path {
        fields.insert("path".to_owned(), path.clone().into());
    }
    if let Some(leaves) = metadata.leaves {
        fields.insert("leaves".to_owned(), leaves.into());
    }
    fields.insert("goals".to_owned(), metadata.goals.clone().into());
    fields.insert("tags".to_owned(), metadata.tags.clone().into());
    fields.insert("attributes".to_owned(), object(&metadata.attributes).into());
    if let Some(reports) = &metadata.reports {
        fields.insert("reports".to_owned(), object(reports).into());
    }
    let value = serde_json::json!({ "shapegram": fields });
    serde_json::value::to_raw_value(&value).expect("a JSON value always serialises")
}

/// The lot nodes of a document: one per lot some part's metadata names, a child of the root
/// node in order of first use, named after the lot's path (`Lot[0]`), without a mesh.
#[derive(Default)]
pub(super) struct LotNodes {
    /// By lot path: the lot's node and its children so far.
    index: HashMap<String, usize>,
    nodes: Vec<(json::Index<json::Node>, Vec<json::Index<json::Node>>)>,
}

impl LotNodes {
    /// Hangs `node` under lot node `lot` (from [`LotNodes::lot_of`]), or under the root
    /// (`root_children`) when it has none.
    pub(super) fn adopt(
        &mut self,
        lot: Option<usize>,
        node: json::Index<json::Node>,
        root_children: &mut Vec<json::Index<json::Node>>,
    ) {
        match lot {
            Some(lot) => self.nodes[lot].1.push(node),
            None => root_children.push(node),
        }
    }

    /// The lot node of `metadata`'s lot, if it names one: made now, before the nodes of its
    /// parts, when this is the lot's first part (a skinned part, whose node must be a scene
    /// root, still makes its lot's node).
    pub(super) fn lot_of(
        &mut self,
        root: &mut json::Root,
        metadata: Option<&Metadata>,
        root_children: &mut Vec<json::Index<json::Node>>,
    ) -> Option<usize> {
        let lot = metadata?.lot.as_deref()?;
        let name = lot.path.clone().unwrap_or_default();
        if let Some(&known) = self.index.get(&name) {
            return Some(known);
        }
        let node = root.push(json::Node {
            name: Some(name.clone()),
            extras: Some(metadata_extras(lot)),
            ..Default::default()
        });
        root_children.push(node);
        self.nodes.push((node, Vec::new()));
        self.index.insert(name, self.nodes.len() - 1);
        Some(self.nodes.len() - 1)
    }

    /// Gives each lot node its children.
    pub(super) fn finish(self, root: &mut json::Root) {
        for (node, children) in self.nodes {
            root.nodes[node.value()].children = (!children.is_empty()).then_some(children);
        }
    }
}
