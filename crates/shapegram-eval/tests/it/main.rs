//! The integration tests, one module per concern, built as one binary: a binary per file
//! linked the whole crate graph once each, which cost CI minutes and gigabytes of disk.

mod align;
mod arrays;
mod asset_functions;
mod boolean;
mod chair_examples;
mod common;
mod context;
mod deform;
mod engine;
mod examples;
mod footprint_ops;
mod goal_examples;
mod goals;
mod implicit;
mod imports;
mod incremental;
mod instances;
mod kinematics;
mod kinematics_examples;
mod michelangelo;
mod named_poses;
mod papers;
mod perimeter;
mod pivot;
mod reference_functions;
mod roof_options;
mod selectors;
mod setback;
mod snapshot;
mod split;
mod tables;
mod tags;
mod texturing;
mod tree;
mod wild_forms;
