//! Feeds arbitrary UTF-8 to the parser and renders every diagnostic: neither may panic, and
//! every span must lie on character boundaries inside the text.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_syntax::{SourceFile, parse};

fuzz_target!(|text: &str| {
    let source = SourceFile::new("fuzz.cga", text);
    let parsed = parse(&source);
    for d in &parsed.diagnostics {
        let (start, end) = (d.span.start as usize, d.span.end as usize);
        assert!(
            start <= end && end <= text.len(),
            "span out of range: {:?}",
            d.span
        );
        assert!(text.is_char_boundary(start) && text.is_char_boundary(end));
        source.render(d);
    }
});
