//! The command line: clap types only, no behaviour.

use std::path::{Path, PathBuf};

use clap::{Args, Parser, Subcommand, ValueEnum};
use shapegram_export::tiles::{Crs, Shard, TileEncoding};
use shapegram_export::{ExportOptions, Format, GlbEncoding};
use shapegram_syntax::Dialect;

/// Procedural modelling with shape grammars.
#[derive(Debug, Parser)]
#[command(
    name = "shapegram",
    version,
    about = "Procedural modelling with shape grammars",
    long_about = "Procedural modelling with shape grammars.\n\n\
        Derives models from CGA-style shape grammars (or builds single primitives) and writes\n\
        them as GLB, OBJ (+MTL) or binary STL; the extension of the output file picks the\n\
        format. `check` reports a grammar's errors and warnings without deriving it.",
    after_help = "Examples:\n  \
        shapegram derive house.cga -o house.glb\n  \
        shapegram derive house.cga --lots parcels.geojson --seed 7 -o street.glb\n  \
        shapegram check rules/*.cga\n  \
        shapegram primitive box --size 10,20,5 -o box.glb\n  \
        shapegram info --json house.glb",
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
    /// Derive a model from a grammar and write it as GLB, OBJ or STL
    #[command(
        long_about = "Derive a model from a grammar and write it as GLB, OBJ or STL.\n\n\
            The grammar is parsed and compiled first; its errors and warnings are printed\n\
            rustc-style on stderr, and any error stops the command (exit code 1). Grammars may be\n\
            written in the main CGA-style syntax, in the notation of Müller et al. 2006 or in\n\
            SGL; the notation is detected from the text unless --dialect names it.\n\n\
            Each initial shape (lot) is a footprint polygon at y = 0, facing up (y is up; x\n\
            and z span the ground). Lots come from --lot and --lots, in that order; without\n\
            either, one default lot of 20 × 30 is used (x from 0 to 20, z from 0 to 30).\n\
            Lots are derived in parallel; the result is the same whatever the number of\n\
            threads (RAYON_NUM_THREADS) and depends only on the grammar, the lots, --seed and\n\
            --attr.\n\n\
            Assets inserted with i(\"path\") (OBJ, GLB or STL), textures and tables are looked\n\
            up as CityEngine does: beside the grammar, then in the project's assets/ folder (the\n\
            nearest folder at or above the grammar's that has one), then in the project. print()\n\
            output goes to stderr as `print: ` lines (also with -q).\n\n\
            A CityEngine rule package (.rpk) is read as it is, without extracting it: its rule\n\
            file (the one PRT runs, or --rule-file), the files that rule file imports and its\n\
            assets all come from the archive, and the start rule is the rule file's @StartRule.\n\
            Without -o nothing is written, which is useful with --stats.\n\n\
            To see how a model came about, --generations N stops after N parallel rewriting\n\
            steps and --at-node N writes the state right after shape N was made (numbered\n\
            from 0), both posed by the model's skeleton (docs/kinematics.md).",
        after_help = "Examples:\n  \
            shapegram derive house.cga -o house.glb\n  \
            shapegram derive house.cga --attr height=20 --seed 3 -o tall.obj\n  \
            shapegram derive house.cga --lot \"0,0 30,0 30,12 12,12 12,25 0,25\" -o l-house.glb\n  \
            shapegram derive house.cga --lots parcels.geojson --group -o block.glb\n  \
            shapegram derive house.cga --lots city.geojson --crs wgs84 --tiles city/\n  \
            shapegram derive house.cga --stats -q | jq .rules\n  \
            shapegram derive candler.rpk -o candler.glb\n  \
            shapegram derive excavator.cga --at-node 40 -o step.glb\n  \
            shapegram derive menger.sgl --dialect sgl -o menger.glb"
    )]
    // Boxed: its many options would make every command as large as it is.
    Derive(Box<DeriveArgs>),
    /// Report the errors and warnings of grammar files without deriving them
    #[command(
        long_about = "Report the errors and warnings of grammar files without deriving them.\n\n\
            Each file is parsed and compiled; its diagnostics are printed rustc-style on\n\
            stderr, followed by one line per file: `ok: FILE (N rules, N attributes, N\n\
            warnings)` or `error: N errors in FILE`. Warnings (for example about CGA features\n\
            that are parsed but not supported yet) are not errors. The exit code is 1 when any\n\
            file has errors.",
        after_help = "Examples:\n  \
            shapegram check house.cga\n  \
            shapegram check candler.rpk\n  \
            shapegram check --quiet-warnings rules/*.cga"
    )]
    Check(CheckArgs),
    /// Derive an L-system and draw it with a turtle (SVG, GLB, OBJ or STL), or print its word
    Lsystem(crate::lsystem::LsystemArgs),
    /// Grow an implicit cave with the SG+M grammar and mesh it (GLB, OBJ or STL)
    Cave(crate::cave::CaveArgs),
    /// Run or compile a topological split grammar (Shape Grammar Editor)
    Topo(crate::topo::TopoArgs),
    /// Run the grammar repository server (accounts, tokens, friends, versioned goal grammars)
    #[command(
        long_about = "Run the grammar repository server: a JSON API over HTTP (described by the\n\
            OpenAPI document at /openapi.json) for accounts, API tokens, friends and versioned,\n\
            checked goal grammars, kept in one SQLite database file, created and migrated on\n\
            start. The address is printed once the server accepts connections; --listen with\n\
            port 0 picks a free port.\n\n\
            Previews (a version derived into a GLB) are made by worker processes of this\n\
            executable that limit their own memory and CPU time and read no files; the server\n\
            kills them at --preview-timeout. See docs/repository.md.",
        after_help = "Examples:\n  \
            shapegram serve\n  \
            shapegram serve --data /srv/grammars.db --listen 0.0.0.0:8080\n  \
            shapegram serve --preview-timeout 5 --preview-memory 512 --preview-workers 1"
    )]
    Serve(crate::serve::ServeArgs),
    /// Edit grammars in the browser with a live 3D preview (local, single user)
    #[command(
        long_about = "Start Shapegram Studio: a local web server on 127.0.0.1 serving a browser\n\
            editor for the grammar files given (and the grammar files in their folders) with a\n\
            live 3D preview, derived as you type, and the parser's diagnostics in place. The\n\
            first line printed is the address to open. The server answers only requests naming\n\
            it as 127.0.0.1:PORT or localhost:PORT, and changes files only for its own page.\n\
            See docs/studio.md.",
        after_help = "Examples:\n  \
            shapegram studio examples/house.cga\n  \
            shapegram studio rules/*.cga --listen 127.0.0.1:8000"
    )]
    Studio(crate::studio::StudioArgs),
    /// Publish, search and fetch goal grammars in a repository; log in, manage friends
    #[command(
        long_about = "Publish, search and fetch goal grammars in a grammar repository (a\n\
            `shapegram serve`); sign up, log in, manage friends and API tokens.\n\n\
            The repository is --repo URL, else $SHAPEGRAM_REPO, else http://127.0.0.1:8080.\n\
            `login` keeps a token per repository in credentials.json (see `repo login --help`);\n\
            SHAPEGRAM_TOKEN overrides it. Exit codes: 0 done, 1 refused by the server (not\n\
            found, not allowed, does not compile), 2 a usage error or no connection. See\n\
            docs/repository.md.",
        after_help = "Examples:\n  \
            shapegram repo signup ana\n  \
            shapegram repo publish examples/chairs/materials/wood.goal --visibility friends\n  \
            shapegram repo search --goal wooden\n  \
            shapegram repo fetch ana/wood -o wood.goal\n  \
            shapegram repo friends add bob"
    )]
    Repo(crate::repo::RepoArgs),
    /// Join the shards of a tileset written by `derive --tiles … --shard K/N`
    #[command(
        long_about = "Join the shards of a tileset written by `derive --tiles DIR --shard K/N`.\n\n\
            `tiles merge` reads each folder's tileset.shard-K-of-N.json, checks that every\n\
            shard of the run is there once, copies the tiles into --out (unless they are there\n\
            already) and writes tileset.json: the same bytes as one run without --shard. See\n\
            docs/tiles.md.",
        after_help = "Examples:\n  \
            shapegram tiles merge part0/ part1/ part2/ --out city/\n  \
            shapegram tiles merge city/ --out city/"
    )]
    Tiles(crate::tiles::TilesArgs),
    /// Derive one goal grammar for the server's previews, under limits (internal)
    #[command(hide = true)]
    PreviewWorker(crate::preview::PreviewWorkerArgs),
}

/// The GLB encoding options that `derive`, `lsystem` and `cave` share (docs/output.md).
#[derive(Debug, Args)]
pub struct GlbArgs {
    /// GLB: positions, normals and uvs as small integers (KHR_mesh_quantization)
    #[arg(long)]
    pub quantize: bool,
    /// GLB: quantise, then compress vertices and indices (EXT_meshopt_compression; readers
    /// need a meshopt decoder)
    #[arg(long)]
    pub meshopt: bool,
    /// GLB: write each flat face's normal on its own corners, as files did before readers were
    /// left to compute them (larger; only for readers that ignore glTF's rule for files without
    /// normals)
    #[arg(long)]
    pub normals: bool,
}

impl GlbArgs {
    /// The encoding and normals these flags ask for.
    pub fn encoding(&self) -> TileEncoding {
        TileEncoding::from_flags(self.quantize, self.meshopt, self.normals)
    }

    /// `options` with the encoding and normals these flags ask for; warns on stderr (unless
    /// `quiet`) when they are given for an `output` that is not a GLB.
    pub fn apply(&self, options: ExportOptions, output: &Path, quiet: bool) -> ExportOptions {
        let TileEncoding {
            encoding,
            flat_normals,
        } = self.encoding();
        let glb = Format::from_path(output).is_ok_and(|f| f == Format::Glb);
        if (encoding != GlbEncoding::Float || self.normals) && !glb && !quiet {
            eprintln!(
                "warning: --quantize, --meshopt and --normals apply to GLB only; {} is written \
                 as usual",
                output.display()
            );
        }
        ExportOptions {
            encoding,
            flat_normals,
            ..options
        }
    }
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

/// Whose published grammars a derivation with a repository draws on (the paper's link modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LinkMode {
    /// Every grammar you may see
    All,
    /// Yours and your friends'
    Friends,
    /// Yours
    Mine,
    /// None: the grammar and its library alone
    This,
}

impl LinkMode {
    /// The name the repository's API and the lock file use.
    pub fn as_str(self) -> &'static str {
        match self {
            LinkMode::All => "all",
            LinkMode::Friends => "friends",
            LinkMode::Mine => "mine",
            LinkMode::This => "this",
        }
    }
}

/// Arguments of `shapegram derive`.
#[derive(Debug, Args)]
pub struct DeriveArgs {
    /// The grammar file, or a CityEngine rule package (.rpk)
    #[arg(value_name = "GRAMMAR")]
    pub grammar: PathBuf,
    /// Rule packages: the rule file to derive, by its path in the package (rules/a.cga) or its
    /// name [default: the one PRT runs, the source of the package's compiled rule file]
    #[arg(long, value_name = "FILE")]
    pub rule_file: Option<String>,
    /// Output file; its extension picks the format: .glb, .obj (writes a .mtl beside it) or .stl.
    /// Without it nothing is written
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// The rule to start from [default: the @StartRule, else the first rule]
    #[arg(long, value_name = "RULE")]
    pub start: Option<String>,
    /// The CGA style to derive: the declarations of `style NAME` (and of the styles it
    /// extends) laid over the default ones [default: the default style]
    #[arg(long, value_name = "NAME")]
    pub style: Option<String>,
    /// A lot: its footprint corners in the xz-plane, at least three, in either winding
    /// (repeatable: one lot each)
    #[arg(long, value_name = "\"X,Z X,Z ...\"", allow_hyphen_values = true)]
    pub lot: Vec<String>,
    /// Lots from a file: every face of an .obj, or every polygon (outer ring) of a .geojson or
    /// .json file, with GeoJSON x as x and GeoJSON y as -z (north is -z) (repeatable)
    #[arg(long, value_name = "FILE")]
    pub lots: Vec<PathBuf>,
    /// The coordinate system of GeoJSON lots: local (metres as they are), wgs84 (longitude and
    /// latitude, RFC 7946) or EPSG:<code> (a UTM zone such as EPSG:32633, a national grid); on
    /// the globe, lots are derived in
    /// the east-north-up plane at the centre of their bounds (docs/tiles.md)
    #[arg(long, value_name = "CRS", default_value = "local", value_parser = parse_crs)]
    pub crs: Crs,
    /// Also write an OGC 3D Tiles 1.1 tileset into this folder: tileset.json, far/ (a box per
    /// lot) and near/ (the full model), a tile per grid cell, each a GLB encoded as --quantize,
    /// --meshopt and --normals ask (docs/tiles.md)
    #[arg(long, value_name = "DIR")]
    pub tiles: Option<PathBuf>,
    /// The side of a tile's square grid cell in metres
    #[arg(long, value_name = "METRES", default_value_t = 200.0, value_parser = parse_tile_size)]
    pub tile_size: f64,
    /// With --tiles: write only shard K of N (K from 0 to N - 1): its share of the parent
    /// tiles and its part of tileset.json, for `shapegram tiles merge` (docs/tiles.md)
    #[arg(long, value_name = "K/N", value_parser = parse_shard, requires = "tiles")]
    pub shard: Option<Shard>,
    /// With --tiles and a grammar with context rules: the lots whose footprint comes within
    /// this many metres of a cell are derived with its lots, as context (docs/tiles.md)
    #[arg(long, value_name = "METRES", default_value_t = 20.0, value_parser = parse_halo)]
    pub halo: f64,
    /// Seed of every random choice
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub seed: u64,
    /// Override an attribute of the grammar: a number, true/false, or else a string (repeatable)
    #[arg(long, value_name = "NAME=VALUE", value_parser = parse_attr)]
    pub attr: Vec<(String, String)>,
    /// Pose joints by name after deriving: a JSON object from joint names to {"rotation": [x, y,
    /// z], "translation": [x, y, z]} (degrees, metres), each within its joint's limits
    #[arg(long, value_name = "FILE")]
    pub pose: Option<PathBuf>,
    /// Fold every locked joint into the nearest joint that may move, so the skeleton keeps a
    /// bone per free joint rather than one per part (the model poses the same)
    #[arg(long)]
    pub merge_locked: bool,
    /// Rewrite in parallel generations and stop after N of them (shapes left become leaves)
    #[arg(long, value_name = "N")]
    pub generations: Option<u32>,
    /// Write the derivation as it stood right after shape N was made, posed (visual
    /// debugging): every shape there was then, as its leaf geometry or, when it was rewritten
    /// later, as its scope box. Shapes are numbered from 0 in the order they were made, lot
    /// after lot, up to the shape count less one
    #[arg(long, value_name = "N")]
    pub at_node: Option<usize>,
    /// Stop with an error after this many shapes
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    pub max_shapes: usize,
    /// Stop with an error when a shape is this many successors deep
    #[arg(long, value_name = "N", default_value_t = 1000)]
    pub max_depth: u32,
    /// Stop with an error after this many rule applications (derivation steps) per lot
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    pub max_steps: usize,
    /// Goal grammars: a goal grammar file, or a folder of them (`*.goal`, subfolders included),
    /// whose rules fulfil the goals the grammar's own rules leave open (repeatable)
    #[arg(long, value_name = "PATH")]
    pub library: Vec<PathBuf>,
    /// Goal grammars: ask the grammar repository at URL (`shapegram serve`) for rules for the
    /// goals that the grammar and its library leave open, and pin the versions found in the lock
    /// file beside the grammar (GRAMMAR.lock), which later runs use (docs/repository.md)
    #[arg(long, value_name = "URL")]
    pub repo: Option<String>,
    /// Whose published grammars --repo draws on [default: all]
    #[arg(long, value_name = "WHOSE")]
    pub link: Option<LinkMode>,
    /// Ask the repository afresh, ignoring the lock file, and rewrite it
    #[arg(long)]
    pub update: bool,
    /// Use the lock file and the local cache of grammars only: no network
    #[arg(long, conflicts_with = "update")]
    pub offline: bool,
    /// Stop with an error when one lot takes longer than this (0: no limit)
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0, value_parser = parse_timeout)]
    pub timeout: f64,
    /// Edge length of the grid cells that implicit solids (`implicit(…)`, `csg(…)`) are
    /// meshed with [default: per group, 4 cells across its smallest member, 64 to 256 along its
    /// longest side]
    #[arg(long, value_name = "SIZE", value_parser = parse_cell)]
    pub implicit_cell: Option<f64>,
    /// Keep one group per leaf symbol and colour (OBJ groups, glTF nodes, named after the symbol)
    /// instead of merging everything of one colour
    #[arg(long)]
    pub group: bool,
    /// GLB: how repeated assets and shapes are written: one mesh drawn by a node per use
    /// (nodes), by EXT_mesh_gpu_instancing (gpu), per asset whichever makes the smaller file
    /// (auto: inserted assets and other mesh leaves only), or each copy flat (none). OBJ and
    /// STL are always flat
    #[arg(long, value_name = "HOW", default_value = "auto")]
    pub instancing: InstancingArg,
    /// GLB: give each leaf a node whose extras name its rule, derivation path and attributes;
    /// with --group, each part's node names its rule, leaf count and the attributes its leaves
    /// share (docs/export.md). --tiles: make each lot a feature of its tiles, with a row of its
    /// rule, path, attributes and reports in each tile's property table (docs/tiles.md)
    #[arg(long)]
    pub metadata: bool,
    /// How a GLB stores its vertices.
    #[command(flatten)]
    pub glb: GlbArgs,
    /// Print counts, times, rule applications and report() values as one JSON object on stdout
    #[arg(long)]
    pub stats: bool,
    /// Do not print warnings and the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
    /// The notation of the grammar [default: detected from its text]
    #[arg(
        long,
        value_name = "DIALECT",
        default_value = "auto",
        hide_default_value = true
    )]
    pub dialect: DialectArg,
    /// What `i("file")` does when the file cannot be read: stop with an error, insert a cube
    /// that fills the scope instead, or insert nothing (a warning names each file once)
    #[arg(long, value_name = "WHAT", default_value = "error")]
    pub missing_assets: MissingAssets,
}

/// The choices of `--instancing`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum InstancingArg {
    /// Every copy with its own vertices
    None,
    /// One mesh per repeated shape, a node per use
    Nodes,
    /// One mesh per repeated shape, drawn by EXT_mesh_gpu_instancing
    Gpu,
    /// Per repeated asset, whichever makes the smaller file
    #[default]
    Auto,
}

impl InstancingArg {
    /// Which leaves the model makes instances of, for the output format.
    pub fn candidates(self, glb: bool) -> shapegram_eval::InstanceCandidates {
        use shapegram_eval::InstanceCandidates;
        match self {
            _ if !glb => InstanceCandidates::None,
            Self::None => InstanceCandidates::None,
            Self::Auto => InstanceCandidates::Meshes,
            Self::Nodes | Self::Gpu => InstanceCandidates::All,
        }
    }
}

impl From<InstancingArg> for shapegram_export::Instancing {
    fn from(instancing: InstancingArg) -> Self {
        match instancing {
            InstancingArg::None => Self::None,
            InstancingArg::Nodes => Self::Nodes,
            InstancingArg::Gpu => Self::Gpu,
            InstancingArg::Auto => Self::Auto,
        }
    }
}

/// What to insert in place of an asset file that cannot be read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum MissingAssets {
    /// Stop the derivation with an error naming the file and the grammar line
    #[default]
    Error,
    /// Insert a cube filling the scope, so the model keeps its massing
    Cube,
    /// Insert nothing
    Skip,
}

impl From<MissingAssets> for shapegram_load::MissingAssets {
    fn from(missing: MissingAssets) -> Self {
        match missing {
            MissingAssets::Error => Self::Error,
            MissingAssets::Cube => Self::Cube,
            MissingAssets::Skip => Self::Skip,
        }
    }
}

/// Arguments of `shapegram check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// The grammar files; a CityEngine rule package (.rpk) checks each of its rule files
    #[arg(value_name = "FILE", required = true)]
    pub files: Vec<PathBuf>,
    /// Count warnings but do not print them
    #[arg(long)]
    pub quiet_warnings: bool,
    /// Goal grammars: check each with this goal grammar file, or the goal grammars of this
    /// folder, as its library (repeatable)
    #[arg(long, value_name = "PATH")]
    pub library: Vec<PathBuf>,
    /// The notation of the grammars [default: detected from each file's text]
    #[arg(
        long,
        value_name = "DIALECT",
        default_value = "auto",
        hide_default_value = true
    )]
    pub dialect: DialectArg,
}

/// The notations `--dialect` names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum DialectArg {
    /// Detect the notation from the text
    #[default]
    Auto,
    /// The main, CGA-style syntax (`Lot --> extrude(10) Mass`)
    Cga,
    /// The notation of Müller et al. 2006 (`lot ~> Subdiv("X", 2, 1r){ A | B }`)
    Muller,
    /// The SGL notation (`rule: { T(0, 1, 0) PlaceShape("Cube") }`)
    Sgl,
    /// The native notation of goal grammars (`fulfills(chair) --> split(y) { … }`)
    Goal,
    /// The C#-style notation of goal grammars in Michelangelo (`new Rules.Split(Axis.Y, …)`)
    Michelangelo,
}

impl DialectArg {
    /// The dialect to read, `None` to detect it.
    pub fn dialect(self) -> Option<Dialect> {
        match self {
            Self::Auto => None,
            Self::Cga => Some(Dialect::Cga),
            Self::Muller => Some(Dialect::Muller2006),
            Self::Sgl => Some(Dialect::Sgl),
            Self::Goal => Some(Dialect::Goal),
            Self::Michelangelo => Some(Dialect::Michelangelo),
        }
    }
}

/// Splits `--attr name=value` at the first `=`.
fn parse_attr(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() => {
            Ok((name.trim().to_owned(), value.to_owned()))
        }
        _ => Err("expected NAME=VALUE, like height=12".to_owned()),
    }
}

/// A timeout in seconds: a finite number, zero or more.
fn parse_timeout(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if (0.0..=1e9).contains(&s) => Ok(s),
        _ => Err("expected a number of seconds, like 60 or 0.5 (0: no limit)".to_owned()),
    }
}

fn parse_shard(text: &str) -> Result<Shard, String> {
    Shard::parse(text)
}

fn parse_halo(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(halo) if (0.0..=1e6).contains(&halo) => Ok(halo),
        _ => Err("expected a distance in metres from 0 to 1,000,000, like 50".to_owned()),
    }
}

fn parse_crs(text: &str) -> Result<Crs, String> {
    Crs::parse(text)
}

fn parse_tile_size(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(size) if (1.0..=1e6).contains(&size) => Ok(size),
        _ => Err("expected a tile size in metres from 1 to 1,000,000, like 200".to_owned()),
    }
}

fn parse_cell(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(h) if h.is_finite() && h > 0.0 => Ok(h),
        _ => Err("expected a cell size above 0, like 0.25".to_owned()),
    }
}

#[cfg(test)]
mod tests {
    use clap::{CommandFactory, Parser};
    use shapegram_syntax::Dialect;

    use super::{Cli, Command, DialectArg, parse_attr, parse_timeout};

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn attributes_split_at_the_first_equals_sign() {
        assert_eq!(parse_attr("height=12"), Ok(("height".into(), "12".into())));
        assert_eq!(parse_attr("name=a=b"), Ok(("name".into(), "a=b".into())));
        assert_eq!(parse_attr("empty="), Ok(("empty".into(), String::new())));
        assert!(parse_attr("height").is_err());
        assert!(parse_attr("=12").is_err());
    }

    #[test]
    fn timeouts_are_non_negative_seconds() {
        assert_eq!(parse_timeout("0"), Ok(0.0));
        assert_eq!(parse_timeout("2.5"), Ok(2.5));
        for bad in ["-1", "NaN", "inf", "soon", "1e300"] {
            assert!(parse_timeout(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn dialects_are_named_or_detected() {
        let dialect = |args: &[&str]| match Cli::try_parse_from(args).map(|cli| cli.command) {
            Ok(Command::Check(args)) => Ok(args.dialect),
            Ok(Command::Derive(args)) => Ok(args.dialect),
            Ok(other) => panic!("{other:?}"),
            Err(e) => Err(e.kind()),
        };
        assert_eq!(
            dialect(&["shapegram", "check", "a.cga"]),
            Ok(DialectArg::Auto)
        );
        assert_eq!(
            dialect(&["shapegram", "check", "--dialect", "muller", "a.txt"]),
            Ok(DialectArg::Muller)
        );
        assert_eq!(
            dialect(&["shapegram", "derive", "t.txt", "--dialect=sgl"]),
            Ok(DialectArg::Sgl)
        );
        assert_eq!(
            dialect(&["shapegram", "derive", "t.txt", "--dialect", "mueller"]),
            Err(clap::error::ErrorKind::InvalidValue)
        );
        assert_eq!(DialectArg::Auto.dialect(), None);
        assert_eq!(DialectArg::Cga.dialect(), Some(Dialect::Cga));
        assert_eq!(DialectArg::Muller.dialect(), Some(Dialect::Muller2006));
        assert_eq!(DialectArg::Sgl.dialect(), Some(Dialect::Sgl));
    }
}
