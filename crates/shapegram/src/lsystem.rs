//! `shapegram lsystem`: the L-system front end.

use clap::Args;

use crate::Failure;

/// Arguments of `shapegram lsystem`.
#[derive(Debug, Args)]
pub struct LsystemArgs {}

/// Runs `shapegram lsystem`.
pub fn run(_args: &LsystemArgs) -> Result<(), Failure> {
    Err(Failure::new("`shapegram lsystem` is not available yet"))
}
