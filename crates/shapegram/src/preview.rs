//! `shapegram preview-worker` (hidden): derives one goal grammar for the repository server's
//! previews (`shapegram_server::preview`) and writes its GLB on stdout.
//!
//! The grammar is untrusted. Before reading it, the worker limits itself with `setrlimit`: its
//! address space, CPU time, file sizes, no core dumps, and no file descriptors beyond stdin,
//! stdout and stderr, so that the kernel stops a runaway grammar and no file can be opened even
//! by mistake. Its assets refuse every file, naming it: `i("/etc/passwd")` is an error, not a
//! read. It derives on one thread, so CPU time and wall-clock time agree.
//!
//! Exit codes: 0 with the GLB on stdout; [`EXIT_DOES_NOT_DERIVE`] with a `WorkerFailure` as
//! JSON on stdout when the grammar does not compile or derive; [`EXIT_BAD_REQUEST`] when stdin
//! is not a request; 1 when a limit cannot be set.

use std::io::{Read, Write};
use std::sync::Arc;

use clap::Args;
use shapegram_eval::{Asset, AssetLoader, DeriveError, DeriveOptions, LibraryOptions, Program};
use shapegram_export::ExportOptions;
use shapegram_geom::Mesh;
use shapegram_implicit::Solid;
use shapegram_server::preview::{
    EXIT_BAD_REQUEST, EXIT_DOES_NOT_DERIVE, WorkerDiagnostic, WorkerFailure, WorkerRequest,
};
use shapegram_syntax::{Diagnostic, SourceFile};

use crate::Failure;

/// Largest request read from stdin: a grammar of 256 KiB escaped as JSON fits.
const MAX_REQUEST_BYTES: u64 = 2 << 20;

/// Arguments of `shapegram preview-worker`: the limits it sets on itself. The request comes on
/// stdin.
#[derive(Debug, Args)]
pub struct PreviewWorkerArgs {
    /// Address space in MiB (RLIMIT_AS)
    #[arg(long, value_name = "MIB")]
    pub memory_mib: Option<u64>,
    /// CPU time in seconds (RLIMIT_CPU: SIGXCPU then, SIGKILL a second later)
    #[arg(long, value_name = "SECONDS")]
    pub cpu_seconds: Option<u64>,
    /// Largest file written, in MiB (RLIMIT_FSIZE: stdout redirected to a file)
    #[arg(long, value_name = "MIB", default_value_t = 64)]
    pub max_output_mib: u64,
}

/// Sets the limits, reads the request, derives and writes the GLB or the failure.
pub fn run(args: &PreviewWorkerArgs) -> Result<(), Failure> {
    // One thread, started before the address space is limited (its stack is mapped now).
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .map_err(|e| Failure::new(format!("cannot start the derivation thread: {e}")))?;
    limit(args).map_err(|e| Failure::new(format!("cannot limit the preview worker: {e}")))?;
    let mut input = Vec::new();
    std::io::stdin()
        .take(MAX_REQUEST_BYTES)
        .read_to_end(&mut input)
        .map_err(|e| {
            Failure::new(format!("cannot read the request: {e}")).with_code(EXIT_BAD_REQUEST)
        })?;
    let request: WorkerRequest = serde_json::from_slice(&input).map_err(|e| {
        Failure::new(format!("the request is not a preview request: {e}"))
            .with_code(EXIT_BAD_REQUEST)
    })?;
    let model = match derive(&request) {
        Ok(model) => model,
        Err(failure) => {
            let text = serde_json::to_string(&failure)
                .map_err(|e| Failure::new(format!("cannot render JSON: {e}")))?;
            crate::print_stdout(&text)?;
            return Err(Failure::reported().with_code(EXIT_DOES_NOT_DERIVE));
        }
    };
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    shapegram_export::write_glb_to(&model, &ExportOptions::default(), &mut out)
        .and_then(|()| out.flush())
        .map_err(|e| Failure::new(format!("cannot write the GLB: {e}")))
}

/// The worker's limits on itself; the hard limits equal the soft ones (CPU: a second more), so
/// the grammar cannot raise them.
#[cfg(unix)]
fn limit(args: &PreviewWorkerArgs) -> std::io::Result<()> {
    use rlimit::{Resource, setrlimit};
    const MIB: u64 = 1 << 20;
    // An abort for want of memory would otherwise dump the whole address space.
    setrlimit(Resource::CORE, 0, 0)?;
    if let Some(mib) = args.memory_mib {
        setrlimit(Resource::AS, mib * MIB, mib * MIB)?;
    }
    if let Some(seconds) = args.cpu_seconds {
        setrlimit(Resource::CPU, seconds, seconds + 1)?;
    }
    let output = args.max_output_mib * MIB;
    setrlimit(Resource::FSIZE, output, output)?;
    // stdin, stdout and stderr are open; no other file can be.
    setrlimit(Resource::NOFILE, 3, 3)
}

#[cfg(not(unix))]
fn limit(_: &PreviewWorkerArgs) -> std::io::Result<()> {
    Err(std::io::Error::other("previews need a Unix system"))
}

/// The model of the grammar, derived on its own from its axioms, as `shapegram derive` does.
fn derive(request: &WorkerRequest) -> Result<shapegram_geom::Model, WorkerFailure> {
    let name = &request.name;
    let source = SourceFile::new(name.clone(), request.text.clone());
    let parsed = shapegram_syntax::parse(&source);
    let mut errors: Vec<&Diagnostic> = parsed.diagnostics.iter().filter(|d| d.is_error()).collect();
    let compiled;
    let program = if errors.is_empty() {
        // Open, as the server checked it on publish: other grammars may set the attributes it
        // reads (a rule reading one that no shape has does not apply).
        let options = LibraryOptions {
            repository_from: 1,
            open: true,
        };
        compiled = Program::compile_library_with(&[(name.as_str(), &parsed.grammar)], &options);
        errors.extend(compiled.1.iter().map(|(_, d)| d).filter(|d| d.is_error()));
        compiled.0.as_ref()
    } else {
        None
    };
    let program = match program {
        Some(program) if errors.is_empty() && program.is_goal_grammar() => program,
        _ => {
            return Err(WorkerFailure {
                error: format!("{name} does not compile as a goal grammar"),
                diagnostics: errors.iter().map(|d| located(&source, d)).collect(),
            });
        }
    };
    let options = DeriveOptions {
        seed: request.seed,
        max_steps: request.max_steps,
        assets: Some(Arc::new(NoFiles)),
        ..DeriveOptions::default()
    };
    let derivation = shapegram_eval::derive(program, &[], &options)
        .map_err(|e| does_not_derive(&source, request, &e))?;
    Ok(derivation.to_model())
}

/// A diagnostic with its line and column.
fn located(source: &SourceFile, d: &Diagnostic) -> WorkerDiagnostic {
    let (line, column) = source.line_col(d.span.start);
    WorkerDiagnostic {
        message: d.message.clone(),
        line,
        column,
        hints: d.hints.clone(),
    }
}

/// The failure of a derivation: the message, and the place when the error has one.
fn does_not_derive(source: &SourceFile, request: &WorkerRequest, e: &DeriveError) -> WorkerFailure {
    // The command line's advice means the server's limit here.
    let hints: Vec<String> = e
        .hints
        .iter()
        .map(|h| {
            if h.contains("--max-steps") {
                format!(
                    "previews stop after {} steps (the server's --preview-steps)",
                    request.max_steps
                )
            } else {
                h.clone()
            }
        })
        .collect();
    let message = e.message.replace('\n', " ");
    let diagnostics = match e.span {
        Some(span) => {
            let (line, column) = source.line_col(span.start);
            vec![WorkerDiagnostic {
                message: message.clone(),
                line,
                column,
                hints,
            }]
        }
        None => Vec::new(),
    };
    WorkerFailure {
        error: format!("{} does not derive: {message}", request.name),
        diagnostics,
    }
}

/// Assets that refuse every file: a preview's grammar reads nothing from the server's disk.
/// Built-in assets (`builtin:cube`) never ask. The engine names the path in the errors of
/// inserts and implicit grammars; the others name it here.
struct NoFiles;

/// Why nothing is read.
const NO_FILES: &str = "previews read no files";

impl AssetLoader for NoFiles {
    fn load(&self, _path: &str) -> Result<Arc<Mesh>, String> {
        Err(NO_FILES.to_owned())
    }

    fn asset(&self, _path: &str, _variant: u32) -> Result<Asset, String> {
        Err(NO_FILES.to_owned())
    }

    fn solid(&self, _path: &str) -> Result<Solid, String> {
        Err(NO_FILES.to_owned())
    }

    fn text(&self, path: &str) -> Result<Arc<str>, String> {
        Err(format!("cannot read `{path}`: {NO_FILES}"))
    }

    fn search(&self, query: &str) -> Result<Vec<Arc<str>>, String> {
        Err(format!("cannot search for `{query}`: {NO_FILES}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(text: &str) -> WorkerRequest {
        WorkerRequest {
            name: "probe".into(),
            text: text.into(),
            seed: 0,
            max_steps: 1_000,
        }
    }

    fn failure(text: &str) -> WorkerFailure {
        match derive(&request(text)) {
            Ok(_) => panic!("{text} derived"),
            Err(failure) => failure,
        }
    }

    #[test]
    fn every_file_function_is_refused_with_its_path() {
        for (call, expect) in [
            (
                r#"i("/etc/passwd")"#,
                "probe does not derive: cannot insert `/etc/passwd`: previews read no files",
            ),
            (
                r#"i("../../secret.obj")"#,
                "probe does not derive: cannot insert `../../secret.obj`: previews read no files",
            ),
            (
                r#"set(@T, readStringTable("/etc/hosts"))"#,
                "probe does not derive: cannot read `/etc/hosts`: previews read no files",
            ),
            (
                r#"set(@T, fileSearch("*.obj"))"#,
                "probe does not derive: cannot search for `*.obj`: previews read no files",
            ),
            (
                r#"implicit("/srv/grotto.cave")"#,
                "probe does not derive: cannot run `/srv/grotto.cave`: previews read no files",
            ),
        ] {
            let text = format!("axiom a size(1, 1, 1)\nfulfills(a) --> {call}\n");
            let failure = failure(&text);
            assert_eq!(failure.error, expect, "{call}");
            assert_eq!(failure.diagnostics.len(), 1, "{call}");
            assert_eq!(failure.diagnostics[0].line, 2, "{call}");
        }
    }

    #[test]
    fn an_attribute_another_grammar_would_set_leaves_its_rule_unused() {
        // `shapegram derive` refuses this grammar on its own (no grammar sets @Width); the
        // server published it, since another grammar may.
        let model = derive(&request(
            "axiom a size(1, 1, 1)\n\
             fulfills(a) --> split(x) { ~1 : +b }\n\
             fulfills(b) --> split(x) { @Width : void | ~1 : void }\n",
        ))
        .unwrap();
        let triangles: usize = model.parts.iter().map(|p| p.mesh.triangulate().len()).sum();
        assert_eq!(triangles, 12, "b is left a box with its goal open");
    }

    #[test]
    fn built_in_assets_are_inserted() {
        let model = derive(&request(
            "axiom a size(1, 1, 1)\nfulfills(a) --> i(\"builtin:cube\")\n",
        ))
        .unwrap();
        let triangles: usize = model.parts.iter().map(|p| p.mesh.triangulate().len()).sum();
        assert_eq!(triangles, 12);
    }

    #[test]
    fn a_grammar_without_axioms_or_one_that_does_not_compile_is_refused() {
        let library = failure("fulfills(wooden) --> color(\"#8b5a2b\")\n");
        assert_eq!(
            library.error,
            "probe does not derive: the grammar `probe` has no axiom to start from"
        );
        let broken = failure("axiom a size(1, 1, 1)\nfulfills(a) --> split(\n");
        assert_eq!(broken.error, "probe does not compile as a goal grammar");
        assert_eq!(broken.diagnostics[0].line, 2);
    }

    #[test]
    fn the_step_limit_is_named_with_the_servers_flag() {
        let failure = failure(
            "axiom a size(1, 1, 1)\n\
             fulfills(a) --> split(x) { ~1 : +b | ~1 : +b }\n\
             fulfills(b) --> split(x) { ~1 : +a | ~1 : +a }\n",
        );
        assert!(
            failure
                .error
                .starts_with("probe does not derive: the derivation took more than 1000 steps"),
            "{}",
            failure.error
        );
        assert!(
            failure.diagnostics[0]
                .hints
                .contains(&"previews stop after 1000 steps (the server's --preview-steps)".into()),
            "{:?}",
            failure.diagnostics
        );
    }
}
