//! Feeds arbitrary UTF-8 to the parser and renders every diagnostic: neither may panic, and
//! every span must lie on character boundaries inside the text.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_syntax::{SourceFile, parse};

fuzz_target!(|text: &str| {
    let source = SourceFile::new("fuzz.cga", text);
    shapegram_fuzz::render(&source, &parse(&source).diagnostics);
});
