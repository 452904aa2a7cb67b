//! Project files (thesis 3.1.8): the authoring state as versioned JSON (see docs/topo.md).
//!
//! Like the thesis's editor, loading retraces the user's steps: symbols are rebuilt from their
//! vertices and faces, each rule's tree is replayed cut by cut from its planes, and every
//! assignment is checked again. Cuts are deterministic, so a loaded project equals the saved one.

use serde::{Deserialize, Serialize};
use shapegram_geom::{Color, DVec3};

use crate::anchor::Anchor;
use crate::cut::CutPlane;
use crate::grammar_file::{MaterialEntry, Point, json_message, point};
use crate::polyhedron::{Index, Polyhedron};
use crate::project::{Assignment, EditError, FaceOffset, NodeId, NodeKind, Project, RuleTree};

/// The `format` field of every project file.
pub const PROJECT_FORMAT: &str = "shapegram-topo-project";
/// The version this library writes; it reads it and every older one (version 1 had no
/// materials and no offset cuts).
pub const PROJECT_VERSION: u32 = 2;

/// Most vertices the sub-shapes of all rule trees of a loaded project may hold together (about
/// 300 MB): every rule copies its symbol's shape and every cut adds two parts, so a small file
/// naming a big symbol in many rules or cuts could otherwise exhaust memory. Hand-made projects
/// hold thousands.
const MAX_PROJECT_VERTICES: usize = 1 << 21;

/// A problem in a project file: where (a JSON path or line and column) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ProjectError {
    /// Where: `rules[1].tree.above.below`, or `3:9` (line:column) for JSON syntax.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for ProjectError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

impl std::error::Error for ProjectError {}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ProjectFile {
    format: String,
    version: u32,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    materials: Vec<MaterialEntry>,
    symbols: Vec<SymbolEntry>,
    rules: Vec<RuleEntry>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SymbolEntry {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    color: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    face_colors: Vec<FaceColorEntry>,
    vertices: Vec<Point>,
    faces: Vec<Vec<Index>>,
    /// `[face, corner]`.
    anchor: [Index; 2],
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FaceColorEntry {
    face: Index,
    color: String,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RuleEntry {
    name: String,
    symbol: String,
    weight: f64,
    tree: NodeEntry,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    face_materials: Vec<FaceMaterialEntry>,
}

/// A face of a node of a rule tree with a material; nodes are numbered as replaying the cuts
/// numbers them (the root 0, cut step `s` makes nodes `2s + 1` below and `2s + 2` above).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FaceMaterialEntry {
    node: NodeId,
    face: Index,
    material: String,
}

/// A cut at a fixed distance from a face of the shape it cuts.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct OffsetEntry {
    face: Index,
    distance: f64,
}

#[derive(Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum NodeEntry {
    Terminal,
    Epsilon,
    Symbol {
        name: String,
        anchor: [Index; 2],
    },
    Cut {
        /// When the cut was made among the rule's cuts (0 first): replaying cuts in this order
        /// reproduces node and virtual-vertex numbering exactly.
        step: u32,
        point: Point,
        normal: Point,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        offset: Option<OffsetEntry>,
        below: Box<NodeEntry>,
        above: Box<NodeEntry>,
    },
}

impl Project {
    /// The project as JSON text (pretty-printed, ending in a newline).
    pub fn to_json(&self) -> String {
        let file = ProjectFile {
            format: PROJECT_FORMAT.into(),
            version: PROJECT_VERSION,
            materials: self.materials.iter().map(MaterialEntry::from).collect(),
            symbols: self
                .symbols
                .iter()
                .map(|s| SymbolEntry {
                    name: s.name.clone(),
                    color: s.color.map(|c| c.to_hex()),
                    face_colors: s
                        .face_colors
                        .iter()
                        .map(|&(face, c)| FaceColorEntry {
                            face,
                            color: c.to_hex(),
                        })
                        .collect(),
                    vertices: s.shape.positions().iter().map(|&p| point(p)).collect(),
                    faces: s.shape.face_loops(),
                    anchor: [s.anchor.face, s.anchor.corner],
                })
                .collect(),
            rules: self
                .rules
                .iter()
                .map(|r| RuleEntry {
                    name: r.name.clone(),
                    symbol: self.symbols[r.symbol as usize].name.clone(),
                    weight: r.weight,
                    tree: self.node_entry(&r.tree, RuleTree::ROOT),
                    face_materials: self.face_material_entries(&r.tree),
                })
                .collect(),
        };
        crate::json::to_text(&file)
    }

    fn node_entry(&self, tree: &RuleTree, id: NodeId) -> NodeEntry {
        match tree.nodes()[id as usize].kind {
            NodeKind::Leaf(Assignment::Terminal) => NodeEntry::Terminal,
            NodeKind::Leaf(Assignment::Epsilon) => NodeEntry::Epsilon,
            NodeKind::Leaf(Assignment::Symbol { symbol, anchor }) => NodeEntry::Symbol {
                name: self.symbols[symbol as usize].name.clone(),
                anchor: [anchor.face, anchor.corner],
            },
            NodeKind::Cut { plane, children } => NodeEntry::Cut {
                step: (children[0] - 1) / 2,
                point: point(plane.point),
                normal: point(plane.normal),
                offset: tree.nodes()[id as usize].offset.map(|o| OffsetEntry {
                    face: o.face,
                    distance: o.distance,
                }),
                below: Box::new(self.node_entry(tree, children[0])),
                above: Box::new(self.node_entry(tree, children[1])),
            },
        }
    }

    /// Every face of every node of `tree` that has a material, by node and face.
    fn face_material_entries(&self, tree: &RuleTree) -> Vec<FaceMaterialEntry> {
        let mut entries = Vec::new();
        for (id, node) in tree.nodes().iter().enumerate() {
            for (face, material) in node.face_materials.iter().enumerate() {
                if let Some(m) = material {
                    entries.push(FaceMaterialEntry {
                        node: id as NodeId,
                        face: face as Index,
                        material: self.materials[*m as usize].name.clone(),
                    });
                }
            }
        }
        entries
    }

    /// Reads a project from JSON text, replaying every cut and checking every assignment.
    pub fn from_json(text: &str) -> Result<Self, ProjectError> {
        let file: ProjectFile = serde_json::from_str(text).map_err(|e| ProjectError {
            location: format!("{}:{}", e.line(), e.column()),
            message: json_message(&e),
        })?;
        let fail = |location: String, message: String| ProjectError { location, message };
        if file.format != PROJECT_FORMAT {
            return Err(fail(
                "format".into(),
                format!(
                    "'{}' is not a topological grammar project (expected '{PROJECT_FORMAT}')",
                    file.format.escape_debug()
                ),
            ));
        }
        if !(1..=PROJECT_VERSION).contains(&file.version) {
            return Err(fail(
                "version".into(),
                format!(
                    "version {} is not supported (this build reads versions 1 to \
                     {PROJECT_VERSION})",
                    file.version
                ),
            ));
        }
        let mut project = Project::new();
        for (i, entry) in file.materials.into_iter().enumerate() {
            let at = format!("materials[{i}]");
            let material = entry
                .into_material(&at)
                .map_err(|e| fail(e.location, e.message))?;
            project
                .add_material(material)
                .map_err(|e| fail(at, e.to_string()))?;
        }
        for (i, entry) in file.symbols.into_iter().enumerate() {
            let at = format!("symbols[{i}]");
            let positions = entry.vertices.into_iter().map(DVec3::from_array).collect();
            let shape = Polyhedron::from_faces(positions, &entry.faces)
                .map_err(|e| fail(at.clone(), e.to_string()))?;
            let [face, corner] = entry.anchor;
            let symbol = project
                .add_symbol(&entry.name, shape, Anchor::new(face, corner))
                .map_err(|e| fail(at.clone(), e.to_string()))?;
            if let Some(hex) = entry.color {
                let color = Color::from_hex(&hex).ok_or_else(|| {
                    fail(
                        format!("{at}.color"),
                        format!("'{}' is not a colour like '#3a6ea5'", hex.escape_debug()),
                    )
                })?;
                project.symbols[symbol as usize].color = Some(color);
            }
            for (k, face_color) in entry.face_colors.iter().enumerate() {
                let at = format!("{at}.face_colors[{k}]");
                let color = Color::from_hex(&face_color.color).ok_or_else(|| {
                    fail(
                        at.clone(),
                        format!(
                            "'{}' is not a colour like '#3a6ea5'",
                            face_color.color.escape_debug()
                        ),
                    )
                })?;
                project
                    .set_face_color(symbol, face_color.face, Some(color))
                    .map_err(|e| fail(at, e.to_string()))?;
            }
        }
        let mut held = 0;
        for (r, entry) in file.rules.into_iter().enumerate() {
            let at = format!("rules[{r}]");
            let symbol = project.symbol_named(&entry.symbol).ok_or_else(|| {
                fail(
                    format!("{at}.symbol"),
                    format!("there is no symbol '{}'", entry.symbol.escape_debug()),
                )
            })?;
            held += project.symbols[symbol as usize].shape.vertex_count();
            if held > MAX_PROJECT_VERTICES {
                return Err(fail(at, too_big()));
            }
            let rule = project
                .add_rule(symbol, &entry.name, entry.weight)
                .map_err(|e| fail(format!("{at}.weight"), e.to_string()))?;
            project
                .replay(rule, &entry.tree, &mut held)
                .map_err(|(path, e)| fail(format!("{at}.tree{path}"), e.to_string()))?;
            for (k, face_material) in entry.face_materials.iter().enumerate() {
                project
                    .restore_face_material(rule, face_material)
                    .map_err(|e| fail(format!("{at}.face_materials[{k}]"), e.to_string()))?;
            }
        }
        Ok(project)
    }

    /// Gives one face of one node its saved material, that face alone (the file lists every
    /// face that has one).
    fn restore_face_material(
        &mut self,
        rule: Index,
        entry: &FaceMaterialEntry,
    ) -> Result<(), EditError> {
        let material = self.material_named(&entry.material).ok_or_else(|| {
            EditError::NotFound(format!(
                "there is no material '{}'",
                entry.material.escape_debug()
            ))
        })?;
        self.rules[rule as usize]
            .tree
            .restore_face_material(entry.node, entry.face, material)
    }

    /// Rebuilds the tree `root` on `rule`: cuts in their recorded order, then assignments.
    /// `held` counts the vertices of all sub-shapes made so far, against
    /// [`MAX_PROJECT_VERTICES`].
    fn replay(
        &mut self,
        rule: Index,
        root: &NodeEntry,
        held: &mut usize,
    ) -> Result<(), (String, EditError)> {
        let mut cuts = Vec::new();
        let mut leaves = Vec::new();
        flatten(root, None, String::new(), &mut cuts, &mut leaves);
        let mut order: Vec<usize> = (0..cuts.len()).collect();
        order.sort_by_key(|&k| cuts[k].step);
        let mut made: Vec<Option<[NodeId; 2]>> = vec![None; cuts.len()];
        for (expected, &k) in order.iter().enumerate() {
            let item = &cuts[k];
            if item.step as usize != expected {
                return Err((
                    item.path.clone(),
                    EditError::Invalid(format!(
                        "cut steps must number the rule's cuts 0 to {} once each; found step {}",
                        cuts.len() - 1,
                        item.step
                    )),
                ));
            }
            let leaf = node_of(item.parent, &made).ok_or_else(|| {
                (
                    item.path.clone(),
                    EditError::Invalid(format!(
                        "step {} cuts a sub-shape that a later step makes",
                        item.step
                    )),
                )
            })?;
            let children = match item.offset {
                None => self.plane_cut(rule, leaf, item.plane),
                Some(offset) => self.replay_offset_cut(rule, leaf, item.plane, offset),
            }
            .map_err(|e| (item.path.clone(), e))?;
            let nodes = self.rules[rule as usize].tree.nodes();
            *held += children
                .iter()
                .map(|&c| nodes[c as usize].shape.vertex_count())
                .sum::<usize>();
            if *held > MAX_PROJECT_VERTICES {
                return Err((item.path.clone(), EditError::Invalid(too_big())));
            }
            made[k] = Some(children);
        }
        for leaf in leaves {
            let id = node_of(leaf.parent, &made).unwrap_or(RuleTree::ROOT);
            let assignment = match leaf.entry {
                NodeEntry::Epsilon => Assignment::Epsilon,
                NodeEntry::Symbol { name, anchor } => {
                    let symbol = self.symbol_named(name).ok_or_else(|| {
                        (
                            leaf.path.clone(),
                            EditError::NotFound(format!(
                                "there is no symbol '{}'",
                                name.escape_debug()
                            )),
                        )
                    })?;
                    Assignment::Symbol {
                        symbol,
                        anchor: Anchor::new(anchor[0], anchor[1]),
                    }
                }
                _ => continue,
            };
            self.assign(rule, id, assignment)
                .map_err(|e| (leaf.path.clone(), e))?;
        }
        Ok(())
    }
}

impl Project {
    /// Replays an offset cut, checking that the saved plane is the one its face and distance
    /// give.
    fn replay_offset_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        saved: CutPlane,
        offset: FaceOffset,
    ) -> Result<[NodeId; 2], EditError> {
        let [slice, rest] = self.offset_cut(rule, leaf, offset.face, offset.distance)?;
        let tree = &self.rules[rule as usize].tree;
        let NodeKind::Cut { plane, .. } = tree.nodes()[leaf as usize].kind else {
            unreachable!("the leaf was just cut");
        };
        let scale = tree.nodes()[leaf as usize].shape.diagonal();
        let normal = saved.normal.normalize_or_zero();
        let same = normal.dot(plane.normal.normalize()) > 1.0 - 1e-9
            && plane.distance(saved.point).abs() <= 1e-9 * scale;
        if !same {
            return Err(EditError::Invalid(format!(
                "the plane is not {} m inside face {} of the shape it cuts",
                offset.distance, offset.face
            )));
        }
        Ok([rest, slice])
    }
}

/// The message for a project over [`MAX_PROJECT_VERTICES`].
fn too_big() -> String {
    format!(
        "the rules' sub-shapes would hold more than {MAX_PROJECT_VERTICES} vertices together \
         (hand-made projects hold thousands)"
    )
}

/// A cut of a project file's tree: its step, plane, and where it sits (its parent cut and side).
struct CutItem {
    step: u32,
    plane: CutPlane,
    offset: Option<FaceOffset>,
    parent: Option<(usize, usize)>,
    path: String,
}

/// A leaf of a project file's tree.
struct LeafItem<'a> {
    entry: &'a NodeEntry,
    parent: Option<(usize, usize)>,
    path: String,
}

/// Lists the cuts and leaves of `entry`, each with its parent cut (index into `cuts`, side).
fn flatten<'a>(
    entry: &'a NodeEntry,
    parent: Option<(usize, usize)>,
    path: String,
    cuts: &mut Vec<CutItem>,
    leaves: &mut Vec<LeafItem<'a>>,
) {
    match entry {
        NodeEntry::Cut {
            step,
            point,
            normal,
            offset,
            below,
            above,
        } => {
            let index = cuts.len();
            cuts.push(CutItem {
                step: *step,
                plane: CutPlane::new(DVec3::from_array(*point), DVec3::from_array(*normal)),
                offset: offset.as_ref().map(|o| FaceOffset {
                    face: o.face,
                    distance: o.distance,
                }),
                parent,
                path: path.clone(),
            });
            flatten(
                below,
                Some((index, 0)),
                format!("{path}.below"),
                cuts,
                leaves,
            );
            flatten(
                above,
                Some((index, 1)),
                format!("{path}.above"),
                cuts,
                leaves,
            );
        }
        _ => leaves.push(LeafItem {
            entry,
            parent,
            path,
        }),
    }
}

/// The node a file node became: the root, or a child of a cut already replayed.
fn node_of(parent: Option<(usize, usize)>, made: &[Option<[NodeId; 2]>]) -> Option<NodeId> {
    match parent {
        None => Some(RuleTree::ROOT),
        Some((cut, side)) => made[cut].map(|children| children[side]),
    }
}
