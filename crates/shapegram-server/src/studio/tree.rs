//! What visual debugging needs of a derivation, sent with its model when the page asks for it
//! (`"tree": true`): the derivation tree, where each node's rule is in the text, and which of
//! the GLB's triangles came from which leaf. Node-major arrays keep it compact: a tree of
//! 5,000 shapes is a few hundred kilobytes of JSON, parsed in milliseconds.

use serde::Serialize;

/// The derivation tree of one derivation, in the order the engine made its shapes (parents
/// before children), and the GLB's triangles by tree node.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct DerivationTree {
    /// The distinct symbol names; nodes name theirs by index.
    pub symbols: Vec<String>,
    /// The grammar's rules, in the engine's order; nodes name the rule applied to them by index.
    pub rules: Vec<RuleInfo>,
    /// The attributes' names; nodes give their values in this order.
    pub attr_names: Vec<String>,
    /// The distinct lists of attribute values nodes have (shown as text); nodes name theirs by
    /// index.
    pub attr_values: Vec<Vec<String>>,
    /// By node: its parent (`-1` for an initial shape).
    pub parent: Vec<i64>,
    /// By node: its symbol, as an index into `symbols`.
    pub symbol: Vec<u32>,
    /// By node: the rule that rewrote it, as an index into `rules` (`-1`: none, as for a leaf
    /// ended by `.` or a part of a split).
    pub rule: Vec<i64>,
    /// By node: its attribute values, as an index into `attr_values`.
    pub attrs: Vec<u32>,
    /// By node: its kinematic section (0 without a skeleton).
    pub section: Vec<u32>,
    /// By node, 15 numbers: the scope at birth, origin, x, y and z axes and size (metres,
    /// rounded to 0.1 mm and 1e-6 for axes).
    pub scopes: Vec<f64>,
    /// How many generations the full derivation takes: rewriting in parallel generations,
    /// this many of them leave no rule unapplied.
    pub generations: u32,
    /// The GLB's triangle primitives and the nodes their triangles belong to.
    pub primitives: Vec<PrimitiveNodes>,
}

/// A rule: its name and, when it is in the text edited, where.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RuleInfo {
    pub name: String,
    /// Where it is; `None` for a rule of an imported file.
    #[serde(flatten)]
    pub place: Option<RulePlace>,
}

/// Where a rule is in the text: lines and columns as [`super::StudioDiagnostic`] counts them.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RulePlace {
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
}

/// One primitive of the GLB (glTF mesh and primitive index) and its triangles in runs: pairs
/// of a tree node and how many consecutive triangles, from the first, are that node's leaf's.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PrimitiveNodes {
    pub mesh: usize,
    pub primitive: usize,
    /// `[node, triangles, node, triangles, …]`; node `-1`: triangles of no leaf (meshed
    /// implicit solids).
    pub runs: Vec<i64>,
}
