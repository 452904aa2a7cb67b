//! A parsed L-system: settings, alphabet, axiom and productions, with the per-symbol plan the
//! rewriting engine follows.

use shapegram_geom::Color;

use crate::alphabet::{Alphabet, SymbolId};
use crate::error::Error;
use crate::expr::Expr;
use crate::word::Word;

/// The settings lines of an L-system file, with their defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// `n:` derivation length (default 1).
    pub iterations: u32,
    /// `angle:` turning angle of `+ - & ^ \ /` in degrees (default 90).
    pub angle: f64,
    /// `step:` length of `F`, `f` and `G` (default 1).
    pub step: f64,
    /// `width:` initial line width (default 0.1).
    pub width: f64,
    /// `width-factor:` what a bare `!` multiplies the width by (default 0.7).
    pub width_factor: f64,
    /// `seed:` seed of stochastic choices (default 0).
    pub seed: u64,
    /// `sides:` sides of tube cross-sections (default 8).
    pub sides: u32,
    /// `colors:` the palette that `'` indexes (default: bark, leaf greens, blossom colours).
    pub colors: Vec<Color>,
    /// `ignore:` names skipped when matching contexts.
    pub ignore: Vec<char>,
    /// `draw:` names that draw a line like `F`.
    pub draw: Vec<char>,
    /// `move:` names that move without drawing like `f`.
    pub moves: Vec<char>,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            iterations: 1,
            angle: 90.0,
            step: 1.0,
            width: 0.1,
            width_factor: 0.7,
            seed: 0,
            sides: 8,
            colors: default_palette(),
            ignore: Vec::new(),
            draw: Vec::new(),
            moves: Vec::new(),
        }
    }
}

/// Bark brown, two leaf greens, then yellow, red, white, blue and near-black.
pub fn default_palette() -> Vec<Color> {
    [
        "#6b4a2b", "#3f7d3a", "#8cc152", "#e8c547", "#c0392b", "#f2efe6", "#3a6ea5", "#222222",
    ]
    .iter()
    .filter_map(|hex| Color::from_hex(hex))
    .collect()
}

/// One module of a successor: its symbol and an expression per parameter.
#[derive(Clone, Debug)]
pub(crate) struct SuccessorModule {
    pub symbol: SymbolId,
    pub args: Vec<Expr>,
}

/// One successor of a production, with its share of the production's probability.
#[derive(Clone, Debug)]
pub(crate) struct Alternative {
    /// Cumulative probability up to and including this alternative (the last is 1).
    pub cumulative: f64,
    pub modules: Vec<SuccessorModule>,
}

/// A production with everything left of the arrow, and its successors (more than one for
/// stochastic productions).
#[derive(Clone, Debug)]
pub(crate) struct Production {
    pub predecessor: SymbolId,
    /// Left context, in reading order.
    pub left: Vec<SymbolId>,
    /// First variable of each left-context module.
    pub left_vars: Vec<u16>,
    /// Right context, in reading order; may hold `[` and `]`.
    pub right: Vec<SymbolId>,
    /// First variable of each right-context module.
    pub right_vars: Vec<u16>,
    pub condition: Option<Expr>,
    pub alternatives: Vec<Alternative>,
    /// Number of variables: the predecessor's parameters, then each context module's.
    pub variables: usize,
}

impl Production {
    /// Whether the production has a left or right context.
    pub fn has_context(&self) -> bool {
        !self.left.is_empty() || !self.right.is_empty()
    }

    /// Whether applying it never needs more than copying a fixed run of symbols.
    fn is_fixed(&self) -> bool {
        !self.has_context()
            && self.condition.is_none()
            && self.alternatives.len() == 1
            && self.alternatives[0]
                .modules
                .iter()
                .all(|m| m.args.is_empty())
    }
}

/// What rewriting does to a symbol.
#[derive(Clone, Debug)]
pub(crate) enum Plan {
    /// No production: the module is copied (identity).
    Copy,
    /// One unconditional, context-free, deterministic production without parameters:
    /// `successors[start..start + len]`.
    Fixed { start: u32, len: u32 },
    /// Productions to try in order (context-sensitive first, then in file order).
    Productions(Vec<u32>),
}

/// Productions with the plan of each symbol: the derivation's rules, or the interpretation
/// rules applied once before drawing.
#[derive(Clone, Debug, Default)]
pub(crate) struct Rules {
    pub productions: Vec<Production>,
    /// Per symbol id.
    pub plans: Vec<Plan>,
    /// The symbols of fixed successors, back to back.
    pub fixed: Vec<SymbolId>,
}

impl Rules {
    /// The rules for an alphabet of `symbols` symbols, with each symbol's plan worked out.
    pub fn new(productions: Vec<Production>, symbols: usize) -> Self {
        let mut plans = vec![Plan::Copy; symbols];
        let mut fixed = Vec::new();
        for (id, plan) in plans.iter_mut().enumerate() {
            let mine: Vec<u32> = (0..productions.len() as u32)
                .filter(|&p| productions[p as usize].predecessor as usize == id)
                .collect();
            *plan = match mine.as_slice() {
                [] => Plan::Copy,
                [only] if productions[*only as usize].is_fixed() => {
                    let start = fixed.len() as u32;
                    let modules = &productions[*only as usize].alternatives[0].modules;
                    fixed.extend(modules.iter().map(|m| m.symbol));
                    Plan::Fixed {
                        start,
                        len: modules.len() as u32,
                    }
                }
                _ => {
                    let (mut order, free): (Vec<u32>, Vec<u32>) = mine
                        .iter()
                        .partition(|&&p| productions[p as usize].has_context());
                    order.extend(free);
                    Plan::Productions(order)
                }
            };
        }
        Self {
            productions,
            plans,
            fixed,
        }
    }

    /// Whether any production needs contexts.
    pub fn has_context(&self) -> bool {
        self.productions.iter().any(Production::has_context)
    }

    /// Whether there are no productions.
    pub fn is_empty(&self) -> bool {
        self.productions.is_empty()
    }

    /// Whether any production chooses among alternatives at random.
    pub fn is_stochastic(&self) -> bool {
        self.productions.iter().any(|p| p.alternatives.len() > 1)
    }
}

/// A complete L-system, ready to derive.
#[derive(Clone, Debug)]
pub struct LSystem {
    /// The settings lines.
    pub settings: Settings,
    pub(crate) alphabet: Alphabet,
    pub(crate) axiom: Word,
    /// The productions of the derivation.
    pub(crate) rules: Rules,
    /// The interpretation rules (`homomorphism:` section), applied once before drawing.
    pub(crate) interpretation: Rules,
    /// Per symbol id: skipped when matching contexts.
    pub(crate) ignored: Vec<bool>,
    /// The ids of `[` and `]`, or `SymbolId::MAX` when unused.
    pub(crate) open: SymbolId,
    pub(crate) close: SymbolId,
}

impl LSystem {
    /// Parses the text format described in `docs/lsystem.md`.
    pub fn parse(text: &str) -> Result<Self, Error> {
        crate::parse::parse(text)
    }

    /// Whether the word depends on the seed: some production or interpretation rule chooses
    /// among alternatives at random.
    pub fn is_stochastic(&self) -> bool {
        self.rules.is_stochastic() || self.interpretation.is_stochastic()
    }

    /// The symbols of this L-system.
    pub fn alphabet(&self) -> &Alphabet {
        &self.alphabet
    }

    /// The axiom (the word of step 0).
    pub fn axiom(&self) -> &Word {
        &self.axiom
    }

    /// The word as text (see [`Word::to_text`]).
    pub fn word_text(&self, word: &Word) -> String {
        word.to_text(&self.alphabet)
    }

    /// Whether every step is a plain table lookup: no parameters anywhere and only fixed
    /// productions.
    pub(crate) fn is_d0l(&self) -> bool {
        self.alphabet.symbols().iter().all(|s| s.arity == 0)
            && self
                .rules
                .plans
                .iter()
                .all(|p| matches!(p, Plan::Copy | Plan::Fixed { .. }))
    }

    /// Assembles the system and works out the plan of each symbol.
    pub(crate) fn assemble(
        settings: Settings,
        alphabet: Alphabet,
        axiom: Word,
        productions: Vec<Production>,
        interpretation: Vec<Production>,
    ) -> Self {
        let ignored = alphabet
            .symbols()
            .iter()
            .map(|s| settings.ignore.contains(&s.name))
            .collect();
        let open = alphabet.id('[', 0).unwrap_or(SymbolId::MAX);
        let close = alphabet.id(']', 0).unwrap_or(SymbolId::MAX);
        Self {
            rules: Rules::new(productions, alphabet.len()),
            interpretation: Rules::new(interpretation, alphabet.len()),
            settings,
            alphabet,
            axiom,
            ignored,
            open,
            close,
        }
    }
}
