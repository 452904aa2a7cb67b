//! A CGA grammar (or one in the papers' notations) as `shapegram derive` takes it: parsed,
//! compiled and derived on the default lot under small limits, the model measured and written.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_fuzz::{compile, default_lot, derive};
use shapegram_syntax::SourceFile;

fuzz_target!(|text: &str| {
    let source = SourceFile::new("fuzz.cga", text);
    if let Some(program) = compile(&source) {
        derive(&source, &program, &[default_lot()]);
    }
});
