//! Production lines and module sequences: `[left <] pred [> right] [(weight)] [: cond] -> succ`.

use rustc_hash::FxHashMap;

use super::Line;
use super::arrow_width;
use super::settings::constant;
use crate::cursor::{Cursor, describe};
use crate::error::{Error, Position};
use crate::expr::{self, Expr, Name};

/// Largest number of parameters of one module.
const MAX_ARITY: usize = 32;

/// Characters with a meaning of their own in the format, so never module names.
const RESERVED: &[char] = &['(', ')', ',', ':', '<', '>', '#'];

/// A module of a successor or the axiom before interning.
pub(super) struct RawModule {
    pub(super) name: char,
    pub(super) position: Position,
    pub(super) args: Vec<Expr>,
}

/// A module of a predecessor or context, with its formal parameters.
pub(super) struct PatternModule {
    pub(super) name: char,
    pub(super) position: Position,
    pub(super) formals: Vec<String>,
}

/// One production line before productions with the same left side are grouped.
pub(super) struct RawProduction {
    pub(super) position: Position,
    /// The left side's modules, arities and condition program: productions with equal keys are
    /// alternatives.
    pub(super) key: String,
    pub(super) left: Vec<PatternModule>,
    pub(super) predecessor: PatternModule,
    pub(super) right: Vec<PatternModule>,
    pub(super) condition: Option<Expr>,
    pub(super) weight: Option<f64>,
    pub(super) successor: Vec<RawModule>,
}

/// A sequence of modules with argument expressions (an axiom or a successor).
pub(super) fn modules(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
) -> Result<Vec<RawModule>, Error> {
    let mut result = Vec::new();
    while !cursor.at_end() {
        let position = cursor.position();
        let name = module_name(cursor)?;
        let mut args = Vec::new();
        if cursor.eat('(') {
            let after = format!("after a parameter of '{name}'");
            args = cursor.list_rest(&after, |cursor| expr::parse(cursor, names))?;
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
            formals = cursor.list_rest("after a parameter name", |cursor| {
                cursor.skip_space();
                cursor.identifier().ok_or_else(|| {
                    cursor.error(format!(
                        "expected a parameter name in the {what}, found {}",
                        describe(cursor.peek())
                    ))
                })
            })?;
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
pub(super) fn production(
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

    // Parameter names do not tell left sides apart: `A(x) (1) -> B` and `A(y) (1) -> C` are
    // alternatives of one stochastic production.
    let pattern = |modules: &[PatternModule]| -> String {
        modules
            .iter()
            .map(|m| format!("{}/{} ", m.name, m.formals.len()))
            .collect()
    };
    let key = format!(
        "{}< {}> {}: {}",
        pattern(&left),
        pattern(std::slice::from_ref(&predecessor)),
        pattern(&right),
        condition
            .as_ref()
            .map_or_else(String::new, Expr::program_key)
    );
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
