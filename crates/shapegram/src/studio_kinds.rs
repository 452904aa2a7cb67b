//! The studio's derivations of the grammar kinds that are not CGA-style: L-systems (a 2D drawing
//! as SVG, a 3D one as a model), implicit caves, topological grammars and goal grammars with the
//! goal grammars of their folder as their library. Each is derived as its command derives the
//! file (`shapegram lsystem`, `cave`, `topo`, `derive --library FOLDER`), and its mistakes come
//! back as diagnostics at their line and column wherever the parser gives one.

use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use shapegram_eval::{DeriveOptions, LibraryOptions};
use shapegram_export::ExportOptions;
use shapegram_geom::Model;
use shapegram_server::studio::{Derived, StudioDiagnostic};
use shapegram_syntax::SourceFile;

use crate::derive::millis;
use crate::studio::located;
use crate::{counted, grammar};

/// Generations of a topological grammar, as `shapegram topo` runs it by default.
const TOPO_GENERATIONS: u32 = 8;

/// An error at `line:column` (1-based, columns in characters) of the file being edited.
fn error_at(line: usize, column: usize, message: impl Into<String>) -> StudioDiagnostic {
    StudioDiagnostic {
        severity: "error",
        message: message.into(),
        label: None,
        hints: Vec::new(),
        line,
        column,
        end_line: line,
        end_column: column + 1,
        file: None,
    }
}

/// A derivation that failed without a place in the text.
fn failed(message: impl Into<String>, started: Instant) -> Derived {
    Derived {
        error: Some(message.into()),
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    }
}

/// A derivation that failed at a place in the text.
fn failed_at(diagnostic: StudioDiagnostic, started: Instant) -> Derived {
    Derived {
        diagnostics: vec![diagnostic],
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    }
}

/// `model` as GLB into `derived`, timing the export.
fn export(mut derived: Derived, model: &Model) -> Derived {
    let exported = Instant::now();
    let mut glb = Vec::new();
    match shapegram_export::write_glb_to(model, &ExportOptions::default(), &mut glb) {
        Ok(()) => derived.glb = Some(glb),
        Err(e) => derived.error = Some(format!("cannot write the GLB: {e}")),
    }
    derived.export_ms = millis(exported.elapsed());
    derived
}

/// An L-system with its file's settings: a drawing that stays in the xy-plane is 2D and comes
/// back as SVG, as `shapegram lsystem -o x.svg` writes it; any other as a tube model.
pub fn lsystem(text: &str) -> Derived {
    use shapegram_lsystem::{DeriveOptions, LSystem};
    let started = Instant::now();
    let at = |e: shapegram_lsystem::Error| match e.position {
        Some(p) => failed_at(
            error_at(p.line as usize, p.column as usize, e.message),
            started,
        ),
        None => failed(e.message, started),
    };
    let system = match LSystem::parse(text) {
        Ok(system) => system,
        Err(e) => return at(e),
    };
    let options = DeriveOptions::default();
    let word = match system.derive(&options) {
        Ok(word) => word,
        Err(e) => return at(e),
    };
    let shown = match system.interpretation(&word, &options) {
        Ok(shown) => shown,
        Err(e) => return at(e),
    };
    let drawing = shapegram_lsystem::interpret(&system, &shown);
    let mut derived = Derived {
        shapes: word.len(),
        leaves: drawing.segment_count() + drawing.polygons.len(),
        summary: Some(format!(
            "{}, {}, {}, {}",
            counted(system.settings.iterations as usize, "step", "steps"),
            counted(word.len(), "module", "modules"),
            counted(drawing.segment_count(), "segment", "segments"),
            counted(drawing.polygons.len(), "polygon", "polygons")
        )),
        ..Derived::default()
    };
    let flat = drawing
        .strokes
        .iter()
        .flat_map(|s| &s.points)
        .chain(drawing.polygons.iter().flat_map(|p| &p.points))
        .all(|p| p.z == 0.0);
    if flat {
        derived.derive_ms = millis(started.elapsed());
        let exported = Instant::now();
        let svg = crate::lsystem::svg_drawing(&drawing, &system.settings);
        derived.svg = Some(shapegram_export::write_svg(&svg));
        derived.export_ms = millis(exported.elapsed());
        return derived;
    }
    let model = shapegram_lsystem::drawing_to_model_within(
        &drawing,
        &system.settings,
        shapegram_lsystem::DEFAULT_MAX_VERTICES,
    );
    derived.derive_ms = millis(started.elapsed());
    match model {
        Ok(model) => export(derived, &model),
        Err(e) => {
            let mut failure = at(e);
            failure.summary = derived.summary;
            failure
        }
    }
}

/// A `.cave` grammar grown with its own seed and meshed at its level of detail, smooth-shaded,
/// as `shapegram cave FILE` does.
pub fn cave(text: &str) -> Derived {
    use shapegram_implicit::{CaveParams, MeshOptions, text::TextError};
    let started = Instant::now();
    let at = |e: TextError| failed_at(error_at(e.line, e.column, e.message), started);
    let program = match shapegram_implicit::text::parse(text) {
        Ok(program) => program,
        Err(e) => return at(e),
    };
    let run = match program.run(None) {
        Ok(run) => run,
        Err(e) => return at(e),
    };
    let lod = program.lod.unwrap_or(CaveParams::default().lod);
    let options = MeshOptions::with_cell_size(1.0 / f64::from(lod));
    let solid = run.builder.solid();
    let meshing = match shapegram_implicit::mesh(solid, &options) {
        Ok(meshing) => meshing,
        Err(e) => return failed(e.to_string(), started),
    };
    let triangles = meshing.mesh.face_count();
    let primitives = solid.primitive_count();
    let mut model = Model::single("cave", crate::cave::ROCK, meshing.mesh);
    model.parts[0].normals =
        shapegram_implicit::surface_normals(solid, &model.parts[0].mesh, options.cell_size / 2.0);
    let derived = Derived {
        shapes: primitives,
        leaves: triangles,
        summary: Some(format!(
            "lod {lod}, {}, {}",
            counted(primitives, "primitive", "primitives"),
            counted(triangles, "triangle", "triangles")
        )),
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    };
    export(derived, &model)
}

/// A topological `.grammar` from its first symbol, seed 0, as `shapegram topo FILE` runs it.
pub fn topo(text: &str) -> Derived {
    use shapegram_topo::{Grammar, GrammarMesh, GrammarState};
    let started = Instant::now();
    let grammar = match Grammar::from_json(text) {
        Ok(grammar) => grammar,
        Err(e) => {
            // JSON syntax errors have a line and column; a wrong field has a path.
            let place = e
                .location
                .split_once(':')
                .and_then(|(l, c)| Some((l.parse().ok()?, c.parse().ok()?)));
            return match place {
                Some((line, column)) => failed_at(error_at(line, column, e.message), started),
                None => failed(format!("{}: {}", e.location, e.message), started),
            };
        }
    };
    let Some(symbol) = grammar.symbol_names().first().map(|s| (*s).to_owned()) else {
        return failed("the grammar has no symbol", started);
    };
    let state = GrammarState::new(&grammar, &symbol).and_then(|state| {
        let mut state = state.with_generations(TOPO_GENERATIONS);
        state.generate_all()?;
        Ok(state)
    });
    let state = match state {
        Ok(state) => state,
        Err(e) => return failed(e.to_string(), started),
    };
    let mesh = GrammarMesh::new(&state);
    let terminals = state.terminals().len();
    let shapes = terminals + state.non_terminals().len();
    let derived = Derived {
        shapes,
        leaves: terminals,
        summary: Some(format!(
            "{} from {symbol}: {} ({terminals} terminal), {}",
            counted(state.generation() as usize, "generation", "generations"),
            counted(shapes, "shape", "shapes"),
            counted(mesh.triangle_count(), "triangle", "triangles")
        )),
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    };
    export(derived, &mesh.to_model())
}

/// A goal grammar with the goal grammars of its folder and its subfolders as its library, as
/// `shapegram derive FILE --library FOLDER` derives it: from its axioms, no lot.
pub fn goal(path: &Path, text: &str, time_budget: Duration) -> Derived {
    let started = Instant::now();
    let folder = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let source = SourceFile::new(path.display().to_string(), text.to_owned());
    let sources = match grammar::read_library(source, path, std::slice::from_ref(&folder), false) {
        Ok(sources) => sources,
        Err(e) => {
            let mut derived = failed(e.message.unwrap_or_default(), started);
            derived.hints = e.hints;
            return derived;
        }
    };
    let options = LibraryOptions::closed(sources.len());
    let (compiled, diagnostics) = grammar::compile_library_silently(sources, None, &options);
    let mut derived = Derived {
        diagnostics: diagnostics
            .iter()
            .map(|(file, d)| located(&compiled.sources, *file, d))
            .collect(),
        ..Derived::default()
    };
    let library = compiled.sources.len() - 1;
    let program = match compiled.program {
        Some(program) if compiled.errors == 0 => program,
        _ => {
            derived.derive_ms = millis(started.elapsed());
            return derived;
        }
    };
    let options = DeriveOptions {
        time_budget: Some(time_budget),
        assets: Some(Arc::new(shapegram_load::FileAssets::new(
            folder,
            shapegram_load::MissingAssets::Error,
        ))),
        ..DeriveOptions::default()
    };
    let derivation = match shapegram_eval::derive(&program, &[], &options) {
        Ok(derivation) => derivation,
        Err(e) => {
            derived.derive_ms = millis(started.elapsed());
            match e.to_diagnostic() {
                Some(d) => {
                    derived
                        .diagnostics
                        .push(located(&compiled.sources, e.file.unwrap_or(0), &d))
                }
                None => {
                    derived.error = Some(e.message.replace('\n', " "));
                    derived.hints = e.hints;
                }
            }
            return derived;
        }
    };
    derived.derive_ms = millis(started.elapsed());
    derived.shapes = derivation.stats.shapes;
    derived.leaves = derivation.stats.leaves;
    derived.prints = derivation.prints.clone();
    derived.summary = Some(format!(
        "{} shapes · {} leaves · library of {}",
        derivation.stats.shapes,
        derivation.stats.leaves,
        counted(library, "file", "files")
    ));
    export(derived, &derivation.to_model())
}
