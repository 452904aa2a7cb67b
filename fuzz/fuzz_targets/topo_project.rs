//! A Shape Grammar Editor project (`.sgproj.json`) as `shapegram topo` and `topo compile` take
//! it: read, compiled, the grammar written and read back, then generated as a `.grammar` is.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_topo::{Grammar, Project, compile};

fuzz_target!(|text: &str| {
    let project = match Project::from_json(text) {
        Ok(project) => project,
        Err(error) => return drop(error.to_string()),
    };
    let grammar = match compile(&project) {
        Ok(grammar) => grammar,
        Err(error) => return drop(error.to_string()),
    };
    let written = grammar.to_json();
    let read = Grammar::from_json(&written).expect("a compiled grammar reads back");
    assert_eq!(read.to_json(), written, "a compiled grammar round-trips");
    shapegram_fuzz::generate(&grammar);
});
