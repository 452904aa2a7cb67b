//! The studio's visual debugging on the engine's side: a derivation kept with its tree becomes
//! the [`DerivationTree`] the page draws beside the preview, with each rule's place in the text
//! and the GLB's triangles mapped back to the leaves they came from (see docs/studio.md).

use std::collections::HashMap;

use shapegram_eval::{Derivation, LeafFaces, Program};
use shapegram_export::{GlbLayout, face_triangles};
use shapegram_geom::Model;
use shapegram_server::studio::{DerivationTree, PrimitiveNodes, RuleInfo, RulePlace};
use shapegram_syntax::{SourceFile, ast};

/// The tree of `derivation` (derived with `keep_tree`), whose model `model` was written as a
/// GLB laid out as `layout`; `faces` says where each leaf went in the model
/// (`Derivation::to_model_with_faces`). Rules are looked up by name and arity in `grammar`,
/// parsed from `source`.
pub fn tree(
    derivation: &Derivation,
    program: &Program,
    grammar: &ast::Grammar,
    source: &SourceFile,
    (model, faces): (&Model, &[LeafFaces]),
    layout: GlbLayout,
) -> DerivationTree {
    let mut tree = DerivationTree {
        attr_names: program.attr_names().map(str::to_owned).collect(),
        ..DerivationTree::default()
    };
    let mut symbols: HashMap<&str, u32> = HashMap::new();
    // Nodes share their attribute lists while no `set` changes them: one entry per list.
    let mut attr_lists: HashMap<*const shapegram_eval::Value, u32> = HashMap::new();
    // By node: the generation whose rule applications made it (see `generations`).
    let mut made_in: Vec<u32> = Vec::with_capacity(derivation.tree.len());
    for node in &derivation.tree {
        let next = symbols.len() as u32;
        let symbol = *symbols.entry(&node.name).or_insert_with(|| {
            tree.symbols.push(node.name.to_string());
            next
        });
        tree.symbol.push(symbol);
        let next = tree.attr_values.len() as u32;
        let attrs = *attr_lists.entry(node.attrs.as_ptr()).or_insert_with(|| {
            tree.attr_values
                .push(node.attrs.iter().map(ToString::to_string).collect());
            next
        });
        tree.attrs.push(attrs);
        tree.parent.push(node.parent.map_or(-1, i64::from));
        tree.rule.push(node.rule.map_or(-1, i64::from));
        tree.section.push(node.section);
        // A shape made by its parent's rule is one generation later than the parent; one
        // made by the same application as its parent (a split's part and its successor) is
        // not. Every rule applied needs the generation after the one that made its shape.
        let generation = node.parent.map_or(0, |p| {
            let p = p as usize;
            made_in[p] + u32::from(derivation.tree[p].rule.is_some())
        });
        made_in.push(generation);
        if node.rule.is_some() {
            tree.generations = tree.generations.max(generation + 1);
        }
        let s = &node.scope;
        let metres = |v: f64| (v * 1e4).round() / 1e4 + 0.0;
        let unit = |v: f64| (v * 1e6).round() / 1e6 + 0.0;
        tree.scopes.extend(s.origin.to_array().map(metres));
        for axis in [s.axes.x_axis, s.axes.y_axis, s.axes.z_axis] {
            tree.scopes.extend(axis.to_array().map(unit));
        }
        tree.scopes.extend(s.size.to_array().map(metres));
    }
    tree.rules = (0..)
        .map_while(|id| program.rule_signature(id))
        .map(|(name, params)| {
            let place = grammar
                .rules
                .iter()
                .find(|r| r.name.name == name && r.params.len() == params)
                .map(|rule| {
                    let (line, column) = source.line_col(rule.span.start);
                    let (end_line, end_column) = source.line_col(rule.span.end);
                    RulePlace {
                        line,
                        column,
                        end_line,
                        end_column,
                    }
                });
            RuleInfo {
                name: name.to_owned(),
                place,
            }
        })
        .collect();
    tree.primitives = primitive_nodes(derivation, model, faces, layout);
    tree
}

/// Each triangle primitive of the GLB as runs of triangles by tree node.
fn primitive_nodes(
    derivation: &Derivation,
    model: &Model,
    faces: &[LeafFaces],
    layout: GlbLayout,
) -> Vec<PrimitiveNodes> {
    // By part: its leaves' tree nodes and their first faces, in order.
    let mut leaves_of: Vec<Vec<&LeafFaces>> = vec![Vec::new(); model.parts.len()];
    for place in faces {
        leaves_of[place.part as usize].push(place);
    }
    let mut primitives = Vec::new();
    // Each part's triangles by face, counted once however many primitives ask.
    let mut triangles_of: Vec<Option<Vec<u32>>> = vec![None; model.parts.len()];
    for (mesh, group) in layout.into_iter().enumerate() {
        for (primitive, sources) in group.into_iter().enumerate() {
            let mut runs: Vec<i64> = Vec::new();
            let mut push = |node: i64, triangles: u32| {
                if triangles == 0 {
                    return;
                }
                match runs.as_mut_slice() {
                    [.., last, count] if *last == node => *count += i64::from(triangles),
                    _ => runs.extend([node, i64::from(triangles)]),
                }
            };
            let mut lines = false;
            for source in sources {
                let Some(part) = source else {
                    lines = true;
                    continue;
                };
                let triangles =
                    triangles_of[part].get_or_insert_with(|| face_triangles(&model.parts[part]));
                if leaves_of[part].is_empty() {
                    push(-1, triangles.iter().sum());
                }
                for place in &leaves_of[part] {
                    let node = derivation.leaves[place.leaf as usize]
                        .node()
                        .map_or(-1, i64::from);
                    let first = place.first as usize;
                    let own = &triangles[first..first + place.count as usize];
                    push(node, own.iter().sum());
                }
            }
            if !lines {
                primitives.push(PrimitiveNodes {
                    mesh,
                    primitive,
                    runs,
                });
            }
        }
    }
    primitives
}
