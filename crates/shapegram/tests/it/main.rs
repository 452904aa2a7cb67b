//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

mod asset_groups;
mod asset_materials;
mod cave;
mod cli;
#[path = "../common/mod.rs"]
mod common;
mod crash;
mod file_functions;
mod gallery;
mod goals;
mod imports;
mod instancing;
mod lsystem;
mod materials;
mod packages;
mod preview;
mod repo;
mod repo_derive;
mod serve;
mod studio;
mod studio_attrs;
mod studio_child;
mod tiles;
mod tiles_encoding;
mod tiles_metadata;
mod topo;
