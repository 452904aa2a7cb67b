//! Readable JSON for grammar and project files: pretty-printed, but arrays of numbers (points,
//! face loops, instructions) kept on one line each.

use serde::Serialize;

/// `value` as pretty JSON with scalar-only arrays on one line, ending in a newline.
pub(crate) fn to_text<T: Serialize>(value: &T) -> String {
    let pretty = serde_json::to_string_pretty(value).expect("file types serialise");
    let lines: Vec<&str> = pretty.lines().collect();
    let mut out = String::with_capacity(pretty.len() / 2);
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.ends_with('[')
            && let Some(end) = scalar_run_end(&lines, i + 1)
        {
            let items: Vec<&str> = lines[i + 1..end].iter().map(|l| l.trim()).collect();
            out.push_str(line);
            out.push_str(&items.join(" "));
            out.push_str(lines[end].trim());
            out.push('\n');
            i = end + 1;
            continue;
        }
        out.push_str(line);
        out.push('\n');
        i += 1;
    }
    out
}

/// The index of the `]` line closing an array whose elements, from line `start`, are all
/// scalars; `None` when an element is an array or object.
fn scalar_run_end(lines: &[&str], start: usize) -> Option<usize> {
    for (k, line) in lines.iter().enumerate().skip(start) {
        let item = line.trim();
        if item.starts_with(']') {
            return Some(k);
        }
        let scalar = item.starts_with(|c: char| c == '-' || c == '"' || c.is_ascii_alphanumeric())
            && !item.ends_with('[')
            && !item.ends_with('{');
        if !scalar {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_arrays_share_a_line_and_the_value_is_unchanged() {
        let value = serde_json::json!({
            "name": "a [b",
            "points": [[0.5, -1.0, 2.0], [3.0, 4.0, 1e-7]],
            "empty": [],
            "nested": [{"x": [1, 2]}],
        });
        let text = to_text(&value);
        assert!(text.contains("[0.5, -1.0, 2.0],"), "{text}");
        assert!(text.contains("\"x\": [1, 2]"), "{text}");
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, value);
    }
}
