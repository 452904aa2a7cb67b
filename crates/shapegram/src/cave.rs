//! `shapegram cave`: the implicit cave front end.

use clap::Args;

use crate::Failure;

/// Arguments of `shapegram cave`.
#[derive(Debug, Args)]
pub struct CaveArgs {}

/// Runs `shapegram cave`.
pub fn run(_args: &CaveArgs) -> Result<(), Failure> {
    Err(Failure::new("`shapegram cave` is not available yet"))
}
