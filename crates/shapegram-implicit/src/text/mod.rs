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

mod lexer;
mod parser;
mod runner;

use lexer::{Token, lex};
pub use parser::parse;

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
