//! `shapegram cave`: grow an implicit cave with the SG+M grammar (the random generator driven by
//! the paper's parameters, or a `.cave` file), mesh it with marching cubes and write it.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use clap::Args;
use serde::Serialize;
use shapegram_export::{ExportOptions, Format};
use shapegram_geom::{Color, Model};
use shapegram_implicit::metrics::DEFAULT_FLAT_ANGLE;
use shapegram_implicit::{
    CaveBuilder, CaveParams, Direction, MeshOptions, Meshing, Metrics, Operation, generate,
    mesh_with_progress, surface_normals_with_progress, text,
};

use crate::cli::GlbArgs;
use crate::derive::millis;
use crate::progress::LateBar;
use crate::{Failure, counted, print_stdout};

/// The colour of cave rock in the written model.
const ROCK: Color = Color::rgb(0.55, 0.48, 0.42);

/// Arguments of `shapegram cave`.
#[derive(Debug, Args)]
#[command(
    long_about = "Grow an implicit cave with the SG+M grammar (shape grammar + morphing, \
        Zawadzki, Nikiel and Warszawski) and mesh it with marching cubes.\n\n\
        Without FILE the random generator runs with the paper's parameters; the defaults are \
        the paper's experiment (L_D = 10, P_C = 10, P_M = 2, L_B = +X, M_P = 52 %, P_S = 3). \
        With FILE the productions come from a .cave grammar (see docs/implicit.md); --lod and \
        --seed override its settings. The level of detail is the grid density: L_D cells per \
        unit of length. The output is closed, consistently oriented and the same for the same \
        input and seed, whatever the number of threads.",
    after_help = "Examples:\n  \
        shapegram cave -o cave.glb\n  \
        shapegram cave --lod 32 --seed 7 -o cave.obj --stats\n  \
        shapegram cave --classic 20 --morphic 4 --direction random --morph 30 -o maze.stl\n  \
        shapegram cave examples/grotto.cave -o grotto.glb\n  \
        shapegram cave --lod 20 --quantize -o cave-small.glb"
)]
pub struct CaveArgs {
    /// A .cave grammar; without it the random SG+M generator runs
    #[arg(value_name = "FILE")]
    pub file: Option<PathBuf>,
    /// Output file; its extension picks the format: .glb, .obj (writes a .mtl beside it) or .stl.
    /// Without it nothing is written, which is useful with --stats
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Level of detail L_D, 1 to 32: grid cells per unit of length [default: 10]
    #[arg(long, value_name = "L_D")]
    pub lod: Option<u32>,
    /// Classic productions P_C (sum, difference, intersection) [default: 10]
    #[arg(long, value_name = "P_C")]
    pub classic: Option<u32>,
    /// Morphic productions P_M [default: 2]
    #[arg(long, value_name = "P_M")]
    pub morphic: Option<u32>,
    /// Labelling direction L_B: -x, +x, -y, +y, -z, +z or random [default: +x]
    #[arg(long, value_name = "L_B", allow_hyphen_values = true)]
    pub direction: Option<String>,
    /// Morphing parameter M_P in percent, 0 to 100 [default: 52]
    #[arg(long, value_name = "M_P")]
    pub morph: Option<f64>,
    /// Productions per shape P_S, 0 to 10 [default: 3]
    #[arg(long, value_name = "P_S")]
    pub per_shape: Option<u32>,
    /// Seed of the random choices [default: 1, or the file's seed]
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Print the metrics (area, volumes, convexity factor, counts) as JSON on stdout
    #[arg(long)]
    pub stats: bool,
    /// How a GLB stores its vertices.
    #[command(flatten)]
    pub glb: GlbArgs,
    /// Do not print the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
}

/// What the cave was grown from.
struct Grown {
    builder: CaveBuilder,
    lod: u32,
    seed: u64,
    source: String,
}

/// Grows, meshes, writes and reports.
pub fn run(args: &CaveArgs) -> Result<(), Failure> {
    // Cheap checks first, so that a typo fails before any work.
    let format = args.output.as_deref().map(Format::from_path).transpose()?;
    let started = Instant::now();
    let grown = match &args.file {
        Some(file) => from_file(args, file)?,
        None => from_parameters(args)?,
    };
    let grow_time = started.elapsed();

    let meshing_started = Instant::now();
    let options = MeshOptions::with_cell_size(1.0 / f64::from(grown.lod));
    let show_progress = !args.quiet && std::io::stderr().is_terminal();
    let bar = LateBar::new(show_progress, "{bar:30} meshing {pos}/{len} blocks");
    let meshing = mesh_with_progress(grown.builder.solid(), &options, &|done, total| {
        bar.update(done as u64, total as u64, String::new)
    });
    bar.finish();
    let meshing = meshing.map_err(|e| Failure::new(e.to_string()))?;
    let mesh_time = meshing_started.elapsed();

    let export_started = Instant::now();
    if let Some(output) = &args.output {
        let mut model = Model::single("cave", ROCK, meshing.mesh.clone());
        // Smooth shading from the field's gradient: marching-cubes surfaces look faceted with a
        // normal per triangle, and averaged normals would round off the creases CSG makes. STL
        // keeps no normals per vertex, so they would be worked out for nothing.
        if format != Some(Format::Stl) {
            let bar = LateBar::new(show_progress, "{bar:30} shading {pos}/{len} vertex groups");
            model.parts[0].normals = surface_normals_with_progress(
                grown.builder.solid(),
                &meshing.mesh,
                options.cell_size / 2.0,
                &|done, total| bar.update(done as u64, total as u64, String::new),
            );
            bar.finish();
        }
        let options = args.glb.apply(ExportOptions::default(), output, args.quiet);
        shapegram_export::save(&model, output, &options)?;
    }
    let export_time = export_started.elapsed();

    let metrics = Metrics::measure(&meshing, grown.builder.elements());
    if !args.quiet {
        if meshing.mesh.is_empty() {
            eprintln!("warning: the cave is empty: the productions removed everything");
        }
        let target = match &args.output {
            Some(output) => format!("wrote {}", output.display()),
            None => "grew the cave (no output file)".to_string(),
        };
        let [x, y, z] = meshing.grid.cells;
        eprintln!(
            "{target}: {}, {}, {}, grid {x} × {y} × {z} (L_D {}), {}",
            counted(grown.builder.applied().len(), "production", "productions"),
            counted(metrics.elements, "primitive", "primitives"),
            counted(metrics.triangles, "triangle", "triangles"),
            grown.lod,
            seconds(started.elapsed()),
        );
    }
    if args.stats {
        let json = StatsJson::new(
            &grown,
            &meshing,
            &metrics,
            [grow_time, mesh_time, export_time],
        );
        let mut text = serde_json::to_string(&json)
            .map_err(|e| Failure::new(format!("cannot render JSON: {e}")))?;
        text.push('\n');
        print_stdout(&text)?;
    }
    Ok(())
}

/// The random generator with the parameters of the command line.
fn from_parameters(args: &CaveArgs) -> Result<Grown, Failure> {
    let defaults = CaveParams::default();
    let direction = match &args.direction {
        Some(text) => text
            .parse::<Direction>()
            .map_err(|e| Failure::new(e.to_string()))?,
        None => defaults.direction,
    };
    let params = CaveParams {
        lod: args.lod.unwrap_or(defaults.lod),
        classic: args.classic.unwrap_or(defaults.classic),
        morphic: args.morphic.unwrap_or(defaults.morphic),
        direction,
        morph_percent: args.morph.unwrap_or(defaults.morph_percent),
        per_shape: args.per_shape.unwrap_or(defaults.per_shape),
        seed: args.seed.unwrap_or(defaults.seed),
    };
    let cave = generate(&params).map_err(|e| Failure::new(e.to_string()))?;
    Ok(Grown {
        builder: cave.builder,
        lod: params.lod,
        seed: params.seed,
        source: "generator".into(),
    })
}

/// The productions of a `.cave` file.
fn from_file(args: &CaveArgs, file: &std::path::Path) -> Result<Grown, Failure> {
    let generator_only = [
        ("--classic", args.classic.is_some(), "classic N"),
        ("--morphic", args.morphic.is_some(), "morphic N"),
        ("--direction", args.direction.is_some(), "direction D"),
        ("--morph", args.morph.is_some(), "morph N%"),
        ("--per-shape", args.per_shape.is_some(), "per_shape N"),
    ];
    if let Some((flag, _, option)) = generator_only.iter().find(|(_, given, _)| *given) {
        return Err(Failure::new(format!(
            "{flag} does not apply to a .cave file: write `generate {option}` in the file"
        )));
    }
    let name = file.display().to_string();
    let bytes =
        std::fs::read(file).map_err(|e| Failure::new(format!("cannot read {name}: {e}")))?;
    let source = String::from_utf8(bytes).map_err(|e| {
        Failure::new(format!(
            "cannot read {name}: not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    let located = |e: text::TextError| Failure::new(format!("{name}:{e}"));
    let program = text::parse(&source).map_err(located)?;
    if let Some(lod) = args.lod
        && !(1..=32).contains(&lod)
    {
        return Err(Failure::new(format!(
            "invalid level of detail {lod}: expected 1 to 32"
        )));
    }
    let run = program.run(args.seed).map_err(located)?;
    Ok(Grown {
        builder: run.builder,
        lod: args
            .lod
            .or(program.lod)
            .unwrap_or(CaveParams::default().lod),
        seed: args.seed.unwrap_or(program.seed),
        source: name,
    })
}

/// `0.84 s`.
fn seconds(d: Duration) -> String {
    format!("{:.2} s", d.as_secs_f64())
}

/// The JSON object of `--stats`; field order is output order.
#[derive(Serialize)]
struct StatsJson<'a> {
    source: &'a str,
    seed: u64,
    lod: u32,
    cell_size: f64,
    grid: [usize; 3],
    productions: usize,
    classic: usize,
    morphic: usize,
    elements: usize,
    triangles: usize,
    vertices: usize,
    area: f64,
    volume_voxels: f64,
    volume_mesh: f64,
    convexity_factor: f64,
    convex_edges: usize,
    concave_edges: usize,
    flat_edges: usize,
    flat_angle_degrees: f64,
    watertight: bool,
    evaluated_samples: u64,
    grow_ms: f64,
    mesh_ms: f64,
    export_ms: f64,
}

impl<'a> StatsJson<'a> {
    fn new(grown: &'a Grown, meshing: &Meshing, metrics: &Metrics, times: [Duration; 3]) -> Self {
        let applied = grown.builder.applied();
        let morphic = applied
            .iter()
            .filter(|a| matches!(a.operation, Operation::Morph(_)))
            .count();
        Self {
            source: &grown.source,
            seed: grown.seed,
            lod: grown.lod,
            cell_size: meshing.grid.cell_size,
            grid: meshing.grid.cells,
            productions: applied.len(),
            classic: applied.len() - morphic,
            morphic,
            elements: metrics.elements,
            triangles: metrics.triangles,
            vertices: metrics.vertices,
            area: metrics.area,
            volume_voxels: metrics.voxel_volume,
            volume_mesh: metrics.mesh_volume,
            convexity_factor: metrics.convexity.factor(),
            convex_edges: metrics.convexity.convex,
            concave_edges: metrics.convexity.concave,
            flat_edges: metrics.convexity.flat,
            flat_angle_degrees: DEFAULT_FLAT_ANGLE,
            watertight: metrics.edges.is_watertight(),
            evaluated_samples: meshing.evaluated_samples,
            grow_ms: millis(times[0]),
            mesh_ms: millis(times[1]),
            export_ms: millis(times[2]),
        }
    }
}
