//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

mod common;
mod compact;
mod errors;
mod features;
mod files;
mod instancing;
mod layout;
mod materials;
mod round_trip;
mod skins;
mod smooth_and_lines;
mod svg;
mod textures;
mod threads;
