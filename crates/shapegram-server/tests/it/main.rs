//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

#[macro_use]
mod common;
mod accounts;
mod authorization;
mod bad_input;
mod grammars;
mod names;
mod openapi;
mod previews;
mod queries;
mod rate_limit;
mod search;
mod store;
mod studio;
mod topo_studio;
mod yank;
