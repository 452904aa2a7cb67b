//! A compiled `.grammar` file as `shapegram topo` takes it: read, its first symbol generated for
//! eight generations (at most 2,000 shapes), the model measured and written.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_topo::Grammar;

fuzz_target!(|text: &str| {
    match Grammar::from_json(text) {
        Ok(grammar) => shapegram_fuzz::generate(&grammar),
        Err(error) => drop(error.to_string()),
    }
});
