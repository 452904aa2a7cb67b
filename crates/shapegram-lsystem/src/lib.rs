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
mod geometry;
mod parse;
mod rewrite;
mod rng;
mod system;
mod turtle;
mod word;

pub use alphabet::{Alphabet, Symbol, SymbolId};
pub use error::{Error, Position};
pub use geometry::{
    DEFAULT_MAX_VERTICES, drawing_to_lines, drawing_to_lines_within, drawing_to_model,
    drawing_to_model_within, fit_into_box, fit_into_scope,
};
pub use rewrite::{DEFAULT_MAX_MODULES, DeriveOptions, MAX_ITERATIONS};
pub use system::{LSystem, Settings, default_palette};
pub use turtle::{Drawing, Polygon, Stroke, interpret};
pub use word::Word;

use shapegram_geom::{Model, Scope};

/// Derives `system`, rewrites the word by its interpretation rules and draws it with the turtle
/// as tubes and leaves. A model over [`DEFAULT_MAX_VERTICES`] vertices is an error.
pub fn model(system: &LSystem, options: &DeriveOptions) -> Result<Model, Error> {
    let word = system.derive(options)?;
    let shown = system.interpretation(&word, options)?;
    let drawing = interpret(system, &shown);
    drawing_to_model_within(&drawing, &system.settings, DEFAULT_MAX_VERTICES)
}

/// [`model`] fitted into `scope` (uniformly scaled, centred on the scope's x and z, standing on
/// its floor): what a shape grammar calls to plant an L-system in the current shape.
pub fn model_in_scope(
    system: &LSystem,
    options: &DeriveOptions,
    scope: &Scope,
) -> Result<Model, Error> {
    Ok(fit_into_scope(&model(system, options)?, scope))
}
