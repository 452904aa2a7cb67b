//! Shape operations: compiling calls such as `split(y){…}` or `extrude(10)` into [`Op`]s.

use shapegram_geom::{Color, FaceClass};
use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, BlockEntry},
};

use crate::program::{CExpr, CKind, CStmt, Compiler};
pub(crate) use crate::selectors::{CompSelector, comp_selector, edge_selector};
use crate::shape::CsgOp;
use crate::texturing;
use crate::value::Value;

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
    /// `label("name")` (or `tag("name")`): names the shape for occlusion queries.
    Label(CExpr),
    Comp {
        kind: CompKind,
        entries: Vec<CompEntry>,
    },
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

/// What `comp` splits into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CompKind {
    Faces,
    Edges,
    /// The edges of each face, shared ones once per face.
    FaceEdges,
    Vertices,
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
    Part { size: CExpr, body: Vec<CStmt> },
    Group(SplitBlock),
}

/// One `selector : body` entry of a component split.
#[derive(Debug)]
pub(crate) struct CompEntry {
    pub selector: CompSelector,
    pub merge: bool,
    pub body: Vec<CStmt>,
}

/// Operations that would only change texturing or shading: accepted without effect.
const VISUAL_ONLY: &[&str] = &[
    "softenNormals",
    "setNormals",
    "cleanupGeom",
    "setPivot",
    "resetMaterial",
    "annotation",
];

/// CGA operations that are recognised but not implemented yet.
const UNSUPPORTED: &[&str] = &[
    "innerCircle",
    "resetGeometry",
    "mirrorScope",
    "rectify",
    "simplify",
    "modify",
    "insertAlongUV",
    "union",
    "subtract",
    "intersect",
    "generalize",
    "reduceGeometry",
    "splitAndSetbackPerimeter",
    "fill",
    "primitiveDisk",
    "primitiveTorus",
    "dissolve",
    "bevel",
    "extrudeFaces",
    "stack",
    "ladder",
    "inline",
];

/// The operations [`compile`] builds, besides the visual-only and unsupported ones.
const IMPLEMENTED: &[&str] = &[
    "setupProjection",
    "projectUV",
    "texture",
    "tileUV",
    "scaleUV",
    "translateUV",
    "offsetUV",
    "rotateUV",
    "deleteUV",
    "copyUV",
    "normalizeUV",
    "extrude",
    "t",
    "r",
    "s",
    "center",
    "mirror",
    "alignScopeToAxes",
    "rotateScope",
    "i",
    "insert",
    "primitiveCube",
    "primitiveQuad",
    "primitivePyramid",
    "primitiveCylinder",
    "primitiveCone",
    "primitiveSphere",
    "split",
    "splitArea",
    "comp",
    "color",
    "set",
    "report",
    "print",
    "reverseNormals",
    "trim",
    "convexify",
    "scatter",
    "translate",
    "rotate",
    "footprint",
    "deleteHoles",
    "cleanupGeometry",
    "envelope",
    "innerRectangle",
    "innerRect",
    "offset",
    "roofGable",
    "roofHip",
    "roofPyramid",
    "roofShed",
    "roofRidge",
    "label",
    "tag",
    "snap",
    "Snap",
    "implicit",
    "csg",
    "alignScopeToGeometry",
    "alignScopeToGeometryBBox",
    "setback",
    "setbackPerEdge",
    "setbackToArea",
    "shapeL",
    "shapeU",
    "shapeO",
    "joint",
    "rotationLimits",
    "translationLimits",
    "rotateJoint",
    "translateJoint",
    "taper",
    "twist",
    "shear",
    "sync",
];

/// The signature of each operation [`compile`] builds, as hints and the studio show it.
const SIGNATURES: &[(&str, &str)] = &[
    ("extrude", "extrude([world.up | face.normal,] distance)"),
    ("t", "t(x, y, z)"),
    ("r", "r([scopeCenter,] x, y, z)"),
    ("s", "s(x, y, z)"),
    ("center", "center(xyz)"),
    ("mirror", "mirror(x, y, z)"),
    (
        "alignScopeToAxes",
        "alignScopeToAxes([x | y | z | world.xyz])",
    ),
    ("rotateScope", "rotateScope(x, y, z)"),
    (
        "i",
        "i(path [, yUp | zUp [, alignSizeAndPosition | keepSizeAndPosition | keepSizeAlignPosition [, numericalCleanup | noCleanup]]])",
    ),
    (
        "insert",
        "i(path [, yUp | zUp [, alignSizeAndPosition | keepSizeAndPosition | keepSizeAlignPosition [, numericalCleanup | noCleanup]]])",
    ),
    (
        "primitiveCube",
        "primitiveCube() | primitiveCube(width, height, depth)",
    ),
    (
        "primitiveQuad",
        "primitiveQuad() | primitiveQuad(width, length)",
    ),
    ("primitivePyramid", "primitivePyramid()"),
    (
        "primitiveCylinder",
        "primitiveCylinder([nSides]) | primitiveCylinder(nSides, radius, height)",
    ),
    ("primitiveCone", "primitiveCone([nSides])"),
    ("primitiveSphere", "primitiveSphere([nRows [, nColumns]])"),
    (
        "split",
        "split(x | y | z [, adjust | noAdjust] [, sequential | parallel] [, snap [, \"tag\"]]) { … } | split(u | v, uvSpace | unitSpace, uvSet) { … }",
    ),
    (
        "splitArea",
        "splitArea(x | y | z [, adjust | noAdjust]) { area : … | … }",
    ),
    ("comp", "comp(f | e | fe | v) { … }"),
    ("color", "color(\"#rrggbb\") | color(r, g, b)"),
    ("set", "set(attribute, value)"),
    ("report", "report(key, value)"),
    ("print", "print(value)"),
    ("reverseNormals", "reverseNormals()"),
    ("trim", "trim()"),
    ("convexify", "convexify([maxCutLength])"),
    (
        "translate",
        "translate(abs | rel, scope | pivot | object | world, x, y, z)",
    ),
    (
        "rotate",
        "rotate(abs | rel, scope | pivot | object | world, xAngle, yAngle, zAngle)",
    ),
    (
        "scatter",
        "scatter(surface | volume | scope, n, uniform | gaussian [, center | front | back | left | right | top | bottom [, stddev]]) { … }",
    ),
    ("footprint", "footprint()"),
    ("deleteHoles", "deleteHoles()"),
    (
        "cleanupGeometry",
        "cleanupGeometry(vertices | edges | faces | all, tolerance)",
    ),
    (
        "envelope",
        "envelope(normal | world.up, maxHeight, frontBase, frontAngle [, backBase, backAngle [, sideBase, sideAngle | rightBase, rightAngle, leftBase, leftAngle]]) | envelope(normal | world.up, maxHeight, baseHeights[], angles[])",
    ),
    (
        "innerRectangle",
        "innerRectangle(scope | edge) { shape : … | remainder : … }",
    ),
    ("innerRect", "innerRect()"),
    ("offset", "offset(distance [, inside | border])"),
    (
        "roofGable",
        "roofGable([byAngle | byHeight,] value [, overhangX [, overhangY [, even [, edgeIndex]]]])",
    ),
    (
        "roofHip",
        "roofHip([byAngle | byHeight,] value [, overhang [, even]])",
    ),
    ("roofPyramid", "roofPyramid([byAngle | byHeight,] value)"),
    (
        "roofShed",
        "roofShed([byAngle | byHeight,] value [, edgeIndex])",
    ),
    ("roofRidge", "roofRidge([byAngle | byHeight,] value)"),
    ("label", "label(\"name\")"),
    ("tag", "label(\"name\")"),
    ("snap", "snap(x | y | z | xy | … [, \"tag\"])"),
    ("Snap", "snap(x | y | z | xy | … [, \"tag\"])"),
    (
        "implicit",
        "implicit(box | sphere | cylinder | cone | pyramid | torus | capsule | \"file.cave\")",
    ),
    (
        "csg",
        "csg(\"group\", union | subtract | intersect [, fillet]) | csg(\"group\", morph, amount)",
    ),
    (
        "alignScopeToGeometry",
        "alignScopeToGeometry(yUp | zUp, [faceIndex | world.lowest | largest | any,] edgeIndex | world.lowest | longest)",
    ),
    (
        "alignScopeToGeometryBBox",
        "alignScopeToGeometryBBox(xy | yx | xz | zx | yz | zy)",
    ),
    (
        "setback",
        "setback(distance) { selector : … | remainder : … }",
    ),
    (
        "setbackPerEdge",
        "setbackPerEdge(distance [, uvSet]) { selector : … | remainder : … }",
    ),
    (
        "setbackToArea",
        "setbackToArea(area [, minDistances[] [, maxDistances[]]] [, uvSet]) { selector : … | remainder : … }",
    ),
    ("shapeL", "shapeL(frontDepth, leftWidth)"),
    ("shapeU", "shapeU(frontDepth, rightWidth, leftWidth)"),
    (
        "shapeO",
        "shapeO(frontDepth, rightWidth, backDepth, leftWidth)",
    ),
    ("joint", "joint(x, y, z)"),
    ("rotationLimits", "rotationLimits(x | y | z, min, max)"),
    (
        "translationLimits",
        "translationLimits(x | y | z, min, max)",
    ),
    ("rotateJoint", "rotateJoint(x, y, z)"),
    ("translateJoint", "translateJoint(x, y, z)"),
    ("taper", "taper(x | y | z, factor) | taper(height)"),
    ("twist", "twist(x | y | z, degrees)"),
    ("shear", "shear(x | y | z, toward x | y | z, amount)"),
    ("sync", "sync(synchronization)"),
    (
        "setupProjection",
        "setupProjection(uvSet, scope.xy, width, height [, widthOffset, heightOffset [, uwFactor]])",
    ),
    ("projectUV", "projectUV(uvSet)"),
    ("texture", "texture(path)"),
    ("tileUV", "tileUV(uvSet, width, height)"),
    ("scaleUV", "scaleUV(uvSet, uFactor, vFactor)"),
    ("translateUV", "translateUV(uvSet, u, v)"),
    ("offsetUV", "translateUV(uvSet, u, v)"),
    ("rotateUV", "rotateUV(uvSet, degrees)"),
    ("deleteUV", "deleteUV(uvSet)"),
    ("copyUV", "copyUV(fromSet, toSet)"),
    (
        "normalizeUV",
        "normalizeUV(uvSet, uv | uvUniform | u | v, separatePerFace | collectiveAllFaces)",
    ),
];

/// The signature of an implemented operation.
pub(crate) fn signature(name: &str) -> Option<&'static str> {
    SIGNATURES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// How far the engine supports an operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Support {
    /// Built and run.
    Implemented,
    /// Accepted without effect: it would change only texturing or shading.
    VisualOnly,
    /// Recognised, skipped with a warning.
    Unsupported,
}

/// Every operation the engine knows, with its support and, when implemented, its signature.
pub fn operations() -> impl Iterator<Item = (&'static str, Support, Option<&'static str>)> {
    let implemented = IMPLEMENTED
        .iter()
        .map(|n| (*n, Support::Implemented, signature(n)));
    let visual = VISUAL_ONLY.iter().map(|n| (*n, Support::VisualOnly, None));
    let unsupported = UNSUPPORTED.iter().map(|n| (*n, Support::Unsupported, None));
    implemented.chain(visual).chain(unsupported)
}

/// Whether an operation of this name exists (implemented or not).
pub(crate) fn is_operation(name: &str) -> bool {
    IMPLEMENTED.contains(&name) || VISUAL_ONLY.contains(&name) || UNSUPPORTED.contains(&name)
}

/// Compiles `call` as an operation. Returns `None` when no operation has that name,
/// `Some(None)` when it is one but the call has errors (already reported).
pub(crate) fn compile(
    c: &mut Compiler,
    call: &ast::Call,
    params: &[ast::Ident],
) -> Option<Option<Op>> {
    let name = call.name.name.as_str();
    if !is_operation(name) {
        return None;
    }
    if !IMPLEMENTED.contains(&name) {
        // Never evaluated: its arguments may use CGA words we do not know, which is no error.
        let mut ctx = Ctx {
            c,
            call,
            params,
            args: Vec::new(),
            words: Vec::new(),
        };
        return Some(ctx.build(name));
    }
    let args: Vec<CExpr> = call
        .args
        .iter()
        .flatten()
        .enumerate()
        .map(|(i, a)| match (&a.value.kind, name, i) {
            // `set(@name, …)` writes the attribute: no read.
            (ast::ExprKind::GoalAttribute { name, .. }, "set", 0) => {
                c.goal_attr_target(name, a.value.span)
            }
            _ => c.arg(&a.value, params),
        })
        .collect();
    let mut args = args;
    // `set` reads its first argument as a name itself, `setupProjection` its second.
    let own_word = match name {
        "set" => Some(0),
        "setupProjection" => Some(1),
        _ => None,
    };
    for (_, a) in args
        .iter_mut()
        .enumerate()
        .filter(|(i, _)| Some(*i) != own_word)
    {
        if let CKind::Selector(word) = &a.kind
            && crate::builtins::Query::is_known_unsupported(word)
        {
            let word = word.clone();
            a.kind = c.unknown_name(&word, a.span, params);
        }
    }
    let stray: Vec<(usize, String, Span)> = args
        .iter()
        .enumerate()
        .filter_map(|(i, a)| match &a.kind {
            CKind::Selector(word) => Some((i, word.clone(), a.span)),
            _ => None,
        })
        .collect();
    let mut ctx = Ctx {
        c,
        call,
        params,
        args,
        words: Vec::new(),
    };
    let op = ctx.build(name);
    // A bare word where the operation wanted a value is a name that does not exist. A skipped
    // operation reads none of its arguments: its words (`cleanupGeometry(all, 1)`) are its own.
    let errors = ctx.c.error_count();
    let reads_words = op.as_ref().is_some_and(|op| !matches!(op, Op::Ignored));
    for (i, word, span) in stray {
        if reads_words && !ctx.words.contains(&i) {
            ctx.c.unknown_name(&word, span, params);
        }
    }
    let failed = ctx.c.error_count() > errors;
    Some(op.filter(|_| !failed))
}

struct Ctx<'a, 'g> {
    c: &'a mut Compiler<'g>,
    call: &'a ast::Call,
    params: &'a [ast::Ident],
    args: Vec<CExpr>,
    /// Argument positions read as bare words (selectors).
    words: Vec<usize>,
}

impl Ctx<'_, '_> {
    fn build(&mut self, name: &str) -> Option<Op> {
        if VISUAL_ONLY.contains(&name) {
            self.warn_once(format!(
                "`{name}` is not supported yet: it is ignored (no effect on geometry)"
            ));
            return Some(Op::Ignored);
        }
        if UNSUPPORTED.contains(&name) {
            self.warn_once(format!(
                "operation `{name}` is not supported yet: it is skipped and the shape goes on unchanged"
            ));
            return Some(Op::Ignored);
        }
        let op = match name {
            "extrude" => self.extrude()?,
            "t" => Op::Translate(self.three()?),
            "r" => self.rotate()?,
            "s" => Op::Size(self.three()?),
            "center" => Op::Center(self.axes_selector()?),
            "mirror" => Op::Mirror(self.three()?),
            "alignScopeToAxes" => self.align()?,
            "alignScopeToGeometry" => self.align_to_geometry()?,
            "alignScopeToGeometryBBox" => self.align_to_bbox()?,
            "rotateScope" => Op::RotateScope(self.three()?),
            "i" | "insert" => self.insert()?,
            "primitiveCube" => self.primitive(Primitive::Cube, &[0, 3])?,
            "primitiveQuad" => self.primitive(Primitive::Quad, &[0, 2])?,
            "primitivePyramid" => self.primitive(Primitive::Pyramid, &[0])?,
            "primitiveCylinder" => self.primitive(Primitive::Cylinder, &[0, 1, 3])?,
            "primitiveCone" => self.primitive(Primitive::Cone, &[0, 1])?,
            "primitiveSphere" => self.primitive(Primitive::Sphere, &[0, 1, 2])?,
            "split" => self.split(false)?,
            "splitArea" => self.split(true)?,
            "joint" => {
                self.c.kinematic = true;
                Op::Joint(self.three()?)
            }
            "rotationLimits" => self.joint_limits(true)?,
            "translationLimits" => self.joint_limits(false)?,
            "rotateJoint" | "translateJoint" => {
                self.c.kinematic = true;
                let values = self.three()?;
                Op::JointPose {
                    rotation: name == "rotateJoint",
                    values,
                }
            }
            "snap" | "Snap" => self.snap()?,
            "label" | "tag" => {
                self.arity(1, 1)?;
                Op::Label(self.args.pop()?)
            }
            "comp" => self.comp()?,
            "setback" => self.setback()?,
            "setbackPerEdge" => {
                self.arity(1, 2)?;
                self.args.truncate(1);
                let blocks = self.setback_block(name, false)?;
                Op::Setback {
                    depths: Depths::PerEdge(self.args.pop()?),
                    entries: blocks.0,
                    shape: None,
                    remainder: blocks.2,
                }
            }
            "setbackToArea" => {
                self.arity(1, 4)?;
                let blocks = self.setback_block(name, false)?;
                Op::Setback {
                    depths: Depths::ToArea(std::mem::take(&mut self.args)),
                    entries: blocks.0,
                    shape: None,
                    remainder: blocks.2,
                }
            }
            "shapeL" => self.shape_luo(&[FaceClass::Front, FaceClass::Left])?,
            "shapeU" => self.shape_luo(&[FaceClass::Front, FaceClass::Right, FaceClass::Left])?,
            "shapeO" => self.shape_luo(&[
                FaceClass::Front,
                FaceClass::Right,
                FaceClass::Back,
                FaceClass::Left,
            ])?,
            "setupProjection" => self.setup_projection()?,
            "projectUV" => {
                self.arity(1, 1)?;
                Op::ProjectUv(self.args.pop()?)
            }
            "texture" => {
                self.arity(1, 1)?;
                Op::Texture(self.args.pop()?)
            }
            "tileUV" => self.edit_uv(UvEdit::Tile, 3)?,
            "scaleUV" => self.edit_uv(UvEdit::Scale, 3)?,
            "translateUV" | "offsetUV" => self.edit_uv(UvEdit::Translate, 3)?,
            "rotateUV" => self.edit_uv(UvEdit::Rotate, 2)?,
            "deleteUV" => self.edit_uv(UvEdit::Delete, 1)?,
            "copyUV" => self.edit_uv(UvEdit::Copy, 2)?,
            "normalizeUV" => self.normalize_uv()?,
            "color" => {
                if !matches!(self.args.len(), 1 | 3 | 4) {
                    return self.wrong_arity();
                }
                let args = std::mem::take(&mut self.args);
                match args.as_slice() {
                    [
                        CExpr {
                            kind: CKind::Value(Value::Str(text)),
                            ..
                        },
                    ] => match Color::from_hex(text) {
                        Some(color) => Op::ColorLiteral(color),
                        None => Op::Color(args),
                    },
                    _ => Op::Color(args),
                }
            }
            "set" => self.set()?,
            "report" => {
                self.arity(2, 2)?;
                let value = self.args.pop()?;
                Op::Report(self.args.pop()?, value)
            }
            "print" => {
                self.arity(1, 1)?;
                Op::Print(self.args.pop()?)
            }
            "reverseNormals" => {
                self.arity(0, 0)?;
                Op::ReverseNormals
            }
            "trim" => {
                self.arity(0, 0)?;
                Op::Trim
            }
            "convexify" => {
                self.arity(0, 1)?;
                Op::Convexify(self.args.pop())
            }
            "translate" | "rotate" => {
                self.arity(5, 5)?;
                let absolute = match self.word(0) {
                    Some("abs") => true,
                    Some("rel") => false,
                    _ => return self.bad_selector(0, "`abs` or `rel`"),
                };
                let system = match self.word(1) {
                    Some("scope" | "pivot") => CoordSystem::Scope,
                    Some("object") => CoordSystem::Object,
                    Some("world") => CoordSystem::World,
                    _ => return self.bad_selector(1, "`scope`, `pivot`, `object` or `world`"),
                };
                self.args.drain(..2);
                Op::Transform {
                    rotate: name == "rotate",
                    absolute,
                    system,
                    values: self.three()?,
                }
            }
            "scatter" => self.scatter()?,
            "footprint" => {
                self.arity(0, 0)?;
                Op::Footprint
            }
            // Shapegram's faces hold no holes: nothing to delete.
            "deleteHoles" => {
                self.arity(0, 0)?;
                Op::Ignored
            }
            "cleanupGeometry" => {
                self.arity(2, 2)?;
                let (vertices, edges, faces) = match self.word(0) {
                    Some("vertices") => (true, false, false),
                    Some("edges") => (false, true, false),
                    Some("faces") => (false, false, true),
                    Some("all") => (true, true, true),
                    _ => return self.bad_selector(0, "`vertices`, `edges`, `faces` or `all`"),
                };
                if edges {
                    self.warn_once(
                        "`cleanupGeometry` does not merge coplanar faces yet: their shared edges stay"
                            .into(),
                    );
                }
                Op::Cleanup {
                    what: shapegram_geom::cleanup::Cleanup { vertices, faces },
                    tolerance: self.args.pop()?,
                }
            }
            "envelope" => {
                if !matches!(self.args.len(), 4 | 6 | 8 | 10) {
                    return self.wrong_arity();
                }
                let world_up = match self.word(0) {
                    Some("world.up") => true,
                    Some("normal") => false,
                    _ => return self.bad_selector(0, "`normal` or `world.up`"),
                };
                Op::Envelope {
                    world_up,
                    params: self.args.split_off(1),
                }
            }
            "innerRectangle" => {
                self.arity(1, 1)?;
                let edge = match self.word(0) {
                    Some("scope") => false,
                    Some("edge") => true,
                    _ => return self.bad_selector(0, "`scope` or `edge`"),
                };
                let (_, shape, remainder) = self.setback_block(name, true)?;
                Op::InnerRectangle {
                    edge,
                    shape,
                    remainder,
                    split: true,
                }
            }
            "innerRect" => {
                self.arity(0, 0)?;
                Op::InnerRectangle {
                    edge: false,
                    shape: None,
                    remainder: None,
                    split: false,
                }
            }
            "offset" => self.offset()?,
            "roofGable" => self.roof(RoofKind::Gable)?,
            "roofHip" => self.roof(RoofKind::Hip)?,
            "roofPyramid" => self.roof(RoofKind::Pyramid)?,
            "roofShed" => self.roof(RoofKind::Shed)?,
            "roofRidge" => self.roof(RoofKind::Ridge)?,
            "implicit" => self.implicit()?,
            "csg" => self.csg()?,
            "taper" => self.deform(DeformKind::Taper)?,
            "twist" => self.deform(DeformKind::Twist)?,
            "shear" => self.deform(DeformKind::Shear { toward: 0 })?,
            "sync" => self.sync()?,
            _ => unreachable!("`{name}` is listed in IMPLEMENTED but not built"),
        };
        // A skipped form (`comp(g) { … }`) keeps the block it was written with.
        let needs_block = matches!(
            op,
            Op::Split { .. }
                | Op::UvSplit { .. }
                | Op::Scatter(_)
                | Op::Comp { .. }
                | Op::Setback { .. }
                | Op::InnerRectangle { split: true, .. }
                | Op::Ignored
        );
        if !needs_block && self.call.block.is_some() {
            self.error(format!("`{name}` takes no `{{…}}` block"));
            return None;
        }
        Some(op)
    }

    fn error(&mut self, message: String) {
        self.c.report(Diagnostic::error(message, self.call.span));
    }

    fn warn_once(&mut self, message: String) {
        self.c.warn_once(
            &self.call.name.name,
            Diagnostic::warning(message, self.call.name.span),
        );
    }

    fn wrong_arity(&mut self) -> Option<Op> {
        let signature = signature(&self.call.name.name).unwrap_or("");
        self.c.report(
            Diagnostic::error(
                format!("wrong number of arguments for `{}`", self.call.name.name),
                self.call.span,
            )
            .with_hint(format!("the signature is `{signature}`")),
        );
        None
    }

    fn arity(&mut self, lo: usize, hi: usize) -> Option<()> {
        if self.args.len() < lo || self.args.len() > hi {
            self.wrong_arity()?;
        }
        Some(())
    }

    fn three(&mut self) -> Option<[CExpr; 3]> {
        self.arity(3, 3)?;
        let z = self.args.pop()?;
        let y = self.args.pop()?;
        Some([self.args.pop()?, y, z])
    }

    /// The bare word (or string literal) of argument `i`.
    fn word(&mut self, i: usize) -> Option<&str> {
        self.words.push(i);
        match &self.args.get(i)?.kind {
            CKind::Selector(s) => Some(s),
            CKind::Value(Value::Str(s)) => Some(s),
            _ => None,
        }
    }

    fn bad_selector(&mut self, i: usize, expected: &str) -> Option<Op> {
        let span = self.args.get(i).map_or(self.call.span, |a| a.span);
        self.c.report(
            Diagnostic::error(format!("expected {expected}"), span)
                .with_label(format!("in `{}`", self.call.name.name)),
        );
        None
    }

    fn setup_projection(&mut self) -> Option<Op> {
        self.arity(4, 7)?;
        let word = self.word(1).map(str::to_owned);
        let parsed = word.as_deref().and_then(|w| {
            let (world, letters) = match w.split_once('.')? {
                ("scope", letters) => (false, letters),
                ("world", letters) => (true, letters),
                _ => return None,
            };
            let axis = |c: char| "xyz".find(c);
            let mut chars = letters.chars();
            let (a, b) = (axis(chars.next()?)?, axis(chars.next()?)?);
            (chars.next().is_none() && a != b).then_some((world, [a, b]))
        });
        let Some((world, axes)) = parsed else {
            return self.bad_selector(1, "projection axes such as `scope.xy` or `world.xz`");
        };
        let mut args = std::mem::take(&mut self.args).into_iter();
        let set = args.next()?;
        let sizes = [args.nth(1)?, args.next()?];
        let rest: Vec<CExpr> = args.collect();
        let (offsets, uw_factor) = match <[CExpr; 3]>::try_from(rest) {
            Ok([a, b, k]) => (Some([a, b]), Some(k)),
            Err(mut rest) if rest.len() == 2 => {
                let b = rest.pop()?;
                (Some([rest.pop()?, b]), None)
            }
            Err(mut rest) => (None, rest.pop()),
        };
        Some(Op::SetupProjection(Box::new(ProjectionSetup {
            set,
            world,
            axes,
            sizes,
            offsets,
            uw_factor,
        })))
    }

    fn normalize_uv(&mut self) -> Option<Op> {
        self.arity(3, 3)?;
        let mode = match self.word(1) {
            Some("uv") => UvNormalization::Each,
            Some("uvUniform") => UvNormalization::Uniform,
            Some("u") => UvNormalization::U,
            Some("v") => UvNormalization::V,
            _ => return self.bad_selector(1, "`uv`, `uvUniform`, `u` or `v`"),
        };
        match self.word(2) {
            Some("collectiveAllFaces") => {}
            Some("separatePerFace") => self.warn_once(
                "`normalizeUV(…, separatePerFace)` normalizes the faces of a shape together (as `collectiveAllFaces`): exact for shapes of one face"
                    .into(),
            ),
            _ => return self.bad_selector(2, "`separatePerFace` or `collectiveAllFaces`"),
        }
        self.args.truncate(1);
        Some(Op::EditUv(
            UvEdit::Normalize(mode),
            std::mem::take(&mut self.args),
        ))
    }

    fn edit_uv(&mut self, edit: UvEdit, count: usize) -> Option<Op> {
        self.arity(count, count)?;
        Some(Op::EditUv(edit, std::mem::take(&mut self.args)))
    }

    fn extrude(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let world_up = if self.args.len() == 2 {
            match self.word(0) {
                Some("world.up" | "world.up.flatTop" | "world.y") => true,
                Some("face.normal" | "vertex.normal") => false,
                _ => {
                    return self.bad_selector(0, "`world.up`, `world.up.flatTop` or `face.normal`");
                }
            }
        } else {
            false
        };
        Some(Op::Extrude {
            world_up,
            distance: self.args.pop()?,
        })
    }

    fn rotate(&mut self) -> Option<Op> {
        let about_center = match self.args.len() {
            3 => false,
            4 => match self.word(0) {
                Some("scopeCenter") => true,
                Some("scopeOrigin") => false,
                _ => return self.bad_selector(0, "`scopeCenter` or `scopeOrigin`"),
            },
            _ => return self.wrong_arity(),
        };
        let z = self.args.pop()?;
        let y = self.args.pop()?;
        let x = self.args.pop()?;
        Some(Op::Rotate {
            about_center,
            degrees: [x, y, z],
        })
    }

    fn axes_selector(&mut self) -> Option<[bool; 3]> {
        self.arity(1, 1)?;
        let word = self.word(0).map(str::to_owned);
        match word.as_deref() {
            Some(w) if !w.is_empty() && w.chars().all(|ch| "xyz".contains(ch)) => {
                Some([w.contains('x'), w.contains('y'), w.contains('z')])
            }
            _ => {
                self.bad_selector(0, "axes such as `x`, `xz` or `xyz`");
                None
            }
        }
    }

    fn align(&mut self) -> Option<Op> {
        self.arity(0, 1)?;
        if self.args.is_empty() {
            return Some(Op::AlignScopeToAxes(None));
        }
        match self.word(0) {
            Some("x" | "world.x") => Some(Op::AlignScopeToAxes(Some(0))),
            Some("y" | "world.y") => Some(Op::AlignScopeToAxes(Some(1))),
            Some("z" | "world.z") => Some(Op::AlignScopeToAxes(Some(2))),
            Some("world.xyz" | "xyz") => Some(Op::AlignScopeToAxes(None)),
            _ => self.bad_selector(0, "`x`, `y`, `z` or `world.xyz`"),
        }
    }

    fn insert(&mut self) -> Option<Op> {
        self.arity(1, 4)?;
        let mut placement = Placement::default();
        if self.args.len() > 1 {
            placement.z_up = match self.word(1) {
                Some("yUp") => false,
                Some("zUp") => true,
                _ => return self.bad_selector(1, "the asset's up axis, `yUp` or `zUp`"),
            };
        }
        if self.args.len() > 2 {
            placement.fit = match self.word(2) {
                Some("alignSizeAndPosition") => InsertFit::Align,
                Some("keepSizeAndPosition") => InsertFit::Keep,
                Some("keepSizeAlignPosition") => InsertFit::KeepSize,
                _ => {
                    return self.bad_selector(
                        2,
                        "`alignSizeAndPosition`, `keepSizeAndPosition` or `keepSizeAlignPosition`",
                    );
                }
            };
        }
        // Shapegram's meshes need no numerical cleanup, so both choices insert alike.
        if self.args.len() > 3 && !matches!(self.word(3), Some("numericalCleanup" | "noCleanup")) {
            return self.bad_selector(3, "`numericalCleanup` or `noCleanup`");
        }
        Some(Op::Insert(self.args.swap_remove(0), placement))
    }

    /// A `primitive…(…)` call with one of the argument counts its forms take.
    fn primitive(&mut self, kind: Primitive, forms: &[usize]) -> Option<Op> {
        if !forms.contains(&self.args.len()) {
            return self.wrong_arity();
        }
        Some(Op::Primitive(kind, std::mem::take(&mut self.args)))
    }

    fn split(&mut self, by_area: bool) -> Option<Op> {
        self.arity(1, 5)?;
        let axis = match self.word(0) {
            Some("x") => 0,
            Some("y") => 1,
            Some("z") => 2,
            Some("u") if !by_area => return self.uv_split(0),
            Some("v") if !by_area => return self.uv_split(1),
            _ => return self.bad_selector(0, "the split axis `x`, `y` or `z`"),
        };
        let mut adjust = true;
        let mut snap = None;
        let mut joints = SplitJoints::Auto;
        let mut i = 1;
        while i < self.args.len() {
            match self.word(i) {
                Some("adjust") if snap.is_none() => adjust = true,
                Some("noAdjust") if snap.is_none() => adjust = false,
                Some("sequential") if snap.is_none() => {
                    joints = SplitJoints::Sequential;
                    self.c.kinematic = true;
                }
                Some("parallel") if snap.is_none() => {
                    joints = SplitJoints::Parallel;
                    self.c.kinematic = true;
                }
                Some("snap") if snap.is_none() => {
                    let tag = self.args.get(i + 1).cloned();
                    i += usize::from(tag.is_some());
                    snap = Some(tag);
                    self.c.uses.context = true;
                }
                _ => {
                    return self.bad_selector(
                        i,
                        "`adjust`, `noAdjust`, `sequential`, `parallel` or `snap`",
                    );
                }
            }
            i += 1;
        }
        if by_area && (snap.is_some() || joints != SplitJoints::Auto) {
            self.error("`splitArea` takes `adjust` or `noAdjust` only".into());
            return None;
        }
        let Some(block) = &self.call.block else {
            let name = &self.call.name.name;
            self.error(format!("`{name}` needs a `{{ size : … }}` block"));
            return None;
        };
        let block = split_block(self.c, block, self.params)?;
        Some(Op::Split {
            axis,
            by_area,
            adjust,
            snap,
            joints,
            block,
        })
    }

    /// `scatter(domain, n, uniform | gaussian [, mean [, stddev]]) { … }`.
    fn scatter(&mut self) -> Option<Op> {
        self.arity(3, 5)?;
        let domain = match self.word(0) {
            Some("surface") => ScatterDomain::Surface,
            Some("volume") => ScatterDomain::Volume,
            Some("scope") => ScatterDomain::Scope,
            _ => return self.bad_selector(0, "`surface`, `volume` or `scope`"),
        };
        let count = self.args.len();
        let gaussian = match self.word(2) {
            Some("uniform") if count == 3 => false,
            Some("gaussian") => true,
            Some("uniform") => return self.bad_selector(3, "nothing after `uniform`"),
            _ => return self.bad_selector(2, "`uniform` or `gaussian`"),
        };
        let mean = if self.args.len() > 3 {
            let at = match self.word(3) {
                Some("center") => [0.5, 0.5, 0.5],
                Some("front") => [0.5, 0.5, 1.0],
                Some("back") => [0.5, 0.5, 0.0],
                Some("left") => [0.0, 0.5, 0.5],
                Some("right") => [1.0, 0.5, 0.5],
                Some("top") => [0.5, 1.0, 0.5],
                Some("bottom") => [0.5, 0.0, 0.5],
                _ => {
                    return self.bad_selector(
                        3,
                        "`center`, `front`, `back`, `left`, `right`, `top` or `bottom`",
                    );
                }
            };
            Some(at)
        } else {
            None
        };
        let stddev = (self.args.len() == 5).then(|| self.args.pop()).flatten();
        let Some(block) = &self.call.block else {
            self.error("`scatter` needs a `{ … }` block with what to do at each point".into());
            return None;
        };
        let [BlockEntry::Part { body, .. }] = block.entries.as_slice() else {
            self.error("`scatter` takes one body in its block: `{ operations }`".into());
            return None;
        };
        let body = self.c.stmts(body, self.params);
        Some(Op::Scatter(Box::new(ScatterSpec {
            domain,
            count: self.args.swap_remove(1),
            gaussian: gaussian.then(|| (mean.unwrap_or([0.5; 3]), stddev)),
            body,
        })))
    }

    /// `split(u | v, uvSpace | unitSpace, uvSet) { … }`.
    fn uv_split(&mut self, coordinate: usize) -> Option<Op> {
        if self.args.len() != 3 {
            return self.wrong_arity();
        }
        let metres = match self.word(1) {
            Some("uvSpace") => false,
            Some("unitSpace") => true,
            _ => return self.bad_selector(1, "`uvSpace` or `unitSpace`"),
        };
        let Some(block) = &self.call.block else {
            self.error("`split` needs a `{ size : … }` block".into());
            return None;
        };
        let block = split_block(self.c, block, self.params)?;
        Some(Op::UvSplit {
            coordinate,
            metres,
            set: self.args.pop()?,
            block,
        })
    }

    /// `rotationLimits(axis, min, max)` and `translationLimits(axis, min, max)`.
    fn joint_limits(&mut self, rotation: bool) -> Option<Op> {
        self.c.kinematic = true;
        self.arity(3, 3)?;
        let axis = match self.word(0) {
            Some("x") => 0,
            Some("y") => 1,
            Some("z") => 2,
            _ => return self.bad_selector(0, "the joint axis `x`, `y` or `z`"),
        };
        let max = self.args.pop()?;
        let min = self.args.pop()?;
        Some(Op::JointLimits {
            rotation,
            axis,
            min,
            max,
        })
    }

    /// `snap(x)`, `snap(xy, "tag")`, Müller's `Snap("X")`.
    fn snap(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let word = self.word(0).map(str::to_ascii_lowercase);
        let mut axes = [false; 3];
        let valid = word.as_deref().is_some_and(|w| {
            !w.is_empty()
                && w.chars().all(|c| match c {
                    'x' | 'y' | 'z' => {
                        axes[c as usize - 'x' as usize] = true;
                        true
                    }
                    _ => false,
                })
        });
        if !valid {
            return self.bad_selector(0, "the axes to snap to: `x`, `y`, `z` or a mix like `xz`");
        }
        Some(Op::Snap {
            axes,
            tag: self.args.get(1).cloned(),
        })
    }

    fn comp(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let kind = match self.word(0) {
            Some("f") => CompKind::Faces,
            Some("e") => CompKind::Edges,
            Some("fe") => CompKind::FaceEdges,
            Some("v") => CompKind::Vertices,
            Some(other) => {
                let other = other.to_owned();
                self.warn_once(format!("`comp({other})` is not supported yet: skipped"));
                return Some(Op::Ignored);
            }
            None => return self.bad_selector(0, "`f`, `e`, `fe` or `v`"),
        };
        let Some(block) = &self.call.block else {
            self.error("`comp` needs a `{ selector : … }` block".into());
            return None;
        };
        let mut entries = Vec::new();
        for entry in &block.entries {
            match entry {
                BlockEntry::Part {
                    key,
                    merge,
                    body,
                    span,
                } => {
                    let selector = comp_selector(self.c, key, *span);
                    entries.push(CompEntry {
                        selector,
                        merge: *merge,
                        body: self.c.stmts(body, self.params),
                    });
                }
                BlockEntry::Group(group) => {
                    self.c.report(Diagnostic::error(
                        "component splits take `selector : …` entries, not groups",
                        group.span,
                    ));
                    return None;
                }
            }
        }
        Some(Op::Comp { kind, entries })
    }

    fn setback(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let blocks = self.setback_block("setback", false)?;
        Some(Op::Setback {
            depths: Depths::Selected(self.args.pop()?),
            entries: blocks.0,
            shape: None,
            remainder: blocks.2,
        })
    }

    fn shape_luo(&mut self, classes: &[FaceClass]) -> Option<Op> {
        self.arity(classes.len(), classes.len())?;
        let name = self.call.name.name.clone();
        let (_, shape, remainder) = self.setback_block(&name, true)?;
        let depths = classes.iter().copied().zip(self.args.drain(..)).collect();
        Some(Op::Setback {
            depths: Depths::ByClass(depths),
            entries: Vec::new(),
            shape,
            remainder,
        })
    }

    /// The block of a setback operation: edge entries (setback), or `shape` (shapeL/U/O), and
    /// `remainder`.
    #[allow(clippy::type_complexity)]
    fn setback_block(
        &mut self,
        name: &str,
        luo: bool,
    ) -> Option<(
        Vec<CompEntry>,
        Option<(bool, Vec<CStmt>)>,
        Option<(bool, Vec<CStmt>)>,
    )> {
        let Some(block) = &self.call.block else {
            let first = if luo { "shape" } else { "selector" };
            self.error(format!(
                "`{name}` needs a `{{ {first} : … | remainder : … }}` block"
            ));
            return None;
        };
        let (mut entries, mut shape, mut remainder) = (Vec::new(), None, None);
        for entry in &block.entries {
            let BlockEntry::Part {
                key,
                merge,
                body,
                span,
            } = entry
            else {
                self.error(format!("`{name}` takes `selector : …` entries, not groups"));
                return None;
            };
            let body = self.c.stmts(body, self.params);
            match &key.kind {
                ast::ExprKind::Name(n) if n == "remainder" => remainder = Some((*merge, body)),
                ast::ExprKind::Name(n) if luo && n == "shape" => shape = Some((*merge, body)),
                _ if luo => {
                    self.c.report(Diagnostic::error(
                        format!("`{name}` selects `shape` or `remainder`"),
                        *span,
                    ));
                    return None;
                }
                _ => entries.push(CompEntry {
                    selector: edge_selector(self.c, key, *span),
                    merge: *merge,
                    body,
                }),
            }
        }
        Some((entries, shape, remainder))
    }

    fn set(&mut self) -> Option<Op> {
        self.arity(2, 2)?;
        let value = self.args.pop()?;
        let target = self.args.pop()?;
        self.words.push(0);
        let name = match &target.kind {
            CKind::Attr(i) => return Some(Op::Set(SetTarget::Attr(*i), value)),
            CKind::GoalAttr(i, _) => return Some(Op::Set(SetTarget::Goal(*i), value)),
            CKind::Selector(name) => name.clone(),
            CKind::Query(crate::builtins::Query::ScopeOrigin(i)) => {
                return Some(Op::Set(SetTarget::ScopeOrigin(*i), value));
            }
            CKind::Query(crate::builtins::Query::ScopeSize(i)) => {
                return Some(Op::Set(SetTarget::ScopeSize(*i), value));
            }
            CKind::Query(_) => {
                self.c.report(
                    Diagnostic::error("`set` cannot write this shape attribute", target.span)
                        .with_hint(
                            "`set` writes attributes, `scope.tx`…`scope.sz`, `material.*` and `trim.*`",
                        ),
                );
                return None;
            }
            _ => {
                self.c.report(
                    Diagnostic::error("`set` needs an attribute name", target.span)
                        .with_hint("declare it with `attr name = …`"),
                );
                return None;
            }
        };
        let target = match name.as_str() {
            "material.color" => SetTarget::Color(None),
            "material.color.r" => SetTarget::Color(Some(0)),
            "material.color.g" => SetTarget::Color(Some(1)),
            "material.color.b" => SetTarget::Color(Some(2)),
            "material.opacity" | "material.color.a" => SetTarget::Color(Some(3)),
            "material.color.rgb" => SetTarget::Color(None),
            "material.name" => SetTarget::MaterialName,
            // Every material is written as a PBR material, whichever shader CityEngine would
            // draw it with.
            "material.shader" => SetTarget::Ignored,
            n if n
                .strip_prefix("material.")
                .and_then(texturing::FinishAttr::from_name)
                .is_some() =>
            {
                SetTarget::Finish(
                    n.strip_prefix("material.")
                        .and_then(texturing::FinishAttr::from_name)?,
                )
            }
            n if n
                .strip_prefix("material.")
                .and_then(texturing::layer)
                .is_some() =>
            {
                SetTarget::Map(n.strip_prefix("material.").and_then(texturing::layer)?)
            }
            "trim.horizontal" => SetTarget::Trim(true),
            "trim.vertical" => SetTarget::Trim(false),
            n if n.starts_with("material.") || n.starts_with("trim.") => {
                self.warn_once(format!("`set({n}, …)` is not supported yet: ignored"));
                SetTarget::Ignored
            }
            n if n.contains('.') => {
                // `style.attr` and `import.attr` name attributes of imported rule files.
                self.warn_once(format!(
                    "`set({n}, …)` sets an attribute of an imported file: imports are not supported yet, ignored"
                ));
                SetTarget::Ignored
            }
            n => {
                let mut d = Diagnostic::error(format!("unknown attribute `{n}`"), target.span)
                    .with_hint("declare it with `attr name = …` before setting it");
                if let Some(close) = shapegram_syntax::suggest(n, self.c.attr_names()) {
                    d = d.with_hint(format!("did you mean `{close}`?"));
                }
                self.c.report(d);
                return None;
            }
        };
        Some(Op::Set(target, value))
    }

    fn sync(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let Some(word) = self.word(0).map(str::to_owned) else {
            return self.bad_selector(0, "the name of a synchronization");
        };
        let span = self.args[0].span;
        let Some(scope) = &self.c.goal else {
            self.c.report(
                Diagnostic::error(
                    "`sync` synchronizes shapes of goal grammars",
                    self.call.span,
                )
                .with_hint("in the main syntax, shapes made by one rule derive alike already"),
            );
            return None;
        };
        if let Some(id) = scope.sync(&word) {
            return Some(Op::Sync(id));
        }
        let mut d = Diagnostic::error(format!("unknown synchronization `{word}`"), span).with_hint(
            format!("declare it: `sync {word}` (`var {word} = new Synchronize();`)"),
        );
        if let Some(close) = shapegram_syntax::suggest(&word, scope.sync_names()) {
            d = d.with_hint(format!("did you mean `{close}`?"));
        }
        self.c.report(d);
        None
    }

    fn offset(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let keep = if self.args.len() == 2 {
            match self.word(1) {
                Some("inside") => OffsetKeep::Inside,
                Some("border") => OffsetKeep::Border,
                Some("all") => OffsetKeep::All,
                _ => return self.bad_selector(1, "`inside`, `border` or `all`"),
            }
        } else {
            OffsetKeep::All
        };
        self.args.truncate(1);
        Some(Op::Offset {
            distance: self.args.pop()?,
            keep,
        })
    }

    fn align_to_geometry(&mut self) -> Option<Op> {
        self.arity(2, 3)?;
        if self.args.len() == 2 {
            // The older two-argument form `(upAxis, edgeIndex)` real files still use: an edge of face 0.
            let span = self.args[1].span;
            let first_face = CExpr {
                kind: CKind::Value(Value::Number(0.0)),
                span,
            };
            self.args.insert(1, first_face);
        }
        let z_up = match self.word(0) {
            Some("yUp") => false,
            Some("zUp") => true,
            _ => return self.bad_selector(0, "`yUp` or `zUp` (`xUp` is not supported)"),
        };
        let is_word = |a: &CExpr| matches!(a.kind, CKind::Selector(_));
        let (face_word, edge_word) = (
            self.word(1).map(str::to_owned),
            self.word(2).map(str::to_owned),
        );
        let edge = match edge_word.as_deref() {
            Some("world.lowest") => EdgeChoice::Lowest,
            Some("longest") => EdgeChoice::Longest,
            _ if is_word(&self.args[2]) => {
                return self.bad_selector(2, "an edge index, `world.lowest` or `longest`");
            }
            _ => EdgeChoice::Index(self.args.pop()?),
        };
        let face = match face_word.as_deref() {
            Some("world.lowest") => FaceChoice::Lowest,
            Some("largest") => FaceChoice::Largest,
            Some("any") if !matches!(edge, EdgeChoice::Index(_)) => FaceChoice::Any,
            Some("any") => {
                return self.bad_selector(
                    1,
                    "a face index, `world.lowest` or `largest` (`any` needs an edge selector)",
                );
            }
            _ if is_word(&self.args[1]) => {
                return self.bad_selector(1, "a face index, `world.lowest`, `largest` or `any`");
            }
            _ => FaceChoice::Index(self.args.swap_remove(1)),
        };
        Some(Op::AlignScopeToGeometry { z_up, face, edge })
    }

    fn align_to_bbox(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let axes: Vec<usize> = self
            .word(0)
            .map(|w| w.chars().filter_map(|c| "xyz".find(c)).collect())
            .unwrap_or_default();
        match axes[..] {
            [first, second] if first != second && self.word(0).is_some_and(|w| w.len() == 2) => {
                Some(Op::AlignScopeToGeometryBBox { first, second })
            }
            _ => self.bad_selector(0, "two axes: `xy`, `yx`, `xz`, `zx`, `yz` or `zy`"),
        }
    }

    fn implicit(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        if let Some(kind) = self.word(0).and_then(ImplicitKind::from_name) {
            return Some(Op::Implicit(kind));
        }
        // Anything else but a bare word is the path of an implicit grammar.
        if matches!(self.args[0].kind, CKind::Selector(_)) {
            return self.bad_selector(
                0,
                "a solid: `box`, `sphere`, `cylinder`, `cone`, `pyramid`, `torus` or `capsule`, or the path of a .cave file",
            );
        }
        Some(Op::ImplicitFile(self.args.pop()?))
    }

    fn csg(&mut self) -> Option<Op> {
        self.arity(2, 3)?;
        let kinds = [
            CsgKind::Union,
            CsgKind::Subtract,
            CsgKind::Intersect,
            CsgKind::Morph,
        ];
        let word = self.word(1);
        let Some(kind) = kinds.into_iter().find(|k| word == Some(k.name())) else {
            return self.bad_selector(1, "`union`, `subtract`, `intersect` or `morph`");
        };
        if kind == CsgKind::Morph && self.args.len() < 3 {
            return self.wrong_arity();
        }
        let amount = (self.args.len() == 3).then(|| self.args.pop()).flatten();
        Some(Op::Csg {
            kind,
            group: self.args.swap_remove(0),
            amount,
        })
    }

    /// `taper(axis, factor)`, `twist(axis, degrees)`, `shear(axis, toward, amount)`; CGA's own
    /// `taper(height)`, which takes one number, is the pyramid over the first face.
    fn deform(&mut self, kind: DeformKind) -> Option<Op> {
        let name = kind.name();
        if kind == DeformKind::Taper
            && self.args.len() == 1
            && !matches!(self.args[0].kind, CKind::Selector(_))
        {
            return Some(Op::Pyramid(self.args.pop()?));
        }
        let count = if matches!(kind, DeformKind::Shear { .. }) {
            3
        } else {
            2
        };
        self.arity(count, count)?;
        let axis = self.axis_word(0, name)?;
        let kind = match kind {
            DeformKind::Shear { .. } => {
                let toward = self.axis_word(1, name)?;
                if toward == axis {
                    let span = self.args[1].span;
                    let word = ["x", "y", "z"][axis];
                    self.c.report(
                        Diagnostic::error(
                            format!(
                                "`shear` needs two different axes, not `{word}` twice: points move \
                                 along the second by their position along the first"
                            ),
                            span,
                        )
                        .with_label("in `shear`"),
                    );
                    return None;
                }
                DeformKind::Shear { toward }
            }
            other => other,
        };
        Some(Op::Deform {
            kind,
            axis,
            amount: self.args.pop()?,
        })
    }

    /// Argument `i` as a scope axis, `x`, `y` or `z`; an error in `op` for anything else.
    fn axis_word(&mut self, i: usize, op: &str) -> Option<usize> {
        let axis = match self.word(i) {
            Some("x") => Some(0),
            Some("y") => Some(1),
            Some("z") => Some(2),
            _ => None,
        };
        if axis.is_none() {
            let span = self.args.get(i).map_or(self.call.span, |a| a.span);
            self.c.report(
                Diagnostic::error("expected the axis `x`, `y` or `z`", span)
                    .with_label(format!("in `{op}`")),
            );
        }
        axis
    }

    fn roof(&mut self, kind: RoofKind) -> Option<Op> {
        let by_height = match self.args.first().map(|a| &a.kind) {
            Some(CKind::Selector(w)) if w == "byAngle" => Some(false),
            Some(CKind::Selector(w)) if w == "byHeight" => Some(true),
            _ => None,
        };
        if by_height.is_some() {
            self.words.push(0);
            self.args.remove(0);
        }
        // The angle or height, then: overhangX, overhangY, even, index (gable); overhang, even
        // (hip); index (shed). CGA's byHeight gable takes no index.
        let max = match kind {
            RoofKind::Gable if by_height.is_some() => 4,
            RoofKind::Gable => 5,
            RoofKind::Hip => 3,
            RoofKind::Pyramid | RoofKind::Ridge => 1,
            RoofKind::Shed => 2,
        };
        self.arity(1, max)?;
        Some(Op::Roof {
            kind,
            by_height: by_height == Some(true),
            params: std::mem::take(&mut self.args),
        })
    }
}

fn split_block(c: &mut Compiler, block: &ast::Block, params: &[ast::Ident]) -> Option<SplitBlock> {
    let mut entries = Vec::with_capacity(block.entries.len());
    for entry in &block.entries {
        entries.push(match entry {
            BlockEntry::Part { key, body, .. } => SplitEntry::Part {
                size: c.expr(key, params),
                body: c.stmts(body, params),
            },
            BlockEntry::Group(group) => SplitEntry::Group(split_block(c, group, params)?),
        });
    }
    Some(SplitBlock {
        entries,
        repeat: block.repeat,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_implemented_operation_has_a_signature_named_after_it() {
        for name in IMPLEMENTED {
            let signature = signature(name).unwrap_or_else(|| panic!("no signature for {name}"));
            let shown = match *name {
                "insert" => "i",
                "tag" => "label",
                "Snap" => "snap",
                "offsetUV" => "translateUV",
                other => other,
            };
            assert!(
                signature.starts_with(&format!("{shown}(")),
                "{name}: {signature}"
            );
        }
        assert_eq!(SIGNATURES.len(), IMPLEMENTED.len());
        let listed: Vec<_> = operations().collect();
        assert_eq!(
            listed.len(),
            IMPLEMENTED.len() + VISUAL_ONLY.len() + UNSUPPORTED.len()
        );
        assert!(listed.contains(&(
            "extrude",
            Support::Implemented,
            Some("extrude([world.up | face.normal,] distance)")
        )));
    }
}
