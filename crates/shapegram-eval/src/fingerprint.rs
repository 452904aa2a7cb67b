//! Fingerprints of a grammar's parts, for deriving again after an edit: two rules with the same
//! fingerprint compile to the same thing wherever they stand in the file.

use std::fmt::{Debug, Write};
use std::hash::Hasher;

use rustc_hash::FxHasher;
use shapegram_syntax::ast::Grammar;

/// What a derivation depends on in a grammar, apart from its rules' bodies.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Fingerprints {
    /// The attributes, constants and functions, and each rule's name, parameters and
    /// annotations: when any of these change, every rule may compile differently.
    pub frame: u64,
    /// Each rule's body and parameters, by rule.
    pub rules: Vec<u64>,
    /// Where each rule starts in the file: spans kept in the output (implicit solids keep the
    /// span of the operation that made them) move with it.
    pub starts: Vec<u32>,
}

impl Fingerprints {
    /// The fingerprints of a parsed grammar.
    pub fn of(grammar: &Grammar) -> Self {
        let mut frame = Printer::default();
        frame.add(&grammar.attrs);
        frame.add(&grammar.consts);
        frame.add(&grammar.functions);
        for rule in &grammar.rules {
            frame.add(&(&rule.annotations, &rule.name, rule.params.len()));
        }
        Self {
            frame: frame.finish(),
            rules: grammar
                .rules
                .iter()
                .map(|r| {
                    let mut p = Printer::default();
                    p.add(&(&r.params, &r.body));
                    p.finish()
                })
                .collect(),
            starts: grammar.rules.iter().map(|r| r.span.start).collect(),
        }
    }
}

/// Hashes the `Debug` text of syntax trees without their spans, so that an item that only moved
/// in the file hashes the same.
#[derive(Default)]
struct Printer {
    text: String,
    hasher: FxHasher,
}

/// How the derived `Debug` of a span starts.
const SPAN: &str = "Span { start: ";

impl Printer {
    fn add(&mut self, item: &impl Debug) {
        self.text.clear();
        write!(self.text, "{item:?}").expect("writing to a string cannot fail");
        let mut rest = self.text.as_str();
        while let Some(at) = rest.find(SPAN) {
            self.hasher.write(&rest.as_bytes()[..at]);
            rest = &rest[at..];
            // The span's text ends at its closing brace: `Span { start: 3, end: 9 }`.
            let close = rest.find('}').map_or(rest.len(), |i| i + 1);
            rest = &rest[close..];
        }
        self.hasher.write(rest.as_bytes());
        self.hasher.write_u8(0xff);
    }

    fn finish(&self) -> u64 {
        self.hasher.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_syntax::{SourceFile, parse};

    fn prints(text: &str) -> Fingerprints {
        let parsed = parse(&SourceFile::new("t.cga", text));
        assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
        Fingerprints::of(&parsed.grammar)
    }

    #[test]
    fn moving_a_rule_keeps_its_fingerprint_and_editing_it_does_not() {
        let a = prints("Lot --> extrude(10) Mass\nMass --> comp(f) { top: Roof }\n");
        let moved = prints("\n\n  Lot -->   extrude(10) Mass\nMass --> comp(f) { top: Roof }\n");
        let edited = prints("Lot --> extrude(11) Mass\nMass --> comp(f) { top: Roof }\n");
        assert_eq!(a.frame, moved.frame);
        assert_eq!(a.rules, moved.rules);
        assert_ne!(a.starts, moved.starts);
        assert_eq!(a.frame, edited.frame);
        assert_ne!(a.rules[0], edited.rules[0]);
        assert_eq!(a.rules[1], edited.rules[1]);
    }

    #[test]
    fn attributes_and_rule_lists_are_the_frame() {
        let a = prints("attr h = 10\nLot --> extrude(h) Mass\n");
        let attr = prints("attr h = 12\nLot --> extrude(h) Mass\n");
        let rule = prints("attr h = 10\nLot --> extrude(h) Mass\nMass --> X\n");
        assert_ne!(a.frame, attr.frame);
        assert_eq!(a.rules[0], attr.rules[0]);
        assert_ne!(a.frame, rule.frame);
    }
}
