//! `shapegram topo`: the topological split grammar front end.

use clap::Args;

use crate::Failure;

/// Arguments of `shapegram topo`.
#[derive(Debug, Args)]
pub struct TopoArgs {}

/// Runs `shapegram topo`.
pub fn run(_args: &TopoArgs) -> Result<(), Failure> {
    Err(Failure::new("`shapegram topo` is not available yet"))
}
