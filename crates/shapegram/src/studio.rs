//! `shapegram studio`: the browser editor with a live preview, served by `shapegram_server::studio`
//! on 127.0.0.1. This side brings the engine: grammar text compiled and derived the way
//! `shapegram derive FILE` does it (notation detected from the text, imports and assets found
//! beside the file, or inside the rule package the file is in; the default lot), then written
//! as GLB; the other kinds of grammar are derived by [`studio_kinds`]. See docs/studio.md.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;
use shapegram_eval::{DeriveError, DeriveOptions};
use shapegram_export::ExportOptions;
use shapegram_load::{FileAssets, Files, MissingAssets};
use shapegram_server::studio::{DeriveJob, Derived, Engine, StudioDiagnostic, StudioOptions};
use shapegram_syntax::{Diagnostic, Severity, SourceFile};

use crate::derive::millis;
use crate::{Failure, grammar, studio_kinds, studio_settings, studio_tree};

/// Arguments of `shapegram studio`.
#[derive(Debug, Args)]
pub struct StudioArgs {
    /// Grammar files or rule packages (.rpk) to edit (their folders' grammar files and packages
    /// are listed too); none: the current folder's
    #[arg(value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Loopback address and port to listen on (port 0: any free port)
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:7370")]
    pub listen: String,
    /// Seconds one derivation may take before it stops with an error
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    pub timeout: f64,
}

/// Starts the studio and serves it until Ctrl-C.
pub fn run(args: &StudioArgs) -> Result<(), Failure> {
    if !(args.timeout > 0.0 && args.timeout <= 3600.0) {
        return Err(Failure::new("--timeout: expected seconds above 0, at most 3600").with_code(2));
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::new(format!("cannot start the server's runtime: {e}")))?;
    let options = StudioOptions {
        files: args.files.clone(),
        listen: args.listen.clone(),
        time_budget: Duration::from_secs_f64(args.timeout),
    };
    runtime
        .block_on(shapegram_server::studio::serve(
            options,
            Arc::new(CliEngine),
            |addr| {
                // Scripts and tests read the address from the first line.
                println!("shapegram studio: http://{addr}/");
                let _ = std::io::Write::flush(&mut std::io::stdout());
            },
        ))
        .map_err(Failure::new)
}

/// The engine as `shapegram derive` runs it.
pub struct CliEngine;

impl Engine for CliEngine {
    fn derive(&self, job: &DeriveJob) -> Derived {
        let extension = job.path.extension().and_then(|e| e.to_str()).unwrap_or("");
        match extension {
            "lsys" => studio_kinds::lsystem(job),
            "cave" => studio_kinds::cave(job),
            "grammar" => studio_kinds::topo(job),
            "goal" => studio_kinds::goal(job),
            _ => {
                let source = SourceFile::new(job.path.display().to_string(), job.text.clone());
                if grammar::is_goal_grammar(&source, None) {
                    studio_kinds::goal(job)
                } else {
                    derive_grammar(job)
                }
            }
        }
    }
}

/// Compiles and derives the job's text as its file, with its seed, attribute values and lot,
/// then writes the GLB (and the derivation tree, when asked for) or the files of its export
/// format.
fn derive_grammar(job: &DeriveJob) -> Derived {
    let (path, text) = (job.path.as_path(), job.text.as_str());
    let started = Instant::now();
    let source = SourceFile::new(path.display().to_string(), text.to_owned());
    // A rule file inside a rule package imports from the package, as `derive package.rpk` does.
    let (compiled, diagnostics) = match &job.package {
        Some(rule) => {
            let input = grammar::Input {
                source,
                files: Files::Package(Arc::clone(&rule.package)),
                path: PathBuf::from(&rule.entry),
            };
            grammar::compile_silently_in(&input, false, None)
        }
        None => grammar::compile_silently(&source, false, None),
    };
    let mut derived = Derived {
        diagnostics: diagnostics
            .iter()
            .map(|(file, d)| located(&compiled.sources, *file, d))
            .collect(),
        ..Derived::default()
    };
    let program = match compiled.program {
        Some(program) if compiled.errors == 0 => program,
        _ => {
            derived.derive_ms = millis(started.elapsed());
            return derived;
        }
    };
    let (lots, lot_notes) = match studio_settings::lots(job.lot.as_ref()) {
        Ok(found) => found,
        Err(message) => {
            derived.error = Some(message);
            return derived;
        }
    };
    derived.notes = lot_notes;
    derived.lots = lots.len();
    let assets = match &job.package {
        Some(rule) => {
            FileAssets::in_package(Arc::clone(&rule.package), &rule.entry, MissingAssets::Error)
        }
        None => {
            let folder = path.parent().unwrap_or(Path::new("")).to_path_buf();
            FileAssets::new(folder, MissingAssets::Error)
        }
    };
    let mut options = DeriveOptions {
        seed: job.seed,
        time_budget: Some(job.time_budget),
        assets: Some(Arc::new(assets)),
        keep_tree: job.tree && job.export.is_none(),
        generations: job.generations,
        control: Some(job.control.clone()),
        ..DeriveOptions::default()
    };
    options.attrs = match studio_settings::defaults(&program, &lots[0], &options) {
        Some(types) => {
            let (kept, dropped, notes) = studio_settings::overrides(&job.attrs, &types);
            derived.dropped = dropped;
            derived.notes.extend(notes);
            kept
        }
        None => job
            .attrs
            .iter()
            .filter(|(name, _)| program.attr(name).is_some())
            .filter_map(|(name, value)| Some((name.clone(), studio_settings::from_json(value)?)))
            .collect(),
    };
    derived.attrs = studio_settings::panel(&compiled.grammar, &program, &lots[0], &options);
    let derivation = match shapegram_eval::derive(&program, &lots, &options) {
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
    let exported = Instant::now();
    let tree = job.tree && job.export.is_none();
    let (mut model, faces) = if tree {
        derivation.to_model_with_faces()
    } else {
        (derivation.to_model(), Vec::new())
    };
    if let Err(e) = studio_kinds::pose(&mut model, job) {
        derived.error = Some(e);
        return derived;
    }
    if !tree {
        return studio_kinds::deliver(derived, &model, job, exported);
    }
    let mut glb = Vec::new();
    match shapegram_export::write_glb_with_layout(&model, &ExportOptions::default(), &mut glb) {
        Ok(layout) => {
            derived.glb = Some(glb);
            derived.tree = Some(studio_tree::tree(
                &derivation,
                &program,
                &compiled.grammar,
                &compiled.sources[0],
                (&model, &faces),
                layout,
            ));
        }
        Err(e) => derived.error = Some(format!("cannot write the GLB: {e}")),
    }
    derived.export_ms = millis(exported.elapsed());
    derived
}

/// Records a derivation's failure: a diagnostic where it has a place in the text, else the
/// error and its hints.
pub(crate) fn record_failure(derived: &mut Derived, sources: &[SourceFile], e: DeriveError) {
    match e.to_diagnostic() {
        Some(d) => derived
            .diagnostics
            .push(located(sources, e.file.unwrap_or(0), &d)),
        None => {
            derived.error = Some(e.message.replace('\n', " "));
            derived.hints = e.hints;
        }
    }
}

/// `d`, found in `sources[file]`, with its place as lines and columns.
pub(crate) fn located(sources: &[SourceFile], file: usize, d: &Diagnostic) -> StudioDiagnostic {
    let source = sources.get(file).unwrap_or(&sources[0]);
    let (line, column) = source.line_col(d.span.start);
    let (end_line, end_column) = source.line_col(d.span.end.max(d.span.start));
    StudioDiagnostic {
        severity: match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        },
        message: d.message.clone(),
        label: d.label.clone(),
        hints: d.hints.clone(),
        line,
        column,
        end_line,
        end_column,
        file: (file != 0).then(|| source.name().to_owned()),
    }
}
