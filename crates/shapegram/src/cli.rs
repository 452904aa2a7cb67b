//! The command line: clap types only, no behaviour.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Procedural modelling with shape grammars.
#[derive(Debug, Parser)]
#[command(
    name = "shapegram",
    version,
    about = "Procedural modelling with shape grammars",
    long_about = "Procedural modelling with shape grammars.\n\n\
        Builds models from primitives (and, soon, grammars) and writes them as GLB, OBJ (+MTL)\n\
        or binary STL; the extension of the output file picks the format.",
    after_help = "Examples:\n  \
        shapegram primitive box --size 10,20,5 -o box.glb\n  \
        shapegram info box.glb\n  \
        shapegram info --json box.glb",
    subcommand_required = true,
    arg_required_else_help = true
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write one primitive shape to a GLB, OBJ or STL file
    #[command(
        long_about = "Write one primitive shape to a GLB, OBJ or STL file.\n\n\
            Every primitive fills the box [0, size] with y up; quad and footprint lie flat in the\n\
            xz-plane at y = 0, facing up. Curved shapes are polyhedra inscribed in the smooth\n\
            ones. A summary line goes to stderr unless -q is given.",
        after_help = "Examples:\n  \
            shapegram primitive box --size 10,20,5 -o box.glb\n  \
            shapegram primitive cylinder --size 2,3,2 --sides 64 --color '#3a6ea5' -o column.obj\n  \
            shapegram primitive sphere --segments 64 --rings 32 -o ball.stl\n  \
            shapegram primitive quad --size 20,0,30 -o lot.glb\n  \
            shapegram primitive footprint --points \"0,0 4,0 4,1 1,1 1,3 0,3\" -o l-shape.glb"
    )]
    Primitive(PrimitiveArgs),
    /// Print counts, bounds, area, volume and watertightness of a GLB, OBJ or STL file
    #[command(
        long_about = "Print counts, bounds, area, volume and watertightness of a GLB, OBJ or STL \
            file.\n\n\
            Each part is welded first (vertices closer than 1e-9 × the bounds diagonal\n\
            merge), so files that store one vertex per corner (STL, flat-shaded glTF) report\n\
            their real connectivity.\n\n\
            The volume is the signed volume enclosed by the faces. It is meaningful only for\n\
            watertight meshes with outward-facing normals (negative means inside out). A mesh is\n\
            watertight when every edge is shared by exactly two faces running along it in\n\
            opposite directions; the edge counts say what is wrong otherwise.\n\n\
            Triangles with an area below 1e-12 × diagonal² count as degenerate.",
        after_help = "Examples:\n  \
            shapegram info box.glb\n  \
            shapegram info --json model.stl | jq .volume"
    )]
    Info(InfoArgs),
    /// Derive a model from a grammar (not available yet)
    #[command(long_about = "Derive a model from a grammar (not available yet).\n\n\
            Reserved: the grammar engine lands with the grammar-language issue. Until then this\n\
            command exits with code 2.")]
    Derive(DeriveArgs),
}

/// Arguments of `shapegram primitive`.
#[derive(Debug, Args)]
pub struct PrimitiveArgs {
    /// The shape to build
    #[arg(value_enum)]
    pub kind: Kind,
    /// Size of the box the shape fills, X,Y,Z with y up (quad uses X and Z) [default: 1,1,1]
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub size: Option<String>,
    /// Sides around a cylinder or cone [default: 32]
    #[arg(long, value_name = "N")]
    pub sides: Option<u32>,
    /// Segments around a sphere [default: 32]
    #[arg(long, value_name = "N")]
    pub segments: Option<u32>,
    /// Rings from pole to pole of a sphere [default: 16]
    #[arg(long, value_name = "N")]
    pub rings: Option<u32>,
    /// Corners of a footprint in the xz-plane, at least three, in either winding
    #[arg(long, value_name = "\"X,Z X,Z ...\"", allow_hyphen_values = true)]
    pub points: Option<String>,
    /// Surface colour as '#rrggbb' (also #rgb or #rrggbbaa) [default: #cccccc]
    #[arg(long, value_name = "HEX")]
    pub color: Option<String>,
    /// Keep parts as separate named groups (OBJ groups, glTF nodes) instead of merging by colour
    #[arg(long)]
    pub group: bool,
    /// Output file; its extension picks the format: .glb, .obj (writes a .mtl beside it) or .stl
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Do not print the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
}

/// The primitives `shapegram primitive` can build.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Kind {
    /// A box filling the whole size
    #[value(name = "box")]
    Cuboid,
    /// A flat rectangle X × Z at y = 0, facing up
    Quad,
    /// A flat polygon at y = 0 from --points, facing up
    Footprint,
    /// An upright prism with --sides around the ellipse inscribed in the box
    Cylinder,
    /// An upright cone with --sides, apex at the top centre
    Cone,
    /// A UV sphere (an ellipsoid for unequal sizes) with --segments and --rings
    Sphere,
    /// A pyramid over the full base, apex at the top centre
    Pyramid,
}

impl Kind {
    /// The name on the command line, also used as the part name in the written file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Cuboid => "box",
            Self::Quad => "quad",
            Self::Footprint => "footprint",
            Self::Cylinder => "cylinder",
            Self::Cone => "cone",
            Self::Sphere => "sphere",
            Self::Pyramid => "pyramid",
        }
    }
}

/// Arguments of `shapegram info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The GLB, OBJ or STL file to inspect
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Print one JSON object instead of text
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `shapegram derive`, reserved for the grammar engine.
#[derive(Debug, Args)]
pub struct DeriveArgs {
    /// The grammar file
    #[arg(value_name = "GRAMMAR")]
    pub grammar: PathBuf,
    /// Output file; its extension picks the format: .glb, .obj or .stl
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::Cli;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
