//! The compiler (thesis 3.1.9): a project's cut trees become lean rules of virtual-vertex
//! instructions and sub-shapes.
//!
//! Named symbols keep their project order; anonymous terminal topologies follow, one symbol per
//! distinct topology. A rule's vertex array is the symbol's vertices in canonical order, then the
//! virtual vertices its cuts made, in the order they were made; each sub-shape lists its vertices
//! in its symbol's canonical order (from the anchor on the leaf, or from the leaf's first face
//! and corner for anonymous terminals). Epsilon leaves are left out.

use std::fmt;

use rustc_hash::FxHashMap;
use shapegram_geom::Color;

use crate::anchor::{Anchor, Topology, canonical_order};
use crate::grammar::{Grammar, GrammarRule, GrammarShape, GrammarSymbol, OffsetCut, SubShape};
use crate::polyhedron::Index;
use crate::project::{Assignment, EditError, NodeKind, Project, RuleTree, Symbol, check_instance};

/// Why a project does not compile.
#[derive(Clone, Debug, PartialEq)]
pub struct CompileError {
    /// Where: `rules[2] (name), sub-shape 5`.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

impl std::error::Error for CompileError {}

/// Compiles `project` into a grammar.
pub fn compile(project: &Project) -> Result<Grammar, CompileError> {
    let mut symbols = Vec::with_capacity(project.symbols.len());
    let mut shapes = Vec::with_capacity(project.symbols.len());
    // Per symbol, the canonical number of each face of its prototype.
    let mut face_ranks = Vec::with_capacity(project.symbols.len());
    for (i, symbol) in project.symbols.iter().enumerate() {
        let order = canonical_order(&symbol.shape, symbol.anchor).ok_or_else(|| CompileError {
            location: format!("symbols[{i}] ({})", symbol.name),
            message: "the reference anchor is not on the shape".into(),
        })?;
        shapes.push(GrammarShape {
            symbol: i as Index,
            vertices: order
                .vertices
                .iter()
                .map(|&v| symbol.shape.position(v))
                .collect(),
        });
        let mut rank = vec![0; order.faces.len()];
        for (canonical, &f) in order.faces.iter().enumerate() {
            rank[f as usize] = canonical as Index;
        }
        face_ranks.push(rank);
        symbols.push(GrammarSymbol {
            name: Some(symbol.name.clone()),
            color: symbol.color,
            face_colors: canonical_face_colors(symbol, &order.faces),
            vertex_count: symbol.shape.vertex_count() as u32,
            faces: order.topology.faces,
            rules: Vec::new(),
        });
    }
    let mut anonymous: FxHashMap<Topology, Index> = FxHashMap::default();
    let mut rules = Vec::with_capacity(project.rules.len());
    for (r, rule) in project.rules.iter().enumerate() {
        let location = |leaf: Option<Index>| match leaf {
            None => format!("rules[{r}] ({})", rule.name),
            Some(leaf) => format!("rules[{r}] ({}), sub-shape {leaf}", rule.name),
        };
        let Some(owner) = symbols.get_mut(rule.symbol as usize) else {
            return Err(CompileError {
                location: location(None),
                message: format!("there is no symbol {}", rule.symbol),
            });
        };
        owner.rules.push(r as Index);
        let tree = &rule.tree;
        let mut sub_shapes = Vec::new();
        for leaf in tree.leaves() {
            let node = &tree.nodes()[leaf as usize];
            let NodeKind::Leaf(assignment) = node.kind else {
                continue;
            };
            let (symbol, anchor) = match assignment {
                Assignment::Epsilon => continue,
                Assignment::Symbol { symbol, anchor } => {
                    check_instance(&node.shape, anchor, &project.symbols, symbol).map_err(
                        |e: EditError| CompileError {
                            location: location(Some(leaf)),
                            message: e.to_string(),
                        },
                    )?;
                    (symbol, anchor)
                }
                Assignment::Terminal => (Index::MAX, Anchor::default()),
            };
            let Some(order) = canonical_order(&node.shape, anchor) else {
                return Err(CompileError {
                    location: location(Some(leaf)),
                    message: "the anchor is not on the shape".into(),
                });
            };
            let symbol = if symbol == Index::MAX {
                *anonymous.entry(order.topology.clone()).or_insert_with(|| {
                    symbols.push(GrammarSymbol {
                        name: None,
                        color: None,
                        face_colors: Vec::new(),
                        vertex_count: node.shape.vertex_count() as u32,
                        faces: order.topology.faces.clone(),
                        rules: Vec::new(),
                    });
                    (symbols.len() - 1) as Index
                })
            } else {
                symbol
            };
            let (materials, from_faces) = if project.materials.is_empty() {
                (Vec::new(), Vec::new())
            } else {
                let rank = &face_ranks[rule.symbol as usize];
                let materials: Vec<Option<Index>> = order
                    .faces
                    .iter()
                    .map(|&f| node.face_materials[f as usize])
                    .collect();
                let from_faces = order
                    .faces
                    .iter()
                    .map(|&f| tree.root_face(leaf, f).map(|g| rank[g as usize]))
                    .collect();
                let given = materials.iter().any(Option::is_some);
                (if given { materials } else { Vec::new() }, from_faces)
            };
            sub_shapes.push(SubShape {
                symbol,
                vertices: order
                    .vertices
                    .iter()
                    .map(|&v| node.vertices[v as usize])
                    .collect(),
                materials,
                from_faces,
            });
        }
        rules.push(GrammarRule {
            symbol: rule.symbol,
            name: rule.name.clone(),
            weight: rule.weight,
            virtual_vertices: tree.virtual_vertices().to_vec(),
            sub_shapes,
            offset_cuts: offset_cuts(tree),
        });
    }
    let grammar = Grammar {
        shapes,
        symbols,
        rules,
        materials: project.materials.clone(),
    };
    grammar.validate().map_err(|e| CompileError {
        location: e.location,
        message: e.message,
    })?;
    Ok(grammar)
}

/// The tree's cuts at a fixed distance from a face, in the order they were made; cuts that made
/// no vertex (their plane only passes through existing ones) have nothing to move.
fn offset_cuts(tree: &RuleTree) -> Vec<OffsetCut> {
    let mut cuts: Vec<OffsetCut> = tree
        .nodes()
        .iter()
        .filter_map(|node| {
            let (NodeKind::Cut { children, .. }, Some(offset)) = (node.kind, node.offset) else {
                return None;
            };
            let step = (children[0] - 1) / 2;
            let vertices: Vec<Index> = tree.cut_vertices(step as usize)?.collect();
            if vertices.is_empty() {
                return None;
            }
            let corners: Vec<Index> = node.shape.face_loop(offset.face).collect();
            let n = corners.len();
            let face = [0, n / 3, 2 * n / 3].map(|k| node.vertices[corners[k] as usize]);
            Some(OffsetCut {
                step,
                face,
                distance: offset.distance,
                vertices,
            })
        })
        .collect();
    cuts.sort_by_key(|c| c.step);
    cuts
}

/// The symbol's face colours in canonical face order (`faces`: shape face per canonical face);
/// empty when it has none.
fn canonical_face_colors(symbol: &Symbol, faces: &[Index]) -> Vec<Option<Color>> {
    if symbol.face_colors.is_empty() {
        return Vec::new();
    }
    faces
        .iter()
        .map(|f| {
            symbol
                .face_colors
                .iter()
                .find(|(g, _)| g == f)
                .map(|&(_, c)| c)
        })
        .collect()
}
