//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

mod bad_input;
mod examples;
mod grammar;
mod materials_and_offsets;
