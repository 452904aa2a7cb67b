//! The text form of cave grammars (`.cave` files): settings, named solids and productions, one
//! statement per line. See `docs/implicit.md` for the reference.
//!
//! ```text
//! lod 12
//! let hall = box(4, 2.5, 3)
//! add hall
//! repeat 3 {
//!   add sphere(rand(1.2, 1.8)) at +x
//! }
//! morph hall 40% at +x
//! ```

use std::fmt;

use glam::DVec3;

use crate::cave::{Attach, CaveBuilder, CaveParams, Direction, GENERATED_OVERLAP, Operation, grow};
use crate::error::ImplicitError;
use crate::primitive::Primitive;
use crate::rng::Rng;
use crate::shape::Shape;

/// The message for a `repeat` block without its `}`, reported at the `repeat`.
const UNCLOSED: &str = "this 'repeat' block has no '}' to close it";

/// Most productions one run may apply (counting every pass of every `repeat`): the base is a
/// chain of one node per production.
pub const MAX_PRODUCTIONS: u64 = 1000;
/// Most operators and transforms in one expression.
const MAX_OPERATORS: usize = 256;
/// Deepest nesting of parentheses and `repeat` blocks.
const MAX_DEPTH: usize = 64;

/// An error in a `.cave` text, at a 1-based line and column (in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextError {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for TextError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

impl std::error::Error for TextError {}

/// A place in the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pos {
    line: usize,
    column: usize,
}

impl Pos {
    fn error(self, message: impl Into<String>) -> TextError {
        TextError {
            line: self.line,
            column: self.column,
            message: message.into(),
        }
    }

    fn wrap(self, error: ImplicitError) -> TextError {
        self.error(error.message())
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Name(String),
    /// A number and how many characters it took.
    Number(f64, usize),
    Punct(char),
}

impl Token {
    fn describe(&self) -> String {
        match self {
            Self::Name(n) => format!("'{n}'"),
            Self::Number(v, _) => format!("number {v}"),
            Self::Punct(c) => format!("'{c}'"),
        }
    }
}

/// Splits one line into tokens with their positions; `#` starts a comment.
fn lex(line: &str, line_no: usize) -> Result<Vec<(Token, Pos)>, TextError> {
    let chars: Vec<char> = line.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let pos = Pos {
            line: line_no,
            column: i + 1,
        };
        if c == '#' {
            break;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push((Token::Name(chars[start..i].iter().collect()), pos));
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let text: String = chars[start..i].iter().collect();
            let value: f64 = text
                .parse()
                .map_err(|_| pos.error(format!("invalid number '{text}'")))?;
            if !value.is_finite() {
                return Err(pos.error(format!("number '{text}' is too large")));
            }
            tokens.push((Token::Number(value, i - start), pos));
        } else if "(),.+-&{}=%".contains(c) {
            tokens.push((Token::Punct(c), pos));
            i += 1;
        } else {
            return Err(pos.error(format!("unexpected character '{}'", c.escape_debug())));
        }
    }
    Ok(tokens)
}

/// A number in the text: a literal or `rand(lo, hi)`, drawn each time it is evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Num {
    Literal(f64),
    Rand(f64, f64),
}

impl Num {
    fn value(self, rng: &mut Rng) -> f64 {
        match self {
            Self::Literal(v) => v,
            Self::Rand(lo, hi) => rng.range(lo, hi),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Expr {
    Primitive(String, Vec<Num>, Pos),
    /// A use of the definition with this index (the nearest `let` above it).
    Name(usize, Pos),
    Binary(char, Box<Expr>, Box<Expr>, Pos),
    Morph(Box<Expr>, Box<Expr>, Num, Pos),
    Smooth(String, Box<Expr>, Box<Expr>, Num, Pos),
    Move(Box<Expr>, [Num; 3], Pos),
    Rotate(Box<Expr>, DVec3, Num, Pos),
    Scale(Box<Expr>, [Num; 3], Pos),
}

#[derive(Clone, Debug, PartialEq)]
enum Statement {
    Production(Operation, Num, Expr, Option<Attach>, Pos),
    Repeat(u64, Vec<Statement>, Pos),
    Direction(Direction),
    Generate(CaveParams, Pos),
}

/// A parsed `.cave` text.
#[derive(Clone, Debug, PartialEq)]
pub struct CaveProgram {
    /// `lod N`: the level of detail, if the text sets one.
    pub lod: Option<u32>,
    /// `seed N` (default 1).
    pub seed: u64,
    /// `overlap X` (default 0.25): how far joined shapes reach into the base.
    pub overlap: f64,
    statements: Vec<Statement>,
    /// The bodies of the `let` definitions, in text order.
    definitions: Vec<Expr>,
}

/// The result of running a program.
#[derive(Clone, Debug)]
pub struct CaveRun {
    /// The base after the last production.
    pub builder: CaveBuilder,
}

const PRIMITIVES: [(&str, usize); 7] = [
    ("sphere", 1),
    ("box", 3),
    ("cylinder", 2),
    ("cone", 2),
    ("pyramid", 3),
    ("torus", 2),
    ("capsule", 2),
];

/// Parses a `.cave` text.
pub fn parse(text: &str) -> Result<CaveProgram, TextError> {
    let mut lines = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let tokens = lex(line, n + 1)?;
        if !tokens.is_empty() {
            lines.push(tokens);
        }
    }
    let mut program = CaveProgram {
        lod: None,
        seed: 1,
        overlap: GENERATED_OVERLAP,
        statements: Vec::new(),
        definitions: Vec::new(),
    };
    let mut settings_seen: Vec<(String, Pos)> = Vec::new();
    let mut parser = Parser {
        lines: &lines,
        line: 0,
        at: 0,
        names: Vec::new(),
        defining: None,
        operators: 0,
        end: Pos {
            line: text.lines().count().max(1),
            column: 1,
        },
    };
    program.statements = parser.block(&mut program, &mut settings_seen, 0)?;
    Ok(program)
}

struct Parser<'a> {
    lines: &'a [Vec<(Token, Pos)>],
    line: usize,
    at: usize,
    end: Pos,
    /// Names defined so far with their definition index; later ones shadow earlier ones.
    names: Vec<(String, usize)>,
    /// The name whose definition is being parsed.
    defining: Option<String>,
    /// Operators and transforms in the statement being parsed.
    operators: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<&(Token, Pos)> {
        self.lines.get(self.line).and_then(|l| l.get(self.at))
    }

    /// Where the next token is, or the end of the current line.
    fn here(&self) -> Pos {
        match (self.peek(), self.lines.get(self.line)) {
            (Some((_, p)), _) => *p,
            (None, Some(line)) => {
                let (last, p) = line.last().expect("lines are not empty");
                let width = match last {
                    Token::Name(n) => n.chars().count(),
                    Token::Number(_, width) => *width,
                    Token::Punct(_) => 1,
                };
                Pos {
                    line: p.line,
                    column: p.column + width,
                }
            }
            (None, None) => self.end,
        }
    }

    fn next(&mut self) -> Option<(Token, Pos)> {
        let t = self.peek().cloned();
        if t.is_some() {
            self.at += 1;
        }
        t
    }

    fn expected(&self, what: &str) -> TextError {
        match self.peek() {
            Some((t, p)) => p.error(format!("expected {what}, found {}", t.describe())),
            None => self
                .here()
                .error(format!("expected {what} before the end of the line")),
        }
    }

    fn eat(&mut self, c: char) -> bool {
        if self.peek().is_some_and(|(t, _)| *t == Token::Punct(c)) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: char) -> Result<(), TextError> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(self.expected(&format!("'{c}'")))
        }
    }

    fn keyword(&mut self, word: &str) -> bool {
        if self
            .peek()
            .is_some_and(|(t, _)| *t == Token::Name(word.into()))
        {
            self.at += 1;
            true
        } else {
            false
        }
    }

    fn end_of_line(&self) -> Result<(), TextError> {
        match self.peek() {
            None => Ok(()),
            Some(_) => Err(self.expected("the end of the line")),
        }
    }

    /// Statements up to a closing `}` (when `depth > 0`) or the end of the text.
    fn block(
        &mut self,
        program: &mut CaveProgram,
        settings: &mut Vec<(String, Pos)>,
        depth: usize,
    ) -> Result<Vec<Statement>, TextError> {
        let mut statements = Vec::new();
        while self.line < self.lines.len() {
            self.at = 0;
            self.operators = 0;
            if self.eat('}') {
                if depth == 0 {
                    return Err(self.lines[self.line][0]
                        .1
                        .error("'}' without a 'repeat' block to close"));
                }
                self.end_of_line()?;
                self.line += 1;
                return Ok(statements);
            }
            if let Some(s) = self.statement(program, settings, depth)? {
                statements.push(s);
            }
        }
        if depth > 0 {
            return Err(self.end.error(UNCLOSED));
        }
        Ok(statements)
    }

    /// One statement starting a line; leaves the parser on the next line.
    fn statement(
        &mut self,
        program: &mut CaveProgram,
        settings: &mut Vec<(String, Pos)>,
        depth: usize,
    ) -> Result<Option<Statement>, TextError> {
        let Some((Token::Name(word), pos)) = self.next() else {
            return Err(self.lines[self.line][0]
                .1
                .error("expected a statement: lod, seed, overlap, direction, let, add, subtract, intersect, morph, repeat or generate"));
        };
        let mut setting = |name: &str| -> Result<(), TextError> {
            if depth > 0 {
                return Err(pos.error(format!(
                    "'{name}' must be at the top level, not inside 'repeat'"
                )));
            }
            if let Some((_, first)) = settings.iter().find(|(n, _)| n == name) {
                return Err(pos.error(format!(
                    "'{name}' is set twice (first at {}:{})",
                    first.line, first.column
                )));
            }
            settings.push((name.to_string(), pos));
            Ok(())
        };
        let statement = match word.as_str() {
            "lod" => {
                setting("lod")?;
                let (v, p) = self.number()?;
                if !(v.fract() == 0.0 && (1.0..=32.0).contains(&v)) {
                    return Err(p.error(format!(
                        "invalid level of detail {v}: expected a whole number from 1 to 32"
                    )));
                }
                program.lod = Some(v as u32);
                None
            }
            "seed" => {
                setting("seed")?;
                program.seed = self.whole("seed", u64::MAX)?;
                None
            }
            "overlap" => {
                setting("overlap")?;
                let (v, p) = self.number()?;
                if !(0.0..=1.0).contains(&v) {
                    return Err(p.error(format!("invalid overlap {v}: expected 0 to 1")));
                }
                program.overlap = v;
                None
            }
            "direction" => Some(Statement::Direction(self.direction()?)),
            "let" => {
                let Some((Token::Name(name), name_pos)) = self.next() else {
                    return Err(self.expected("a name after 'let'"));
                };
                if is_reserved(&name) {
                    return Err(name_pos.error(format!(
                        "'{name}' is a reserved word and cannot name a solid"
                    )));
                }
                self.expect('=')?;
                self.defining = Some(name.clone());
                let body = self.expr(0);
                self.defining = None;
                program.definitions.push(body?);
                self.names.push((name, program.definitions.len() - 1));
                None
            }
            "add" | "subtract" | "intersect" | "morph" => {
                let expr = self.expr(0)?;
                let (operation, amount) = match word.as_str() {
                    "add" => (Operation::Sum, Num::Literal(0.0)),
                    "subtract" => (Operation::Difference, Num::Literal(0.0)),
                    "intersect" => (Operation::Intersection, Num::Literal(0.0)),
                    _ => {
                        let amount = self.num()?;
                        self.expect('%')?;
                        (Operation::Morph(0.0), amount)
                    }
                };
                let attach = if self.keyword("at") {
                    Some(if self.keyword("centre") || self.keyword("center") {
                        Attach::Centre
                    } else {
                        Attach::Bond(self.direction()?)
                    })
                } else {
                    None
                };
                Some(Statement::Production(operation, amount, expr, attach, pos))
            }
            "repeat" => {
                if depth >= MAX_DEPTH {
                    return Err(pos.error(format!("'repeat' blocks nest deeper than {MAX_DEPTH}")));
                }
                let count = self.whole("repeat count", MAX_PRODUCTIONS)?;
                self.expect('{')?;
                self.end_of_line()?;
                self.line += 1;
                let body = self.block(program, settings, depth + 1).map_err(|e| {
                    if e.message == UNCLOSED {
                        pos.error(UNCLOSED)
                    } else {
                        e
                    }
                })?;
                return Ok(Some(Statement::Repeat(count, body, pos)));
            }
            "generate" => Some(Statement::Generate(self.generate()?, pos)),
            _ => {
                return Err(pos.error(format!(
                    "unknown statement '{word}': expected lod, seed, overlap, direction, let, add, subtract, intersect, morph, repeat or generate"
                )));
            }
        };
        self.end_of_line()?;
        self.line += 1;
        Ok(statement)
    }

    /// `generate` options: `classic N morphic N direction D morph N% per_shape N`, any order.
    fn generate(&mut self) -> Result<CaveParams, TextError> {
        let mut params = CaveParams::default();
        while let Some((Token::Name(option), pos)) = self.peek().cloned() {
            self.at += 1;
            match option.as_str() {
                "classic" => params.classic = self.whole("classic", u64::from(u32::MAX))? as u32,
                "morphic" => params.morphic = self.whole("morphic", u64::from(u32::MAX))? as u32,
                "per_shape" => {
                    params.per_shape = self.whole("per_shape", u64::from(u32::MAX))? as u32
                }
                "direction" => params.direction = self.direction()?,
                "morph" => {
                    params.morph_percent = self.number()?.0;
                    self.expect('%')?;
                }
                _ => {
                    return Err(pos.error(format!(
                        "unknown generate option '{option}': expected classic, morphic, direction, morph or per_shape"
                    )));
                }
            }
        }
        Ok(params)
    }

    fn direction(&mut self) -> Result<Direction, TextError> {
        let pos = self.here();
        let sign = if self.eat('+') {
            "+"
        } else if self.eat('-') {
            "-"
        } else {
            ""
        };
        match self.next() {
            Some((Token::Name(axis), _)) => format!("{sign}{axis}")
                .parse()
                .map_err(|e: ImplicitError| pos.wrap(e)),
            _ => Err(pos.error("expected a direction: -x, +x, -y, +y, -z, +z or random")),
        }
    }

    /// A plain number, with an optional sign.
    fn number(&mut self) -> Result<(f64, Pos), TextError> {
        let pos = self.here();
        let start = self.at;
        let negative = self.eat('-');
        if !negative {
            self.eat('+');
        }
        if let Some((Token::Number(v, _), _)) = self.peek().cloned() {
            self.at += 1;
            return Ok((if negative { -v } else { v }, pos));
        }
        self.at = start;
        Err(self.expected("a number"))
    }

    fn whole(&mut self, what: &str, max: u64) -> Result<u64, TextError> {
        let (v, p) = self.number()?;
        if v.fract() != 0.0 || v < 0.0 || v > max as f64 {
            return Err(p.error(format!(
                "invalid {what} {v}: expected a whole number from 0 to {max}"
            )));
        }
        Ok(v as u64)
    }

    /// A number or `rand(lo, hi)`.
    fn num(&mut self) -> Result<Num, TextError> {
        if self.keyword("rand") {
            let pos = self.here();
            self.expect('(')?;
            let (lo, _) = self.number()?;
            self.expect(',')?;
            let (hi, _) = self.number()?;
            self.expect(')')?;
            if lo > hi {
                return Err(pos.error(format!(
                    "invalid rand({lo}, {hi}): the lower bound is above the upper"
                )));
            }
            Ok(Num::Rand(lo, hi))
        } else {
            Ok(Num::Literal(self.number()?.0))
        }
    }

    fn nums(&mut self, count: usize, what: &str, pos: Pos) -> Result<Vec<Num>, TextError> {
        self.expect('(')?;
        let mut values = Vec::new();
        if !self.eat(')') {
            loop {
                values.push(self.num()?);
                if self.eat(')') {
                    break;
                }
                if !self.eat(',') {
                    return Err(self.expected("',' or ')'"));
                }
            }
        }
        if values.len() != count {
            return Err(pos.error(format!(
                "{what} takes {count} number{}, found {}",
                if count == 1 { "" } else { "s" },
                values.len()
            )));
        }
        Ok(values)
    }

    /// `term (('+' | '-' | '&') term)*`, left to right.
    fn expr(&mut self, depth: usize) -> Result<Expr, TextError> {
        if depth > MAX_DEPTH {
            return Err(self
                .here()
                .error(format!("expression nests deeper than {MAX_DEPTH}")));
        }
        let mut left = self.term(depth)?;
        loop {
            let pos = self.here();
            let op = ['+', '-', '&'].into_iter().find(|&c| self.eat(c));
            let Some(op) = op else { return Ok(left) };
            self.operator(pos)?;
            let right = self.term(depth)?;
            left = Expr::Binary(op, Box::new(left), Box::new(right), pos);
        }
    }

    /// Counts one more operator or transform in the statement.
    fn operator(&mut self, pos: Pos) -> Result<(), TextError> {
        self.operators += 1;
        if self.operators > MAX_OPERATORS {
            return Err(pos.error(format!(
                "more than {MAX_OPERATORS} operators and transforms in one statement: split it \
                 with 'let'"
            )));
        }
        Ok(())
    }

    /// An atom followed by `.move(…)`, `.rotate(…)`, `.scale(…)`.
    fn term(&mut self, depth: usize) -> Result<Expr, TextError> {
        let mut e = self.atom(depth)?;
        while self.eat('.') {
            let Some((Token::Name(method), pos)) = self.next() else {
                return Err(self.expected("move, rotate or scale after '.'"));
            };
            self.operator(pos)?;
            e = match method.as_str() {
                "move" => {
                    let v = self.nums(3, "move", pos)?;
                    Expr::Move(Box::new(e), [v[0], v[1], v[2]], pos)
                }
                "scale" => {
                    self.expect('(')?;
                    let first = self.num()?;
                    let v = if self.eat(')') {
                        [first; 3]
                    } else {
                        self.expect(',')?;
                        let y = self.num()?;
                        self.expect(',')?;
                        let z = self.num()?;
                        self.expect(')')?;
                        [first, y, z]
                    };
                    Expr::Scale(Box::new(e), v, pos)
                }
                "rotate" => {
                    self.expect('(')?;
                    let axis_pos = self.here();
                    let axis = match self.next() {
                        Some((Token::Name(a), _)) if a == "x" => DVec3::X,
                        Some((Token::Name(a), _)) if a == "y" => DVec3::Y,
                        Some((Token::Name(a), _)) if a == "z" => DVec3::Z,
                        _ => return Err(axis_pos.error("expected the axis x, y or z")),
                    };
                    self.expect(',')?;
                    let degrees = self.num()?;
                    self.expect(')')?;
                    Expr::Rotate(Box::new(e), axis, degrees, pos)
                }
                _ => {
                    return Err(pos.error(format!(
                        "unknown transform '{method}': expected move, rotate or scale"
                    )));
                }
            };
        }
        Ok(e)
    }

    fn atom(&mut self, depth: usize) -> Result<Expr, TextError> {
        let pos = self.here();
        if self.eat('(') {
            let e = self.expr(depth + 1)?;
            self.expect(')')?;
            return Ok(e);
        }
        let Some((Token::Name(name), _)) = self.peek().cloned() else {
            let mut error = self.expected("a solid: a primitive, a name, morph(…) or '('");
            if matches!(self.peek(), Some((Token::Number(..), _))) {
                // `morph hall -5%` reads as the difference `hall - 5`.
                error.message.push_str(
                    " (after a solid, + - & combine it with another; a morphing amount is 0 to 100 %, as in `morph hall 55%`)",
                );
            }
            return Err(error);
        };
        self.at += 1;
        if let Some(&(_, count)) = PRIMITIVES.iter().find(|(n, _)| *n == name) {
            let args = self.nums(count, &name, pos)?;
            return Ok(Expr::Primitive(name, args, pos));
        }
        match name.as_str() {
            "morph" | "smooth_union" | "smooth_difference" | "smooth_intersection" => {
                self.expect('(')?;
                let a = self.expr(depth + 1)?;
                self.expect(',')?;
                let b = self.expr(depth + 1)?;
                self.expect(',')?;
                let t = self.num()?;
                let percent = name == "morph" && self.eat('%');
                self.expect(')')?;
                if name == "morph" {
                    let t = match t {
                        Num::Literal(v) if percent => Num::Literal(v / 100.0),
                        Num::Rand(lo, hi) if percent => Num::Rand(lo / 100.0, hi / 100.0),
                        t => t,
                    };
                    Ok(Expr::Morph(Box::new(a), Box::new(b), t, pos))
                } else {
                    Ok(Expr::Smooth(name, Box::new(a), Box::new(b), t, pos))
                }
            }
            _ if is_reserved(&name) => Err(pos.error(format!("expected a solid, found '{name}'"))),
            _ if self.defining.as_deref() == Some(name.as_str()) => {
                Err(pos.error(format!("'{name}' cannot be used in its own definition")))
            }
            _ => match self.names.iter().rev().find(|(n, _)| *n == name) {
                Some(&(_, index)) => Ok(Expr::Name(index, pos)),
                None => Err(pos.error(format!(
                    "unknown solid '{name}': define it above with 'let {name} = …'"
                ))),
            },
        }
    }
}

fn is_reserved(name: &str) -> bool {
    PRIMITIVES.iter().any(|(n, _)| *n == name)
        || [
            "lod",
            "seed",
            "overlap",
            "direction",
            "let",
            "add",
            "subtract",
            "intersect",
            "morph",
            "repeat",
            "generate",
            "at",
            "rand",
            "smooth_union",
            "smooth_difference",
            "smooth_intersection",
            "centre",
            "center",
        ]
        .contains(&name)
}

/// A solid under evaluation, with its bonds and primitive count.
struct Value {
    shape: Shape,
    elements: usize,
}

struct Runner<'a> {
    builder: CaveBuilder,
    rng: Rng,
    definitions: &'a [Expr],
    direction: Direction,
    /// Expression nodes evaluated so far, against definitions that use each other many times.
    evaluated: u64,
    /// The production being applied.
    current: Pos,
}

/// Deepest nesting of operations, transforms and names in one production's solid: evaluation and
/// the solid's own walks recurse that deep.
const MAX_NESTING: usize = 128;

/// Most expression nodes one run may evaluate.
const MAX_EVALUATED: u64 = 1_000_000;

impl CaveProgram {
    /// Runs the productions on an empty base; `seed` overrides the text's `seed`.
    pub fn run(&self, seed: Option<u64>) -> Result<CaveRun, TextError> {
        let origin = Pos { line: 1, column: 1 };
        count_productions(&self.statements, 0)?;
        let mut runner = Runner {
            builder: CaveBuilder::new(self.overlap).map_err(|e| origin.wrap(e))?,
            rng: Rng::new(seed.unwrap_or(self.seed)),
            definitions: &self.definitions,
            direction: Direction::PosX,
            evaluated: 0,
            current: origin,
        };
        runner.run(&self.statements)?;
        Ok(CaveRun {
            builder: runner.builder,
        })
    }
}

impl<'a> Runner<'a> {
    fn run(&mut self, statements: &'a [Statement]) -> Result<(), TextError> {
        for statement in statements {
            match statement {
                Statement::Direction(d) => self.direction = *d,
                Statement::Repeat(count, body, _) => {
                    for _ in 0..*count {
                        self.run(body)?;
                    }
                }
                Statement::Production(operation, amount, expr, attach, pos) => {
                    self.current = *pos;
                    let value = self.eval(expr, 0)?;
                    let operation = match operation {
                        Operation::Morph(_) => {
                            let percent = amount.value(&mut self.rng);
                            if !(0.0..=100.0).contains(&percent) {
                                return Err(pos.error(format!(
                                    "invalid morphing parameter {percent}%: expected 0 to 100"
                                )));
                            }
                            Operation::Morph(percent / 100.0)
                        }
                        op => *op,
                    };
                    let attach = attach.unwrap_or(Attach::Bond(self.direction));
                    self.builder
                        .apply(
                            &value.shape,
                            value.elements,
                            operation,
                            attach,
                            &mut self.rng,
                        )
                        .map_err(|e| pos.wrap(e))?;
                }
                Statement::Generate(params, pos) => {
                    grow(&mut self.builder, params, &mut self.rng).map_err(|e| pos.wrap(e))?;
                }
            }
        }
        Ok(())
    }

    fn eval(&mut self, expr: &'a Expr, depth: usize) -> Result<Value, TextError> {
        self.evaluated += 1;
        if self.evaluated > MAX_EVALUATED {
            return Err(self.current.error(format!(
                "the solids are too large: more than {MAX_EVALUATED} parts evaluated"
            )));
        }
        if depth > MAX_NESTING {
            return Err(self.current.error(format!(
                "the solid nests deeper than {MAX_NESTING} operations and names: build it from \
                 fewer, wider parts"
            )));
        }
        // The recursion stays in this frame and the work of each node in a function of its
        // own, so that a frame holds the operands and little else: nesting runs to
        // MAX_NESTING deep on a thread's default stack, in debug builds too.
        match expr {
            Expr::Primitive(kind, args, pos) => self.primitive(kind, args, *pos),
            Expr::Name(index, _) => self.eval(&self.definitions[*index], depth + 1),
            Expr::Binary(op, a, b, _) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                Ok(combined(*op, a, b))
            }
            Expr::Morph(a, b, t, pos) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                let t = t.value(&mut self.rng);
                morphed(a, b, t, *pos)
            }
            Expr::Smooth(kind, a, b, k, pos) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                let k = k.value(&mut self.rng);
                smoothed(kind, a, b, k, *pos)
            }
            Expr::Move(e, v, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let offset = DVec3::from_array(v.map(|n| n.value(&mut self.rng)));
                transformed(inner, *pos, |shape| shape.translate(offset))
            }
            Expr::Rotate(e, axis, degrees, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let degrees = degrees.value(&mut self.rng);
                transformed(inner, *pos, |shape| shape.rotate(*axis, degrees))
            }
            Expr::Scale(e, v, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let scale = DVec3::from_array(v.map(|n| n.value(&mut self.rng)));
                transformed(inner, *pos, |shape| shape.scale(scale))
            }
        }
    }

    /// A primitive with its arguments drawn.
    #[inline(never)]
    fn primitive(&mut self, kind: &str, args: &[Num], pos: Pos) -> Result<Value, TextError> {
        let v: Vec<f64> = args.iter().map(|n| n.value(&mut self.rng)).collect();
        let primitive = match kind {
            "sphere" => Primitive::Sphere { radius: v[0] },
            "box" => Primitive::Cuboid {
                size: DVec3::new(v[0], v[1], v[2]),
            },
            "cylinder" => Primitive::Cylinder {
                radius: v[0],
                height: v[1],
            },
            "cone" => Primitive::Cone {
                radius: v[0],
                height: v[1],
            },
            "pyramid" => Primitive::Pyramid {
                size: DVec3::new(v[0], v[1], v[2]),
            },
            "torus" => Primitive::Torus {
                major: v[0],
                minor: v[1],
            },
            _ => Primitive::Capsule {
                radius: v[0],
                length: v[1],
            },
        };
        Ok(Value {
            shape: Shape::primitive(primitive).map_err(|e| pos.wrap(e))?,
            elements: 1,
        })
    }
}

/// `a + b`, `a - b` or `a & b`.
#[inline(never)]
fn combined(op: char, a: Value, b: Value) -> Value {
    let shape = match op {
        '+' => a.shape.union(&b.shape),
        '-' => a.shape.difference(&b.shape),
        _ => a.shape.intersection(&b.shape),
    };
    Value {
        shape,
        elements: a.elements + b.elements,
    }
}

/// `morph(a, b, t)`.
#[inline(never)]
fn morphed(a: Value, b: Value, t: f64, pos: Pos) -> Result<Value, TextError> {
    Ok(Value {
        shape: a.shape.morph(&b.shape, t).map_err(|e| pos.wrap(e))?,
        elements: a.elements + b.elements,
    })
}

/// `smooth_union(a, b, k)` and its kin; only a union keeps the bonds of both.
#[inline(never)]
fn smoothed(kind: &str, a: Value, b: Value, k: f64, pos: Pos) -> Result<Value, TextError> {
    let solid = match kind {
        "smooth_union" => a.shape.solid.smooth_union(&b.shape.solid, k),
        "smooth_difference" => a.shape.solid.smooth_difference(&b.shape.solid, k),
        _ => a.shape.solid.smooth_intersection(&b.shape.solid, k),
    }
    .map_err(|e| pos.wrap(e))?;
    let mut bonds = a.shape.bonds;
    if kind == "smooth_union" {
        bonds.extend(&b.shape.bonds);
    }
    Ok(Value {
        shape: Shape { solid, bonds },
        elements: a.elements + b.elements,
    })
}

/// A moved, turned or scaled value.
#[inline(never)]
fn transformed(
    inner: Value,
    pos: Pos,
    map: impl FnOnce(&Shape) -> crate::Result<Shape>,
) -> Result<Value, TextError> {
    Ok(Value {
        shape: map(&inner.shape).map_err(|e| pos.wrap(e))?,
        elements: inner.elements,
    })
}

/// Adds up the productions `statements` apply (after `before` others), failing where the total
/// passes [`MAX_PRODUCTIONS`]: there are no conditions, so the count is known before running.
fn count_productions(statements: &[Statement], before: u64) -> Result<u64, TextError> {
    let mut total = before;
    let too_many = |pos: Pos| pos.error(format!("more than {MAX_PRODUCTIONS} productions"));
    for statement in statements {
        let (added, pos) = match statement {
            Statement::Production(.., pos) => (1, *pos),
            Statement::Generate(params, pos) => {
                (u64::from(params.classic) + u64::from(params.morphic), *pos)
            }
            Statement::Repeat(count, body, pos) => {
                let once = count_productions(body, total)? - total;
                (once.saturating_mul(*count), *pos)
            }
            Statement::Direction(_) => (0, Pos { line: 0, column: 0 }),
        };
        total = total.saturating_add(added);
        if total > MAX_PRODUCTIONS {
            return Err(too_many(pos));
        }
    }
    Ok(total)
}
