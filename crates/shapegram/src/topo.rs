//! `shapegram topo`: run a topological split grammar (Shape Grammar Editor) to a model, or
//! compile an editor project into a `.grammar` file.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use shapegram_export::{ExportOptions, Format};
use shapegram_topo::{
    Grammar, GrammarMesh, GrammarState, PROJECT_FORMAT, Project, SEED_MASK, compile,
};

use crate::{Failure, counted};

/// Arguments of `shapegram topo`.
#[derive(Debug, Args)]
#[command(
    args_conflicts_with_subcommands = true,
    long_about = "Run a topological split grammar (the Shape Grammar Editor's), or compile an \
        editor project.\n\n\
        `shapegram topo GRAMMAR` starts from the prototype shape of --symbol and rewrites every \
        non-terminal shape once per generation, choosing among a symbol's rules at random \
        (weighted, from --seed), then writes every shape left as GLB, OBJ or STL: one part per \
        symbol, in the symbol's colour. GRAMMAR is a compiled `.grammar` file or a project file \
        (compiled on the fly). `shapegram topo compile PROJECT -o GRAMMAR.grammar` writes the \
        compiled grammar. The formats are described in docs/topo.md.",
    after_help = "Examples:\n  \
        shapegram topo examples/topo_house.grammar --symbol House --generations 8 --seed 0x2a -o house.glb\n  \
        shapegram topo examples/topo_pyramid.sgproj.json --generations 4 -o pyramid.stl\n  \
        shapegram topo compile examples/topo_house.sgproj.json -o house.grammar"
)]
pub struct TopoArgs {
    /// Compile a project instead of running a grammar
    #[command(subcommand)]
    pub command: Option<TopoCommand>,
    /// The `.grammar` file (or project file) to run
    #[arg(value_name = "GRAMMAR")]
    pub grammar: Option<PathBuf>,
    /// The symbol to start from [default: the first symbol]
    #[arg(long, value_name = "NAME")]
    pub symbol: Option<String>,
    /// Number of generations
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(0..=10_000))]
    pub generations: u32,
    /// Seed of the rule choices: a 48-bit number, decimal or hexadecimal (0x2a)
    #[arg(long, value_name = "SEED", default_value = "0", value_parser = parse_seed)]
    pub seed: u64,
    /// Stop with an error when a generation would hold more shapes than this
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    pub max_shapes: usize,
    /// Output file; its extension picks the format: .glb, .obj (writes a .mtl beside it) or .stl.
    /// Without it nothing is written
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Keep one group per symbol (OBJ groups, glTF nodes) instead of merging by colour
    #[arg(long)]
    pub group: bool,
    /// Do not print the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
}

/// Subcommands of `shapegram topo`.
#[derive(Debug, Subcommand)]
pub enum TopoCommand {
    /// Compile a project file into a `.grammar` file
    Compile(CompileArgs),
}

/// Arguments of `shapegram topo compile`.
#[derive(Debug, Args)]
pub struct CompileArgs {
    /// The project file
    #[arg(value_name = "PROJECT")]
    pub project: PathBuf,
    /// The `.grammar` file to write
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Do not print the summary line on stderr
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `shapegram topo`.
pub fn run(args: &TopoArgs) -> Result<(), Failure> {
    match &args.command {
        Some(TopoCommand::Compile(compile_args)) => run_compile(compile_args),
        None => run_grammar(args),
    }
}

/// Loads, generates, meshes and writes.
fn run_grammar(args: &TopoArgs) -> Result<(), Failure> {
    let Some(path) = &args.grammar else {
        return Err(Failure::new(
            "missing GRAMMAR: `shapegram topo GRAMMAR.grammar -o model.glb` or `shapegram topo \
             compile PROJECT -o GRAMMAR.grammar`",
        ));
    };
    if let Some(output) = &args.output {
        Format::from_path(output)?;
    }
    let grammar = load_grammar(path)?;
    let symbol = match &args.symbol {
        Some(name) => name.clone(),
        None => grammar
            .symbol_names()
            .first()
            .map(|s| (*s).to_owned())
            .ok_or_else(|| {
                Failure::new(format!("{}: the grammar has no symbol", path.display()))
            })?,
    };
    let mut state = GrammarState::new(&grammar, &symbol)
        .map_err(|e| Failure::new(e.to_string()))?
        .with_seed(args.seed)
        .with_generations(args.generations);
    state.max_shapes = args.max_shapes;
    state
        .generate_all()
        .map_err(|e| Failure::new(e.to_string()))?;
    let mesh = GrammarMesh::new(&state);
    let summary = format!(
        "{} from {symbol}: {} ({} terminal), {}",
        counted(state.generation() as usize, "generation", "generations"),
        counted(
            state.terminals().len() + state.non_terminals().len(),
            "shape",
            "shapes"
        ),
        state.terminals().len(),
        counted(mesh.triangle_count(), "triangle", "triangles")
    );
    match &args.output {
        Some(output) => {
            let options = ExportOptions {
                group_by_part: args.group,
                ..ExportOptions::default()
            };
            shapegram_export::save(&mesh.to_model(), output, &options)?;
            if !args.quiet {
                eprintln!("wrote {}: {summary}", output.display());
            }
        }
        None if !args.quiet => eprintln!("{summary} (nothing written: no -o)"),
        None => {}
    }
    Ok(())
}

/// Compiles a project and writes the grammar, never over the project itself.
fn run_compile(args: &CompileArgs) -> Result<(), Failure> {
    let text = read(&args.project)?;
    let project =
        Project::from_json(&text).map_err(|e| located(&args.project, &e.location, &e.message))?;
    let grammar = compile(&project).map_err(|e| located(&args.project, &e.location, &e.message))?;
    if same_file(&args.project, &args.output) {
        return Err(Failure::new(format!(
            "refusing to overwrite the project {} with its grammar: choose another -o",
            args.project.display()
        )));
    }
    write_replacing(&args.output, grammar.to_json().as_bytes())?;
    if !args.quiet {
        let non_terminals = grammar
            .symbols
            .iter()
            .filter(|s| !s.rules.is_empty())
            .count();
        eprintln!(
            "wrote {}: {} ({non_terminals} non-terminal), {}",
            args.output.display(),
            counted(grammar.symbols.len(), "symbol", "symbols"),
            counted(grammar.rules.len(), "rule", "rules")
        );
    }
    Ok(())
}

/// A grammar from a `.grammar` file, or compiled from a project file.
fn load_grammar(path: &Path) -> Result<Grammar, Failure> {
    let text = read(path)?;
    let is_project = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("format").and_then(|f| f.as_str()).map(str::to_owned))
        .is_some_and(|f| f == PROJECT_FORMAT);
    if is_project {
        let project =
            Project::from_json(&text).map_err(|e| located(path, &e.location, &e.message))?;
        compile(&project).map_err(|e| located(path, &e.location, &e.message))
    } else {
        Grammar::from_json(&text).map_err(|e| located(path, &e.location, &e.message))
    }
}

fn read(path: &Path) -> Result<String, Failure> {
    std::fs::read_to_string(path)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", path.display())))
}

/// `file:line:column: message` for JSON syntax errors, `file: path: message` otherwise.
fn located(path: &Path, location: &str, message: &str) -> Failure {
    let separator = if location.starts_with(|c: char| c.is_ascii_digit()) {
        ":"
    } else {
        ": "
    };
    Failure::new(format!(
        "{}{separator}{location}: {message}",
        path.display()
    ))
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Writes through a temporary file beside `path`, so a failed write leaves no half file.
fn write_replacing(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    let mut temporary = path.as_os_str().to_owned();
    temporary.push(".partial");
    let temporary = PathBuf::from(temporary);
    std::fs::write(&temporary, bytes)
        .and_then(|()| std::fs::rename(&temporary, path))
        .map_err(|e| {
            let _ = std::fs::remove_file(&temporary);
            Failure::new(format!("cannot write {}: {e}", path.display()))
        })
}

/// A seed: decimal or `0x` hexadecimal, below 2^48.
fn parse_seed(text: &str) -> Result<u64, String> {
    let text = text.trim();
    let parsed = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => text.parse::<u64>(),
    };
    match parsed {
        Ok(seed) if seed <= SEED_MASK => Ok(seed),
        Ok(_) => Err("seeds are 48-bit: at most 0xffffffffffff".into()),
        Err(_) => Err("expected a number like 42 or 0x2a".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_seed;

    #[test]
    fn seeds_are_decimal_or_hex_and_48_bit() {
        assert_eq!(parse_seed("0x2a"), Ok(42));
        assert_eq!(parse_seed("42"), Ok(42));
        assert_eq!(parse_seed("0XFFFFFFFFFFFF"), Ok((1 << 48) - 1));
        assert!(parse_seed("0x1000000000000").is_err());
        assert!(parse_seed("-1").is_err());
        assert!(parse_seed("0xg").is_err());
    }
}
