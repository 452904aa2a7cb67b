//! L-systems: bracketed, stochastic, context-sensitive and parametric rewriting (ABOP; the
//! paper's section 3.2), with a turtle that draws the derived word in 2D or 3D.
//!
//! ```
//! use shapegram_lsystem::{DeriveOptions, LSystem};
//!
//! let system = LSystem::parse("n: 5\naxiom: a\na -> ab\nb -> a\n").unwrap();
//! let word = system.derive(&DeriveOptions::default()).unwrap();
//! assert_eq!(system.word_text(&word), "abaababaabaab");
//! ```
//!
//! The text format is documented in `docs/lsystem.md`.

mod alphabet;
mod context;
mod cursor;
mod error;
mod expr;
mod parse;
mod rewrite;
mod rng;
mod system;
mod word;

pub use alphabet::{Alphabet, Symbol, SymbolId};
pub use error::{Error, Position};
pub use rewrite::{DEFAULT_MAX_MODULES, DeriveOptions};
pub use system::{LSystem, Settings, default_palette};
pub use word::Word;
