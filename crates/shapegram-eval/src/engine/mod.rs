//! The derivation engine: rewriting shapes with rules until only leaves are left.
//!
//! The driver is in two files: `derive.rs` holds the entry point [`derive()`], the lots, the
//! batches they derive in and the two phases of grammars with context rules; `machine.rs` holds
//! the engine of one lot (its state, work queue, rule bodies, statements and limits) and
//! `Engine::op`, which hands each operation to its family. Each family has a file of its own,
//! which owns all that its operations do to a shape:
//!
//! - `scope.rs`: `t`, `r`, `s`, `center`, `mirror`, `alignScopeTo…`, `rotateScope`;
//! - `split.rs`: `split` and its repeats;
//! - `comp.rs`: `comp(f)`, `comp(e)`, `comp(v)`;
//! - `footprint.rs`: `extrude`, `offset`, `setback`, `shapeL/U/O`, `reverseNormals`;
//! - `roof.rs`: `roofGable`, `roofHip`, `roofPyramid`, `roofShed`;
//! - `deform.rs`: `taper`, `twist`, `shear`;
//! - `insert.rs`: `i()` with assets and built-in shapes, `primitive…()`;
//! - `implicit.rs`: `implicit(…)` and `csg(…)`;
//! - `boolean.rs`: `union`, `subtract`, `intersect` and `inline`;
//! - `attributes.rs`: `color`, `set`, `report`, `print`;
//! - `context.rs`: what `label`, `snap`, `comp` and `split(…, snap)` record for context
//!   queries and ask of them.
//!
//! Operations are compiled from calls in [`crate::ops`]: a new one gets its `Op` there, an arm
//! in `Engine::op` and its work in its family's file.

mod attr_values;
mod attributes;
mod auto_tags;
mod boolean;
mod comp;
mod context;
mod control;
mod deform;
mod derive;
mod edge_depths;
mod envelope;
mod footprint;
mod goals;
mod implicit;
mod inner_rect;
mod insert;
mod instances;
mod kinematics;
mod leaf_metadata;
mod machine;
mod palette;
mod perimeter;
mod pivot;
mod reuse;
mod roof;
mod roof_edges;
mod scatter;
mod scope;
mod setback_tags;
mod split;
mod statements;
mod tagging;
mod texturing;
mod trace;
mod transform;

use std::sync::Arc;
use std::time::Duration;

use rustc_hash::FxHashMap;
use shapegram_geom::{
    Bone, Color, DVec3, Mesh, MetaValue, Metadata, Model, Part as ModelPart, Scope, SurfaceKey,
    primitives,
};
use shapegram_kinematics::{Frame, SectionId, Skeleton};

use crate::asset_look::{Piece, ShapeMaterial};
use crate::error::DeriveError;
use crate::goals::{GoalQuery, LeafSemantics};
use crate::shape::Geometry;
use crate::texturing::Texturing;
use crate::value::Value;

pub use attr_values::{AttrValue, attr_values};
pub use control::DeriveControl;
pub use derive::derive;
pub(crate) use insert::builtin_asset;
pub use insert::{ASSET_VARIANTS, Asset, AssetLoader, AssetNaming};
pub use instances::InstanceCandidates;
pub use palette::{Paint, PaintId};
pub use reuse::{Rederivation, derive_again};
pub use trace::Trace;

/// How to derive.
#[derive(Clone)]
pub struct DeriveOptions {
    /// The run's seed: with the grammar and attributes it fixes every random choice.
    pub seed: u64,
    /// Attribute values overriding the grammar's defaults.
    pub attrs: Vec<(String, Value)>,
    /// The rule to start from; the grammar's `@StartRule` (or first rule) when `None`.
    pub start_rule: Option<String>,
    /// Stop with an error after this many shapes (per initial shape and in total).
    pub max_shapes: usize,
    /// Stop with an error when a shape is this many successors deep.
    pub max_depth: u32,
    /// Stop with an error after this much time per initial shape.
    pub time_budget: Option<Duration>,
    /// Rewrite in parallel generations and stop after this many (shapes left become leaves).
    pub generations: Option<u32>,
    /// Where `i("file.obj")` finds files.
    pub assets: Option<Arc<dyn AssetLoader>>,
    /// Keep the derivation tree (every shape that existed) in [`Derivation::tree`].
    pub keep_tree: bool,
    /// Edge length of the grid cells implicit solids are meshed with; `None` picks one per
    /// group from its size and its smallest member.
    pub implicit_cell: Option<f64>,
    /// Keep a [`Trace`] in [`Derivation::trace`], so that [`derive_again`] can reuse this
    /// derivation after rules change (depth-first derivations without context rules only).
    pub trace: bool,
    /// Stop with an error after this many rule applications (per initial shape): how goal
    /// grammars whose rules keep calling each other end.
    pub max_steps: usize,
    /// Lets another thread cancel the derivation and read its progress.
    pub control: Option<Arc<DeriveControl>>,
}

impl Default for DeriveOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            attrs: Vec::new(),
            start_rule: None,
            max_shapes: 10_000_000,
            max_depth: 1_000,
            time_budget: None,
            generations: None,
            assets: None,
            keep_tree: false,
            implicit_cell: None,
            trace: false,
            max_steps: 10_000_000,
            control: None,
        }
    }
}

/// How [`Derivation::to_model_with`] turns leaves into a model's parts.
#[derive(Clone, Debug, Default)]
pub struct ModelOptions {
    /// Which leaves may become instances: each such leaf whose geometry another leaf repeats
    /// (up to its scope and size) becomes parts of its own that carry their
    /// [`shapegram_geom::Instance`], instead of joining its rule's part.
    pub instances: InstanceCandidates,
    /// Only leaves whose sharing makes a GLB smaller (by the GLB writer's estimate of GPU
    /// instancing) become instances; the others stay with their rule's part, so that a model
    /// in which nothing is worth sharing is exactly the one without instancing.
    pub smaller_only: bool,
    /// Which parts carry [`Metadata`] (see [`MetadataScope`]).
    pub metadata: MetadataScope,
    /// The grammar's attribute names in order ([`crate::Program::attr_names`]), which name
    /// the attributes in the metadata.
    pub attr_names: Vec<String>,
}

/// What the parts of a model built by [`Derivation::to_model_with`] say about their leaves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MetadataScope {
    /// Nothing beyond goal grammars' semantics.
    #[default]
    None,
    /// Each leaf gets parts of its own carrying its rule, and when the derivation kept its
    /// tree ([`DeriveOptions::keep_tree`]), its derivation path and attributes.
    Leaf,
    /// Parts are made as without metadata, each carrying its rule, how many leaves it holds and
    /// the attributes all of them agree on.
    Part,
}

/// An initial shape: a planar footprint polygon in world coordinates, counter-clockwise about
/// its up side (a lot faces +y).
#[derive(Clone, Debug, PartialEq)]
pub struct InitialShape {
    /// The polygon's corners.
    pub footprint: Vec<DVec3>,
    /// The lot's number in the whole input, when it is derived apart from the lots before it
    /// (a tile of a city): its seed and `initialShape.name` come from this number, so that
    /// it derives as it would among all of them. `None`: its place among the lots derived.
    pub index: Option<u64>,
}

impl InitialShape {
    /// A lot from `(x, z)` corners in either winding, at y = 0, facing up.
    pub fn from_xz(points: &[shapegram_geom::DVec2]) -> Option<Self> {
        let mesh = primitives::footprint(points)?;
        Some(Self {
            footprint: mesh.face_points(0).collect(),
            index: None,
        })
    }
}

/// A leaf's symbol: the index of its name in [`Derivation::names`]. A leaf names its symbol
/// by index rather than by a shared string, so that making and dropping a leaf (millions in a
/// city) touches no reference count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Symbol(pub u32);

/// A finished shape: part of the model.
///
/// Laid out in declaration order: what dropping a leaf reads (its geometry and extras) comes
/// first, in one cache line, and the 4-byte fields last, so that no padding lies between them.
#[derive(Clone, Debug, PartialEq)]
#[repr(C)]
pub struct Leaf {
    /// Its geometry, relative to the scope.
    pub geometry: Geometry,
    /// What few leaves carry (see [`LeafExtras`]); `None` for a leaf with none of it. Kept out
    /// of line so that the common leaf stays small: a city derives millions of them.
    extras: Option<Box<LeafExtras>>,
    /// Its scope.
    pub scope: Scope,
    /// Its node in [`Derivation::tree`], [`NO_NODE`] when the tree is not kept (read through
    /// [`Leaf::node`]): 4 bytes where an `Option<u32>` takes 8.
    node: u32,
    /// The initial shape it grew from, as an index into the derivation's initial shapes.
    pub lot: u32,
    /// The symbol of the shape (the rule that made it); [`Derivation::name`] spells it.
    pub name: Symbol,
    /// Its colour, and whether the grammar set it: [`Derivation::paint`] (or
    /// [`Derivation::color`]) reads it.
    pub paint: PaintId,
}

/// [`Leaf::node`] of a leaf without a tree node (the tree is kept only on request, and a tree
/// never numbers this many shapes: derivations stop at [`DeriveOptions::max_shapes`]).
const NO_NODE: u32 = u32::MAX;

/// The rarely set parts of a [`Leaf`]: material name, texturing, kinematic section and goal
/// semantics.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LeafExtras {
    material: Option<Arc<str>>,
    texturing: Option<Arc<Texturing>>,
    section: u32,
    semantics: Option<Arc<LeafSemantics>>,
}

impl LeafExtras {
    /// The extras of a leaf, `None` when it has none of them.
    pub(crate) fn of(
        material: Option<Arc<str>>,
        texturing: Option<Arc<Texturing>>,
        section: u32,
        semantics: Option<Arc<LeafSemantics>>,
    ) -> Option<Box<Self>> {
        if material.is_none() && texturing.is_none() && section == 0 && semantics.is_none() {
            return None;
        }
        Some(Box::new(Self {
            material,
            texturing,
            section,
            semantics,
        }))
    }
}

/// Appends the leaf `make` builds, written straight into `leaves`: a leaf built first and then
/// pushed is built on the stack and copied (a `memcpy` of its 168 bytes per leaf).
#[inline(always)]
pub(crate) fn push_leaf(leaves: &mut Vec<Leaf>, make: impl FnOnce() -> Leaf) {
    leaves.reserve(1);
    let len = leaves.len();
    leaves.spare_capacity_mut()[0].write(make());
    // SAFETY: `reserve(1)` made room for the element at `len`, which `write` initialised.
    unsafe { leaves.set_len(len + 1) };
}

/// A shape in the derivation tree.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeNode {
    /// The shape's symbol when it was made.
    pub name: Arc<str>,
    /// The shape it came from (`None` for initial shapes).
    pub parent: Option<u32>,
    /// Its scope when it was made (its birth snapshot).
    pub scope: Scope,
    /// The initial shape it grew from.
    pub lot: u32,
    /// The kinematic section it was attached to when it was made (0 without a skeleton): with
    /// [`Derivation::node_motion`] any shape of the tree can be shown posed.
    pub section: u32,
    /// The shape's attribute values when it was made, in the order of
    /// [`Program::attr_names`](crate::Program::attr_names); shared between nodes while no
    /// `set` changes them.
    pub attrs: Arc<[Value]>,
    /// The rule that rewrote the shape; `None` for a shape no rule was applied to (a leaf
    /// made by its successor's `.`, a part of a split named after the shape split, a shape
    /// left when the generations ran out).
    pub rule: Option<crate::RuleId>,
}

impl Leaf {
    /// A leaf of the given geometry and look, made from `lot`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        name: Symbol,
        scope: Scope,
        geometry: Geometry,
        paint: PaintId,
        node: Option<u32>,
        lot: u32,
        extras: Option<Box<LeafExtras>>,
    ) -> Self {
        Self {
            name,
            geometry,
            extras,
            scope,
            node: node.unwrap_or(NO_NODE),
            lot,
            paint,
        }
    }

    /// Its node in [`Derivation::tree`], when the tree is kept.
    pub fn node(&self) -> Option<u32> {
        (self.node != NO_NODE).then_some(self.node)
    }

    /// The same leaf at tree node `node`.
    pub(crate) fn with_node(mut self, node: Option<u32>) -> Self {
        self.node = node.unwrap_or(NO_NODE);
        self
    }

    /// Its material name, when one was set.
    pub fn material(&self) -> Option<&Arc<str>> {
        self.extras.as_ref()?.material.as_ref()
    }

    /// Its uv sets, texture layers and other material attributes, when texturing operations or
    /// `set(material.…)` ran on it or its ancestors.
    pub fn texturing(&self) -> Option<&Arc<Texturing>> {
        self.extras.as_ref()?.texturing.as_ref()
    }

    /// The kinematic section it hangs from, in the skeleton of its lot (see
    /// [`Derivation::skeletons`]); 0 when the grammar builds none.
    pub fn section(&self) -> u32 {
        self.extras.as_ref().map_or(0, |e| e.section)
    }

    /// Goal grammars: the goals, tags and named attributes it ended with.
    pub fn semantics(&self) -> Option<&Arc<LeafSemantics>> {
        self.extras.as_ref()?.semantics.as_ref()
    }

    /// The same leaf hanging from kinematic section `section`.
    pub(crate) fn with_section(mut self, section: u32) -> Self {
        if section != self.section() {
            self.extras.get_or_insert_default().section = section;
        }
        self
    }

    /// The leaf's geometry in world coordinates (`None` when it has none).
    pub fn world_mesh(&self) -> Option<Mesh> {
        self.geometry.world_mesh(&self.scope)
    }

    /// The leaf's world mesh `mesh` in `paint` as the model draws it: one piece in the shape's material,
    /// or, when it holds an inserted asset with a look, one per material of the asset (see
    /// [`crate::asset_look`]).
    fn pieces(&self, mesh: Mesh, paint: Paint) -> Vec<Piece> {
        let material = ShapeMaterial {
            color: paint.color,
            painted: paint.painted,
            material: self.material(),
            texturing: self.texturing().map(|t| &**t),
        };
        // An asset's uvs count only when something is drawn through them: a look without
        // materials on a shape without texture layers draws as the shape's material alone.
        let worn = self.texturing().and_then(|t| {
            let drawn = t.maps.iter().any(Option::is_some);
            t.asset
                .as_ref()
                .filter(|worn| drawn || worn.look.has_materials())
        });
        let Some(worn) = worn else {
            return vec![material.piece(mesh)];
        };
        let local = match &self.geometry {
            Geometry::Mesh(local, _) => Some(&**local),
            _ => None,
        };
        material.pieces(worn.dress(mesh, local), &worn.look)
    }

    /// The uvs of uv set `set` at the vertices of `mesh` (the leaf's [`Leaf::world_mesh`]);
    /// `None` when the leaf has no such set.
    pub fn uvs(&self, set: usize, mesh: &Mesh) -> Option<Vec<shapegram_geom::DVec2>> {
        let map = self.texturing()?.uvs.get(set)?.as_ref()?;
        Some(mesh.positions().iter().map(|&p| map.at(p)).collect())
    }
}

/// Where a leaf's faces are in the model of [`Derivation::to_model_with_faces`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LeafFaces {
    /// The leaf, as an index into [`Derivation::leaves`].
    pub leaf: u32,
    /// The part its mesh was appended to, as an index into the model's parts.
    pub part: u32,
    /// Its first face in that part's mesh.
    pub first: u32,
    /// How many faces it has there.
    pub count: u32,
}

/// Counts of a derivation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Shapes created (initial shapes, successors and parts of splits).
    pub shapes: usize,
    /// Leaves in the model.
    pub leaves: usize,
    /// How often each rule was applied, by rule name, in rule order.
    pub rules: Vec<(String, usize)>,
    /// Goal grammars: rule applications (derivation steps) in all.
    pub steps: usize,
    /// Goal grammars: rule applications by grammar of the library, in library order.
    pub grammars: Vec<(String, usize)>,
}

/// The result of a derivation.
#[derive(Clone, Debug, Default)]
pub struct Derivation {
    /// The leaves, initial shape by initial shape, in derivation order.
    pub leaves: Vec<Leaf>,
    /// The names of the symbols leaves are named by ([`Leaf::name`] indexes it): the
    /// program's symbols, in its order.
    pub names: Arc<[Arc<str>]>,
    /// The looks of the leaves ([`Leaf::paint`] indexes it), in order of first use.
    pub paints: Vec<Paint>,
    /// `report(key, value)` calls in derivation order.
    pub reports: Vec<(String, Value)>,
    /// The tree node of the shape each report was made on, parallel to [`Derivation::reports`],
    /// when [`DeriveOptions::keep_tree`] is set; empty otherwise. It ties reports to their lot
    /// and to the leaves below them (see [`ModelOptions::metadata`]).
    pub report_nodes: Vec<u32>,
    /// `print(value)` output in derivation order.
    pub prints: Vec<String>,
    /// The initial shape (by its index among the derivation's) each line of
    /// [`Derivation::prints`] was printed on, parallel to it: a tiled run prints the lines of
    /// the lots it derives for their tiles and not those of the lots around them it derives as
    /// context.
    pub print_lots: Vec<u32>,
    /// Every shape that existed, parents before children, when [`DeriveOptions::keep_tree`]
    /// is set; empty otherwise.
    pub tree: Vec<TreeNode>,
    /// The implicit solids of the leaves, meshed with smooth normals: a part per CSG group of
    /// each initial shape, then a part per solid that belongs to no group.
    pub solids: Vec<ModelPart>,
    /// The kinematic skeletons, one per initial shape, by initial shape, when the grammar uses
    /// kinematic operations; empty otherwise.
    pub skeletons: Vec<(u32, Skeleton)>,
    /// Counts.
    pub stats: Stats,
    /// What [`derive_again`] reuses, when [`DeriveOptions::trace`] was set.
    pub trace: Option<Arc<Trace>>,
    /// Goal grammars: every distinct combination of open goals, tags and attributes that shapes
    /// sought rules for (local goals left out), sorted: what a repository of other people's
    /// grammars would be asked.
    pub queries: Vec<GoalQuery>,
    /// Goal grammars: the queries (as [`Derivation::queries`]) of shapes that no rule applied
    /// to, so that they kept goals open: what a repository is asked for rules.
    pub unmatched: Vec<GoalQuery>,
}

impl Derivation {
    /// The name of `symbol` (a [`Leaf::name`]).
    pub fn name(&self, symbol: Symbol) -> &str {
        &self.names[symbol.0 as usize]
    }

    /// The look of `leaf`: its colour, and whether the grammar set it.
    pub fn paint(&self, leaf: &Leaf) -> Paint {
        self.paints[leaf.paint.0 as usize]
    }

    /// The colour of `leaf`.
    pub fn color(&self, leaf: &Leaf) -> Color {
        self.paint(leaf).color
    }

    /// The rigid motion that takes tree node `node` (its scope and geometry, in the rest pose)
    /// into the current pose of its section; `None` when its lot has no skeleton or there is
    /// no such node. Visual debugging shows any shape of the derivation posed with it.
    pub fn node_motion(&self, node: usize) -> Option<Frame> {
        let n = self.tree.get(node)?;
        let (_, skeleton) = self.skeletons.iter().find(|(lot, _)| *lot == n.lot)?;
        skeleton.motion(SectionId(n.section))
    }

    /// The leaves as a model: one part per (symbol, colour) in order of first appearance, each
    /// holding the world-space geometry of its leaves, then the meshed implicit [`solids`].
    /// Leaves of goal grammars are parted by their semantics too, which their part carries as
    /// [`Metadata`].
    ///
    /// [`solids`]: Derivation::solids
    pub fn to_model(&self) -> Model {
        self.build_model(None, &ModelOptions::default())
    }

    /// [`Derivation::to_model`] with instances and leaf metadata as `options` ask: instanced
    /// leaves and leaves with metadata get parts of their own, in leaf order among the others.
    pub fn to_model_with(&self, options: &ModelOptions) -> Model {
        self.build_model(None, options)
    }

    /// Whether [`Derivation::to_model`] would hold a face: a meshed solid with one, or a leaf
    /// (not of an implicit solid) with a mesh that has one. It looks at leaves until it finds
    /// one, without building the model.
    pub fn has_geometry(&self) -> bool {
        self.solids.iter().any(|part| !part.mesh.is_empty())
            || self.leaves.iter().any(|leaf| {
                !matches!(leaf.geometry, Geometry::Implicit(_))
                    && leaf.world_mesh().is_some_and(|mesh| !mesh.is_empty())
            })
    }

    /// Each lot's metadata, by its index among the derivation's lots, as a GLB's lot nodes
    /// carry it with `--metadata` (rule, path, attributes named by `attr_names`, leaf count,
    /// report summaries); `None` for a lot without a tree node (the tree was not kept). A
    /// lot's path starts with its number in `numbers` (its place in the whole input, for a
    /// tile's lots derived apart), or with its index where `numbers` has none.
    pub fn lot_metadata(
        &self,
        attr_names: &[String],
        numbers: &[u32],
    ) -> Vec<Option<Arc<Metadata>>> {
        leaf_metadata::LeafDescriber::new(self, attr_names, numbers).into_lots()
    }

    /// [`Derivation::to_model`], and where each leaf's faces went: for every leaf that is in a
    /// part of its own kind (not an implicit solid, not without geometry), in leaf order, its
    /// [`LeafFaces`]. Visual debugging maps the model's triangles back to the leaves with it.
    pub fn to_model_with_faces(&self) -> (Model, Vec<LeafFaces>) {
        let mut faces = Vec::new();
        let model = self.build_model(Some(&mut faces), &ModelOptions::default());
        (model, faces)
    }

    fn build_model(
        &self,
        mut places: Option<&mut Vec<LeafFaces>>,
        options: &ModelOptions,
    ) -> Model {
        let mut parts: Vec<ModelPart> = Vec::new();
        type Key<'a> = (
            &'a str,
            [u32; 4],
            Option<Bone>,
            Option<PartMetadata>,
            Option<Arc<str>>,
            Option<Arc<str>>,
            // Boxed: most leaves have no surface, and the table holds a key per part (with
            // `--metadata`, per leaf), each of which would otherwise carry its 680 bytes.
            Option<Box<SurfaceKey>>,
        );
        let mut slot: FxHashMap<Key, usize> = FxHashMap::default();
        let mut metadata = MetadataCache::default();
        let mut describer = (options.metadata != MetadataScope::None)
            .then(|| leaf_metadata::LeafDescriber::new(self, &options.attr_names, &[]));
        let mut summaries = leaf_metadata::PartSummaries::default();
        let skeleton_of: FxHashMap<u32, u32> = self
            .skeletons
            .iter()
            .enumerate()
            .map(|(i, (lot, _))| (*lot, i as u32))
            .collect();
        // Which pieces are instances is known only once every leaf was seen.
        let mut assigned = if options.instances == InstanceCandidates::None {
            Vec::new()
        } else {
            // Skinned parts follow their bones, never a prototype.
            let skinned = |leaf: &Leaf| skeleton_of.contains_key(&leaf.lot);
            let leaves = self.leaves.iter().map(|leaf| {
                let frame = instances::Prototypes::frame(leaf, options.instances)
                    .filter(|_| !skinned(leaf))?;
                Some((frame, leaf.pieces(leaf.world_mesh()?, self.paint(leaf))))
            });
            instances::assign(leaves, options.smaller_only)
        }
        .into_iter();
        for (index, leaf) in self.leaves.iter().enumerate() {
            let mut leaf_instances = assigned.next().unwrap_or_default().into_iter();
            if matches!(leaf.geometry, Geometry::Implicit(_)) {
                continue;
            }
            let Some(mesh) = leaf.world_mesh() else {
                continue;
            };
            let bone = skeleton_of.get(&leaf.lot).map(|&skeleton| Bone {
                skeleton,
                section: SectionId(leaf.section()),
            });
            let description = describer
                .as_mut()
                .map(|d| d.describe(leaf, leaf.semantics().map(|s| &**s)));
            // Per leaf, the description is the part's metadata; per part, it is summarised.
            let (meta, description) = match (options.metadata, description) {
                (MetadataScope::Leaf, Some(description)) => (Some(Arc::new(description)), None),
                (_, description) => (leaf.semantics().map(|s| metadata.of(s)), description),
            };
            for piece in leaf.pieces(mesh, self.paint(leaf)) {
                let instance = leaf_instances.next().flatten();
                if instance.is_some() {
                    if options.metadata == MetadataScope::Part
                        && let Some(description) = &description
                    {
                        summaries.add(parts.len(), index, description);
                    }
                    if let Some(places) = places.as_deref_mut() {
                        places.push(LeafFaces {
                            leaf: index as u32,
                            part: parts.len() as u32,
                            first: 0,
                            count: piece.mesh.face_count() as u32,
                        });
                    }
                    parts.push(ModelPart {
                        bone,
                        name: self.name(leaf.name).to_string(),
                        color: piece.color,
                        normals: Vec::new(),
                        metadata: meta.clone(),
                        texture: piece.colormap,
                        uvs: piece.uvs.unwrap_or_default(),
                        material: piece.material,
                        surface: piece.surface.map(Arc::from),
                        instance,
                        mesh: piece.mesh,
                    });
                    continue;
                }
                let key = (
                    self.name(leaf.name),
                    piece.color.to_array().map(f32::to_bits),
                    bone,
                    meta.clone().map(PartMetadata),
                    piece.colormap.as_ref().map(|texture| texture.path.clone()),
                    piece.material.clone(),
                    piece.surface.as_ref().map(|s| Box::new(s.key())),
                );
                let i = *slot.entry(key).or_insert_with(|| {
                    parts.push(ModelPart {
                        bone,
                        name: self.name(leaf.name).to_string(),
                        color: piece.color,
                        mesh: Mesh::new(),
                        normals: Vec::new(),
                        metadata: meta.clone(),
                        texture: piece.colormap.clone(),
                        uvs: Vec::new(),
                        material: piece.material.clone(),
                        surface: piece.surface.clone().map(Arc::from),
                        instance: None,
                    });
                    parts.len() - 1
                });
                if let Some(uvs) = piece.uvs {
                    parts[i].uvs.extend(uvs);
                }
                if options.metadata == MetadataScope::Part
                    && let Some(description) = &description
                {
                    summaries.add(i, index, description);
                }
                if let Some(places) = places.as_deref_mut() {
                    places.push(LeafFaces {
                        leaf: index as u32,
                        part: i as u32,
                        first: parts[i].mesh.face_count() as u32,
                        count: piece.mesh.face_count() as u32,
                    });
                }
                parts[i].mesh.append(&piece.mesh);
            }
        }
        summaries.finish(&mut parts);
        parts.extend(self.solids.iter().cloned());
        Model {
            skeletons: self.skeletons.iter().map(|(_, s)| s.clone()).collect(),
            parts,
            lines: Vec::new(),
        }
    }
}

/// A part's metadata in the key that gathers leaves into parts: equal as metadata are, but
/// hashed by path where there is one, which tells leaves apart as well as the whole would at a
/// fraction of the cost (with `--metadata`, every leaf has its own).
#[derive(PartialEq, Eq)]
struct PartMetadata(Arc<Metadata>);

impl std::hash::Hash for PartMetadata {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        match &self.0.path {
            Some(path) => path.hash(state),
            None => self.0.hash(state),
        }
    }
}

/// Leaves' semantics as part metadata: equal semantics share one [`Metadata`], and the
/// leaves of one shape's parts share their semantics, so the last one is remembered.
#[derive(Default)]
struct MetadataCache {
    last: Option<(Arc<LeafSemantics>, Arc<Metadata>)>,
    seen: FxHashMap<Arc<Metadata>, ()>,
}

impl MetadataCache {
    fn of(&mut self, semantics: &Arc<LeafSemantics>) -> Arc<Metadata> {
        if let Some((last, meta)) = &self.last
            && Arc::ptr_eq(last, semantics)
        {
            return meta.clone();
        }
        let names = |list: &[Arc<str>]| list.iter().map(|s| s.to_string()).collect();
        let meta = Arc::new(Metadata {
            rule: None,
            path: None,
            leaves: None,
            goals: names(&semantics.goals),
            tags: names(&semantics.tags),
            attributes: semantics
                .attributes
                .iter()
                .map(|(name, value)| (name.to_string(), meta_value(value)))
                .collect(),
            reports: None,
            lot: None,
        });
        let meta = match self.seen.get_key_value(&meta) {
            Some((shared, _)) => shared.clone(),
            None => {
                self.seen.insert(meta.clone(), ());
                meta
            }
        };
        self.last = Some((semantics.clone(), meta.clone()));
        meta
    }
}

fn meta_value(value: &Value) -> MetaValue {
    match value {
        Value::Number(n) => MetaValue::Number(*n),
        Value::Bool(b) => MetaValue::Bool(*b),
        other => MetaValue::Text(other.to_string()),
    }
}

/// What engine steps return.
type Fallible<T> = std::result::Result<T, DeriveError>;

#[cfg(test)]
mod tests {
    use super::Leaf;

    /// A city derives millions of leaves: what most of them lack stays out of line, and the
    /// name is a symbol index, so that a leaf is a scope (120 bytes) with little more.
    #[test]
    fn a_leaf_stays_small() {
        assert_eq!(std::mem::size_of::<Leaf>(), 168);
        assert_eq!(std::mem::size_of::<crate::shape::Geometry>(), 24);
    }

    /// Every rule application copies a shape's state: it stays within five cache lines.
    #[test]
    fn a_shape_state_stays_small() {
        assert_eq!(std::mem::size_of::<crate::shape::State>(), 320);
    }
}
