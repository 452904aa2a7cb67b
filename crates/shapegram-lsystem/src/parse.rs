//! The text format: settings lines (`key: value`) and productions (`pred -> successor`), one
//! per line, `#` comments. See `docs/lsystem.md`.
//!
//! A file is read line by line: `settings` reads the settings, `production` the productions and
//! the axiom's modules, and `assemble` interns symbols and groups stochastic alternatives into
//! the [`LSystem`] the engine runs.

mod assemble;
mod production;
mod settings;

use rustc_hash::FxHashMap;

use crate::alphabet::Alphabet;
use crate::cursor::Cursor;
use crate::error::{Error, Position};
use crate::expr::Name;
use crate::system::{LSystem, Settings};

/// One line of the file as characters, with its number.
struct Line {
    number: u32,
    chars: Vec<char>,
    /// End of the content before any comment.
    end: usize,
}

impl Line {
    fn cursor(&self, start: usize, end: usize) -> Cursor<'_> {
        Cursor::new(&self.chars, start, end, self.number)
    }
}

/// Parses a whole file.
pub(crate) fn parse(text: &str) -> Result<LSystem, Error> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<Line> = text
        .lines()
        .enumerate()
        .map(|(i, line)| {
            let chars: Vec<char> = line.chars().collect();
            let end = comment_start(&chars);
            Line {
                number: i as u32 + 1,
                chars,
                end,
            }
        })
        .collect();

    let mut settings = Settings::default();
    let mut constants: FxHashMap<String, f64> = FxHashMap::default();
    let mut seen: FxHashMap<String, u32> = FxHashMap::default();
    let mut axiom_line: Option<(&Line, usize)> = None;
    let mut production_lines = Vec::new();
    let mut section = Section::Productions;

    for line in &lines {
        let mut cursor = line.cursor(0, line.end);
        if cursor.at_end() {
            continue;
        }
        if let Some(arrow) = find_arrow(&line.chars[..line.end]) {
            production_lines.push((line, arrow, section));
            continue;
        }
        if let Some(open) = unclosed_before_arrow(&line.chars[..line.end]) {
            return Err(Error::at(
                Position::new(line.number, open as u32 + 1),
                "this '(' is not closed before the production's arrow",
            ));
        }
        let key_start = cursor.index();
        let key = match directive(&line.chars) {
            Some((word, after)) => {
                cursor = line.cursor(after, line.end);
                cursor.skip_space();
                cursor.eat(':');
                word.to_string()
            }
            None => {
                if let Some(next) = section_of(&line.chars[..line.end]) {
                    section = next;
                    continue;
                }
                settings::setting_key(&mut cursor).ok_or_else(|| {
                    cursor.error("expected a setting like `n: 5` or a production like `A -> AB`")
                })?
            }
        };
        if key == "decomposition" {
            return Err(Error::at(
                cursor.position_of(key_start),
                "decomposition rules are not supported (interpretation rules are: `homomorphism:`)",
            ));
        }
        if key != "define"
            && let Some(first) = seen.insert(key.clone(), line.number)
        {
            return Err(Error::at(
                cursor.position_of(key_start),
                format!("'{key}' is set twice (first on line {first})"),
            ));
        }
        cursor.skip_space();
        match key.as_str() {
            "axiom" => axiom_line = Some((line, cursor.index())),
            "define" => {
                let (name, value) = settings::define(&mut cursor, &constants)?;
                constants.insert(name, value);
            }
            "colors" => {
                settings.colors =
                    settings::colors(&line.chars[..line.end], cursor.index(), line.number)?;
            }
            _ => settings::setting(&mut cursor, &key, key_start, &constants, &mut settings)?,
        }
    }

    let mut alphabet = Alphabet::default();
    let (axiom_line, axiom_start) = axiom_line
        .ok_or_else(|| Error::general("the L-system has no axiom: add a line like `axiom: F`"))?;
    let constant_names = |name: &str| constants.get(name).map(|&c| Name::Constant(c));
    let mut cursor = axiom_line.cursor(axiom_start, axiom_line.end);
    let axiom_modules = production::modules(&mut cursor, &constant_names)?;
    let axiom = assemble::build_axiom(&axiom_modules, &mut alphabet)?;

    let mut raws = Vec::new();
    let mut interpretation_raws = Vec::new();
    for (line, arrow, section) in production_lines {
        let raw = production::production(line, arrow, &constants)?;
        match section {
            Section::Productions => raws.push(raw),
            Section::Interpretation => interpretation_raws.push(raw),
        }
    }
    let produced = assemble::produced(&axiom_modules, raws.iter().chain(&interpretation_raws));
    let ignored = &settings.ignore;
    let productions = assemble::group(raws, &mut alphabet, &produced, ignored)?;
    let interpretation = assemble::group(interpretation_raws, &mut alphabet, &produced, ignored)?;
    Ok(LSystem::assemble(
        settings,
        alphabet,
        axiom,
        productions,
        interpretation,
    ))
}

/// Which rules a production line adds to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Section {
    /// The productions of the derivation.
    Productions,
    /// Interpretation rules, applied once before drawing (`homomorphism:`).
    Interpretation,
}

/// The section a line of L-Py's and cpfg's section syntax starts: `homomorphism:` (or
/// `interpretation:`) starts interpretation rules; `Lsystem: 1`, `production:` and `endlsystem`
/// go back to (or stay with) the derivation's productions. `None` for other lines.
fn section_of(chars: &[char]) -> Option<Section> {
    let text: String = chars.iter().collect::<String>().trim().to_lowercase();
    let head = text.split(':').next().unwrap_or("").trim();
    match head {
        "lsystem" | "production" | "productions" | "endlsystem" | "endrule" => {
            Some(Section::Productions)
        }
        "homomorphism" | "interpretation" => Some(Section::Interpretation),
        _ => None,
    }
}

/// Where a `#` comment starts (the line length when there is none). In `colors:` lines, a `#`
/// directly followed by a character other than a space starts a colour, not a comment.
fn comment_start(chars: &[char]) -> usize {
    let text: String = chars.iter().collect();
    let trimmed = text.trim_start();
    let is_colors = trimmed.starts_with("colors") || trimmed.starts_with("colours");
    let from = directive(chars).map_or(0, |(_, after)| after);
    (from..chars.len())
        .find(|&i| {
            chars[i] == '#' && !(is_colors && chars.get(i + 1).is_some_and(|c| !c.is_whitespace()))
        })
        .unwrap_or(chars.len())
}

/// The index of the `->` (or `→`) at parenthesis depth 0, if the line is a production.
fn find_arrow(chars: &[char]) -> Option<usize> {
    let mut depth = 0i32;
    for (i, &c) in chars.iter().enumerate() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if depth == 0 && is_arrow(chars, i) => return Some(i),
            _ => {}
        }
    }
    None
}

/// Whether an arrow starts at `i`: `→`, `->` or L-Py's and cpfg's long `-->`.
fn is_arrow(chars: &[char], i: usize) -> bool {
    match chars[i] {
        '→' => true,
        '-' => match chars.get(i + 1) {
            Some('>') => true,
            Some('-') => chars.get(i + 2) == Some(&'>'),
            _ => false,
        },
        _ => false,
    }
}

/// The `(` left open where an arrow stands inside parentheses (`F(x -> F`): the line is a
/// production with a typo, not a setting.
fn unclosed_before_arrow(chars: &[char]) -> Option<usize> {
    let mut open = Vec::new();
    for (i, &c) in chars.iter().enumerate() {
        match c {
            '(' => open.push(i),
            ')' => {
                open.pop();
            }
            _ if is_arrow(chars, i) => return open.last().copied(),
            _ => {}
        }
    }
    None
}

/// The width of the arrow at `index`: `→`, `->` or `-->`.
fn arrow_width(chars: &[char], index: usize) -> usize {
    match (chars[index], chars.get(index + 1)) {
        ('→', _) => 1,
        (_, Some('-')) => 3,
        _ => 2,
    }
}

/// A cpfg-style directive at the start of a line, `#define NAME value` or `#ignore: symbols`:
/// its kind and the index after its word.
fn directive(chars: &[char]) -> Option<(&'static str, usize)> {
    let start = chars.iter().position(|c| !c.is_whitespace())?;
    let rest: String = chars[start..].iter().take(8).collect();
    ["define", "ignore"].into_iter().find_map(|word| {
        let after = start + 1 + word.len();
        let boundary = chars
            .get(after)
            .is_none_or(|&c| c.is_whitespace() || c == ':');
        (rest.starts_with('#') && rest[1..].starts_with(word) && boundary).then_some((word, after))
    })
}
