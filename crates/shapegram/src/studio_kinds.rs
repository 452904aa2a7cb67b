//! The studio's derivations of the grammar kinds that are not CGA-style: L-systems (a 2D drawing
//! as SVG, a 3D one as a model), implicit caves, topological grammars and goal grammars with the
//! goal grammars of their folder as their library. Each is derived as its command derives the
//! file (`shapegram lsystem`, `cave`, `topo`, `derive --library FOLDER`), and its mistakes come
//! back as diagnostics at their line and column wherever the parser gives one. Caves and
//! topological grammars load and derive through `shapegram-runtime`, as every host's do; an
//! L-system needs its drawing (is it flat?) and a goal grammar its library, which the runtime
//! does not give, so those two are derived here.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use shapegram_eval::{DeriveOptions, LibraryOptions};
use shapegram_export::ExportOptions;
use shapegram_geom::Model;
use shapegram_implicit::CaveParams;
use shapegram_runtime::{Derived as RuntimeDerived, Grammar, Kind, Settings, TopoGrammar};
use shapegram_server::studio::{DeriveJob, Derived, StudioDiagnostic};
use shapegram_syntax::SourceFile;

use crate::derive::millis;
use crate::studio::{located, record_failure};
use crate::{counted, grammar, studio_settings};

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

/// Poses `model` as the job asks (`derive --pose`), keeping the error for the page.
pub(crate) fn pose(model: &mut Model, job: &DeriveJob) -> Result<(), String> {
    match &job.pose {
        Some(pose) => {
            crate::pose::apply_text(&pose.to_string(), model).map_err(|e| format!("pose: {e}"))
        }
        None => Ok(()),
    }
}

/// `model` into `derived` as the job asks: the files of its export format, else the GLB; the
/// time taken from `exported` on.
pub(crate) fn deliver(
    mut derived: Derived,
    model: &Model,
    job: &DeriveJob,
    exported: Instant,
) -> Derived {
    match job.export {
        Some(format) => {
            let stem = job
                .path
                .file_stem()
                .map_or_else(|| "model".into(), |s| s.to_string_lossy());
            match studio_settings::export(model, format, &stem) {
                Ok(files) => derived.files = files,
                Err(e) => derived.error = Some(e),
            }
        }
        None => {
            let mut glb = Vec::new();
            match shapegram_export::write_glb_to(model, &ExportOptions::default(), &mut glb) {
                Ok(()) => derived.glb = Some(glb),
                Err(e) => derived.error = Some(format!("cannot write the GLB: {e}")),
            }
        }
    }
    derived.export_ms = millis(exported.elapsed());
    derived
}

/// `model` posed and delivered as the job asks.
fn finish(mut derived: Derived, mut model: Model, job: &DeriveJob) -> Derived {
    let exported = Instant::now();
    if let Err(e) = pose(&mut model, job) {
        derived.error = Some(e);
        return derived;
    }
    deliver(derived, &model, job, exported)
}

/// An L-system with its file's settings: a drawing that stays in the xy-plane is 2D and comes
/// back as SVG, as `shapegram lsystem -o x.svg` writes it; any other as a tube model, as
/// `shapegram lsystem -o x.glb` makes it.
/// Downloads (`job.export`) get that model too.
pub fn lsystem(job: &DeriveJob) -> Derived {
    let text = job.text.as_str();
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
    let word = match system.derive_until(&options, |_, _| {}, || job.control.is_cancelled()) {
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
    if flat && job.export.is_none() {
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
        Ok(model) => finish(derived, model, job),
        Err(e) => {
            let mut failure = at(e);
            failure.summary = derived.summary;
            failure
        }
    }
}

/// A runtime error as the studio shows it: at its place in the text when it has one.
fn runtime_failure(error: shapegram_runtime::Error, started: Instant) -> Derived {
    match error.place {
        Some(place) => failed_at(error_at(place.line, place.column, place.message), started),
        None => failed(error.message, started),
    }
}

/// A `.cave` grammar grown with its own seed and meshed at its level of detail, smooth-shaded,
/// as `shapegram cave FILE` does (through the runtime).
pub fn cave(job: &DeriveJob) -> Derived {
    let started = Instant::now();
    let grammar = match Grammar::load(&job.path.display().to_string(), &job.text, Some(Kind::Cave))
    {
        Ok(grammar) => grammar,
        Err(e) => return runtime_failure(e, started),
    };
    let Grammar::Cave(program) = &grammar else {
        unreachable!("a cave loads as a cave");
    };
    let lod = program.lod.unwrap_or(CaveParams::default().lod);
    let settings = Settings {
        seed: program.seed,
        control: job.control.clone(),
        ..Settings::default()
    };
    let model = match grammar.derive(&settings) {
        Ok(RuntimeDerived::Model(model)) => model,
        Ok(RuntimeDerived::Triangles(_)) => unreachable!("a cave derives a model"),
        Err(e) => return runtime_failure(e, started),
    };
    let triangles = model.parts[0].mesh.face_count();
    let derived = Derived {
        leaves: triangles,
        summary: Some(format!(
            "lod {lod}, {}",
            counted(triangles, "triangle", "triangles")
        )),
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    };
    finish(derived, model, job)
}

/// A topological `.grammar` from its first symbol, seed 0, 8 generations, as `shapegram topo
/// FILE` runs it (through the runtime), its textures read beside it and embedded in the GLB.
pub fn topo(job: &DeriveJob) -> Derived {
    let started = Instant::now();
    let grammar = match Grammar::load(&job.path.display().to_string(), &job.text, Some(Kind::Topo))
    {
        Ok(grammar) => grammar,
        Err(e) => return runtime_failure(e, started),
    };
    let settings = Settings {
        control: job.control.clone(),
        ..Settings::default()
    };
    let topo = match grammar.derive(&settings) {
        Ok(RuntimeDerived::Triangles(topo)) => topo,
        Ok(RuntimeDerived::Model(_)) => unreachable!("a topological grammar derives triangles"),
        Err(e) => return runtime_failure(e, started),
    };
    let Grammar::Topo(TopoGrammar { symbol, .. }) = &grammar else {
        unreachable!("a topological grammar loads as one");
    };
    let mesh = &topo.mesh;
    let parts = mesh
        .parts
        .iter()
        .filter(|p| !p.triangles.is_empty())
        .count();
    let derived = Derived {
        shapes: parts,
        leaves: mesh.triangle_count(),
        summary: Some(format!(
            "from {symbol}: {}, {}",
            counted(mesh.triangle_count(), "triangle", "triangles"),
            counted(parts, "part", "parts")
        )),
        derive_ms: millis(started.elapsed()),
        ..Derived::default()
    };
    finish(derived, topo.to_model(), job)
}

/// A goal grammar with the goal grammars of its folder and its subfolders as its library, as
/// `shapegram derive FILE --library FOLDER` derives it: from its axioms, no lot.
pub fn goal(job: &DeriveJob) -> Derived {
    let (path, text) = (job.path.as_path(), job.text.as_str());
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
        seed: job.seed,
        time_budget: Some(job.time_budget),
        generations: job.generations,
        control: Some(job.control.clone()),
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
            record_failure(&mut derived, &compiled.sources, e);
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
    finish(derived, derivation.to_model(), job)
}
