//! Features in GLB: each vertex's feature id (`EXT_mesh_features`, a `_FEATURE_ID_0`
//! attribute) and a property table with a row per feature (`EXT_structural_metadata`), made
//! from the features' [`Metadata`]: a 3D Tiles tile's lots, one feature each
//! (`docs/tiles.md`, "Metadata").
//!
//! The table's columns are the metadata's `rule` and `path` (STRING), `leaves` (UINT32), each
//! attribute and each report key of any row, by name: FLOAT64 where every row that has it holds
//! a number, BOOLEAN where every row holds a boolean, STRING otherwise (numbers and booleans
//! then written as in JSON). A row without a value takes the property's `noData`, a value no
//! row holds: "" for STRING (`(none)` if a row holds ""), the lowest f64 for FLOAT64 (or the
//! next one up that no row holds), `u32::MAX` for UINT32 (BOOLEAN has no `noData`, so a
//! boolean with gaps becomes STRING). Property ids are the names with every character but
//! ASCII letters, digits and `_` made `_` (`floor.area_sum` → `floor_area_sum`), made unique
//! by a suffix `_2`, `_3`, …; a property whose id differs from its name carries the name.

use std::collections::BTreeMap;

use gltf_json::accessor::ComponentType;
use serde_json::{Map, Value, json};
use shapegram_geom::{MetaValue, Metadata};

/// The names of the two extensions.
pub(super) const MESH_FEATURES: &str = "EXT_mesh_features";
pub(super) const STRUCTURAL_METADATA: &str = "EXT_structural_metadata";

/// The schema's class, whose instances the rows are.
const CLASS: &str = "lot";

/// What a GLB's features are: a row of metadata per feature, in feature id order, and the
/// feature of each model part and line set. Vertices of different features are never shared
/// and faces of different features never merged.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Features<'a> {
    /// Each feature's metadata, by feature id.
    pub rows: Vec<&'a Metadata>,
    /// The feature id of each of the model's parts, by part index.
    pub parts: Vec<u32>,
    /// The feature id of each of the model's line sets, by index.
    pub lines: Vec<u32>,
}

impl Features<'_> {
    /// The smallest component type that holds every feature id (the spec allows any):
    /// `_FEATURE_ID_0` elements are padded to 4 bytes all the same, as glTF wants.
    pub(super) fn component(&self) -> ComponentType {
        match self.rows.len() {
            0..=256 => ComponentType::U8,
            257..=65_536 => ComponentType::U16,
            _ => ComponentType::U32,
        }
    }
}

/// A column of the property table.
enum Column {
    Strings(Vec<Option<String>>),
    Floats(Vec<Option<f64>>),
    Counts(Vec<Option<u32>>),
    Bools(Vec<bool>),
}

/// The property table, encoded: the extension's JSON (with buffer views counted from a base)
/// and the views' bytes, in order.
pub(super) struct PropertyTable {
    count: usize,
    /// By property id: its class property and how many views its values take (1 or 2).
    properties: Vec<(String, Value, usize)>,
    pub(super) views: Vec<Vec<u8>>,
}

impl PropertyTable {
    /// The table of `rows`.
    pub(super) fn new(rows: &[&Metadata]) -> Self {
        let mut columns: Vec<(String, Column)> = vec![
            (
                "rule".to_owned(),
                Column::Strings(rows.iter().map(|r| r.rule.clone()).collect()),
            ),
            (
                "path".to_owned(),
                Column::Strings(rows.iter().map(|r| r.path.clone()).collect()),
            ),
            (
                "leaves".to_owned(),
                Column::Counts(rows.iter().map(|r| r.leaves).collect()),
            ),
        ];
        columns.extend(named_columns(rows, |r| &r.attributes));
        columns.extend(named_columns(rows, |r| r.reports.as_deref().unwrap_or(&[])));
        let mut ids: Vec<String> = Vec::with_capacity(columns.len());
        let mut properties = Vec::with_capacity(columns.len());
        let mut views = Vec::new();
        for (name, column) in columns {
            let id = unique_id(&name, &ids);
            let (mut property, values, offsets) = encode(column);
            if id != name {
                property.insert("name".to_owned(), name.into());
            }
            views.push(values);
            let taken = match offsets {
                Some(offsets) => {
                    views.push(offsets);
                    2
                }
                None => 1,
            };
            properties.push((id.clone(), Value::Object(property), taken));
            ids.push(id);
        }
        Self {
            count: rows.len(),
            properties,
            views,
        }
    }

    /// The root's `EXT_structural_metadata`, its views numbered from `first_view`.
    pub(super) fn extension(&self, first_view: u32) -> Value {
        let mut class = Map::new();
        let mut table = Map::new();
        let mut view = first_view;
        for (id, property, taken) in &self.properties {
            class.insert(id.clone(), property.clone());
            let mut columns = json!({ "values": view });
            if *taken == 2 {
                columns["stringOffsets"] = json!(view + 1);
            }
            table.insert(id.clone(), columns);
            view += *taken as u32;
        }
        json!({
            "schema": {
                "id": "shapegram",
                "classes": { CLASS: { "properties": class } },
            },
            "propertyTables": [{
                "class": CLASS,
                "count": self.count,
                "properties": table,
            }],
        })
    }
}

/// The columns of the named values (attributes or reports) of any row, in name order, each
/// row's value of a name being the last it gives.
fn named_columns<'a>(
    rows: &[&'a Metadata],
    values: impl Fn(&'a Metadata) -> &'a [(String, MetaValue)],
) -> Vec<(String, Column)> {
    let mut by_name: BTreeMap<&'a str, Vec<Option<&'a MetaValue>>> = BTreeMap::new();
    for (row, metadata) in rows.iter().enumerate() {
        for (name, value) in values(metadata) {
            by_name
                .entry(name)
                .or_insert_with(|| vec![None; rows.len()])[row] = Some(value);
        }
    }
    by_name
        .into_iter()
        .map(|(name, values)| (name.to_owned(), column(&values)))
        .collect()
}

/// A column of values of one name: of their kind where all are numbers, or all booleans
/// without gaps; text otherwise.
fn column(values: &[Option<&MetaValue>]) -> Column {
    let present = || values.iter().flatten();
    if present().all(|v| matches!(v, MetaValue::Number(_))) {
        return Column::Floats(
            values
                .iter()
                .map(|v| match v {
                    Some(MetaValue::Number(n)) => Some(*n),
                    _ => None,
                })
                .collect(),
        );
    }
    let gaps = values.iter().any(Option::is_none);
    if !gaps && present().all(|v| matches!(v, MetaValue::Bool(_))) {
        return Column::Bools(
            values
                .iter()
                .map(|v| matches!(v, Some(MetaValue::Bool(true))))
                .collect(),
        );
    }
    Column::Strings(
        values
            .iter()
            .map(|v| {
                v.map(|v| match v {
                    MetaValue::Text(t) => t.clone(),
                    MetaValue::Number(n) => serde_json::to_string(n).expect("numbers serialise"),
                    MetaValue::Bool(b) => b.to_string(),
                })
            })
            .collect(),
    )
}

/// A column's class property (with `noData` when some row lacks a value) and its values'
/// bytes, with the string offsets of a STRING column; each padded to 8 bytes.
fn encode(column: Column) -> (Map<String, Value>, Vec<u8>, Option<Vec<u8>>) {
    let mut property = Map::new();
    let mut values = Vec::new();
    let mut offsets = None;
    match column {
        Column::Strings(strings) => {
            property.insert("type".to_owned(), "STRING".into());
            let no_data = strings
                .iter()
                .any(Option::is_none)
                .then(|| text_no_data(&strings));
            if let Some(no_data) = &no_data {
                property.insert("noData".to_owned(), no_data.as_str().into());
            }
            let mut ends = Vec::with_capacity(4 * (strings.len() + 1));
            ends.extend_from_slice(&0u32.to_le_bytes());
            for s in &strings {
                let text = s.as_deref().or(no_data.as_deref()).unwrap_or_default();
                values.extend_from_slice(text.as_bytes());
                ends.extend_from_slice(&(values.len() as u32).to_le_bytes());
            }
            offsets = Some(padded(ends));
        }
        Column::Floats(floats) => {
            property.insert("type".to_owned(), "SCALAR".into());
            property.insert("componentType".to_owned(), "FLOAT64".into());
            let no_data = number_no_data(&floats);
            if floats.iter().any(Option::is_none) {
                property.insert("noData".to_owned(), no_data.into());
            }
            for f in floats {
                values.extend_from_slice(&f.unwrap_or(no_data).to_le_bytes());
            }
        }
        Column::Counts(counts) => {
            property.insert("type".to_owned(), "SCALAR".into());
            property.insert("componentType".to_owned(), "UINT32".into());
            if counts.iter().any(Option::is_none) {
                property.insert("noData".to_owned(), u32::MAX.into());
            }
            for c in counts {
                values.extend_from_slice(&c.unwrap_or(u32::MAX).to_le_bytes());
            }
        }
        Column::Bools(bools) => {
            property.insert("type".to_owned(), "BOOLEAN".into());
            // A bitstream: row i is bit i % 8 of byte i / 8.
            values = vec![0; bools.len().div_ceil(8)];
            for (i, _) in bools.iter().enumerate().filter(|(_, b)| **b) {
                values[i / 8] |= 1 << (i % 8);
            }
        }
    }
    (property, padded(values), offsets)
}

/// A STRING column's `noData`: "" unless a row holds "" (then a missing value would read as
/// that row's), else the first of `(none)`, `(none) 2`, … that no row holds.
fn text_no_data(strings: &[Option<String>]) -> String {
    let held = |candidate: &str| strings.iter().flatten().any(|s| s == candidate);
    if !held("") {
        return String::new();
    }
    (1..)
        .map(|n| match n {
            1 => "(none)".to_owned(),
            n => format!("(none) {n}"),
        })
        .find(|candidate| !held(candidate))
        .expect("some candidate is free: there are fewer rows than candidates")
}

/// A FLOAT64 column's `noData`: the lowest f64 unless a row holds it, else the lowest value
/// above it that no row holds.
fn number_no_data(floats: &[Option<f64>]) -> f64 {
    let mut candidate = f64::MIN;
    while floats.iter().flatten().any(|&f| f == candidate) {
        candidate = candidate.next_up();
    }
    candidate
}

/// `bytes` padded with zeros to a multiple of 8: every view of the table starts on an 8-byte
/// boundary, as the extension requires.
fn padded(mut bytes: Vec<u8>) -> Vec<u8> {
    bytes.resize(bytes.len().next_multiple_of(8), 0);
    bytes
}

/// `name` as a schema identifier (letters, digits and `_`, not starting with a digit), unlike
/// every id in `taken`.
fn unique_id(name: &str, taken: &[String]) -> String {
    let mut id: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    if !taken.contains(&id) {
        return id;
    }
    (2..)
        .map(|n| format!("{id}_{n}"))
        .find(|candidate| !taken.contains(candidate))
        .expect("some suffix is free")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(values: &[u8], offsets: &[u8], count: usize) -> Vec<String> {
        let ends: Vec<usize> = offsets
            .chunks_exact(4)
            .take(count + 1)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap()) as usize)
            .collect();
        ends.windows(2)
            .map(|w| String::from_utf8(values[w[0]..w[1]].to_vec()).unwrap())
            .collect()
    }

    #[test]
    fn rows_become_columns_with_no_data_where_a_row_lacks_a_value() {
        let first = Metadata {
            rule: Some("Lot".to_owned()),
            path: Some("Lot[3]".to_owned()),
            leaves: Some(12),
            attributes: vec![
                ("height".to_owned(), MetaValue::Number(20.5)),
                ("style".to_owned(), MetaValue::Text("brick".to_owned())),
                ("roof".to_owned(), MetaValue::Bool(true)),
            ],
            reports: Some(vec![(
                "floor.area_sum".to_owned(),
                MetaValue::Number(300.0),
            )]),
            ..Metadata::default()
        };
        let second = Metadata {
            rule: Some("Lot".to_owned()),
            path: Some("Lot[7]".to_owned()),
            leaves: Some(4),
            attributes: vec![
                ("height".to_owned(), MetaValue::Number(9.0)),
                ("style".to_owned(), MetaValue::Number(2.0)),
                ("roof".to_owned(), MetaValue::Bool(false)),
                ("1st".to_owned(), MetaValue::Bool(false)),
            ],
            reports: Some(Vec::new()),
            ..Metadata::default()
        };
        let table = PropertyTable::new(&[&first, &second]);
        let ext = table.extension(5);
        let class = &ext["schema"]["classes"]["lot"]["properties"];
        let mut ids: Vec<&String> = class.as_object().unwrap().keys().collect();
        ids.sort();
        assert_eq!(
            ids,
            [
                "_1st",
                "floor_area_sum",
                "height",
                "leaves",
                "path",
                "roof",
                "rule",
                "style"
            ]
        );
        assert_eq!(
            class["leaves"],
            json!({"type": "SCALAR", "componentType": "UINT32"})
        );
        assert_eq!(
            class["floor_area_sum"],
            json!({"type": "SCALAR", "componentType": "FLOAT64", "noData": f64::MIN,
                   "name": "floor.area_sum"})
        );
        assert_eq!(class["roof"], json!({"type": "BOOLEAN"}));
        // A boolean with a gap, and text beside a number: strings.
        assert_eq!(
            class["_1st"],
            json!({"type": "STRING", "noData": "", "name": "1st"})
        );
        assert_eq!(class["style"], json!({"type": "STRING"}));
        let tables = &ext["propertyTables"];
        assert_eq!(tables[0]["count"], 2);
        assert_eq!(tables[0]["class"], "lot");
        // Views in column order from 5: rule (2), path (2), leaves, _1st (2), height, roof,
        // style (2), floor_area_sum: 12.
        let props = &tables[0]["properties"];
        assert_eq!(props["rule"], json!({"values": 5, "stringOffsets": 6}));
        assert_eq!(props["leaves"], json!({"values": 9}));
        assert_eq!(props["floor_area_sum"], json!({"values": 16}));
        assert_eq!(table.views.len(), 12);
        assert!(table.views.iter().all(|v| v.len() % 8 == 0));
        let view = |k: u64| &table.views[(k - 5) as usize];
        let at = |name: &str, key: &str| props[name][key].as_u64().unwrap();
        assert_eq!(
            strings(
                view(at("path", "values")),
                view(at("path", "stringOffsets")),
                2
            ),
            ["Lot[3]", "Lot[7]"]
        );
        assert_eq!(
            strings(
                view(at("style", "values")),
                view(at("style", "stringOffsets")),
                2
            ),
            ["brick", "2.0"]
        );
        assert_eq!(
            strings(
                view(at("_1st", "values")),
                view(at("_1st", "stringOffsets")),
                2
            ),
            ["", "false"]
        );
        assert_eq!(
            &view(at("leaves", "values"))[..8],
            [12, 0, 0, 0, 4, 0, 0, 0]
        );
        assert_eq!(view(at("roof", "values")), &[1, 0, 0, 0, 0, 0, 0, 0]);
        let floats: Vec<f64> = view(at("floor_area_sum", "values"))
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(floats, [300.0, f64::MIN]);
    }

    #[test]
    fn no_data_is_a_value_no_row_holds() {
        let row = |attributes: Vec<(&str, MetaValue)>| Metadata {
            attributes: attributes
                .into_iter()
                .map(|(name, value)| (name.to_owned(), value))
                .collect(),
            ..Metadata::default()
        };
        let text = |t: &str| MetaValue::Text(t.to_owned());
        let rows = [
            row(vec![
                ("sign", text("")),
                ("label", text("(none)")),
                ("depth", MetaValue::Number(f64::MIN)),
            ]),
            row(vec![("label", text(""))]),
            row(vec![("sign", text("shop"))]),
        ];
        let table = PropertyTable::new(&rows.iter().collect::<Vec<_>>());
        let ext = table.extension(0);
        let class = &ext["schema"]["classes"]["lot"]["properties"];
        assert_eq!(class["sign"], json!({"type": "STRING", "noData": "(none)"}));
        assert_eq!(
            class["label"],
            json!({"type": "STRING", "noData": "(none) 2"})
        );
        assert_eq!(class["depth"]["noData"], json!(f64::MIN.next_up()));
        let props = &ext["propertyTables"][0]["properties"];
        let view =
            |name: &str, key: &str| &table.views[props[name][key].as_u64().unwrap() as usize];
        assert_eq!(
            strings(view("sign", "values"), view("sign", "stringOffsets"), 3),
            ["", "(none)", "shop"]
        );
        assert_eq!(
            strings(view("label", "values"), view("label", "stringOffsets"), 3),
            ["(none)", "", "(none) 2"]
        );
        let depths: Vec<f64> = view("depth", "values")
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(depths, [f64::MIN, f64::MIN.next_up(), f64::MIN.next_up()]);
    }

    #[test]
    fn ids_take_the_smallest_component_that_holds_them() {
        let row = Metadata::default();
        let features = |n: usize| Features {
            rows: vec![&row; n],
            ..Features::default()
        };
        assert_eq!(features(1).component(), ComponentType::U8);
        assert_eq!(features(256).component(), ComponentType::U8);
        assert_eq!(features(257).component(), ComponentType::U16);
        assert_eq!(features(65_537).component(), ComponentType::U32);
        assert_eq!(
            unique_id("a.b", &["a_b".to_owned(), "a_b_2".to_owned()]),
            "a_b_3"
        );
    }
}
