//! What the page draws: the project's symbols and rules with their cut trees, and the sub-shapes
//! of the rule (or symbol) in the edit view as triangles with face ids for picking, face loops
//! for edges and cutting planes, and anchors; and the meshes the tester generates.

use std::collections::BTreeSet;

use serde::Serialize;
use shapegram_geom::{Color, DVec2, DVec3};
use shapegram_topo::{
    Assignment, GrammarMesh, Material, NodeId, NodeKind, Polyhedron, Project, RuleTree,
    canonical_order, planar_uv,
};

/// Colours of sub-shapes in the edit view, by their place among the leaves (thesis 3.1: each
/// shape its own colour).
const PALETTE: [&str; 10] = [
    "#e07a5f", "#3d85c6", "#81b29a", "#f2cc8f", "#9b5de5", "#00a6a6", "#f15bb5", "#8d99ae",
    "#ffb703", "#6a994e",
];

/// A symbol in the explorer.
#[derive(Serialize)]
pub struct SymbolView {
    pub name: String,
    pub color: Option<String>,
    /// Its rules, by index.
    pub rules: Vec<u32>,
    pub vertices: usize,
    pub faces: u32,
}

/// A rule in the explorer, with its cut tree.
#[derive(Serialize)]
pub struct RuleView {
    pub name: String,
    pub symbol: u32,
    pub weight: f64,
    pub tree: TreeView,
}

/// A node of a cut tree.
#[derive(Serialize)]
pub struct TreeView {
    pub node: NodeId,
    /// `cut`, `terminal`, `epsilon` or `symbol`.
    pub kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symbol: Option<u32>,
    /// `[face, corner]` of a symbol's anchor.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub anchor: Option<[u32; 2]>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub children: Vec<TreeView>,
}

/// One sub-shape in the edit view.
#[derive(Serialize)]
pub struct PartView {
    pub node: NodeId,
    pub color: String,
    pub hidden: bool,
    /// `terminal`, `epsilon` or `symbol`.
    pub kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symbol: Option<u32>,
    /// Triangle corners, three numbers each, nine per triangle.
    pub positions: Vec<f32>,
    /// The face of each triangle.
    pub triangle_faces: Vec<u32>,
    /// Each face's corners, counter-clockwise from its first corner (anchor corners count so).
    pub faces: Vec<Vec<[f64; 3]>>,
    /// Each face's outward unit normal.
    pub normals: Vec<[f64; 3]>,
    /// For a symbol: its anchor and the edge it names.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub anchor: Option<AnchorView>,
    /// Each face's material (an index into the project's materials), or `null`.
    pub face_materials: Vec<Option<u32>>,
    /// Texture coordinates, two numbers per triangle corner as `positions` has them, in tiles
    /// of each face's material (shapegram-topo's `planar_uv`, as generated meshes have them);
    /// empty when no face has a material.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub uvs: Vec<f32>,
}

/// A material in the material picker, drawn in the edit view by its surface colour.
#[derive(Serialize)]
pub struct MaterialView {
    pub name: String,
    pub color: Option<String>,
    /// The colour faces with it are drawn in when it has no texture (a texture is tinted by
    /// `color`, or drawn as it is).
    pub surface: String,
    pub texture: Option<String>,
    pub tile: [f64; 2],
}

/// An anchor: where it is and the directed edge it names.
#[derive(Serialize)]
pub struct AnchorView {
    pub face: u32,
    pub corner: u32,
    pub from: [f64; 3],
    pub to: [f64; 3],
}

/// The edit view: a rule's sub-shapes, or a symbol's prototype.
#[derive(Serialize, Default)]
pub struct EditView {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rule: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symbol: Option<u32>,
    pub parts: Vec<PartView>,
}

/// Everything the page shows of an open project.
#[derive(Serialize)]
pub struct ProjectView {
    pub path: String,
    pub symbols: Vec<SymbolView>,
    pub rules: Vec<RuleView>,
    pub undo: usize,
    pub redo: usize,
    /// Whether the project differs from the file.
    pub dirty: bool,
    pub materials: Vec<MaterialView>,
    pub edit: EditView,
}

/// The project's materials.
pub fn materials(project: &Project) -> Vec<MaterialView> {
    project
        .materials
        .iter()
        .map(|m| MaterialView {
            name: m.name.clone(),
            color: m.color.map(|c| c.to_hex()),
            surface: m.surface_color().to_hex(),
            texture: m.texture.clone(),
            tile: m.tile.to_array(),
        })
        .collect()
}

/// The explorer's view of `project`.
pub fn symbols_and_rules(project: &Project) -> (Vec<SymbolView>, Vec<RuleView>) {
    let symbols = project
        .symbols
        .iter()
        .enumerate()
        .map(|(i, s)| SymbolView {
            name: s.name.clone(),
            color: s.color.map(|c| c.to_hex()),
            rules: (0..project.rules.len() as u32)
                .filter(|&r| project.rules[r as usize].symbol == i as u32)
                .collect(),
            vertices: s.shape.vertex_count(),
            faces: s.shape.face_count(),
        })
        .collect();
    let rules = project
        .rules
        .iter()
        .map(|r| RuleView {
            name: r.name.clone(),
            symbol: r.symbol,
            weight: r.weight,
            tree: tree_view(&r.tree, RuleTree::ROOT),
        })
        .collect();
    (symbols, rules)
}

fn tree_view(tree: &RuleTree, id: NodeId) -> TreeView {
    let leaf = |kind| TreeView {
        node: id,
        kind,
        symbol: None,
        anchor: None,
        children: Vec::new(),
    };
    match tree.nodes()[id as usize].kind {
        NodeKind::Leaf(Assignment::Terminal) => leaf("terminal"),
        NodeKind::Leaf(Assignment::Epsilon) => leaf("epsilon"),
        NodeKind::Leaf(Assignment::Symbol { symbol, anchor }) => TreeView {
            symbol: Some(symbol),
            anchor: Some([anchor.face, anchor.corner]),
            ..leaf("symbol")
        },
        NodeKind::Cut { children, .. } => TreeView {
            children: children.iter().map(|&c| tree_view(tree, c)).collect(),
            ..leaf("cut")
        },
    }
}

/// The edit view of rule `rule` (its leaves, `hidden` ones flagged) or else of symbol `symbol`.
pub fn edit_view(
    project: &Project,
    rule: Option<u32>,
    symbol: Option<u32>,
    hidden: &BTreeSet<(u32, NodeId)>,
) -> EditView {
    if let Some(r) = rule.and_then(|r| project.rules.get(r as usize).map(|x| (r, x))) {
        let (index, rule) = r;
        let parts = rule
            .tree
            .leaves()
            .into_iter()
            .enumerate()
            .map(|(k, id)| {
                let node = &rule.tree.nodes()[id as usize];
                let (kind, symbol, anchor) = match node.kind {
                    NodeKind::Leaf(Assignment::Symbol { symbol, anchor }) => {
                        ("symbol", Some(symbol), Some(anchor))
                    }
                    NodeKind::Leaf(Assignment::Epsilon) => ("epsilon", None, None),
                    _ => ("terminal", None, None),
                };
                let color = symbol
                    .and_then(|s| project.symbols[s as usize].color)
                    .map_or_else(|| PALETTE[k % PALETTE.len()].to_owned(), |c| c.to_hex());
                let mut part = part_view(id, &node.shape, color);
                part.face_materials = node.face_materials.clone();
                part.uvs = face_uvs(&node.shape, &part.face_materials, &project.materials);
                part.kind = kind;
                part.symbol = symbol;
                part.hidden = hidden.contains(&(index, id));
                part.anchor = anchor.and_then(|a| {
                    let h = a.half_edge(&node.shape)?;
                    Some(AnchorView {
                        face: a.face,
                        corner: a.corner,
                        from: node.shape.position(node.shape.origin(h)).to_array(),
                        to: node.shape.position(node.shape.destination(h)).to_array(),
                    })
                });
                part
            })
            .collect();
        return EditView {
            rule: Some(index),
            symbol: Some(rule.symbol),
            parts,
        };
    }
    let Some((index, prototype)) =
        symbol.and_then(|s| project.symbols.get(s as usize).map(|x| (s, x)))
    else {
        return EditView::default();
    };
    let color = prototype
        .color
        .map_or_else(|| PALETTE[0].to_owned(), |c| c.to_hex());
    let mut part = part_view(RuleTree::ROOT, &prototype.shape, color);
    part.kind = "symbol";
    part.symbol = Some(index);
    EditView {
        rule: None,
        symbol: Some(index),
        parts: vec![part],
    }
}

/// A shape's triangles (its convex faces as fans), face loops and normals.
fn part_view(node: NodeId, shape: &Polyhedron, color: String) -> PartView {
    let mut positions = Vec::new();
    let mut triangle_faces = Vec::new();
    let mut faces = Vec::new();
    let mut normals = Vec::new();
    for f in 0..shape.face_count() {
        let corners: Vec<DVec3> = shape.face_loop(f).map(|v| shape.position(v)).collect();
        for k in 1..corners.len().saturating_sub(1) {
            for p in [corners[0], corners[k], corners[k + 1]] {
                positions.extend([p.x as f32, p.y as f32, p.z as f32]);
            }
            triangle_faces.push(f);
        }
        faces.push(corners.iter().map(|p| p.to_array()).collect());
        normals.push(shape.face_normal(f).to_array());
    }
    let faces_len = faces.len();
    PartView {
        node,
        color,
        hidden: false,
        kind: "terminal",
        symbol: None,
        positions,
        triangle_faces,
        faces,
        normals,
        anchor: None,
        face_materials: vec![None; faces_len],
        uvs: Vec::new(),
    }
}

/// The texture coordinates of a shape's triangles (the fans of [`part_view`]) under the
/// materials of its faces; faces without one get zeros.
fn face_uvs(shape: &Polyhedron, chosen: &[Option<u32>], materials: &[Material]) -> Vec<f32> {
    if chosen.iter().all(Option::is_none) {
        return Vec::new();
    }
    let mut uvs = Vec::new();
    for f in 0..shape.face_count() {
        let corners: Vec<DVec3> = shape.face_loop(f).map(|v| shape.position(v)).collect();
        let tile = chosen
            .get(f as usize)
            .copied()
            .flatten()
            .and_then(|m| materials.get(m as usize))
            .map(|m| m.tile);
        let normal = shape.face_normal(f);
        for k in 1..corners.len().saturating_sub(1) {
            for p in [corners[0], corners[k], corners[k + 1]] {
                let uv = tile.map_or(DVec2::ZERO, |tile| planar_uv(p, normal, tile));
                uvs.extend([uv.x as f32, uv.y as f32]);
            }
        }
    }
    uvs
}

/// One coloured part of a generated model.
#[derive(Serialize)]
pub struct MeshView {
    pub name: String,
    pub color: String,
    /// Triangle corners, nine numbers per triangle.
    pub positions: Vec<f32>,
}

/// The tester's model: one part per symbol colour, triangles unindexed.
pub fn mesh_view(mesh: &GrammarMesh) -> Vec<MeshView> {
    mesh.parts
        .iter()
        .map(|part| MeshView {
            name: part.name.clone(),
            color: hex(part.color),
            positions: part
                .triangles
                .iter()
                .flat_map(|t| t.iter().map(|&i| part.positions[i as usize]))
                .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
                .collect(),
        })
        .collect()
}

fn hex(color: Color) -> String {
    color.to_hex()
}

/// The vertices of sub-shape `shape` in the canonical order of `anchor`, for generating from it.
pub fn anchored_vertices(shape: &Polyhedron, anchor: shapegram_topo::Anchor) -> Option<Vec<DVec3>> {
    canonical_order(shape, anchor).map(|o| o.vertices.iter().map(|&v| shape.position(v)).collect())
}
