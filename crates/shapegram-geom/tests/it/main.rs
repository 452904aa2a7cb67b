//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

#[path = "../common/mod.rs"]
mod common;
mod deform;
mod fit;
mod kernel;
mod occlusion;
mod offsets;
mod perimeter;
mod primitives;
mod roofs;
mod setback;
mod split;
mod split_props;
mod triangulate;
