//! Parsing a `.cave` text's lines of tokens into settings, definitions and statements.

use super::*;

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
