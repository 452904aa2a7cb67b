//! Metadata in GLB: a part's [`Metadata`] as its node's extras, and a node per lot above the
//! nodes of the lot's leaves, carrying the lot's own metadata (rule, attributes, leaf count,
//! reports). `docs/export.md` documents the keys.

use std::collections::HashMap;

use gltf_json as json;
use serde::ser::{Serialize, SerializeMap, Serializer};
use shapegram_geom::{MetaValue, Metadata};

/// A part's metadata as node extras: `{"shapegram": {"rule": …, "path": …, "leaves": n,
/// "goals": […], "tags": […], "attributes": {name: value}, "reports": {key: value}}}`
/// (`rule`, `path`, `leaves` and `reports` when known), keys sorted within each object.
pub(super) fn metadata_extras(metadata: &Metadata) -> Box<json::extras::RawValue> {
    serde_json::value::to_raw_value(&Extras(metadata)).expect("metadata always serialises")
}

/// Serialises [`Metadata`] straight to JSON text, in the bytes a `serde_json::Value` of it
/// would give (objects' keys in sorted order, the last of equal keys winning), without
/// building that tree: a city has a node per leaf.
struct Extras<'a>(&'a Metadata);

impl Serialize for Extras<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut outer = serializer.serialize_map(Some(1))?;
        outer.serialize_entry("shapegram", &Fields(self.0))?;
        outer.end()
    }
}

/// The object under `"shapegram"`, its keys in sorted order.
struct Fields<'a>(&'a Metadata);

impl Serialize for Fields<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let m = self.0;
        let mut map = serializer.serialize_map(None)?;
        map.serialize_entry("attributes", &Object(&m.attributes))?;
        map.serialize_entry("goals", &m.goals)?;
        if let Some(leaves) = m.leaves {
            map.serialize_entry("leaves", &leaves)?;
        }
        if let Some(path) = &m.path {
            map.serialize_entry("path", path)?;
        }
        if let Some(reports) = &m.reports {
            map.serialize_entry("reports", &Object(reports))?;
        }
        if let Some(rule) = &m.rule {
            map.serialize_entry("rule", rule)?;
        }
        map.serialize_entry("tags", &m.tags)?;
        map.end()
    }
}

/// Named values as a JSON object: by name, the last value of a name written more than once.
struct Object<'a>(&'a [(String, MetaValue)]);

impl Serialize for Object<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut entries: Vec<&(String, MetaValue)> = self.0.iter().collect();
        // Stable, so that of equal names the one given last stays last.
        if !entries.is_sorted_by(|a, b| a.0 < b.0) {
            entries.sort_by(|a, b| a.0.cmp(&b.0));
        }
        let mut map = serializer.serialize_map(None)?;
        for (i, (name, value)) in entries.iter().map(|e| (&e.0, &e.1)).enumerate() {
            if entries.get(i + 1).is_some_and(|next| next.0 == *name) {
                continue;
            }
            match value {
                MetaValue::Number(n) => map.serialize_entry(name, n)?,
                MetaValue::Text(t) => map.serialize_entry(name, t)?,
                MetaValue::Bool(b) => map.serialize_entry(name, b)?,
            }
        }
        map.end()
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// What the extras were before they were serialised directly: a `serde_json::Value` of
    /// the metadata, whose objects sort their keys and keep the last of equal ones.
    fn as_value(metadata: &Metadata) -> String {
        let object =
            |entries: &[(String, MetaValue)]| -> serde_json::Map<String, serde_json::Value> {
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
        serde_json::json!({ "shapegram": fields }).to_string()
    }

    fn entries(list: &[(&str, MetaValue)]) -> Vec<(String, MetaValue)> {
        list.iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect()
    }

    #[test]
    fn extras_are_the_bytes_of_the_value_tree() {
        let full = Metadata {
            rule: Some("Win\"dow/é".to_owned()),
            path: Some("Lot[0]/Mass[0]/Window[3]".to_owned()),
            leaves: Some(7),
            goals: vec!["chair".to_owned()],
            tags: vec!["wooden".to_owned(), "tab\t".to_owned()],
            // Out of order, and a name given twice: the last one is kept, in its sorted place.
            attributes: entries(&[
                ("z", MetaValue::Number(-0.0)),
                ("a", MetaValue::Text("x".to_owned())),
                ("m", MetaValue::Bool(true)),
                ("a", MetaValue::Number(1e21)),
                ("n", MetaValue::Number(f64::NAN)),
            ]),
            reports: Some(entries(&[
                ("k_n", MetaValue::Number(1.0)),
                ("k_sum", MetaValue::Number(0.1 + 0.2)),
                ("k_n", MetaValue::Number(3.0)),
                ("k_avg", MetaValue::Text("y".to_owned())),
            ])),
            lot: None,
        };
        let bare = Metadata::default();
        for metadata in [&full, &bare] {
            assert_eq!(metadata_extras(metadata).get(), as_value(metadata));
        }
        let text = metadata_extras(&full).get().to_owned();
        assert!(text.contains(r#""m":true,"n":null,"z":"#), "{text}");
        assert_eq!(text.matches(r#""a":"#).count(), 1, "{text}");
    }
}
