//! Source files: line/column lookup and rustc-style rendering of diagnostics.

use std::fmt::Write as _;

use crate::diagnostic::{Diagnostic, Severity};

/// How many columns a tab takes when a source line is shown under a diagnostic.
const TAB_WIDTH: usize = 4;

/// A named grammar text with an index of its line starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceFile {
    name: String,
    text: String,
    /// Byte offset of the first byte of each line; always starts with 0.
    line_starts: Vec<u32>,
}

impl SourceFile {
    /// A source file called `name` (usually its path) holding `text`.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        let text = text.into();
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| (i + 1) as u32))
            .collect();
        Self {
            name: name.into(),
            text,
            line_starts,
        }
    }

    /// The file's name as given to [`SourceFile::new`].
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The whole text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The 1-based line and column (counted in characters) of a byte offset; offsets past the
    /// end or inside a multi-byte character are clamped to the previous character boundary.
    pub fn line_col(&self, offset: u32) -> (usize, usize) {
        let offset = self.floor_boundary(offset as usize);
        let line = self.line_index(offset);
        let start = self.line_starts[line] as usize;
        (line + 1, self.text[start..offset].chars().count() + 1)
    }

    /// Renders `d` the way rustc does (without colours), ending with a newline:
    ///
    /// ```text
    /// error: expected `:` after the split size
    ///   --> facade.cga:12:19
    ///    |
    /// 12 |     split(y){ 4.5 Ground | ~3 : Floor }*
    ///    |                   ^^^^^^ expected `:` here
    ///    = hint: …
    /// ```
    ///
    /// Only the first line of a multi-line span is shown; tabs are expanded to four spaces.
    pub fn render(&self, d: &Diagnostic) -> String {
        let start = self.floor_boundary(d.span.start as usize);
        let end = self.floor_boundary(d.span.end as usize).max(start);
        let (line, col) = self.line_col(start as u32);
        let line_start = self.line_starts[line - 1] as usize;
        let line_end = self.text[line_start..]
            .find('\n')
            .map_or(self.text.len(), |i| line_start + i);
        let source_line = self.text[line_start..line_end].trim_end_matches('\r');
        let before = &source_line[..(start - line_start).min(source_line.len())];
        let marked = &self.text[start..end.min(line_end)];

        let gutter = line.to_string().len();
        let pad = " ".repeat(gutter);
        let severity = match d.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let carets = "^".repeat(display_width(marked).max(1));

        let mut out = String::new();
        // Writing to a String cannot fail.
        let _ = writeln!(out, "{severity}: {}", d.message);
        let _ = writeln!(out, "{pad}--> {}:{line}:{col}", self.name);
        let _ = writeln!(out, "{pad} |");
        let _ = writeln!(out, "{line} | {}", expand_tabs(source_line));
        let _ = write!(out, "{pad} | {}{carets}", " ".repeat(display_width(before)));
        match &d.label {
            Some(label) => {
                let _ = writeln!(out, " {label}");
            }
            None => out.push('\n'),
        }
        for hint in &d.hints {
            let _ = writeln!(out, "{pad} = hint: {hint}");
        }
        out
    }

    fn line_index(&self, offset: usize) -> usize {
        self.line_starts
            .partition_point(|&s| s as usize <= offset)
            .saturating_sub(1)
    }

    fn floor_boundary(&self, offset: usize) -> usize {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        offset
    }
}

/// Columns `s` takes on screen with tabs expanded.
fn display_width(s: &str) -> usize {
    s.chars()
        .map(|c| if c == '\t' { TAB_WIDTH } else { 1 })
        .sum()
}

fn expand_tabs(s: &str) -> String {
    s.replace('\t', &" ".repeat(TAB_WIDTH))
}
