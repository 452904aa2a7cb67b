//! Shapes during derivation: scope, geometry, attributes and the rest of a shape's state.

use std::rc::Rc;
use std::sync::{Arc, Weak};

use shapegram_geom::{Color, DAffine3, DVec3, Mesh, Scope, primitives};
use shapegram_implicit::{MeshOptions, Solid};
use shapegram_syntax::Span;

use crate::goals::Semantics;
use crate::program::Sym;
use crate::rng::{Rng, child_seed};
use crate::tags::FaceTags;
use crate::texturing::Texturing;
use crate::trim::Trim;
use crate::value::Value;

/// What a shape is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// The scope box itself. When one size is zero the box is flat: a rectangle facing the
    /// positive direction of that axis (a lot faces +y, a facade +z). Most shapes of real grammars
    /// are boxes and rectangles, and splitting them is arithmetic.
    Box,
    /// A polygon mesh in scope-local coordinates, with what its faces carry when any carries
    /// something: the part of an `offset` they are, their tags and their edges' (see
    /// [`crate::tags`]). The tags sit behind a thin pointer, which keeps a geometry (and so
    /// every shape and leaf) 8 bytes smaller.
    Mesh(Arc<Mesh>, Option<Arc<Vec<FaceTags>>>),
    /// An implicit solid in scope-local coordinates (`implicit(sphere)`), possibly a member of
    /// a CSG group; meshed when the model is made.
    Implicit(Arc<Implicit>),
    /// No geometry: edges and vertices of a component split, until something is inserted.
    Empty,
}

/// An implicit solid and the CSG group it belongs to, if any.
#[derive(Clone, Debug, PartialEq)]
pub struct Implicit {
    /// The solid, in scope-local coordinates.
    pub solid: Solid,
    /// Its membership of a group (`csg("rock", union)` and friends); `None` for a solid meshed
    /// with the other solids of its rule and colour.
    pub csg: Option<Csg>,
    /// The operation that made the solid, for error messages.
    pub span: Span,
}

/// How an implicit solid joins a named group: the members of a group (within one initial shape)
/// are combined into one solid and meshed as one surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Csg {
    /// The group's name.
    pub group: Arc<str>,
    /// What the member does to the group.
    pub op: CsgOp,
    /// The operation that made it a member, for error messages.
    pub span: Span,
}

/// What a member does to its group's solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CsgOp {
    /// Adds the member (`csg(…, union)`), with a round fillet of this radius where it meets the rest
    /// (0 for a sharp seam).
    Union(f64),
    /// Blends the group towards the group with the member added, by this amount in `0..=1`
    /// (`csg(…, morph, a)`, the SG+M morphic production).
    Morph(f64),
    /// Carves the member away (`csg(…, subtract)`), filleted like a union.
    Subtract(f64),
    /// Keeps only what lies inside the member (`csg(…, intersect)`), filleted like a union.
    Intersect(f64),
}

impl CsgOp {
    /// Whether the member adds to its group (`union`, `morph`) rather than carving or trimming.
    pub fn adds(self) -> bool {
        matches!(self, Self::Union(_) | Self::Morph(_))
    }
}

/// Cells along the longest side of an implicit solid's bounds when it is meshed during the
/// derivation: for geometry queries (`geometry.area`) and for fitting scopes around it.
pub const IMPLICIT_CELLS: usize = 48;

/// The mesh of an implicit solid with [`IMPLICIT_CELLS`] cells along its longest side (`None`
/// when it is empty).
pub fn implicit_mesh(solid: &Solid) -> Option<Mesh> {
    if solid.is_empty() {
        return None;
    }
    let options = MeshOptions::cells_along_longest(solid, IMPLICIT_CELLS);
    let mesh = shapegram_implicit::mesh(solid, &options).ok()?.mesh;
    (!mesh.is_empty()).then_some(mesh)
}

impl Geometry {
    /// A mesh geometry without tags.
    pub fn mesh(mesh: Mesh) -> Self {
        Self::Mesh(Arc::new(mesh), None)
    }

    /// The geometry as a mesh in scope-local coordinates (`None` for empty geometry or a box
    /// flat in more than one axis).
    pub fn local_mesh(&self, size: DVec3) -> Option<Mesh> {
        match self {
            Self::Box => box_mesh(size),
            Self::Mesh(mesh, _) => Some((**mesh).clone()),
            Self::Implicit(implicit) => implicit_mesh(&implicit.solid),
            Self::Empty => None,
        }
    }

    /// An implicit geometry holding `solid`, with the membership of `self` when it is implicit.
    /// (`self` must be implicit; anything else keeps its own geometry).
    pub fn with_solid(&self, solid: Solid) -> Self {
        match self {
            Self::Implicit(implicit) => Self::Implicit(Arc::new(Implicit {
                solid,
                csg: implicit.csg.clone(),
                span: implicit.span,
            })),
            other => other.clone(),
        }
    }

    /// The geometry in world coordinates.
    pub fn world_mesh(&self, scope: &Scope) -> Option<Mesh> {
        let mut mesh = self.local_mesh(scope.size)?;
        mesh.transform(&scope.local_to_world());
        Some(mesh)
    }

    /// A mesh geometry whose faces carry `tags` (none when no face carries anything).
    pub fn tagged_mesh(mesh: Mesh, tags: Vec<FaceTags>) -> Self {
        let tags = tags.iter().any(|t| !t.is_plain()).then(|| tags.into());
        Self::Mesh(Arc::new(mesh), tags)
    }

    /// What each face carries, if any face carries anything.
    pub fn tags(&self) -> Option<&[FaceTags]> {
        match self {
            Self::Mesh(_, Some(tags)) => Some(tags),
            _ => None,
        }
    }

    /// What each face carries, shared, if any face carries anything.
    pub fn shared_tags(&self) -> Option<Arc<Vec<FaceTags>>> {
        match self {
            Self::Mesh(_, tags) => tags.clone(),
            _ => None,
        }
    }
}

/// The axis along which a flat box has no extent, if exactly one has none.
pub fn flat_axis(size: DVec3) -> Option<usize> {
    let zero: Vec<usize> = (0..3).filter(|&i| size[i] == 0.0).collect();
    (zero.len() == 1).then(|| zero[0])
}

/// Whether a local polygon is exactly the flat box of its scope (a rectangle at its corners).
pub fn fills_box(local: &[DVec3], size: DVec3) -> bool {
    let Some(axis) = flat_axis(size) else {
        return false;
    };
    let eps = 1e-9 * size.length().max(1.0);
    local.len() == 4
        && local.iter().all(|p| {
            (0..3).all(|i| {
                i == axis && p[i].abs() <= eps
                    || i != axis && (p[i].abs() <= eps || (p[i] - size[i]).abs() <= eps)
            })
        })
        && (Mesh::from_polygon(local).area() - size[(axis + 1) % 3] * size[(axis + 2) % 3]).abs()
            <= eps * size.length().max(1.0)
}

/// The mesh of a box geometry in local coordinates: a cuboid, a rectangle facing the positive
/// direction of its one flat axis, or nothing.
pub fn box_mesh(size: DVec3) -> Option<Mesh> {
    let (x, y, z) = (size.x, size.y, size.z);
    let quad = |points: [DVec3; 4]| Some(Mesh::from_polygon(&points));
    match flat_axis(size) {
        None if size.cmpgt(DVec3::ZERO).all() => Some(primitives::cuboid(size)),
        // First edges follow the component-frame convention: along x where x has extent.
        Some(2) => quad([
            DVec3::ZERO,
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x, y, 0.0),
            DVec3::new(0.0, y, 0.0),
        ]),
        Some(1) => quad([
            DVec3::new(0.0, 0.0, z),
            DVec3::new(x, 0.0, z),
            DVec3::new(x, 0.0, 0.0),
            DVec3::ZERO,
        ]),
        Some(0) => quad([
            DVec3::ZERO,
            DVec3::new(0.0, y, 0.0),
            DVec3::new(0.0, y, z),
            DVec3::new(0.0, 0.0, z),
        ]),
        _ => None,
    }
}

/// The state of a shape: what operations act on and successors inherit.
#[derive(Clone, Debug)]
pub struct State {
    /// The shape's symbol (the rule that made it or will rewrite it).
    pub symbol: Sym,
    /// The shape's scope.
    pub scope: Scope,
    /// The shape's geometry.
    pub geometry: Geometry,
    /// Attribute values, shared until one is set.
    pub attrs: Rc<Vec<Value>>,
    /// Surface colour.
    pub color: Color,
    /// Whether the grammar set the colour (`color()`, `set(material.color…)`): only then does
    /// it win over an inserted asset's own (see [`crate::asset_look`]).
    pub painted: bool,
    /// Material name set with `set(material.name, …)`.
    pub material: Option<Arc<str>>,
    /// Projections, uv sets, texture layers and the other material attributes; `None` until a
    /// texturing operation or `set(material.…)` runs.
    pub texturing: Option<Arc<Texturing>>,
    /// Position among the parts of the split that made it, and their count.
    pub split: (u32, u32),
    /// Position among the components of the component split that made it, and their count.
    pub comp: (u32, u32),
    /// The selector that took it in that component split (`comp.sel`), as an index into
    /// [`crate::ops::CompSelector::NAMES`]; 0 when none.
    pub comp_sel: u8,
    /// Derivation depth (initial shapes are 0).
    pub depth: u32,
    /// The shape's identity in the derivation: the seed of its random stream.
    pub seed: u64,
    /// The shape's random stream (`rand`, `p`, stochastic rules).
    pub rng: Rng,
    /// How many children this shape has made so far (their seeds depend on it).
    pub children: u64,
    /// The shape's node in the derivation tree (when one is kept).
    pub node: u32,
    /// The rule application the shape belongs to, as CGA's `getTreeKey` names it: the initial
    /// shape's is `[0]`, and each successor a rule names adds its position among that rule's
    /// successors.
    pub tree_key: Rc<[u32]>,
    /// The nearest ancestor (or the shape itself) that is an occluder, as an index into the
    /// occluders of the derivation ([`NO_OCCLUDER`] when none): occlusion queries ignore it and
    /// its ancestors.
    pub occluder: u32,
    /// The kinematic section the shape is attached to, in its lot's skeleton (0, the root,
    /// when the grammar builds none).
    pub section: u32,
    /// The trim planes of the face component it came from, and which kinds of them cut.
    pub trim: Trim,
    /// Goal grammars: the shape's goals, tags and named attributes (`None` otherwise).
    pub semantics: Option<Arc<Semantics>>,
    /// The mesh `i()` inserted, while the shape may still hold it (`geometry.isInstanced`):
    /// a weak pointer, so that it keeps no cut-up asset alive, and no other mesh can take its
    /// address while it is compared.
    pub instance: Option<Weak<Mesh>>,
}

impl FrozenState {
    /// Renumbers the shape's tree node and occluder when the lists they index are appended to
    /// longer ones.
    pub fn rebase(&mut self, node_base: u32, occluder_base: u32) {
        self.node += node_base;
        if self.occluder != NO_OCCLUDER {
            self.occluder += occluder_base;
        }
    }

    /// The state again, ready to derive on this thread.
    pub fn thaw(self) -> State {
        State {
            symbol: self.symbol,
            scope: self.scope,
            geometry: self.geometry,
            attrs: Rc::new(self.attrs),
            color: self.color,
            painted: self.painted,
            material: self.material,
            texturing: self.texturing,
            split: self.split,
            comp: self.comp,
            comp_sel: self.comp_sel,
            depth: self.depth,
            seed: self.seed,
            rng: self.rng,
            children: self.children,
            node: self.node,
            tree_key: Rc::from(&*self.tree_key),
            occluder: self.occluder,
            section: self.section,
            trim: self.trim,
            semantics: self.semantics,
            instance: self.instance,
        }
    }
}

/// [`State::occluder`] of a shape without an occluding ancestor.
pub const NO_OCCLUDER: u32 = u32::MAX;

/// A [`State`] that can move between threads (attributes not shared): how shapes waiting for
/// the second phase of a derivation are kept.
#[derive(Clone, Debug)]
pub struct FrozenState {
    symbol: Sym,
    scope: Scope,
    geometry: Geometry,
    attrs: Vec<Value>,
    color: Color,
    painted: bool,
    material: Option<Arc<str>>,
    texturing: Option<Arc<Texturing>>,
    split: (u32, u32),
    comp: (u32, u32),
    comp_sel: u8,
    depth: u32,
    seed: u64,
    rng: Rng,
    children: u64,
    node: u32,
    tree_key: Arc<[u32]>,
    occluder: u32,
    section: u32,
    trim: Trim,
    semantics: Option<Arc<Semantics>>,
    instance: Option<Weak<Mesh>>,
}

impl State {
    /// A fresh state for an initial shape.
    pub fn initial(symbol: Sym, scope: Scope, geometry: Geometry, seed: u64) -> Self {
        Self {
            symbol,
            scope,
            geometry,
            attrs: Rc::new(Vec::new()),
            color: Color::default(),
            painted: false,
            material: None,
            texturing: None,
            split: (0, 1),
            comp: (0, 1),
            comp_sel: 0,
            depth: 0,
            seed,
            rng: Rng::new(seed),
            children: 0,
            node: 0,
            tree_key: Rc::from([0]),
            occluder: NO_OCCLUDER,
            section: 0,
            trim: Trim::default(),
            semantics: None,
            instance: None,
        }
    }

    /// A child: a copy of this state with its own seed and random stream.
    pub fn spawn(&mut self) -> State {
        let seed = self.next_child_seed();
        let mut child = self.clone();
        child.adopt(seed, self.depth + 1);
        child
    }

    /// Turns this state into its own next child, for a successor that ends a rule: the parent
    /// is not needed any more, so nothing is copied. The child is the one [`State::spawn`]
    /// would have made.
    pub fn make_child(&mut self) {
        let seed = self.next_child_seed();
        let depth = self.depth + 1;
        self.adopt(seed, depth);
    }

    /// Moves the state out, leaving a shape without geometry, material or trim planes behind (to
    /// be dropped).
    pub fn take(&mut self) -> State {
        State {
            symbol: self.symbol,
            scope: self.scope,
            geometry: std::mem::replace(&mut self.geometry, Geometry::Empty),
            attrs: self.attrs.clone(),
            color: self.color,
            painted: self.painted,
            material: self.material.take(),
            texturing: self.texturing.take(),
            split: self.split,
            comp: self.comp,
            comp_sel: self.comp_sel,
            depth: self.depth,
            seed: self.seed,
            rng: self.rng.clone(),
            children: self.children,
            node: self.node,
            tree_key: self.tree_key.clone(),
            occluder: self.occluder,
            section: self.section,
            trim: std::mem::take(&mut self.trim),
            semantics: self.semantics.take(),
            instance: self.instance.take(),
        }
    }

    /// The state with its attributes copied out of the shared list, so it can change threads.
    pub fn freeze(self) -> FrozenState {
        FrozenState {
            symbol: self.symbol,
            scope: self.scope,
            geometry: self.geometry,
            attrs: Rc::try_unwrap(self.attrs).unwrap_or_else(|shared| (*shared).clone()),
            color: self.color,
            painted: self.painted,
            material: self.material,
            texturing: self.texturing,
            split: self.split,
            comp: self.comp,
            comp_sel: self.comp_sel,
            depth: self.depth,
            seed: self.seed,
            rng: self.rng,
            children: self.children,
            node: self.node,
            tree_key: Arc::from(&*self.tree_key),
            occluder: self.occluder,
            section: self.section,
            trim: self.trim,
            semantics: self.semantics,
            instance: self.instance,
        }
    }

    fn next_child_seed(&mut self) -> u64 {
        let seed = child_seed(self.seed, self.children);
        self.children += 1;
        seed
    }

    /// Joins a synchronization whose random stream starts from `seed`: the shape and its
    /// children draw what the other members and theirs draw.
    pub fn synchronize(&mut self, seed: u64) {
        let depth = self.depth;
        self.adopt(seed, depth);
    }

    fn adopt(&mut self, seed: u64, depth: u32) {
        self.seed = seed;
        self.rng = Rng::new(seed);
        self.children = 0;
        self.depth = depth;
    }

    /// Whether the geometry is the very mesh `i()` inserted: no operation has cut, trimmed or
    /// rebuilt it since (each makes a new mesh).
    pub fn is_instanced(&self) -> bool {
        match (&self.geometry, &self.instance) {
            (Geometry::Mesh(mesh, _), Some(inserted)) => inserted.as_ptr() == Arc::as_ptr(mesh),
            _ => false,
        }
    }

    /// Replaces the scope while keeping the geometry where it is in world space.
    pub fn rescope(&mut self, scope: Scope) {
        if let Geometry::Implicit(implicit) = &self.geometry {
            self.geometry = self.geometry.with_solid(moved(
                &implicit.solid,
                scope.world_to_local() * self.scope.local_to_world(),
            ));
        } else if let Some(mut mesh) = self.geometry.world_mesh(&self.scope) {
            mesh.transform(&scope.world_to_local());
            let tags = self.geometry.shared_tags();
            self.geometry = Geometry::Mesh(Arc::new(mesh), tags);
        }
        self.scope = scope;
    }

    /// Turns scope axis `i` around: the scope becomes mirrored, and the geometry, whose local
    /// coordinates stay, is mirrored through the plane of the origin across that axis. (Faces
    /// keep facing outward: placing geometry with a mirrored frame turns their winding.)
    pub fn mirror_axis(&mut self, i: usize) {
        let mut flip = DVec3::ONE;
        flip[i] = -1.0;
        self.scope.axes *= shapegram_geom::DMat3::from_diagonal(flip);
    }

    /// Sets the scope size, scaling mesh geometry along (CGA `s`). Axes of zero size keep the
    /// geometry's own extent along them.
    pub fn resize(&mut self, size: DVec3) {
        let old = self.scope.size;
        let factor = DVec3::select(old.cmpeq(DVec3::ZERO), DVec3::ONE, size / old);
        match &self.geometry {
            Geometry::Mesh(mesh, tags) => {
                let scaled = mesh.transformed(&DAffine3::from_scale(factor));
                self.geometry = Geometry::Mesh(Arc::new(scaled), tags.clone());
            }
            // A zero size squashes a solid to nothing.
            Geometry::Implicit(_) if factor.cmpeq(DVec3::ZERO).any() => {
                self.geometry = Geometry::Empty;
            }
            Geometry::Implicit(implicit) => {
                let map = DAffine3::from_scale(factor);
                self.geometry = self.geometry.with_solid(moved(&implicit.solid, map));
            }
            Geometry::Box | Geometry::Empty => {}
        }
        self.scope.size = size;
    }
}

/// `solid` under `map`, an invertible affine map made of scope frames and finite non-zero
/// scales; should it fail to invert all the same (sizes beyond f64 range), the solid stays put.
pub fn moved(solid: &Solid, map: DAffine3) -> Solid {
    solid.transform(&map).unwrap_or_else(|_| solid.clone())
}
