//! Arithmetic and logic of parametric L-systems (ABOP §1.10): parsed with precedence climbing
//! and compiled to a small stack program over `f64`.
//!
//! Truth is a number: comparisons give 1 or 0, and any non-zero value counts as true.
//! Trigonometric functions take and give degrees, like the turtle's angles.

use crate::cursor::{Cursor, describe};
use crate::error::{Error, Position};

/// What a name in an expression stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Name {
    /// The `i`-th variable of the production (a formal parameter).
    Variable(u16),
    /// A constant from a `define:` line.
    Constant(f64),
}

/// A built-in function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Function {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Atan2,
    Sqrt,
    Abs,
    Floor,
    Ceil,
    Round,
    Exp,
    Ln,
    Min,
    Max,
    Pow,
    Sign,
}

impl Function {
    fn by_name(name: &str) -> Option<(Self, usize)> {
        Some(match name {
            "sin" => (Self::Sin, 1),
            "cos" => (Self::Cos, 1),
            "tan" => (Self::Tan, 1),
            "asin" => (Self::Asin, 1),
            "acos" => (Self::Acos, 1),
            "atan" => (Self::Atan, 1),
            "atan2" => (Self::Atan2, 2),
            "sqrt" => (Self::Sqrt, 1),
            "abs" => (Self::Abs, 1),
            "floor" => (Self::Floor, 1),
            "ceil" => (Self::Ceil, 1),
            "round" => (Self::Round, 1),
            "exp" => (Self::Exp, 1),
            "ln" | "log" => (Self::Ln, 1),
            "min" => (Self::Min, 2),
            "max" => (Self::Max, 2),
            "pow" => (Self::Pow, 2),
            "sign" => (Self::Sign, 1),
            _ => return None,
        })
    }

    fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Self::Sin => a.to_radians().sin(),
            Self::Cos => a.to_radians().cos(),
            Self::Tan => a.to_radians().tan(),
            Self::Asin => a.asin().to_degrees(),
            Self::Acos => a.acos().to_degrees(),
            Self::Atan => a.atan().to_degrees(),
            Self::Atan2 => a.atan2(b).to_degrees(),
            Self::Sqrt => a.sqrt(),
            Self::Abs => a.abs(),
            Self::Floor => a.floor(),
            Self::Ceil => a.ceil(),
            Self::Round => a.round(),
            Self::Exp => a.exp(),
            Self::Ln => a.ln(),
            Self::Min => a.min(b),
            Self::Max => a.max(b),
            Self::Pow => a.powf(b),
            Self::Sign => {
                if a == 0.0 {
                    0.0
                } else {
                    a.signum()
                }
            }
        }
    }
}

/// One instruction of the stack program.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Constant(f64),
    Variable(u16),
    Negate,
    Not,
    Binary(Binary),
    Call(Function, u8),
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Binary {
    Or,
    And,
    Equal,
    NotEqual,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    Add,
    Subtract,
    Multiply,
    Divide,
    Remainder,
    Power,
}

impl Binary {
    /// Binding strength; higher binds tighter.
    fn precedence(self) -> u8 {
        match self {
            Self::Or => 1,
            Self::And => 2,
            Self::Equal | Self::NotEqual => 3,
            Self::Less | Self::LessEqual | Self::Greater | Self::GreaterEqual => 4,
            Self::Add | Self::Subtract => 5,
            Self::Multiply | Self::Divide | Self::Remainder => 6,
            Self::Power => 8,
        }
    }

    #[inline]
    fn apply(self, a: f64, b: f64) -> f64 {
        // A comparison with NaN is not false but undefined: the condition failed to evaluate.
        if a.is_nan() || b.is_nan() {
            return f64::NAN;
        }
        let truth = |t: bool| if t { 1.0 } else { 0.0 };
        // Parameters are always finite, so an infinite operand of a comparison or a logical
        // operator comes from a division by zero or an overflow: undefined as well, rather than
        // a condition that quietly holds.
        let logical = !matches!(
            self,
            Self::Add
                | Self::Subtract
                | Self::Multiply
                | Self::Divide
                | Self::Remainder
                | Self::Power
        );
        if logical && !(a.is_finite() && b.is_finite()) {
            return f64::NAN;
        }
        match self {
            Self::Or => truth(a != 0.0 || b != 0.0),
            Self::And => truth(a != 0.0 && b != 0.0),
            Self::Equal => truth(a == b),
            Self::NotEqual => truth(a != b),
            Self::Less => truth(a < b),
            Self::LessEqual => truth(a <= b),
            Self::Greater => truth(a > b),
            Self::GreaterEqual => truth(a >= b),
            Self::Add => a + b,
            Self::Subtract => a - b,
            Self::Multiply => a * b,
            Self::Divide => a / b,
            Self::Remainder => a % b,
            Self::Power => a.powf(b),
        }
    }
}

/// A compiled expression and where it starts in the file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Expr {
    ops: Vec<Op>,
    /// Where the expression starts, for errors about its value.
    pub position: Position,
}

impl Expr {
    /// A text equal for two expressions exactly when they compute alike: variables by their
    /// place in the production, not their names (`x > 1` in `A(x)` is `y > 1` in `A(y)`).
    pub fn program_key(&self) -> String {
        format!("{:?}", self.ops)
    }

    /// The value when the expression uses no variables.
    pub fn constant(&self) -> Option<f64> {
        match self.ops.as_slice() {
            [Op::Constant(c)] => Some(*c),
            _ => None,
        }
    }

    /// Evaluates with `variables` bound, using `stack` as scratch space.
    #[inline]
    pub fn eval(&self, variables: &[f64], stack: &mut Vec<f64>) -> f64 {
        // Most successor parameters are a constant, a variable or `x op c`: no stack needed.
        match *self.ops.as_slice() {
            [Op::Constant(c)] => c,
            [Op::Variable(v)] => variables[v as usize],
            [Op::Variable(v), Op::Constant(c), Op::Binary(op)] => {
                op.apply(variables[v as usize], c)
            }
            _ => self.run(variables, stack),
        }
    }

    /// Runs the stack program.
    fn run(&self, variables: &[f64], stack: &mut Vec<f64>) -> f64 {
        stack.clear();
        for op in &self.ops {
            match *op {
                Op::Constant(c) => stack.push(c),
                Op::Variable(v) => stack.push(variables[v as usize]),
                Op::Negate => {
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(-a);
                }
                Op::Not => {
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(if a.is_nan() {
                        a
                    } else if a == 0.0 {
                        1.0
                    } else {
                        0.0
                    });
                }
                Op::Binary(binary) => {
                    let b = stack.pop().unwrap_or(f64::NAN);
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(binary.apply(a, b));
                }
                Op::Call(function, arity) => {
                    let b = if arity == 2 {
                        stack.pop().unwrap_or(f64::NAN)
                    } else {
                        0.0
                    };
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(function.apply(a, b));
                }
            }
        }
        stack.pop().unwrap_or(f64::NAN)
    }
}

/// Parses an expression at the cursor, stopping before the first character that cannot continue
/// it (`,`, `)`, `->`, the end). `names` says what each identifier means (`None`: unknown).
pub(crate) fn parse(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
) -> Result<Expr, Error> {
    cursor.skip_space();
    let position = cursor.position();
    let mut ops = Emitter::default();
    binary(cursor, names, 0, &mut ops)?;
    let folded = fold(&ops.ops);
    Ok(Expr {
        ops: folded,
        position,
    })
}

/// Parses operands and operators binding tighter than `min`.
fn binary(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    min: u8,
    ops: &mut Emitter,
) -> Result<(), Error> {
    unary(cursor, names, ops)?;
    loop {
        cursor.skip_space();
        let save = cursor.clone();
        let Some(op) = operator(cursor) else {
            return Ok(());
        };
        let precedence = op.precedence();
        if precedence <= min {
            *cursor = save;
            return Ok(());
        }
        // `^` is right-associative: its right side may hold another `^`.
        let next = if op == Binary::Power {
            precedence - 1
        } else {
            precedence
        };
        binary(cursor, names, next, ops)?;
        ops.push(Op::Binary(op));
    }
}

/// Reads a binary operator, if one is next (and not the arrow `->`).
fn operator(cursor: &mut Cursor) -> Option<Binary> {
    let first = cursor.peek()?;
    let second = cursor.peek_second();
    let (op, width) = match (first, second) {
        ('|', Some('|')) => (Binary::Or, 2),
        ('&', Some('&')) => (Binary::And, 2),
        ('=', Some('=')) => (Binary::Equal, 2),
        ('!', Some('=')) => (Binary::NotEqual, 2),
        ('<', Some('=')) => (Binary::LessEqual, 2),
        ('>', Some('=')) => (Binary::GreaterEqual, 2),
        ('<', _) => (Binary::Less, 1),
        ('>', _) => (Binary::Greater, 1),
        ('-', Some('>')) => return None,
        ('+', _) => (Binary::Add, 1),
        ('-', _) => (Binary::Subtract, 1),
        ('*', Some('*')) => (Binary::Power, 2),
        ('*', _) => (Binary::Multiply, 1),
        ('/', _) => (Binary::Divide, 1),
        ('%', _) => (Binary::Remainder, 1),
        ('^', _) => (Binary::Power, 1),
        _ => return None,
    };
    for _ in 0..width {
        cursor.bump();
    }
    Some(op)
}

/// How deeply expressions may nest (parentheses, prefix operators, powers), so that hostile
/// input cannot exhaust the stack.
const MAX_DEPTH: u32 = 256;

/// The program being compiled, and how deep the parser is.
#[derive(Default)]
struct Emitter {
    ops: Vec<Op>,
    depth: u32,
}

impl Emitter {
    fn push(&mut self, op: Op) {
        self.ops.push(op);
    }
}

/// Parses a prefix operator and its operand, or a primary (every nesting passes here, so this
/// is where depth is limited).
fn unary(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    ops: &mut Emitter,
) -> Result<(), Error> {
    if ops.depth >= MAX_DEPTH {
        return Err(cursor.error(format!(
            "the expression nests more than {MAX_DEPTH} levels deep"
        )));
    }
    ops.depth += 1;
    let result = unary_unlimited(cursor, names, ops);
    ops.depth -= 1;
    result
}

/// [`unary`] without the depth check.
fn unary_unlimited(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    ops: &mut Emitter,
) -> Result<(), Error> {
    cursor.skip_space();
    match cursor.peek() {
        Some('-') => {
            cursor.bump();
            // Binds looser than `^`, so `-2^2` is -4 as in mathematics.
            unary(cursor, names, ops)?;
            ops.push(Op::Negate);
            Ok(())
        }
        Some('+') => {
            cursor.bump();
            unary(cursor, names, ops)
        }
        Some('!') => {
            cursor.bump();
            unary(cursor, names, ops)?;
            ops.push(Op::Not);
            Ok(())
        }
        _ => {
            primary(cursor, names, ops)?;
            power_tail(cursor, names, ops)
        }
    }
}

/// A `^ operand` chain after a primary (right-associative, tighter than prefix minus).
fn power_tail(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    ops: &mut Emitter,
) -> Result<(), Error> {
    cursor.skip_space();
    let save = cursor.clone();
    if operator(cursor) == Some(Binary::Power) {
        unary(cursor, names, ops)?;
        ops.push(Op::Binary(Binary::Power));
    } else {
        *cursor = save;
    }
    Ok(())
}

/// A number, a name, a call or a parenthesised expression.
fn primary(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    ops: &mut Emitter,
) -> Result<(), Error> {
    cursor.skip_space();
    let start = cursor.index();
    match cursor.peek() {
        Some(c) if c.is_ascii_digit() || c == '.' => {
            let value = number(cursor)?;
            ops.push(Op::Constant(value));
            Ok(())
        }
        Some('(') => {
            cursor.bump();
            binary(cursor, names, 0, ops)?;
            cursor.skip_space();
            if !cursor.eat(')') {
                return Err(cursor.error(format!(
                    "expected ')' to close the '(' at column {}, found {}",
                    start + 1,
                    describe(cursor.peek())
                )));
            }
            Ok(())
        }
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {
            let name = cursor.identifier().unwrap_or_default();
            cursor.skip_space();
            if cursor.peek() == Some('(') {
                return call(cursor, names, &name, start, ops);
            }
            match names(&name) {
                Some(Name::Variable(v)) => ops.push(Op::Variable(v)),
                Some(Name::Constant(c)) => ops.push(Op::Constant(c)),
                None => {
                    return Err(Error::at(
                        cursor.position_of(start),
                        format!(
                            "unknown name '{name}' (not a parameter of this production or a defined constant)"
                        ),
                    ));
                }
            }
            Ok(())
        }
        other => Err(cursor.error(format!(
            "expected a number, a name or '(', found {}",
            describe(other)
        ))),
    }
}

/// A function call `name(args)`; the cursor is at the `(`.
fn call(
    cursor: &mut Cursor,
    names: &dyn Fn(&str) -> Option<Name>,
    name: &str,
    start: usize,
    ops: &mut Emitter,
) -> Result<(), Error> {
    let Some((function, arity)) = Function::by_name(name) else {
        return Err(Error::at(
            cursor.position_of(start),
            format!("unknown function '{name}'"),
        ));
    };
    cursor.bump();
    let mut count = 0;
    loop {
        cursor.skip_space();
        if count == 0 && cursor.eat(')') {
            break;
        }
        binary(cursor, names, 0, ops)?;
        count += 1;
        cursor.skip_space();
        if cursor.eat(',') {
            continue;
        }
        if cursor.eat(')') {
            break;
        }
        return Err(cursor.error(format!(
            "expected ',' or ')' in the call of {name}, found {}",
            describe(cursor.peek())
        )));
    }
    if count != arity {
        return Err(Error::at(
            cursor.position_of(start),
            format!(
                "{name} takes {arity} argument{}, not {count}",
                if arity == 1 { "" } else { "s" }
            ),
        ));
    }
    ops.push(Op::Call(function, arity as u8));
    Ok(())
}

/// A decimal number: `12`, `0.5`, `.5`, `1e-3`.
pub(crate) fn number(cursor: &mut Cursor) -> Result<f64, Error> {
    let start = cursor.index();
    let digits = |cursor: &mut Cursor| {
        while cursor.peek().is_some_and(|c| c.is_ascii_digit()) {
            cursor.bump();
        }
    };
    digits(cursor);
    if cursor.peek() == Some('.') {
        cursor.bump();
        digits(cursor);
    }
    if matches!(cursor.peek(), Some('e' | 'E'))
        && cursor
            .peek_second()
            .is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+')
    {
        cursor.bump();
        if matches!(cursor.peek(), Some('-' | '+')) {
            cursor.bump();
        }
        digits(cursor);
    }
    let text = cursor.text_since(start);
    text.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| {
            Error::at(
                cursor.position_of(start),
                format!("invalid number '{text}'"),
            )
        })
}

/// Constant folding: a program without variables becomes one constant.
fn fold(ops: &[Op]) -> Vec<Op> {
    if ops.iter().any(|op| matches!(op, Op::Variable(_))) {
        return ops.to_vec();
    }
    let expr = Expr {
        ops: ops.to_vec(),
        position: Position::new(1, 1),
    };
    vec![Op::Constant(expr.eval(&[], &mut Vec::new()))]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str, vars: &[f64]) -> f64 {
        let chars: Vec<char> = text.chars().collect();
        let mut cursor = Cursor::new(&chars, 0, chars.len(), 1);
        let names = |n: &str| match n {
            "x" => Some(Name::Variable(0)),
            "y" => Some(Name::Variable(1)),
            "k" => Some(Name::Constant(10.0)),
            _ => None,
        };
        let expr = parse(&mut cursor, &names).unwrap();
        assert!(cursor.at_end(), "{text}: left over");
        expr.eval(vars, &mut Vec::new())
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(eval("1 + 2 * 3", &[]), 7.0);
        assert_eq!(eval("(1 + 2) * 3", &[]), 9.0);
        assert_eq!(eval("2 ^ 3 ^ 2", &[]), 512.0);
        assert_eq!(eval("-2^2", &[]), -4.0);
        assert_eq!(eval("10 - 4 - 3", &[]), 3.0);
        assert_eq!(eval("x*y + k", &[2.0, 3.0]), 16.0);
        assert_eq!(eval("x <= 3 && y > 1 || 0", &[3.0, 2.0]), 1.0);
        assert_eq!(eval("!(x == 3)", &[3.0]), 0.0);
        assert_eq!(eval("min(x, 4) + max(1, 2) + sqrt(16)", &[7.0]), 10.0);
        assert_eq!(eval("7 % 4", &[]), 3.0);
        assert!((eval("sin(30)", &[]) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        for text in [
            "(".repeat(100_000),
            "-".repeat(100_000),
            "2^".repeat(100_000),
        ] {
            let chars: Vec<char> = format!("{text}1").chars().collect();
            let mut cursor = Cursor::new(&chars, 0, chars.len(), 1);
            let err = parse(&mut cursor, &|_: &str| None).unwrap_err();
            assert!(err.message.contains("nests more than 256 levels"), "{err}");
        }
    }

    #[test]
    fn errors_point_at_the_problem() {
        let err = |text: &str| {
            let chars: Vec<char> = text.chars().collect();
            let mut cursor = Cursor::new(&chars, 0, chars.len(), 4);
            parse(&mut cursor, &|_: &str| None).unwrap_err()
        };
        assert_eq!(
            err("1 + z").to_string(),
            "4:5: unknown name 'z' (not a parameter of this production or a defined constant)"
        );
        assert_eq!(
            err("1 + ").to_string(),
            "4:5: expected a number, a name or '(', found the end of the line"
        );
        assert_eq!(
            err("(1").to_string(),
            "4:3: expected ')' to close the '(' at column 1, found the end of the line"
        );
        assert_eq!(err("foo(1)").to_string(), "4:1: unknown function 'foo'");
        assert_eq!(
            err("min(1)").to_string(),
            "4:1: min takes 2 arguments, not 1"
        );
    }
}
