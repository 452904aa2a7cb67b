//! The text format: settings lines (`key: value`) and productions (`pred -> successor`), one
//! per line, `#` comments. See `docs/lsystem.md`.

use rustc_hash::FxHashMap;
use shapegram_geom::Color;

use crate::alphabet::{Alphabet, Symbol, SymbolId};
use crate::cursor::{Cursor, describe};
use crate::error::{Error, Position};
use crate::expr::{self, Expr, Name};
use crate::system::{Alternative, LSystem, Production, Settings, SuccessorModule};
use crate::word::Word;

/// Largest accepted `n:`; more steps than this never finish for a growing word anyway.
const MAX_ITERATIONS: u32 = 10_000;
/// Largest number of parameters of one module.
const MAX_ARITY: usize = 32;
/// Characters with a meaning of their own in the format, so never module names.
const RESERVED: &[char] = &['(', ')', ',', ':', '<', '>', '#'];

/// The setting keys, for the hint on an unknown key.
const KEYS: &str =
    "n, angle, step, width, width-factor, seed, sides, colors, ignore, draw, move, define, axiom";

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

/// A module of a successor or the axiom before interning.
struct RawModule {
    name: char,
    position: Position,
    args: Vec<Expr>,
}

/// A module of a predecessor or context, with its formal parameters.
struct PatternModule {
    name: char,
    position: Position,
    formals: Vec<String>,
}

/// One production line before productions with the same left side are grouped.
struct RawProduction {
    position: Position,
    /// The left side without spaces or weight: productions with equal keys are alternatives.
    key: String,
    left: Vec<PatternModule>,
    predecessor: PatternModule,
    right: Vec<PatternModule>,
    condition: Option<Expr>,
    weight: Option<f64>,
    successor: Vec<RawModule>,
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

    for line in &lines {
        let mut cursor = line.cursor(0, line.end);
        if cursor.at_end() {
            continue;
        }
        if let Some(arrow) = find_arrow(&line.chars[..line.end]) {
            production_lines.push((line, arrow));
            continue;
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
                if is_section_marker(&line.chars[..line.end]) {
                    continue;
                }
                setting_key(&mut cursor).ok_or_else(|| {
                    cursor.error("expected a setting like `n: 5` or a production like `A -> AB`")
                })?
            }
        };
        if matches!(
            key.as_str(),
            "homomorphism" | "decomposition" | "interpretation"
        ) {
            return Err(Error::at(
                cursor.position_of(key_start),
                format!(
                    "{key} rules are not supported: write drawing symbols with `draw:` and `move:`"
                ),
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
                let (name, value) = define(&mut cursor, &constants)?;
                constants.insert(name, value);
            }
            "colors" => {
                settings.colors = colors(&line.chars[..line.end], cursor.index(), line.number)?;
            }
            _ => setting(&mut cursor, &key, key_start, &constants, &mut settings)?,
        }
    }

    let mut alphabet = Alphabet::default();
    let (axiom_line, axiom_start) = axiom_line
        .ok_or_else(|| Error::general("the L-system has no axiom: add a line like `axiom: F`"))?;
    let constant_names = |name: &str| constants.get(name).map(|&c| Name::Constant(c));
    let mut cursor = axiom_line.cursor(axiom_start, axiom_line.end);
    let axiom_modules = modules(&mut cursor, &constant_names)?;
    let axiom = build_axiom(&axiom_modules, &mut alphabet)?;

    let mut raws = Vec::with_capacity(production_lines.len());
    for (line, arrow) in production_lines {
        raws.push(production(line, arrow, &constants)?);
    }
    let productions = group(raws, &mut alphabet, &axiom_modules)?;
    Ok(LSystem::assemble(settings, alphabet, axiom, productions))
}

/// Whether the line is one of L-Py's and cpfg's section lines (`Lsystem: 1`, `production:`,
/// `endlsystem`), which carry nothing here.
fn is_section_marker(chars: &[char]) -> bool {
    let text: String = chars.iter().collect::<String>().trim().to_lowercase();
    let head = text.split(':').next().unwrap_or("").trim();
    matches!(
        head,
        "lsystem" | "production" | "productions" | "endlsystem" | "endrule"
    )
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
            '→' if depth == 0 => return Some(i),
            '-' if depth == 0 && chars.get(i + 1) == Some(&'>') => return Some(i),
            // L-Py's and cpfg's long arrow.
            '-' if depth == 0
                && chars.get(i + 1) == Some(&'-')
                && chars.get(i + 2) == Some(&'>') =>
            {
                return Some(i);
            }
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

/// Reads `key:` and returns the key, lower-case, with the aliases of other notations mapped to
/// ours (`derivation length:` as in L-Py and cpfg, `ω:` and `δ:` as in ABOP).
fn setting_key(cursor: &mut Cursor) -> Option<String> {
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

/// `define: name = expression` (the `=` may be left out, as in cpfg's `#define name value`).
fn define(cursor: &mut Cursor, constants: &FxHashMap<String, f64>) -> Result<(String, f64), Error> {
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
fn constant(cursor: &mut Cursor, constants: &FxHashMap<String, f64>) -> Result<f64, Error> {
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
fn setting(
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
fn colors(chars: &[char], start: usize, line: u32) -> Result<Vec<Color>, Error> {
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

/// A sequence of modules with argument expressions (an axiom or a successor).
fn modules(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
) -> Result<Vec<RawModule>, Error> {
    let mut result = Vec::new();
    while !cursor.at_end() {
        let position = cursor.position();
        let name = module_name(cursor)?;
        let mut args = Vec::new();
        if cursor.eat('(') {
            loop {
                args.push(expr::parse(cursor, names)?);
                cursor.skip_space();
                if cursor.eat(',') {
                    continue;
                }
                if cursor.eat(')') {
                    break;
                }
                return Err(cursor.error(format!(
                    "expected ',' or ')' after a parameter of '{name}', found {}",
                    describe(cursor.peek())
                )));
            }
        }
        check_arity(name, args.len(), position)?;
        result.push(RawModule {
            name,
            position,
            args,
        });
    }
    Ok(result)
}

/// A module name: any character but whitespace and the reserved ones.
fn module_name(cursor: &mut Cursor) -> Result<char, Error> {
    match cursor.peek() {
        Some(c) if !RESERVED.contains(&c) => {
            cursor.bump();
            Ok(c)
        }
        other => Err(cursor.error(format!(
            "expected a module, found {}{}",
            describe(other),
            if other == Some('(') {
                " (parameters follow their module without a space: F(1))"
            } else {
                ""
            }
        ))),
    }
}

/// Brackets carry no parameters; other modules at most [`MAX_ARITY`].
fn check_arity(name: char, arity: usize, position: Position) -> Result<(), Error> {
    if (name == '[' || name == ']') && arity > 0 {
        return Err(Error::at(position, format!("'{name}' takes no parameters")));
    }
    if arity > MAX_ARITY {
        return Err(Error::at(
            position,
            format!("'{name}' has {arity} parameters; at most {MAX_ARITY} are allowed"),
        ));
    }
    Ok(())
}

/// Modules with formal parameter names (a predecessor or a context).
fn patterns(cursor: &mut Cursor, what: &str) -> Result<Vec<PatternModule>, Error> {
    let mut result = Vec::new();
    while !cursor.at_end() {
        let position = cursor.position();
        let name = module_name(cursor)?;
        let mut formals = Vec::new();
        if cursor.eat('(') {
            loop {
                cursor.skip_space();
                let formal = cursor.identifier().ok_or_else(|| {
                    cursor.error(format!(
                        "expected a parameter name in the {what}, found {}",
                        describe(cursor.peek())
                    ))
                })?;
                formals.push(formal);
                cursor.skip_space();
                if cursor.eat(',') {
                    continue;
                }
                if cursor.eat(')') {
                    break;
                }
                return Err(cursor.error(format!(
                    "expected ',' or ')' after a parameter name, found {}",
                    describe(cursor.peek())
                )));
            }
        }
        check_arity(name, formals.len(), position)?;
        result.push(PatternModule {
            name,
            position,
            formals,
        });
    }
    Ok(result)
}

/// Indices of the top-level (parenthesis depth 0) occurrences of `c` in `chars[start..end]`.
fn top_level(chars: &[char], start: usize, end: usize, c: char) -> Vec<usize> {
    let mut depth = 0i32;
    let mut found = Vec::new();
    for (i, &d) in chars.iter().enumerate().take(end).skip(start) {
        match d {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ if d == c && depth == 0 => found.push(i),
            _ => {}
        }
    }
    found
}

/// Parses one production line; `arrow` is where its arrow starts.
fn production(
    line: &Line,
    arrow: usize,
    constants: &FxHashMap<String, f64>,
) -> Result<RawProduction, Error> {
    let chars = &line.chars;
    let position = Position::new(line.number, 1);
    let start = label_end(line, arrow);
    let colon = top_level(chars, start, arrow, ':').first().copied();
    let main_end = colon.unwrap_or(arrow);
    let (main_end, weight) = weight(line, start, main_end, constants)?;
    let lt = top_level(chars, start, main_end, '<');
    let gt = top_level(chars, start, main_end, '>');
    if lt.len() > 1 {
        return Err(Error::at(
            Position::new(line.number, lt[1] as u32 + 1),
            "a production has at most one left context '<'",
        ));
    }
    if gt.len() > 1 {
        return Err(Error::at(
            Position::new(line.number, gt[1] as u32 + 1),
            "a production has at most one right context '>'",
        ));
    }
    let pred_start = lt.first().map_or(start, |&i| i + 1);
    let pred_end = gt.first().copied().unwrap_or(main_end);
    if pred_end < pred_start {
        return Err(Error::at(
            Position::new(line.number, pred_end as u32 + 1),
            "the right context '>' must come after the left context '<'",
        ));
    }
    let left = match lt.first() {
        Some(&i) => patterns(&mut line.cursor(start, i), "left context")?,
        None => Vec::new(),
    };
    if let Some(bracket) = left.iter().find(|m| m.name == '[' || m.name == ']') {
        return Err(Error::at(
            bracket.position,
            "a left context cannot hold brackets: it is read along the path to the root",
        ));
    }
    let right = match gt.first() {
        Some(&i) => patterns(&mut line.cursor(i + 1, main_end), "right context")?,
        None => Vec::new(),
    };
    let mut pred_cursor = line.cursor(pred_start, pred_end);
    let mut predecessor = patterns(&mut pred_cursor, "predecessor")?;
    if predecessor.len() != 1 {
        let at = predecessor
            .get(1)
            .map_or(pred_cursor.position(), |m| m.position);
        return Err(Error::at(
            at,
            format!(
                "the predecessor must be exactly one module, found {}{}",
                predecessor.len(),
                if predecessor.len() > 1 {
                    " (write contexts with < and >)"
                } else {
                    ""
                }
            ),
        ));
    }
    let predecessor = predecessor.remove(0);
    if left.is_empty() && !lt.is_empty() {
        return Err(Error::at(
            Position::new(line.number, lt[0] as u32 + 1),
            "expected a left context before '<'",
        ));
    }
    if right.is_empty() && !gt.is_empty() {
        return Err(Error::at(
            Position::new(line.number, gt[0] as u32 + 1),
            "expected a right context after '>'",
        ));
    }

    // Variables: the predecessor's parameters, then each context module's, left to right.
    let mut formals: Vec<&str> = Vec::new();
    for module in std::iter::once(&predecessor).chain(&left).chain(&right) {
        for name in &module.formals {
            if formals.contains(&name.as_str()) {
                return Err(Error::at(
                    module.position,
                    format!("the parameter name '{name}' is used twice in this production"),
                ));
            }
            formals.push(name);
        }
    }
    let names = |name: &str| {
        formals
            .iter()
            .position(|&n| n == name)
            .map(|i| Name::Variable(i as u16))
            .or_else(|| constants.get(name).map(|&c| Name::Constant(c)))
    };
    let condition = match colon {
        Some(c) => {
            let mut cursor = line.cursor(c + 1, arrow);
            let expr = expr::parse(&mut cursor, &names)?;
            if !cursor.at_end() {
                return Err(cursor.error(format!(
                    "unexpected {} after the condition{}",
                    describe(cursor.peek()),
                    if cursor.peek() == Some('(') {
                        " (a weight goes before the condition: `A(x) (0.5) : x > 1 -> …`)"
                    } else {
                        ""
                    }
                )));
            }
            Some(expr)
        }
        None => None,
    };
    let mut cursor = line.cursor(arrow + arrow_width(chars, arrow), line.end);
    let successor = modules(&mut cursor, &names)?;

    let key: String = chars[start..main_end]
        .iter()
        .chain(colon.map_or(&[][..], |c| &chars[c..arrow]))
        .filter(|c| !c.is_whitespace())
        .collect();
    let position = Position {
        column: predecessor.position.column,
        ..position
    };
    Ok(RawProduction {
        position,
        key,
        left,
        predecessor,
        right,
        condition,
        weight,
        successor,
    })
}

/// Where the production starts after an ABOP-style label like `p1:` (0 without a label).
fn label_end(line: &Line, arrow: usize) -> usize {
    let mut cursor = line.cursor(0, arrow);
    cursor.skip_space();
    if !cursor.eat('p') {
        return 0;
    }
    let digits = cursor.index();
    while cursor.peek().is_some_and(|c| c.is_ascii_digit()) {
        cursor.bump();
    }
    if cursor.index() == digits {
        return 0;
    }
    cursor.skip_space();
    if cursor.eat(':') { cursor.index() } else { 0 }
}

/// Splits a trailing weight `(0.33)` off `chars[start..end]`: a parenthesised constant after
/// whitespace. Returns the new end and the weight.
fn weight(
    line: &Line,
    start: usize,
    end: usize,
    constants: &FxHashMap<String, f64>,
) -> Result<(usize, Option<f64>), Error> {
    let chars = &line.chars;
    let mut last = end;
    while last > start && chars[last - 1].is_whitespace() {
        last -= 1;
    }
    if last == start || chars[last - 1] != ')' {
        return Ok((end, None));
    }
    let mut depth = 0;
    let mut open = last - 1;
    loop {
        match chars[open] {
            ')' => depth += 1,
            '(' => depth -= 1,
            _ => {}
        }
        if depth == 0 || open == start {
            break;
        }
        open -= 1;
    }
    if chars[open] != '(' || open == start || !chars[open - 1].is_whitespace() {
        return Ok((end, None));
    }
    let mut cursor = line.cursor(open + 1, last - 1);
    let position = cursor.position();
    let value = constant(&mut cursor, constants).map_err(|e| {
        Error::at(
            e.position.unwrap_or(position),
            format!(
                "{} (a weight in parentheses must be a number; parameters follow their module without a space: F(x))",
                e.message
            ),
        )
    })?;
    if value <= 0.0 {
        return Err(Error::at(
            position,
            format!("a weight must be positive, not {value}"),
        ));
    }
    Ok((open, Some(value)))
}

/// Interns the axiom's modules and evaluates their (constant) parameters.
fn build_axiom(modules: &[RawModule], alphabet: &mut Alphabet) -> Result<Word, Error> {
    let mut word = Word::default();
    for module in modules {
        word.symbols.push(intern(
            alphabet,
            module.name,
            module.args.len(),
            module.position,
        )?);
        for arg in &module.args {
            let value = arg.constant().unwrap_or(f64::NAN);
            if !value.is_finite() {
                return Err(Error::at(arg.position, "the value is not a finite number"));
            }
            word.params.push(value);
        }
    }
    Ok(word)
}

/// The id of a symbol, or an error when the alphabet is full.
fn intern(
    alphabet: &mut Alphabet,
    name: char,
    arity: usize,
    position: Position,
) -> Result<SymbolId, Error> {
    alphabet
        .intern(Symbol {
            name,
            arity: arity as u8,
        })
        .ok_or_else(|| Error::at(position, "too many different symbols (at most 65,535)"))
}

/// Groups productions with the same left side (stochastic alternatives), interns their symbols
/// and checks that contexts can ever match.
fn group(
    raws: Vec<RawProduction>,
    alphabet: &mut Alphabet,
    axiom: &[RawModule],
) -> Result<Vec<Production>, Error> {
    // Every symbol a word can hold: the axiom's and the successors'.
    let mut produced: Vec<Symbol> = axiom
        .iter()
        .map(|m| Symbol {
            name: m.name,
            arity: m.args.len() as u8,
        })
        .collect();
    for raw in &raws {
        produced.extend(raw.successor.iter().map(|m| Symbol {
            name: m.name,
            arity: m.args.len() as u8,
        }));
    }

    let mut order: Vec<String> = Vec::new();
    let mut groups: FxHashMap<String, Vec<RawProduction>> = FxHashMap::default();
    for raw in raws {
        if !groups.contains_key(&raw.key) {
            order.push(raw.key.clone());
        }
        groups.entry(raw.key.clone()).or_default().push(raw);
    }

    let mut productions = Vec::with_capacity(order.len());
    for key in order {
        let members = groups.remove(&key).unwrap_or_default();
        if members.len() > 1 {
            // Point at a later line when possible: the first one is usually the intended rule.
            let unweighted = (1..members.len())
                .chain([0])
                .find(|&k| members[k].weight.is_none());
            if let Some(k) = unweighted {
                let other = if k == 0 { 1 } else { 0 };
                return Err(Error::at(
                    members[k].position,
                    format!(
                        "another production with the same left side is on line {}: give each alternative a weight, as in `{} (0.5) -> …`",
                        members[other].position.line, members[k].predecessor.name
                    ),
                ));
            }
        }
        productions.push(build_production(members, alphabet, &produced)?);
    }
    Ok(productions)
}

/// One production from its alternatives (all with the same left side).
fn build_production(
    members: Vec<RawProduction>,
    alphabet: &mut Alphabet,
    produced: &[Symbol],
) -> Result<Production, Error> {
    let first = &members[0];
    let pattern_id = |alphabet: &mut Alphabet, module: &PatternModule, context: bool| {
        let symbol = Symbol {
            name: module.name,
            arity: module.formals.len() as u8,
        };
        let structural = module.name == '[' || module.name == ']';
        if context && !structural && !produced.contains(&symbol) {
            let mut arities: Vec<u8> = produced
                .iter()
                .filter(|s| s.name == symbol.name)
                .map(|s| s.arity)
                .collect();
            arities.sort_unstable();
            arities.dedup();
            let others: Vec<String> = arities.iter().map(u8::to_string).collect();
            return Err(Error::at(
                module.position,
                if others.is_empty() {
                    format!(
                        "unknown symbol '{}' in a context: it is in neither the axiom nor any successor, so the production could never apply",
                        module.name
                    )
                } else {
                    format!(
                        "'{}' never has {} parameter{} in a word (it has {}), so this context could never match",
                        module.name,
                        symbol.arity,
                        if symbol.arity == 1 { "" } else { "s" },
                        others.join(" or ")
                    )
                },
            ));
        }
        intern(alphabet, module.name, module.formals.len(), module.position)
    };
    let predecessor = pattern_id(alphabet, &first.predecessor, false)?;
    let mut variables = first.predecessor.formals.len();
    let mut context = |alphabet: &mut Alphabet, modules: &[PatternModule]| {
        let mut ids = Vec::with_capacity(modules.len());
        let mut bases = Vec::with_capacity(modules.len());
        for module in modules {
            ids.push(pattern_id(alphabet, module, true)?);
            bases.push(variables as u16);
            variables += module.formals.len();
        }
        Ok::<_, Error>((ids, bases))
    };
    let (left, left_vars) = context(alphabet, &first.left)?;
    let (right, right_vars) = context(alphabet, &first.right)?;

    let total: f64 = members.iter().map(|m| m.weight.unwrap_or(1.0)).sum();
    let mut cumulative = 0.0;
    let mut alternatives = Vec::with_capacity(members.len());
    let count = members.len();
    let condition = first.condition.clone();
    for (k, member) in members.into_iter().enumerate() {
        cumulative += member.weight.unwrap_or(1.0) / total;
        let mut modules = Vec::with_capacity(member.successor.len());
        for module in member.successor {
            modules.push(SuccessorModule {
                symbol: intern(alphabet, module.name, module.args.len(), module.position)?,
                args: module.args,
            });
        }
        alternatives.push(Alternative {
            // The last alternative takes every draw below 1, whatever the rounding.
            cumulative: if k + 1 == count { 1.0 } else { cumulative },
            modules,
        });
    }
    Ok(Production {
        predecessor,
        left,
        left_vars,
        right,
        right_vars,
        condition,
        alternatives,
        variables,
    })
}
