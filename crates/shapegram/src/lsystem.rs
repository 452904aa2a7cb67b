//! `shapegram lsystem`: derive an L-system, then print its word or draw it with the turtle as
//! SVG (2D), as a tube model (GLB, OBJ, STL) or as a line model (GLB, OBJ).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use shapegram_export::{ExportOptions, Format, SvgDrawing, SvgPolygon, SvgPolyline, write_svg};
use shapegram_geom::DVec2;
use shapegram_lsystem::{
    DEFAULT_MAX_MODULES, DEFAULT_MAX_VERTICES, DeriveOptions, Drawing, LSystem, Settings,
    drawing_to_lines_within, drawing_to_model_within, interpret,
};

use crate::cli::GlbArgs;
use crate::derive::duration;
use crate::progress::{LateBar, with_spinner};
use crate::{Failure, counted, print_stdout};

/// Arguments of `shapegram lsystem`.
#[derive(Debug, Args)]
#[command(
    long_about = "Derive an L-system and draw it with a turtle.\n\n\
        The file holds settings (n, angle, step, width, seed, ignore, define, axiom, ...) and \
        productions, one per line: `F -> F[+F]F[-F]F`, `F (0.33) -> ...` (stochastic), \
        `b < a > c -> ...` (context), `A(x,y) : y <= 3 -> A(2*x, x+y)` (parametric). \
        See docs/lsystem.md for the format and the turtle commands.\n\n\
        Models draw strokes as smooth-shaded tubes of `sides:` sides; with --lines, as line \
        segments without thickness (GLB LINES primitives, OBJ `l` elements), which are ten \
        times smaller and quicker for words of millions of segments. Polygons (leaves) stay \
        faces either way.",
    after_help = "Examples:\n  \
        shapegram lsystem examples/koch-island.lsys -o island.svg\n  \
        shapegram lsystem examples/tree-3d.lsys -o tree.glb\n  \
        shapegram lsystem examples/bush-3d.lsys --lines -o bush-lines.glb\n  \
        shapegram lsystem examples/tree-3d.lsys --meshopt -o tree-small.glb\n  \
        shapegram lsystem examples/stochastic-plant.lsys -o plant.svg --seed 3\n  \
        shapegram lsystem examples/algae.lsys -n 5 --string"
)]
pub struct LsystemArgs {
    /// The L-system file
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Derivation length (overrides `n:` in the file)
    #[arg(short = 'n', long = "iterations", value_name = "N")]
    pub iterations: Option<u32>,
    /// Seed of stochastic productions (overrides `seed:` in the file)
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// Output file; its extension picks the format: .svg (2D, the xy-plane), .glb, .obj (writes
    /// a .mtl beside it) or .stl
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Print the derived word on stdout
    #[arg(long)]
    pub string: bool,
    /// Draw strokes as lines without thickness instead of tubes (.glb or .obj; STL holds
    /// triangles only)
    #[arg(long)]
    pub lines: bool,
    /// Stop with an error when a word would grow beyond this many modules
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_MODULES)]
    pub max_modules: usize,
    /// Stop with an error when a model (GLB, OBJ, STL) would have more than this many vertices
    /// (tube rings count `sides` each; with --lines, every point counts one)
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_VERTICES)]
    pub max_vertices: usize,
    /// How a GLB stores its vertices.
    #[command(flatten)]
    pub glb: GlbArgs,
    /// Do not print the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
}

/// Where the drawing goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Output {
    Svg,
    Model(Format),
}

impl Output {
    fn of(path: &Path) -> Result<Self, Failure> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if extension.as_deref() == Some("svg") {
            return Ok(Self::Svg);
        }
        Format::from_path(path).map(Self::Model).map_err(|_| {
            Failure::new(format!(
                "unknown file format '{}': use .svg, .glb, .obj or .stl",
                path.display()
            ))
        })
    }
}

/// Derives, prints or draws, and reports.
pub fn run(args: &LsystemArgs) -> Result<(), Failure> {
    // Cheap checks first, so that a typo fails before any work.
    let output = args.output.as_deref().map(Output::of).transpose()?;
    if args.lines && output == Some(Output::Model(Format::Stl)) {
        return Err(Failure::new(
            "STL holds triangles only; --lines needs a .glb or .obj output",
        ));
    }
    let name = args.file.display().to_string();
    let bytes =
        std::fs::read(&args.file).map_err(|e| Failure::new(format!("cannot read {name}: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        Failure::new(format!(
            "cannot read {name}: not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    let system = LSystem::parse(&text).map_err(|e| reported(&e.render(&name, &text)))?;

    let options = DeriveOptions {
        iterations: args.iterations,
        seed: args.seed,
        max_modules: args.max_modules,
    };
    let started = Instant::now();
    let progress = !args.quiet && std::io::stderr().is_terminal();
    let word =
        derive(&system, &options, progress).map_err(|e| reported(&e.render(&name, &text)))?;

    if args.string {
        let mut line = system.word_text(&word);
        line.push('\n');
        print_stdout(&line)?;
    }
    let mut drawn = None;
    if let (Some(path), Some(output)) = (&args.output, output) {
        let export = args.glb.apply(ExportOptions::default(), path, args.quiet);
        let label = format!("drawing {}", path.display());
        let drawing = with_spinner(progress, &label, || {
            let shown = system
                .interpretation(&word, &options)
                .map_err(|e| reported(&e.render(&name, &text)))?;
            let drawing = interpret(&system, &shown);
            match output {
                Output::Svg => {
                    std::fs::write(path, write_svg(&svg_drawing(&drawing, &system.settings)))
                        .map_err(|e| {
                            Failure::new(format!("cannot write {}: {e}", path.display()))
                        })?
                }
                Output::Model(_) => {
                    let build = if args.lines {
                        drawing_to_lines_within
                    } else {
                        drawing_to_model_within
                    };
                    let model = build(&drawing, &system.settings, args.max_vertices)
                        .map_err(|e| reported(&e.render(&name, &text)))?;
                    shapegram_export::save(&model, path, &export)?;
                }
            }
            Ok::<_, Failure>(drawing)
        })?;
        drawn = Some(drawing);
    }

    if !args.quiet {
        if let Some(drawing) = &drawn
            && drawing.segment_count() == 0
            && drawing.polygons.is_empty()
        {
            eprintln!("warning: the drawing is empty: the word draws no line (F) and no polygon");
        }
        let iterations = args.iterations.unwrap_or(system.settings.iterations);
        let mut summary = format!(
            "{}, {}",
            counted(iterations as usize, "step", "steps"),
            counted(word.len(), "module", "modules")
        );
        if let Some(drawing) = &drawn {
            summary.push_str(&format!(
                ", {}, {}",
                counted(drawing.segment_count(), "segment", "segments"),
                counted(drawing.polygons.len(), "polygon", "polygons")
            ));
        }
        let target = match &args.output {
            Some(path) => path.display().to_string(),
            None => name.clone(),
        };
        eprintln!(
            "derived {target}: {summary}, {}",
            duration(started.elapsed())
        );
    }
    Ok(())
}

/// A failure whose (multi-line, caret-marked) explanation is printed now.
fn reported(rendered: &str) -> Failure {
    eprint!("error: {rendered}");
    Failure::reported()
}

/// Derives, showing a progress bar on stderr (when `progress`) once a run takes more than half
/// a second.
fn derive(
    system: &LSystem,
    options: &DeriveOptions,
    progress: bool,
) -> Result<shapegram_lsystem::Word, shapegram_lsystem::Error> {
    let steps = options.iterations.unwrap_or(system.settings.iterations);
    let bar = LateBar::new(progress, "{bar:30} step {pos}/{len}: {msg}");
    let result = system.derive_with_progress(options, |step, modules| {
        bar.update(u64::from(step), u64::from(steps), || {
            counted(modules, "module", "modules")
        });
    });
    bar.finish();
    result
}

/// The drawing in the xy-plane: a polyline per run of equal width of each stroke, a polygon per
/// polygon.
pub(crate) fn svg_drawing(drawing: &Drawing, settings: &Settings) -> SvgDrawing {
    let color = |index: usize| {
        settings
            .colors
            .get(index.min(settings.colors.len().saturating_sub(1)))
            .copied()
            .unwrap_or_default()
    };
    let flat = |p: &shapegram_geom::DVec3| DVec2::new(p.x, p.y);
    let mut svg = SvgDrawing::default();
    for stroke in &drawing.strokes {
        let mut start = 0;
        for k in 1..=stroke.widths.len() {
            if k == stroke.widths.len() || stroke.widths[k] != stroke.widths[start] {
                svg.polylines.push(SvgPolyline {
                    points: stroke.points[start..=k].iter().map(flat).collect(),
                    width: stroke.widths[start],
                    color: color(stroke.color),
                });
                start = k;
            }
        }
    }
    for polygon in &drawing.polygons {
        svg.polygons.push(SvgPolygon {
            points: polygon.points.iter().map(flat).collect(),
            color: color(polygon.color),
        });
    }
    svg
}
