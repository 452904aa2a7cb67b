//! Built-in functions and shape queries of the expression language.

use crate::arrays::ArrayFn;
use crate::asset_queries::AssetFn;
use crate::colors::ColorFn;
use crate::tag_queries::TagFn;
use crate::text::Text;
use crate::uv_queries::UvQuery;

/// Every built-in function's name with its signature (`None` for the functions of one number,
/// `sin`, `floor`, …), for editors to offer.
pub fn functions() -> impl Iterator<Item = (&'static str, Option<&'static str>)> {
    Builtin::all_names().filter_map(|name| {
        let signature = Builtin::from_name(name)?.signature();
        Some((name, (signature != "f(number)").then_some(signature)))
    })
}

/// Every shape query's name (`scope.sx`, `split.index`, …).
pub fn queries() -> impl Iterator<Item = &'static str> {
    Query::NAMES.iter().copied()
}

/// A built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Builtin {
    Rand,
    P,
    Floor,
    Ceil,
    Round,
    Rint,
    IsNan,
    IsInf,
    Abs,
    Min,
    Max,
    Sqrt,
    Pow,
    Exp,
    Ln,
    Log10,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Clamp,
    Str,
    Float,
    Bool,
    Len,
    Inside,
    Overlaps,
    Touches,
    Occ,
    IsRectangular,
    IsConcave,
    IsPlanar,
    IsClosedSurface,
    EdgeCount,
    BoundaryLength,
    Height,
    ReadStringTable,
    ReadFloatTable,
    Rows,
    Columns,
    FileSearch,
    FilesSearch,
    FileRandom,
    FileExists,
    ReadTextFile,
    Angle,
    ContextCount,
    ContextCompare,
    MinimumDistance,
    Print,
    Convert,
    /// An asset or image function.
    Asset(AssetFn),
    ColorRamp,
    Sel,
    GeoCoord,
    EdgeAttrFloat,
    EdgeAttrString,
    EdgeAttrBool,
    IsOriented,
    /// `geometry.isInstanced()`: whether the geometry is still the asset `i()` inserted.
    IsInstanced,
    /// `geometry.area(selector)`; without arguments `geometry.area` is a [`Query`].
    AreaOf,
    GetMaterial,
    ReadMaterial,
    /// A string or string-list function.
    Text(Text),
    /// An array function or `isNull`.
    Array(ArrayFn),
    /// A colour conversion.
    Color(ColorFn),
    /// A uv query (`geometry.uMin` and the others).
    Uv(UvQuery),
    /// A tag function (`geometry.tags`, `geometry.hasTags`).
    Tags(TagFn),
}

impl Builtin {
    /// Every built-in's name, in the order of [`Builtin::ALL`].
    pub const NAMES: &'static [&'static str] = &[
        "rand",
        "p",
        "floor",
        "ceil",
        "round",
        "rint",
        "isnan",
        "isinf",
        "abs",
        "min",
        "max",
        "sqrt",
        "pow",
        "exp",
        "ln",
        "log10",
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "atan2",
        "clamp",
        "str",
        "float",
        "bool",
        "size",
        "inside",
        "overlaps",
        "touches",
        "occ",
        "geometry.isRectangular",
        "geometry.isConcave",
        "geometry.isPlanar",
        "geometry.isClosedSurface",
        "geometry.nEdges",
        "geometry.boundaryLength",
        "geometry.height",
        "readStringTable",
        "readFloatTable",
        "nRows",
        "nColumns",
        "fileSearch",
        "filesSearch",
        "fileRandom",
        "fileExists",
        "readTextFile",
        "geometry.angle",
        "contextCount",
        "contextCompare",
        "minimumDistance",
        "print",
        "convert",
        "colorRamp",
        "sel",
        "getGeoCoord",
        "edgeAttr.getFloat",
        "edgeAttr.getString",
        "edgeAttr.getBool",
        "geometry.isOriented",
        "geometry.isInstanced",
        "geometry.area",
        "getMaterial",
        "readMaterial",
    ];

    const ALL: [Builtin; 65] = [
        Self::Rand,
        Self::P,
        Self::Floor,
        Self::Ceil,
        Self::Round,
        Self::Rint,
        Self::IsNan,
        Self::IsInf,
        Self::Abs,
        Self::Min,
        Self::Max,
        Self::Sqrt,
        Self::Pow,
        Self::Exp,
        Self::Ln,
        Self::Log10,
        Self::Sin,
        Self::Cos,
        Self::Tan,
        Self::Asin,
        Self::Acos,
        Self::Atan,
        Self::Atan2,
        Self::Clamp,
        Self::Str,
        Self::Float,
        Self::Bool,
        Self::Len,
        Self::Inside,
        Self::Overlaps,
        Self::Touches,
        Self::Occ,
        Self::IsRectangular,
        Self::IsConcave,
        Self::IsPlanar,
        Self::IsClosedSurface,
        Self::EdgeCount,
        Self::BoundaryLength,
        Self::Height,
        Self::ReadStringTable,
        Self::ReadFloatTable,
        Self::Rows,
        Self::Columns,
        Self::FileSearch,
        Self::FilesSearch,
        Self::FileRandom,
        Self::FileExists,
        Self::ReadTextFile,
        Self::Angle,
        Self::ContextCount,
        Self::ContextCompare,
        Self::MinimumDistance,
        Self::Print,
        Self::Convert,
        Self::ColorRamp,
        Self::Sel,
        Self::GeoCoord,
        Self::EdgeAttrFloat,
        Self::EdgeAttrString,
        Self::EdgeAttrBool,
        Self::IsOriented,
        Self::IsInstanced,
        Self::AreaOf,
        Self::GetMaterial,
        Self::ReadMaterial,
    ];

    /// The built-in with this name.
    pub fn from_name(name: &str) -> Option<Self> {
        // The Müller notation asks `Shape.occ("noparent")` (Sunde writes `Scope.occ`).
        if matches!(name, "Shape.occ" | "Scope.occ") {
            return Some(Self::Occ);
        }
        Self::NAMES
            .iter()
            .position(|&n| n == name)
            .map(|i| Self::ALL[i])
            .or_else(|| Text::from_name(name).map(Self::Text))
            .or_else(|| ArrayFn::from_name(name).map(Self::Array))
            .or_else(|| ColorFn::from_name(name).map(Self::Color))
            .or_else(|| UvQuery::from_name(name).map(Self::Uv))
            .or_else(|| AssetFn::from_name(name).map(Self::Asset))
            .or_else(|| TagFn::from_name(name).map(Self::Tags))
    }

    /// Every built-in's name, the string functions' included.
    pub fn all_names() -> impl Iterator<Item = &'static str> {
        Self::NAMES
            .iter()
            .copied()
            .chain(Text::names())
            .chain(ArrayFn::names())
            .chain(ColorFn::names())
            .chain(UvQuery::names())
            .chain(AssetFn::names())
            .chain(TagFn::names())
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Self::Rand => (0, 2),
            Self::Min | Self::Max | Self::Pow | Self::Atan2 => (2, 2),
            Self::Clamp | Self::ContextCompare => (3, 3),
            Self::Convert => (4, 7),
            Self::Asset(f) => (f.arity(), f.arity()),
            Self::ColorRamp | Self::GetMaterial => (2, 2),
            Self::ContextCount | Self::MinimumDistance => (2, 2),
            Self::Inside | Self::Overlaps | Self::Touches => (0, 2),
            Self::Occ => (0, 1),
            Self::IsConcave
            | Self::IsInstanced
            | Self::IsClosedSurface
            | Self::EdgeCount
            | Self::BoundaryLength
            | Self::Height => (0, 0),
            Self::Text(t) => t.arity(),
            Self::Array(f) => f.arity(),
            Self::Color(f) => (f.arity(), f.arity()),
            Self::Uv(q) => q.arity(),
            Self::Tags(f) => f.arity(),
            _ => (1, 1),
        }
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        match self {
            Self::Rand => "rand() | rand(max) | rand(min, max)",
            Self::P => "p(probability)",
            Self::Min => "min(a, b)",
            Self::Max => "max(a, b)",
            Self::Pow => "pow(base, exponent)",
            Self::Atan2 => "atan2(y, x)",
            Self::Clamp => "clamp(value, min, max)",
            Self::Str => "str(value)",
            Self::Float => "float(value)",
            Self::Bool => "bool(value)",
            Self::Len => "size(array)",
            Self::Inside => "inside([all | intra | inter [, label]])",
            Self::Overlaps => "overlaps([all | intra | inter [, label]])",
            Self::Touches => "touches([all | intra | inter [, label]])",
            Self::Occ => "occ([\"noparent\" | label])",
            Self::IsRectangular => "geometry.isRectangular(tolerance)",
            Self::IsPlanar => "geometry.isPlanar(tolerance)",
            Self::IsConcave => "geometry.isConcave()",
            Self::IsClosedSurface => "geometry.isClosedSurface()",
            Self::EdgeCount => "geometry.nEdges()",
            Self::BoundaryLength => "geometry.boundaryLength()",
            Self::Height => "geometry.height()",
            Self::ReadStringTable => "readStringTable(filePath)",
            Self::ReadFloatTable => "readFloatTable(filePath)",
            Self::Rows => "nRows(table)",
            Self::Columns => "nColumns(table)",
            Self::FileSearch => "fileSearch(query)",
            Self::FilesSearch => "filesSearch(query)",
            Self::FileRandom => "fileRandom(query)",
            Self::FileExists => "fileExists(filePath)",
            Self::ReadTextFile => "readTextFile(filePath)",
            Self::Angle => "geometry.angle(maxSlope | azimuth | zenith)",
            Self::ContextCount => "contextCount(intra | inter | all, label)",
            Self::ContextCompare => {
                "contextCompare(intra | inter | all, label, world.northernmost | …)"
            }
            Self::MinimumDistance => "minimumDistance(intra | inter | all, label)",
            Self::Print => "print(value)",
            Self::ColorRamp => {
                "colorRamp(whiteToBlack | greenToRed | yellowToRed | redToBlue | orangeToBlue | brownToBlue | spectrum, value)"
            }
            Self::Sel => "sel(selString)",
            Self::GeoCoord => "getGeoCoord(x | y | lon | lat)",
            Self::EdgeAttrFloat => "edgeAttr.getFloat(attributeName)",
            Self::EdgeAttrString => "edgeAttr.getString(attributeName)",
            Self::EdgeAttrBool => "edgeAttr.getBool(attributeName)",
            Self::IsOriented => "geometry.isOriented(orientation)",
            Self::IsInstanced => "geometry.isInstanced()",
            Self::AreaOf => "geometry.area() | geometry.area(faceOrientation)",
            Self::GetMaterial => "getMaterial(used | shape | geometry, changed | all)",
            Self::ReadMaterial => "readMaterial(filePath)",
            Self::Convert => {
                "convert(x | y | z, from, to, pos | orient, x, y, z) | convert(from, to, pos | orient, [x, y, z])"
            }
            Self::Text(t) => t.signature(),
            Self::Array(f) => f.signature(),
            Self::Color(f) => f.signature(),
            Self::Uv(q) => q.signature(),
            Self::Asset(f) => f.signature(),
            Self::Tags(f) => f.signature(),
            _ => "f(number)",
        }
    }

    /// Whether the built-in takes bare words as arguments (`inside(intra)`,
    /// `geometry.angle(azimuth)`).
    pub fn takes_words(self) -> bool {
        self.is_context_query()
            || matches!(
                self,
                Self::Angle
                    | Self::Convert
                    | Self::Uv(_)
                    | Self::Asset(_)
                    | Self::Tags(_)
                    | Self::GeoCoord
                    | Self::IsOriented
                    | Self::AreaOf
                    | Self::GetMaterial
            )
    }

    /// Whether the built-in asks about other shapes (occlusion), which makes the rules that
    /// use it wait for the second phase of a derivation.
    pub fn is_context_query(self) -> bool {
        matches!(
            self,
            Self::Inside
                | Self::Overlaps
                | Self::Touches
                | Self::Occ
                | Self::ContextCount
                | Self::ContextCompare
                | Self::MinimumDistance
        )
    }

    /// CGA functions that parse but are not implemented yet: a warning, and an error if reached.
    pub fn is_known_unsupported(name: &str) -> bool {
        const NAMES: &[&str] = &[
            "index",
            "comp",
            "isInside",
            "isOccluded",
            "scope",
            "geometry",
            "colorHSOToHex",
            "item",
            "isect",
            "edgeAttr",
            "infoDebug",
            "trim",
        ];
        // A name that is implemented is never "not supported", whatever the list says.
        NAMES.contains(&name) && Self::from_name(name).is_none()
    }
}

/// A query of the current shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Query {
    ScopeSize(usize),
    ScopeOrigin(usize),
    ScopeRotation(usize),
    SplitIndex,
    SplitTotal,
    CompIndex,
    CompTotal,
    GeometryArea,
    GeometryVolume,
    GeometryVertices,
    GeometryFaces,
    /// Always 0: Shapegram's faces have no holes (lots are read by their outer rings, and no
    /// operation makes a face with a hole).
    GeometryHoles,
    InitialOrigin(usize),
    Seed,
    Depth,
    CompSel,
    /// `initialShape.startRule`: the name of the rule the derivation started from.
    StartRule,
    /// `scope.elevation`: the world height of the scope's origin.
    Elevation,
    /// `initialShape.name`: the name PRT's clients give an initial shape, `shape_<index>`.
    InitialName,
    /// `initialShape.origin.ox/oy/oz`: the Euler angles of the initial shape's object frame.
    InitialRotation(usize),
    /// `getTreeKey`: the shape's rule application in the derivation tree, as `0;2;1;`.
    TreeKey,
}

impl Query {
    /// Every query name.
    pub const NAMES: &'static [&'static str] = &[
        "scope.sx",
        "scope.sy",
        "scope.sz",
        "scope.tx",
        "scope.ty",
        "scope.tz",
        "scope.rx",
        "scope.ry",
        "scope.rz",
        "split.index",
        "split.total",
        "comp.index",
        "comp.total",
        "geometry.area",
        "geometry.volume",
        "geometry.nVertices",
        "geometry.nFaces",
        "initialShape.origin.px",
        "initialShape.origin.py",
        "initialShape.origin.pz",
        "seedian",
        "shape.depth",
        "comp.sel",
        "geometry.nHoles",
        "initialShape.startRule",
        "scope.elevation",
        "initialShape.name",
        "initialShape.origin.ox",
        "initialShape.origin.oy",
        "initialShape.origin.oz",
        "getTreeKey",
    ];

    /// The query with this name.
    pub fn from_name(name: &str) -> Option<Self> {
        let i = Self::NAMES.iter().position(|&n| n == name)?;
        Some(match i {
            0..=2 => Self::ScopeSize(i),
            3..=5 => Self::ScopeOrigin(i - 3),
            6..=8 => Self::ScopeRotation(i - 6),
            9 => Self::SplitIndex,
            10 => Self::SplitTotal,
            11 => Self::CompIndex,
            12 => Self::CompTotal,
            13 => Self::GeometryArea,
            14 => Self::GeometryVolume,
            15 => Self::GeometryVertices,
            16 => Self::GeometryFaces,
            17..=19 => Self::InitialOrigin(i - 17),
            20 => Self::Seed,
            21 => Self::Depth,
            22 => Self::CompSel,
            23 => Self::GeometryHoles,
            24 => Self::StartRule,
            25 => Self::Elevation,
            26 => Self::InitialName,
            27..=29 => Self::InitialRotation(i - 27),
            _ => Self::TreeKey,
        })
    }

    /// Dotted names of CGA queries that are not implemented yet.
    pub fn is_known_unsupported(name: &str) -> bool {
        const PREFIXES: &[&str] = &[
            "scope.",
            "geometry.",
            "comp.",
            "split.",
            "initialShape.",
            "material.",
            "split.",
        ];
        PREFIXES.iter().any(|p| name.starts_with(p))
    }
}
