//! `shapegram tiles merge`, and the report of `derive --tiles`, whose lots are written as a 3D
//! Tiles tileset by `shapegram_runtime::tiles` (docs/tiles.md).

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use shapegram_export::tiles::TilesetSummary;

pub use shapegram_runtime::tiles::{Tiling, stream, write};

use crate::{Failure, counted};

/// Arguments of `shapegram tiles`.
#[derive(Debug, Args)]
pub struct TilesArgs {
    /// What to do with tilesets.
    #[command(subcommand)]
    pub command: TilesCommand,
}

/// Subcommands of `shapegram tiles`.
#[derive(Debug, Subcommand)]
pub enum TilesCommand {
    /// Join the shards written by `derive --tiles DIR --shard K/N` into one tileset
    Merge(MergeArgs),
}

/// Arguments of `shapegram tiles merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The folders the shards wrote (one may hold several shards)
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// The tileset's folder: the tiles are copied there and tileset.json written
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Print nothing but errors
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `shapegram tiles`.
pub fn run(args: &TilesArgs) -> Result<(), Failure> {
    match &args.command {
        TilesCommand::Merge(merge) => {
            let summary = shapegram_export::tiles::merge(&merge.dirs, &merge.out)?;
            if !merge.quiet {
                eprintln!("wrote {}", described(&merge.out, &summary));
            }
            Ok(())
        }
    }
}

/// `city/tileset.json: 16 near tiles, 4 far tiles of 32 lots`.
pub fn described(dir: &Path, summary: &TilesetSummary) -> String {
    format!(
        "{}: {}, {} of {}",
        dir.join("tileset.json").display(),
        counted(summary.near, "near tile", "near tiles"),
        counted(summary.far, "far tile", "far tiles"),
        counted(summary.lots, "lot", "lots")
    )
}
