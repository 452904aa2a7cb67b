//! The `shapegram` command: parses the command line, runs one subcommand, reports failure as one
//! `error: ...` line on stderr with exit code 1 (2 for usage errors).

mod cave;
mod check;
mod cli;
mod derive;
mod grammar;
mod info;
mod lots;
mod lsystem;
mod pose;
mod preview;
mod primitive;
mod progress;
mod repo;
mod resolve;
mod serve;
mod studio;
mod studio_kinds;
mod studio_settings;
mod studio_tree;
mod tiles;
mod topo;

use std::io::{self, Write};
use std::process::ExitCode;

use clap::Parser;

use cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Primitive(args) => primitive::run(args),
        Command::Info(args) => info::run(args),
        Command::Derive(args) => derive::run(args),
        Command::Check(args) => check::run(args),
        Command::Lsystem(args) => lsystem::run(args),
        Command::Cave(args) => cave::run(args),
        Command::Topo(args) => topo::run(args),
        Command::Serve(args) => serve::run(args),
        Command::Studio(args) => studio::run(args),
        Command::Repo(args) => repo::run(args),
        Command::Tiles(args) => tiles::run(args),
        Command::PreviewWorker(args) => preview::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            failure.print();
            ExitCode::from(failure.code)
        }
    }
}

/// Why a command failed: a one-line message (without the `error: ` prefix), hints printed as
/// `  = hint: …` lines after it, and the exit code.
#[derive(Debug)]
pub struct Failure {
    /// `None` when the command has already printed why it failed.
    message: Option<String>,
    hints: Vec<String>,
    code: u8,
}

impl Failure {
    /// A failure with exit code 1.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: Some(message.into()),
            hints: Vec::new(),
            code: 1,
        }
    }

    /// A usage error: exit code 2, as for a bad command line.
    pub fn usage(message: impl Into<String>) -> Self {
        Self {
            code: 2,
            ..Self::new(message)
        }
    }

    /// A failure with exit code 1 whose explanation has already been printed.
    pub fn reported() -> Self {
        Self {
            message: None,
            hints: Vec::new(),
            code: 1,
        }
    }

    /// The same failure with another exit code (2: usage errors, no connection).
    pub fn with_code(mut self, code: u8) -> Self {
        self.code = code;
        self
    }

    /// Prints the message and hints on stderr, unless they have been printed already.
    pub fn print(&self) {
        if let Some(message) = &self.message {
            eprintln!("error: {message}");
            for hint in &self.hints {
                eprintln!("  = hint: {hint}");
            }
        }
    }

    /// The same failure with `= hint:` lines.
    pub fn with_hints(mut self, hints: impl IntoIterator<Item = String>) -> Self {
        self.hints.extend(hints);
        self
    }
}

/// `n` with the singular or plural noun: `1 lot`, `2 lots`.
pub fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

impl From<shapegram_runtime::Error> for Failure {
    fn from(error: shapegram_runtime::Error) -> Self {
        Self::new(error.message)
    }
}

impl From<shapegram_export::Error> for Failure {
    fn from(error: shapegram_export::Error) -> Self {
        Self::new(error.to_string())
    }
}

/// Writes `text` to stdout. A closed pipe (`shapegram info x.glb | head -1`) is not a failure:
/// the reader has all it wanted.
pub fn print_stdout(text: &str) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => {
            Err(Failure::new(format!("cannot write to stdout: {e}")))
        }
        _ => Ok(()),
    }
}
