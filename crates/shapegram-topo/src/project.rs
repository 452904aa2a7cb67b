//! The editor's model (thesis 3.1.3–3.1.4): symbols with a prototype shape and a reference
//! anchor, and rules as trees of cuts whose leaves are assigned a symbol, left as anonymous
//! terminals or made epsilon.

use std::fmt;

use rustc_hash::FxHashMap;
use shapegram_geom::Color;

use crate::anchor::{Anchor, Topology, all_anchors, canonical_order};
use crate::cut::{CutError, CutPlane, VertexSource, cut};
use crate::grammar::VirtualVertex;
use crate::material::Material;
use crate::polyhedron::{Index, Polyhedron, PolyhedronError};

/// A node of a rule tree, by index.
pub type NodeId = Index;

/// Deepest a rule tree may grow: deeper trees are not hand-made, and project files nest two JSON
/// levels per cut under the JSON reader's limit of 128.
pub const MAX_TREE_DEPTH: usize = 48;

/// Everything the user authored: symbols, rules and materials.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Project {
    /// Symbols in creation order.
    pub symbols: Vec<Symbol>,
    /// Rules in creation order.
    pub rules: Vec<Rule>,
    /// Materials in creation order; faces of sub-shapes name them by index.
    pub materials: Vec<Material>,
}

/// A symbol: a name, a prototype shape and its reference anchor.
#[derive(Clone, Debug, PartialEq)]
pub struct Symbol {
    /// Unique, non-blank name.
    pub name: String,
    /// Colour of its shapes in meshes (`None`: default grey).
    pub color: Option<Color>,
    /// Colours of single faces of the prototype, overriding `color` (face index, colour), in
    /// increasing face order.
    pub face_colors: Vec<(Index, Color)>,
    /// The prototype shape: the geometry rules are drawn on and generation starts from.
    pub shape: Polyhedron,
    /// The reference anchor, fixing the symbol's vertex order and so its direction.
    pub anchor: Anchor,
}

impl Symbol {
    /// The symbol's topology under its reference anchor.
    pub fn topology(&self) -> Topology {
        canonical_order(&self.shape, self.anchor)
            .map(|o| o.topology)
            .unwrap_or_default()
    }
}

/// A rule: a cut tree over an instance of its symbol.
#[derive(Clone, Debug, PartialEq)]
pub struct Rule {
    /// Name (for messages and the tree view).
    pub name: String,
    /// The symbol it rewrites.
    pub symbol: Index,
    /// Relative weight among the symbol's rules (chosen at random in proportion).
    pub weight: f64,
    /// The cuts and sub-shapes.
    pub tree: RuleTree,
}

/// What a leaf of a rule tree becomes when the rule is applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Assignment {
    /// An anonymous terminal shape (the thesis's empty symbol field).
    Terminal,
    /// Nothing: the volume is removed.
    Epsilon,
    /// A shape of `symbol`, its vertices ordered from `anchor` on the leaf's shape.
    Symbol {
        /// The symbol.
        symbol: Index,
        /// Where the symbol's reference anchor goes on this shape.
        anchor: Anchor,
    },
}

/// A node of a rule tree: a shape, how its vertices are built, and either a cut or a leaf.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The shape the node stands for.
    pub shape: Polyhedron,
    /// For each vertex of `shape`, its index in the rule's vertex array.
    pub vertices: Vec<Index>,
    /// The parent node (`None` for the root).
    pub parent: Option<NodeId>,
    /// A cut or a leaf.
    pub kind: NodeKind,
    /// For each face of `shape`, the face of the parent's shape it is a piece of (`None` for
    /// the face the parent's cut made); the root's faces are their own sources.
    pub face_sources: Vec<Option<Index>>,
    /// For each face of `shape`, the material it was given (an index into
    /// [`Project::materials`]); the parts of a cut face keep its material.
    pub face_materials: Vec<Option<Index>>,
    /// For a cut node, the face and distance when the cut was placed at a fixed distance from
    /// a face of this node's shape ([`crate::Project::offset_cut`]); `None` otherwise.
    pub offset: Option<FaceOffset>,
}

/// A cut placed at a fixed distance from a face: derivation keeps the distance in metres on
/// shapes of any size instead of the fraction it is of the prototype.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceOffset {
    /// The face of the cut node's shape.
    pub face: Index,
    /// The distance inside the face, in metres.
    pub distance: f64,
}

/// Inner node or leaf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NodeKind {
    /// A leaf: a sub-shape.
    Leaf(Assignment),
    /// A cut into two children: `[below, above]` the plane.
    Cut {
        /// The plane.
        plane: CutPlane,
        /// The parts behind and in front of the plane.
        children: [NodeId; 2],
    },
}

/// A rule's cut tree and the virtual vertices its cuts made.
#[derive(Clone, Debug, PartialEq)]
pub struct RuleTree {
    base_count: usize,
    virtual_vertices: Vec<VirtualVertex>,
    nodes: Vec<Node>,
    /// Per cut, in the order they were made: the virtual vertices it made (indices into
    /// `virtual_vertices`).
    cut_vertices: Vec<std::ops::Range<Index>>,
}

/// Why an authoring step was refused (the project is left unchanged).
#[derive(Clone, Debug, PartialEq)]
pub enum EditError {
    /// No such symbol, rule, node or face.
    NotFound(String),
    /// The node is not a leaf, or has a symbol (which must be unassigned before cutting).
    NotCuttable(String),
    /// The plane does not cut the shape.
    Cut(CutError),
    /// A shape is not a valid convex polyhedron.
    Shape(PolyhedronError),
    /// The sub-shape's topology under the anchor differs from the symbol's.
    TopologyMismatch(String),
    /// A name or number is unusable.
    Invalid(String),
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotFound(what) => write!(f, "{what}"),
            Self::NotCuttable(why) => write!(f, "{why}"),
            Self::Cut(e) => write!(f, "{e}"),
            Self::Shape(e) => write!(f, "{e}"),
            Self::TopologyMismatch(why) => write!(f, "{why}"),
            Self::Invalid(why) => write!(f, "{why}"),
        }
    }
}

impl std::error::Error for EditError {}

impl From<CutError> for EditError {
    fn from(e: CutError) -> Self {
        Self::Cut(e)
    }
}

impl RuleTree {
    /// A tree of one leaf: an instance of `symbol`'s prototype, its vertices numbered as the
    /// symbol orders them.
    pub fn new(symbol: &Symbol) -> Self {
        let rank = canonical_order(&symbol.shape, symbol.anchor)
            .map(|o| o.rank)
            .unwrap_or_default();
        let faces = symbol.shape.face_count();
        Self {
            base_count: symbol.shape.vertex_count(),
            virtual_vertices: Vec::new(),
            nodes: vec![Node {
                shape: symbol.shape.clone(),
                vertices: rank,
                parent: None,
                kind: NodeKind::Leaf(Assignment::Terminal),
                face_sources: (0..faces).map(Some).collect(),
                face_materials: vec![None; faces as usize],
                offset: None,
            }],
            cut_vertices: Vec::new(),
        }
    }

    /// The root node (the whole symbol shape).
    pub const ROOT: NodeId = 0;

    /// All nodes; the root first.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Node `id`.
    pub fn node(&self, id: NodeId) -> Result<&Node, EditError> {
        self.nodes
            .get(id as usize)
            .ok_or_else(|| EditError::NotFound(format!("the rule has no node {id}")))
    }

    /// Number of vertices of the symbol's shape (the first entries of the vertex array).
    pub fn base_count(&self) -> usize {
        self.base_count
    }

    /// How the vertices beyond the shape's are made, in order.
    pub fn virtual_vertices(&self) -> &[VirtualVertex] {
        &self.virtual_vertices
    }

    /// The virtual vertices cut `step` made (the rule's cuts numbered 0 up in the order they
    /// were made), as indices into [`RuleTree::virtual_vertices`].
    pub fn cut_vertices(&self, step: usize) -> Option<std::ops::Range<Index>> {
        self.cut_vertices.get(step).cloned()
    }

    /// The face of the root (the symbol's shape) that face `face` of node `id` is a piece of;
    /// `None` when it lies on a cut.
    pub fn root_face(&self, mut id: NodeId, mut face: Index) -> Option<Index> {
        while let Some(parent) = self.nodes[id as usize].parent {
            face = self.nodes[id as usize].face_sources[face as usize]?;
            id = parent;
        }
        Some(face)
    }

    /// Gives face `face` of node `id` the material `material` (`None` clears it), and the
    /// pieces of that face in every sub-shape cut from the node too.
    pub fn set_face_material(
        &mut self,
        id: NodeId,
        face: Index,
        material: Option<Index>,
    ) -> Result<(), EditError> {
        let faces = self.node(id)?.shape.face_count();
        if face >= faces {
            return Err(EditError::NotFound(format!(
                "sub-shape {id} has no face {face} (it has {faces})"
            )));
        }
        let mut stack = vec![(id, face)];
        while let Some((id, face)) = stack.pop() {
            let node = &mut self.nodes[id as usize];
            node.face_materials[face as usize] = material;
            if let NodeKind::Cut { children, .. } = node.kind {
                for child in children {
                    let sources = &self.nodes[child as usize].face_sources;
                    stack.extend(
                        (0..sources.len())
                            .filter(|&k| sources[k] == Some(face))
                            .map(|k| (child, k as Index)),
                    );
                }
            }
        }
        Ok(())
    }

    /// Gives face `face` of node `id` the material `material`, that face alone (loading a
    /// project, which lists every face with a material).
    pub(crate) fn restore_face_material(
        &mut self,
        id: NodeId,
        face: Index,
        material: Index,
    ) -> Result<(), EditError> {
        let node = self.node(id)?;
        let faces = node.face_materials.len();
        if face as usize >= faces {
            return Err(EditError::NotFound(format!(
                "node {id} has no face {face} (it has {faces})"
            )));
        }
        self.nodes[id as usize].face_materials[face as usize] = Some(material);
        Ok(())
    }

    /// The leaves in depth-first order (below before above).
    pub fn leaves(&self) -> Vec<NodeId> {
        let mut out = Vec::new();
        let mut stack = vec![Self::ROOT];
        while let Some(id) = stack.pop() {
            match self.nodes[id as usize].kind {
                NodeKind::Leaf(_) => out.push(id),
                NodeKind::Cut { children, .. } => {
                    stack.push(children[1]);
                    stack.push(children[0]);
                }
            }
        }
        out
    }

    /// The leaves that can be cut (unassigned terminals), depth-first.
    pub fn cuttable_leaves(&self) -> Vec<NodeId> {
        self.leaves()
            .into_iter()
            .filter(|&id| self.nodes[id as usize].kind == NodeKind::Leaf(Assignment::Terminal))
            .collect()
    }

    fn depth(&self, mut id: NodeId) -> usize {
        let mut depth = 0;
        while let Some(parent) = self.nodes[id as usize].parent {
            depth += 1;
            id = parent;
        }
        depth
    }

    /// Cuts leaf `id` by `plane`; returns the new leaves `[below, above]`.
    pub fn cut(&mut self, id: NodeId, plane: CutPlane) -> Result<[NodeId; 2], EditError> {
        self.cut_with(id, plane, None)
    }

    /// Cuts leaf `id` by `plane`, recording that the plane lies at a fixed distance from a face
    /// of the leaf when `offset` is given; returns the new leaves `[below, above]`.
    pub(crate) fn cut_with(
        &mut self,
        id: NodeId,
        plane: CutPlane,
        offset: Option<FaceOffset>,
    ) -> Result<[NodeId; 2], EditError> {
        let node = self.node(id)?;
        match node.kind {
            NodeKind::Leaf(Assignment::Terminal) => {}
            NodeKind::Leaf(Assignment::Epsilon) => {
                return Err(EditError::NotCuttable(format!(
                    "sub-shape {id} is epsilon; make it a terminal before cutting it"
                )));
            }
            NodeKind::Leaf(Assignment::Symbol { .. }) => {
                return Err(EditError::NotCuttable(format!(
                    "sub-shape {id} has a symbol; unassign it before cutting it"
                )));
            }
            NodeKind::Cut { .. } => {
                return Err(EditError::NotCuttable(format!(
                    "node {id} is already cut; cut one of its sub-shapes"
                )));
            }
        }
        if self.depth(id) >= MAX_TREE_DEPTH {
            return Err(EditError::NotCuttable(format!(
                "sub-shape {id} is {MAX_TREE_DEPTH} cuts deep, the most a rule may nest"
            )));
        }
        let result = cut(&node.shape, &plane)?;
        let parent_vertices = node.vertices.clone();
        let parent_materials = node.face_materials.clone();
        let first_virtual = self.virtual_vertices.len() as Index;
        let mut made: FxHashMap<(Index, Index), Index> = FxHashMap::default();
        let mut children = [0; 2];
        for (k, part) in [result.below, result.above].into_iter().enumerate() {
            let vertices = part
                .sources
                .iter()
                .map(|source| match *source {
                    VertexSource::Vertex(v) => parent_vertices[v as usize],
                    VertexSource::Edge { from, to, t } => {
                        *made.entry((from, to)).or_insert_with(|| {
                            self.virtual_vertices.push(VirtualVertex {
                                from: parent_vertices[from as usize],
                                to: parent_vertices[to as usize],
                                t,
                            });
                            (self.base_count + self.virtual_vertices.len() - 1) as Index
                        })
                    }
                })
                .collect();
            children[k] = self.nodes.len() as NodeId;
            let face_materials = part
                .face_sources
                .iter()
                .map(|source| source.and_then(|f| parent_materials[f as usize]))
                .collect();
            self.nodes.push(Node {
                shape: part.shape,
                vertices,
                parent: Some(id),
                kind: NodeKind::Leaf(Assignment::Terminal),
                face_sources: part.face_sources,
                face_materials,
                offset: None,
            });
        }
        self.cut_vertices
            .push(first_virtual..self.virtual_vertices.len() as Index);
        let node = &mut self.nodes[id as usize];
        node.kind = NodeKind::Cut { plane, children };
        node.offset = offset;
        Ok(children)
    }

    /// Sets what leaf `id` becomes, checking a symbol's topology against the leaf's under the
    /// anchor.
    pub fn assign(
        &mut self,
        id: NodeId,
        assignment: Assignment,
        symbols: &[Symbol],
    ) -> Result<(), EditError> {
        let node = self.node(id)?;
        if let NodeKind::Cut { .. } = node.kind {
            return Err(EditError::NotCuttable(format!(
                "node {id} is a cut, not a sub-shape"
            )));
        }
        if let Assignment::Symbol { symbol, anchor } = assignment {
            check_instance(&node.shape, anchor, symbols, symbol)?;
        }
        self.nodes[id as usize].kind = NodeKind::Leaf(assignment);
        Ok(())
    }
}

/// Checks that `shape` under `anchor` has the topology of `symbols[symbol]`.
pub(crate) fn check_instance(
    shape: &Polyhedron,
    anchor: Anchor,
    symbols: &[Symbol],
    symbol: Index,
) -> Result<(), EditError> {
    let target = symbols
        .get(symbol as usize)
        .ok_or_else(|| EditError::NotFound(format!("there is no symbol {symbol}")))?;
    let order = canonical_order(shape, anchor).ok_or_else(|| {
        EditError::NotFound(format!(
            "the anchor (face {}, corner {}) is not on the shape",
            anchor.face, anchor.corner
        ))
    })?;
    let expected = target.topology();
    if order.topology == expected {
        return Ok(());
    }
    let other_anchor_fits = all_anchors(shape)
        .any(|a| canonical_order(shape, a).is_some_and(|o| o.topology == expected));
    Err(EditError::TopologyMismatch(if other_anchor_fits {
        format!(
            "the shape matches symbol '{}' only with another anchor (mirror or turn it)",
            target.name
        )
    } else {
        format!(
            "the shape ({} vertices, {} faces) does not have the topology of symbol '{}' ({} \
             vertices, {} faces)",
            shape.vertex_count(),
            shape.face_count(),
            target.name,
            target.shape.vertex_count(),
            target.shape.face_count()
        )
    }))
}
