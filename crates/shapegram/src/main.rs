//! The `shapegram` command: parses the command line, runs one subcommand, reports failure as one
//! `error: ...` line on stderr with exit code 1 (2 for usage errors).

mod cli;
mod info;
mod primitive;

use std::io::{self, Write};
use std::process::ExitCode;

use clap::Parser;

use cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Primitive(args) => primitive::run(args),
        Command::Info(args) => info::run(args),
        Command::Derive(_) => Err(Failure {
            message: "derive is not available yet: the grammar engine lands with the \
                      grammar-language issue"
                .into(),
            code: 2,
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            eprintln!("error: {}", failure.message);
            ExitCode::from(failure.code)
        }
    }
}

/// Why a command failed: a one-line message (without the `error: ` prefix) and the exit code.
#[derive(Debug)]
pub struct Failure {
    message: String,
    code: u8,
}

impl Failure {
    /// A failure with exit code 1.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            code: 1,
        }
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
