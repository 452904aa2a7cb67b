//! Settings lines: `key: value`, `define: name = value`, `colors: …`.

use rustc_hash::FxHashMap;
use shapegram_geom::Color;

use crate::cursor::{Cursor, describe};
use crate::error::{Error, Position};
use crate::expr::{self, Name};
use crate::rewrite::MAX_ITERATIONS;
use crate::system::Settings;

/// The setting keys, for the hint on an unknown key.
const KEYS: &str =
    "n, angle, step, width, width-factor, seed, sides, colors, ignore, draw, move, define, axiom";

/// Reads `key:` and returns the key, lower-case, with the aliases of other notations mapped to
/// ours (`derivation length:` as in L-Py and cpfg, `ω:` and `δ:` as in ABOP).
pub(super) fn setting_key(cursor: &mut Cursor) -> Option<String> {
    let start = cursor.index();
    while cursor
        .peek()
        .is_some_and(|c| c.is_alphanumeric() || c == '-' || c == '_' || c == ' ')
    {
        cursor.bump();
    }
    let key = cursor.text_since(start).trim_end().to_lowercase();
    cursor.skip_space();
    if key.is_empty() || !cursor.eat(':') {
        return None;
    }
    Some(
        match key.as_str() {
            "ω" => "axiom",
            "δ" | "delta" => "angle",
            "derivation length" | "derivation-length" | "iterations" => "n",
            "colours" => "colors",
            other => other,
        }
        .to_string(),
    )
}

/// `define: name = expression` (the `=` may be left out, as in cpfg's `#define name value`).
pub(super) fn define(
    cursor: &mut Cursor,
    constants: &FxHashMap<String, f64>,
) -> Result<(String, f64), Error> {
    let name = cursor
        .identifier()
        .ok_or_else(|| cursor.error("expected a name after `define:`, as in `define: r = 0.5`"))?;
    cursor.skip_space();
    if !cursor.eat('=') && cursor.at_end() {
        return Err(cursor.error(format!(
            "expected '=' after the name '{name}', found {}",
            describe(cursor.peek())
        )));
    }
    let value = constant(cursor, constants)?;
    Ok((name, value))
}

/// An expression over constants only, and nothing after it.
pub(super) fn constant(
    cursor: &mut Cursor,
    constants: &FxHashMap<String, f64>,
) -> Result<f64, Error> {
    let names = |name: &str| constants.get(name).map(|&c| Name::Constant(c));
    let expr = expr::parse(cursor, &names)?;
    if !cursor.at_end() {
        return Err(cursor.error(format!(
            "unexpected {} after the value",
            describe(cursor.peek())
        )));
    }
    let value = expr.constant().unwrap_or(f64::NAN);
    if !value.is_finite() {
        return Err(Error::at(expr.position, "the value is not a finite number"));
    }
    Ok(value)
}

/// A numeric or symbol-list setting.
pub(super) fn setting(
    cursor: &mut Cursor,
    key: &str,
    key_start: usize,
    constants: &FxHashMap<String, f64>,
    settings: &mut Settings,
) -> Result<(), Error> {
    let value_position = cursor.position();
    let symbols = |cursor: &mut Cursor| {
        let mut names = Vec::new();
        while let Some(c) = cursor.bump() {
            if !c.is_whitespace() {
                names.push(c);
            }
        }
        names
    };
    let number = |cursor: &mut Cursor| constant(cursor, constants);
    let positive = |cursor: &mut Cursor| {
        let value = constant(cursor, constants)?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(Error::at(
                value_position,
                format!("{key} must be positive, not {value}"),
            ))
        }
    };
    let whole = |cursor: &mut Cursor, max: f64| {
        let value = constant(cursor, constants)?;
        if value.fract() == 0.0 && (0.0..=max).contains(&value) {
            Ok(value)
        } else {
            Err(Error::at(
                value_position,
                format!("{key} must be a whole number from 0 to {max}, not {value}"),
            ))
        }
    };
    match key {
        "n" => settings.iterations = whole(cursor, f64::from(MAX_ITERATIONS))? as u32,
        "angle" => settings.angle = number(cursor)?,
        "step" => settings.step = positive(cursor)?,
        "width" => settings.width = positive(cursor)?,
        "width-factor" => settings.width_factor = positive(cursor)?,
        "seed" => settings.seed = whole(cursor, 2f64.powi(53))? as u64,
        "sides" => {
            let sides = whole(cursor, 64.0)?;
            if sides < 3.0 {
                return Err(Error::at(value_position, "sides must be at least 3"));
            }
            settings.sides = sides as u32;
        }
        "ignore" => {
            settings.ignore = symbols(cursor);
            if settings.ignore.iter().any(|&c| c == '[' || c == ']') {
                return Err(Error::at(
                    value_position,
                    "brackets cannot be ignored: they give words their branch structure",
                ));
            }
        }
        "draw" => settings.draw = symbols(cursor),
        "move" => settings.moves = symbols(cursor),
        _ => {
            return Err(Error::at(
                cursor.position_of(key_start),
                format!("unknown setting '{key}' (the settings are: {KEYS})"),
            ));
        }
    }
    Ok(())
}

/// `colors: #rrggbb …`.
pub(super) fn colors(chars: &[char], start: usize, line: u32) -> Result<Vec<Color>, Error> {
    let mut result = Vec::new();
    let mut i = start;
    while i < chars.len() {
        if chars[i].is_whitespace() {
            i += 1;
            continue;
        }
        let begin = i;
        while i < chars.len() && !chars[i].is_whitespace() {
            i += 1;
        }
        let word: String = chars[begin..i].iter().collect();
        let color = Color::from_hex(&word).ok_or_else(|| {
            Error::at(
                Position::new(line, begin as u32 + 1),
                format!("invalid colour '{word}': expected #rrggbb"),
            )
        })?;
        result.push(color);
    }
    if result.is_empty() {
        return Err(Error::at(
            Position::new(line, start as u32 + 1),
            "expected at least one colour like #3f7d3a",
        ));
    }
    Ok(result)
}
