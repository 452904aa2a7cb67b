//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

#[path = "../common/mod.rs"]
mod common;
mod dialects;
mod errors;
mod goal;
mod michelangelo;
mod parse;
mod suggest;
