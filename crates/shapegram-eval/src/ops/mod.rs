//! Shape operations: compiling calls such as `split(y){…}` or `extrude(10)` into [`Op`]s.
//!
//! `catalogue` names every operation CGA has and what Shapegram does with it; `build` turns a
//! call into an [`Op`] and checks its arguments; `forms` reads each family's arguments.

mod build;
mod catalogue;
mod forms;
mod tagging;

use shapegram_geom::{Color, FaceClass};
use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, BlockEntry},
};

use crate::booleans::BooleanOp;
use crate::program::{CExpr, CKind, CStmt, Compiler};
pub(crate) use crate::selectors::{CompSelector, comp_selector, edge_selector};
use crate::shape::CsgOp;
use crate::texturing;
use crate::value::Value;

pub(crate) use build::compile;
pub use catalogue::{Support, operations};
pub(crate) use catalogue::{is_operation, signature};

/// A compiled shape operation.
#[derive(Debug)]
pub(crate) enum Op {
    Extrude {
        world_up: bool,
        distance: CExpr,
    },
    Translate([CExpr; 3]),
    Rotate {
        about_center: bool,
        degrees: [CExpr; 3],
    },
    Size([CExpr; 3]),
    Center([bool; 3]),
    Mirror([CExpr; 3]),
    AlignScopeToAxes(Option<usize>),
    /// `alignScopeToGeometry(yUp | zUp, face, edge)`: axes along an edge of a face, the face's
    /// normal up.
    AlignScopeToGeometry {
        z_up: bool,
        face: FaceChoice,
        edge: EdgeChoice,
    },
    /// `alignScopeToGeometryBBox(xz)`: the first two axes along the minimum-area rectangle
    /// around the geometry seen along the third, the first along its longer side.
    AlignScopeToGeometryBBox {
        first: usize,
        second: usize,
    },
    RotateScope([CExpr; 3]),
    /// `mirrorScope(x, y, z)`: the flagged scope axes turned round, the geometry staying.
    MirrorScope([CExpr; 3]),
    /// `setPivot(xyz | yzx | zxy, corner)`: the scope's origin at a corner, its axes turned
    /// into the box, the new y along old axis `up`; the geometry staying.
    SetPivot {
        up: usize,
        corner: CExpr,
    },
    /// `resetGeometry()`: the initial shape's geometry and scope back.
    ResetGeometry,
    /// `i(path [, yUp | zUp [, mode [, cleanup]]])`: the asset at the path, placed so.
    Insert(CExpr, Placement),
    Primitive(Primitive, Vec<CExpr>),
    Split {
        axis: usize,
        /// `splitArea`: the sizes are areas of the parts, not lengths.
        by_area: bool,
        adjust: bool,
        /// `split(x, snap [, "tag"])`: boundaries move to snap planes (with the tag, if given).
        snap: Option<Option<CExpr>>,
        /// How the parts join the skeleton.
        joints: SplitJoints,
        block: SplitBlock,
    },
    /// `split(u | v, uvSpace | unitSpace, uvSet) { … }`: a split along a texture coordinate.
    UvSplit {
        /// 0 for u, 1 for v.
        coordinate: usize,
        /// Sizes in metres (`unitSpace`) rather than in uv units.
        metres: bool,
        set: CExpr,
        block: SplitBlock,
    },
    /// `snap(x [, "tag"])`: snap planes across the given scope axes, at both ends of the scope.
    Snap {
        axes: [bool; 3],
        tag: Option<CExpr>,
    },
    /// `label("name")`: names the shape for occlusion queries.
    Label(CExpr),
    /// `tag(name [, components])`: tags the geometry's faces (`auto`, `faces`) or edges.
    Tag {
        name: CExpr,
        target: crate::tags::TagTarget,
    },
    /// `deleteTags([query [, components]])`: removes the tags the query matches.
    DeleteTags {
        query: Option<CExpr>,
        target: crate::tags::TagTarget,
    },
    Comp {
        kind: CompKind,
        entries: Vec<CompEntry>,
    },
    /// `splitAndSetbackPerimeter(offset [, firstEdge, mask]) { len : depth : … }[*] {
    /// remainder : … }`: the perimeter split into sections, each set back by its depth.
    PerimeterSplit(Box<PerimeterSplit>),
    /// `setback(d) { front : … | remainder : … }` and `shapeL(front, left) { shape : … |
    /// remainder : … }` (and `shapeU`, `shapeO`): strips along edges, their outline, the rest.
    Setback {
        depths: Depths,
        /// Entries selecting the edges that move (setback), each taking their strips.
        entries: Vec<CompEntry>,
        /// The `shape` entry (shapeL/U/O): whether it merges (`shape = …`) and its body.
        shape: Option<(bool, Vec<CStmt>)>,
        /// The `remainder` entry, likewise.
        remainder: Option<(bool, Vec<CStmt>)>,
    },
    Color(Vec<CExpr>),
    /// `color("#rrggbb")` with a literal: parsed once, when compiled.
    ColorLiteral(Color),
    Set(SetTarget, CExpr),
    /// A dynamic import's attributes (`id(a = v).Rule`): the overrides, evaluated where the
    /// call is, then every other attribute of the import from its default, in order.
    Reimport {
        attrs: Vec<u32>,
        overrides: Vec<(u32, CExpr)>,
    },
    Report(CExpr, CExpr),
    Print(CExpr),
    ReverseNormals,
    /// `trim()`: the shape's geometry cut at its trim planes.
    Trim,
    /// `envelope(normal | world.up, maxHeight, …)`: the volume under a height limit and under
    /// planes rising inward from the edges, by base heights and angles per edge class (or per
    /// face edge, from two arrays).
    Envelope {
        world_up: bool,
        params: Vec<CExpr>,
    },
    /// `cleanupGeometry(vertices | edges | faces | all, tolerance)`: close vertices merged,
    /// straight corners and small faces dropped.
    Cleanup {
        what: shapegram_geom::cleanup::Cleanup,
        tolerance: CExpr,
    },
    /// `translate(abs | rel, frame, x, y, z)` and `rotate(abs | rel, frame, x, y, z)`.
    Transform {
        rotate: bool,
        absolute: bool,
        system: CoordSystem,
        values: [CExpr; 3],
    },
    /// `scatter(surface | volume | scope, n, uniform | gaussian [, mean [, stddev]]) { … }`:
    /// `n` point shapes at random places.
    Scatter(Box<ScatterSpec>),
    /// CGA's `taper(height)`: a pyramid over the first face.
    Pyramid(CExpr),
    /// `footprint()`: the geometry projected onto the scope's xz-plane.
    Footprint,
    /// `convexify([maxCut])`: concave faces cut into convex ones.
    Convexify(Option<CExpr>),
    /// `innerRectangle(scope | edge) { shape : … | remainder : … }`: the largest rectangle in
    /// each face, and the rest; without a block (`innerRect`), the rectangles replace the faces.
    InnerRectangle {
        /// Sides along an edge of the face rather than the scope's axes.
        edge: bool,
        shape: Option<(bool, Vec<CStmt>)>,
        remainder: Option<(bool, Vec<CStmt>)>,
        /// Whether the operation has a block (`innerRectangle`) or not (`innerRect`).
        split: bool,
    },
    Offset {
        distance: CExpr,
        keep: OffsetKeep,
    },
    /// `roofGable(…)` and the others: the angle (or with `byHeight` the height) first, then the
    /// roof's options in order.
    Roof {
        kind: RoofKind,
        by_height: bool,
        params: Vec<CExpr>,
    },
    /// `implicit(sphere)`: the shape becomes an implicit solid filling its scope.
    Implicit(ImplicitKind),
    /// `implicit("grotto.cave")`: the solid of an implicit grammar, stretched to the scope.
    ImplicitFile(CExpr),
    /// `csg("group", union [, fillet])` and friends: the shape's solid joins a CSG group.
    Csg {
        kind: CsgKind,
        group: CExpr,
        /// The fillet radius, or the amount of a morph.
        amount: Option<CExpr>,
    },
    /// `union`, `subtract` and `intersect`: two operands derived at once, each from a copy of
    /// the shape (`None`: the shape as it is), and combined; the first is the target, whose
    /// scope, attributes and material the result keeps.
    Boolean {
        kind: BooleanOp,
        operands: [Option<Vec<CStmt>>; 2],
    },
    /// `inline([append | unify | recompose]) { ops }` (or one call): the operations derived at
    /// once from a copy of the shape, their leaves merged back into it.
    Inline {
        mode: InlineMode,
        body: Vec<CStmt>,
    },
    /// `joint(x, y, z)`: the shape's joint moves to this point of its scope (metres, or `'`
    /// fractions of the scope's size), its axes along the scope's.
    Joint([CExpr; 3]),
    /// `rotationLimits(axis, min, max)` (degrees) and `translationLimits(axis, min, max)`
    /// (metres): how far the joint may move about or along one of its axes.
    JointLimits {
        rotation: bool,
        axis: usize,
        min: CExpr,
        max: CExpr,
    },
    /// `rotateJoint(x, y, z)` (degrees) and `translateJoint(x, y, z)` (metres): the joint's
    /// current pose, within its limits.
    JointPose {
        rotation: bool,
        values: [CExpr; 3],
    },
    /// `taper(axis, factor)`, `twist(axis, degrees)` and `shear(axis, toward, amount)`: the
    /// geometry deformed along a scope axis (see [`shapegram_geom::deform`]).
    Deform {
        kind: DeformKind,
        axis: usize,
        amount: CExpr,
    },
    /// `sync(windows)`: the shape joins a synchronization of its goal grammar.
    Sync(u32),
    /// `setupProjection(…)`: a projection frozen in world space.
    SetupProjection(Box<ProjectionSetup>),
    /// `projectUV(uvSet)`: the uv set from its projection.
    ProjectUv(CExpr),
    /// `texture(path)`: the colour map.
    Texture(CExpr),
    /// `tileUV`, `scaleUV`, `translateUV` (`offsetUV`), `rotateUV`, `deleteUV`, `copyUV`,
    /// `normalizeUV`: a uv set edited, its arguments in order (`normalizeUV`'s words are in
    /// its [`UvEdit`]).
    EditUv(UvEdit, Vec<CExpr>),
    /// Parsed and accepted, but without effect on the model yet (texturing and the like).
    Ignored,
}

/// `setupProjection(uvSet, scope.xy | world.xz | …, width, height [, widthOffset,
/// heightOffset [, uwFactor]])`, and the deprecated `setupProjection(uvSet, axes, width,
/// height, uwFactor)`.
#[derive(Debug)]
pub(crate) struct ProjectionSetup {
    pub set: CExpr,
    /// World axes (`world.xy`) rather than the scope's.
    pub world: bool,
    /// The axes u and v run along.
    pub axes: [usize; 2],
    /// Width and height of a texture tile.
    pub sizes: [CExpr; 2],
    pub offsets: Option<[CExpr; 2]>,
    pub uw_factor: Option<CExpr>,
}

/// The edits of a uv set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UvEdit {
    /// `tileUV(uvSet, width, height)`.
    Tile,
    /// `scaleUV(uvSet, u, v)`.
    Scale,
    /// `translateUV(uvSet, u, v)`.
    Translate,
    /// `rotateUV(uvSet, degrees)`.
    Rotate,
    /// `deleteUV(uvSet)`.
    Delete,
    /// `copyUV(from, to)`.
    Copy,
    /// `normalizeUV(uvSet, mode, type)`: the uvs mapped into `[0, 1]`.
    Normalize(UvNormalization),
}

/// Which axes `normalizeUV` maps into `[0, 1]` (its mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum UvNormalization {
    /// `uv`: u and v each by itself.
    Each,
    /// `uvUniform`: both by one scale, the larger extent becoming 1, keeping the aspect.
    Uniform,
    /// `u`: u alone.
    U,
    /// `v`: v alone.
    V,
}

/// The deformations, with what each takes besides its axis and amount.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DeformKind {
    Taper,
    Twist,
    /// Points move along this axis.
    Shear {
        toward: usize,
    },
}

impl DeformKind {
    /// The operation's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Taper => "taper",
            Self::Twist => "twist",
            Self::Shear { .. } => "shear",
        }
    }
}

/// How the parts of a split join the kinematic skeleton (§4.1 of the Procedural Skeletons
/// paper).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SplitJoints {
    /// Sequential when the split axis runs along the shape's bone, else parallel when the
    /// shape allows it, else sequential.
    Auto,
    /// A chain: each part a child of the one before, the shape's children moved to the last.
    Sequential,
    /// A fork: each part a child of the shape's parent.
    Parallel,
}

/// How `i()` places its asset: the asset's up axis and how the scope is fitted to it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Placement {
    /// `zUp`: the asset's up axis is z, so it is turned −90° about x before it is placed.
    pub z_up: bool,
    /// How the asset and the scope meet.
    pub fit: InsertFit,
}

/// The modes of `i()` (its third argument).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum InsertFit {
    /// `alignSizeAndPosition` (the default): the asset stretched to fill the scope.
    #[default]
    Align,
    /// `keepSizeAndPosition`: the asset as it is, in scope coordinates (as after `s(0,0,0)`).
    Keep,
    /// `keepSizeAlignPosition`: the asset at its own size, centred in scope x and z and
    /// standing on the scope's floor.
    KeepSize,
}

/// Built-in primitives inserted by `primitiveCube()` and friends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Primitive {
    Cube,
    /// A flat polygon round the ellipse in the scope's flat face.
    Disk,
    Cylinder,
    Cone,
    Sphere,
    Quad,
    Pyramid,
}

/// How far each edge of a setback moves.
#[derive(Debug)]
pub(crate) enum Depths {
    /// The edges the entries select, all by this distance.
    Selected(CExpr),
    /// Edges by the class of their outward direction (shapeL/U/O); other edges stay.
    ByClass(Vec<(FaceClass, CExpr)>),
    /// `setbackPerEdge(d)`: every face edge by `d` evaluated on that edge.
    PerEdge(CExpr),
    /// `setbackToArea(area [, minDists [, maxDists]])`: the selected edges by a common distance
    /// (added to their minimum, capped at their maximum) that leaves the remainder `area`.
    ToArea(Vec<CExpr>),
}

/// What `scatter` scatters over and how.
#[derive(Debug)]
pub(crate) struct ScatterSpec {
    pub domain: ScatterDomain,
    pub count: CExpr,
    /// Gaussian about a point of the scope (a fraction of its size per axis), with a standard
    /// deviation per axis (`None`: `'0.16`); uniform when `None`.
    pub gaussian: Option<([f64; 3], Option<CExpr>)>,
    pub body: Vec<CStmt>,
}

/// Where `scatter` puts its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ScatterDomain {
    Surface,
    Volume,
    Scope,
}

/// The frame `translate` and `rotate` take their values in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CoordSystem {
    /// The scope's (also for `pivot`, which Shapegram does not keep apart).
    Scope,
    /// The initial shape's.
    Object,
    /// The world's.
    World,
}

/// Which face `alignScopeToGeometry` takes.
#[derive(Debug)]
pub(crate) enum FaceChoice {
    Index(CExpr),
    Lowest,
    Largest,
    /// The face of the edge the edge choice picks among all edges.
    Any,
}

/// Which edge of the face `alignScopeToGeometry` takes.
#[derive(Debug)]
pub(crate) enum EdgeChoice {
    Index(CExpr),
    Lowest,
    Longest,
}

/// The solids of `implicit(…)`, each fitted to the scope.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ImplicitKind {
    Box,
    Sphere,
    Cylinder,
    Cone,
    Pyramid,
    Torus,
    Capsule,
}

impl ImplicitKind {
    /// Each kind with the word `implicit(…)` takes for it.
    pub const NAMED: [(Self, &str); 7] = [
        (Self::Box, "box"),
        (Self::Sphere, "sphere"),
        (Self::Cylinder, "cylinder"),
        (Self::Cone, "cone"),
        (Self::Pyramid, "pyramid"),
        (Self::Torus, "torus"),
        (Self::Capsule, "capsule"),
    ];

    /// The word for this kind.
    pub fn name(self) -> &'static str {
        Self::NAMED
            .iter()
            .find(|(k, _)| *k == self)
            .map_or("", |(_, n)| n)
    }

    fn from_name(name: &str) -> Option<Self> {
        Self::NAMED
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(k, _)| *k)
    }
}

/// The CSG group operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CsgKind {
    Union,
    Subtract,
    Intersect,
    Morph,
}

impl CsgKind {
    /// The word in `csg(group, word)`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Union => "union",
            Self::Subtract => "subtract",
            Self::Intersect => "intersect",
            Self::Morph => "morph",
        }
    }

    /// The operation with its fillet radius or morph amount.
    pub fn op(self, amount: f64) -> CsgOp {
        match self {
            Self::Union => CsgOp::Union(amount),
            Self::Subtract => CsgOp::Subtract(amount),
            Self::Intersect => CsgOp::Intersect(amount),
            Self::Morph => CsgOp::Morph(amount),
        }
    }
}

/// How `inline` merges the leaves it derived.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum InlineMode {
    /// `append` (the default): their meshes side by side.
    Append,
    /// `unify`: their Boolean union.
    Unify,
    /// `recompose`: their meshes welded where vertices meet.
    Recompose,
}

/// What `comp` splits into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CompKind {
    Faces,
    Edges,
    /// The edges of each face, shared ones once per face.
    FaceEdges,
    Vertices,
    /// The corners of each face, shared ones once per face.
    FaceVertices,
    /// The holes of the faces: Shapegram's faces have none.
    Holes,
    /// The faces by the material they wear (an inserted asset's).
    Materials,
    /// The faces by the group of the inserted asset they belong to.
    Groups,
}

/// Which part of an offset polygon to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OffsetKeep {
    All,
    Inside,
    Border,
}

/// The roof operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RoofKind {
    Gable,
    Hip,
    Pyramid,
    Shed,
    /// One ridge along the scope's x axis.
    Ridge,
}

/// The target of `set(…)`.
#[derive(Debug)]
pub(crate) enum SetTarget {
    Attr(u32),
    /// A named attribute of a goal grammar's shape (`set(@Leg.Size, …)`).
    Goal(crate::goals::AttrId),
    Color(Option<usize>),
    MaterialName,
    /// A texture layer (`material.colormap` and the others of [`texturing::LAYERS`]).
    Map(usize),
    /// Another material attribute (`material.metallic`, …).
    Finish(texturing::FinishAttr),
    /// `trim.horizontal` (true) or `trim.vertical` (false).
    Trim(bool),
    /// `scope.tx`, `scope.ty` or `scope.tz`: the scope moved to it, the geometry with it.
    ScopeOrigin(usize),
    /// `scope.sx`, `scope.sy` or `scope.sz`: the scope sized to it, the geometry scaled.
    ScopeSize(usize),
    Ignored,
}

/// The `{ … }` of a split: sized parts and repeated groups.
#[derive(Debug)]
pub(crate) struct SplitBlock {
    pub entries: Vec<SplitEntry>,
    pub repeat: bool,
}

/// One entry of a split block.
#[derive(Debug)]
pub(crate) enum SplitEntry {
    Part {
        size: CExpr,
        /// A perimeter split's setback depth for the section.
        depth: Option<CExpr>,
        body: Vec<CStmt>,
    },
    Group(SplitBlock),
}

/// A perimeter split: where its pattern starts, which face edges it runs along, its sections
/// (each size with its depth) and the remainder's entry.
#[derive(Debug)]
pub(crate) struct PerimeterSplit {
    /// Metres along the perimeter (`'`: a fraction of it) where the pattern starts.
    pub offset: CExpr,
    /// The face edge the perimeter starts on.
    pub first_edge: Option<CExpr>,
    /// Which face edges belong to the perimeter (booleans in face-edge order).
    pub mask: Option<CExpr>,
    pub sections: SplitBlock,
    /// The `remainder` entry: whether it merges, and its body.
    pub remainder: Option<(bool, Vec<CStmt>)>,
}

/// One `selector : body` entry of a component split.
#[derive(Debug)]
pub(crate) struct CompEntry {
    pub selector: CompSelector,
    pub merge: bool,
    pub body: Vec<CStmt>,
}
