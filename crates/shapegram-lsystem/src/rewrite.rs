//! The derivation: every module of the word rewritten in parallel (in the L-system sense), step
//! after step.
//!
//! Systems without parameters whose productions are all fixed (D0L and bracketed D0L) take a
//! fast path: each step sums the successor lengths to size the new word exactly, then copies
//! one precomputed slice per module. Everything else goes module by module through its
//! symbol's productions.

use std::borrow::Cow;
use std::cell::Cell;

use crate::alphabet::SymbolId;
use crate::context::{Structure, pair_brackets};
use crate::error::Error;
use crate::rng;
use crate::system::{LSystem, Plan, Production, Rules};
use crate::word::{Word, push_number};

/// Default limit on the number of modules of a word.
pub const DEFAULT_MAX_MODULES: usize = 50_000_000;

/// Largest derivation length, from `n:` or [`DeriveOptions::iterations`]: a word that stops
/// growing would otherwise be rewritten for billions of steps.
pub const MAX_ITERATIONS: u32 = 10_000;

/// Choices of one derivation; `None` takes the value from the L-system's settings.
#[derive(Clone, Debug)]
pub struct DeriveOptions {
    /// Derivation length (overrides `n:`), at most [`MAX_ITERATIONS`].
    pub iterations: Option<u32>,
    /// Seed of stochastic choices (overrides `seed:`).
    pub seed: Option<u64>,
    /// A word may not grow beyond this many modules, nor hold more parameters than this; a
    /// step that would is an error.
    pub max_modules: usize,
}

impl Default for DeriveOptions {
    fn default() -> Self {
        Self {
            iterations: None,
            seed: None,
            max_modules: DEFAULT_MAX_MODULES,
        }
    }
}

/// Which rewriting pass a message is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    /// A derivation step, from 1.
    Step(u32),
    /// The interpretation rules, applied once before drawing.
    Interpretation,
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Step(step) => write!(f, "step {step}"),
            Self::Interpretation => f.write_str("interpretation"),
        }
    }
}

/// Buffers reused from step to step.
#[derive(Default)]
struct Scratch {
    variables: Vec<f64>,
    stack: Vec<f64>,
    partners: Vec<u32>,
    brackets: Vec<u32>,
    offsets: Vec<u32>,
    found_left: Vec<usize>,
    found_right: Vec<usize>,
    backtrack: Vec<(usize, usize)>,
}

impl LSystem {
    /// Derives the word after the configured number of steps.
    pub fn derive(&self, options: &DeriveOptions) -> Result<Word, Error> {
        self.derive_with_progress(options, |_, _| {})
    }

    /// Like [`LSystem::derive`], calling `progress(step, modules)` after each step.
    pub fn derive_with_progress(
        &self,
        options: &DeriveOptions,
        progress: impl FnMut(u32, usize),
    ) -> Result<Word, Error> {
        self.derive_until(options, progress, || false)
    }

    /// Like [`LSystem::derive_with_progress`], giving up with a "cancelled" error when `stop()`
    /// says so before a step: a host cancels a long derivation from another thread this way.
    pub fn derive_until(
        &self,
        options: &DeriveOptions,
        mut progress: impl FnMut(u32, usize),
        stop: impl Fn() -> bool,
    ) -> Result<Word, Error> {
        let cancelled = || Error::general("the derivation was cancelled");
        let iterations = options.iterations.unwrap_or(self.settings.iterations);
        if iterations > MAX_ITERATIONS {
            return Err(Error::general(format!(
                "{} derivation steps asked for; at most {} are allowed",
                group_digits(iterations as usize),
                group_digits(MAX_ITERATIONS as usize)
            )));
        }
        let seed = options.seed.unwrap_or(self.settings.seed);
        let max = options.max_modules;
        if self.axiom.len() > max {
            return Err(limit_error(0, self.axiom.len(), max));
        }
        let mut word = self.axiom.clone();
        let mut next = Word::default();
        if self.is_d0l() {
            let (table, slab) = self.d0l_table();
            for step in 1..=iterations {
                if stop() {
                    return Err(cancelled());
                }
                step_d0l(&word, &mut next, &table, &slab, step, max)?;
                std::mem::swap(&mut word, &mut next);
                progress(step, word.len());
            }
            return Ok(word);
        }
        let arities = self.arities();
        let mut scratch = Scratch::default();
        for step in 1..=iterations {
            if stop() {
                return Err(cancelled());
            }
            let key = rng::step_key(seed, step);
            let pass = Pass {
                rules: &self.rules,
                stage: Stage::Step(step),
                key,
                max,
                arities: &arities,
            };
            self.step(&pass, &word, &mut next, &mut scratch)?;
            std::mem::swap(&mut word, &mut next);
            progress(step, word.len());
        }
        Ok(word)
    }

    /// The word the turtle draws: `word` with the interpretation rules (the `homomorphism:`
    /// section) applied once, in parallel like a derivation step; `word` itself when there are
    /// none. The seed and the module limit come from `options`.
    pub fn interpretation<'a>(
        &self,
        word: &'a Word,
        options: &DeriveOptions,
    ) -> Result<Cow<'a, Word>, Error> {
        if self.interpretation.is_empty() {
            return Ok(Cow::Borrowed(word));
        }
        let seed = options.seed.unwrap_or(self.settings.seed);
        let arities = self.arities();
        let pass = Pass {
            rules: &self.interpretation,
            stage: Stage::Interpretation,
            // Its own stream: the interpretation never repeats a derivation step's draws.
            key: rng::step_key(seed, u32::MAX),
            max: options.max_modules,
            arities: &arities,
        };
        let mut out = Word::default();
        self.step(&pass, word, &mut out, &mut Scratch::default())?;
        Ok(Cow::Owned(out))
    }

    /// The number of parameters of each symbol, by id.
    fn arities(&self) -> Vec<usize> {
        self.alphabet
            .symbols()
            .iter()
            .map(|s| s.arity as usize)
            .collect()
    }

    /// Per symbol, the slice of `slab` it becomes in a D0L system.
    fn d0l_table(&self) -> (Vec<(u32, u32)>, Vec<SymbolId>) {
        let mut slab = self.rules.fixed.clone();
        let table = self
            .rules
            .plans
            .iter()
            .enumerate()
            .map(|(id, plan)| match *plan {
                Plan::Fixed { start, len } => (start, len),
                _ => {
                    slab.push(id as SymbolId);
                    (slab.len() as u32 - 1, 1)
                }
            })
            .collect();
        (table, slab)
    }

    /// One step of the general engine: `input` rewritten into `out` by `pass.rules`.
    fn step(
        &self,
        pass: &Pass,
        input: &Word,
        out: &mut Word,
        scratch: &mut Scratch,
    ) -> Result<(), Error> {
        let (rules, stage, max, arities) = (pass.rules, pass.stage, pass.max, pass.arities);
        out.symbols.clear();
        out.params.clear();
        let contexts = rules.has_context();
        if contexts {
            pair_brackets(
                &input.symbols,
                self.open,
                self.close,
                &mut scratch.partners,
                &mut scratch.brackets,
            );
            scratch.offsets.clear();
            if !input.params.is_empty() {
                let mut offset = 0u32;
                scratch.offsets.extend(input.symbols.iter().map(|&s| {
                    let at = offset;
                    offset += arities[s as usize] as u32;
                    at
                }));
            }
        }
        let structure = Structure {
            symbols: &input.symbols,
            partners: &scratch.partners,
            ignored: &self.ignored,
            open: self.open,
            close: self.close,
            work: Cell::new(0),
            // Far more than any sensible system needs (a few symbols per production tried), far
            // less than the quadratic work of a pathological one.
            budget: 1024 * input.symbols.len() as u64 + 1_000_000,
        };
        let mut engine = Applier {
            system: self,
            rules,
            input,
            structure,
            offsets: &scratch.offsets,
            arities,
            key: pass.key,
            stage,
            variables: &mut scratch.variables,
            stack: &mut scratch.stack,
            found_left: &mut scratch.found_left,
            found_right: &mut scratch.found_right,
            backtrack: &mut scratch.backtrack,
        };
        let symbols = &input.symbols;
        let n = symbols.len();
        let (mut i, mut p) = (0, 0);
        while i < n {
            // Terminal symbols pile up as a word grows: copy runs of them in one go.
            let (run, param_run) = (i, p);
            while i < n && matches!(rules.plans[symbols[i] as usize], Plan::Copy) {
                p += arities[symbols[i] as usize];
                i += 1;
            }
            out.symbols.extend_from_slice(&symbols[run..i]);
            out.params.extend_from_slice(&input.params[param_run..p]);
            if i < n {
                let s = symbols[i];
                let arity = arities[s as usize];
                let params = &input.params[p..p + arity];
                match &rules.plans[s as usize] {
                    Plan::Copy => {}
                    Plan::Fixed { start, len } => out
                        .symbols
                        .extend_from_slice(&rules.fixed[*start as usize..(*start + *len) as usize]),
                    Plan::Productions(list) => {
                        if !engine.apply(list, i, params, out)? {
                            copy(out, s, params);
                        }
                        if engine.structure.work.get() > engine.structure.budget {
                            return Err(Error::general(format!(
                                "{stage}: matching contexts takes too long (at module {i} of {}): the searches run through long runs of ignored symbols or of sibling branches, for many modules or for this one",
                                group_digits(n)
                            )));
                        }
                    }
                }
                p += arity;
                i += 1;
            }
            if out.symbols.len() > max {
                return Err(Error::general(format!(
                    "{stage}: the word grew past the limit of {} modules after rewriting {} of the {} modules before it (raise the limit, or derive fewer steps)",
                    group_digits(max),
                    group_digits(i),
                    group_digits(n)
                )));
            }
            // Parameters count against the same limit, so memory stays bounded by it.
            if out.params.len() > max {
                return Err(Error::general(format!(
                    "{stage}: the word's parameters grew past the limit of {} values after rewriting {} of the {} modules before it (raise the module limit, or derive fewer steps)",
                    group_digits(max),
                    group_digits(i),
                    group_digits(n)
                )));
            }
        }
        Ok(())
    }
}

/// Appends a module unchanged.
fn copy(out: &mut Word, symbol: SymbolId, params: &[f64]) {
    out.symbols.push(symbol);
    out.params.extend_from_slice(params);
}

/// One D0L step: exact size first, then one slice copy per module.
fn step_d0l(
    input: &Word,
    out: &mut Word,
    table: &[(u32, u32)],
    slab: &[SymbolId],
    step: u32,
    max: usize,
) -> Result<(), Error> {
    let len: u64 = input
        .symbols
        .iter()
        .map(|&s| u64::from(table[s as usize].1))
        .sum();
    if len > max as u64 {
        return Err(limit_error(step, len as usize, max));
    }
    out.symbols.clear();
    out.symbols.resize(len as usize, 0);
    let mut at = 0;
    for &s in &input.symbols {
        let (start, n) = table[s as usize];
        let (start, n) = (start as usize, n as usize);
        out.symbols[at..at + n].copy_from_slice(&slab[start..start + n]);
        at += n;
    }
    Ok(())
}

/// The error of a step whose word would be too long.
fn limit_error(step: u32, len: usize, max: usize) -> Error {
    Error::general(format!(
        "step {step} would make a word of {} module{}, over the limit of {} (raise the limit, or derive fewer steps)",
        group_digits(len),
        if len == 1 { "" } else { "s" },
        group_digits(max)
    ))
}

/// `12345678` as `12,345,678`.
pub(crate) fn group_digits(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The rounds of attempts over a symbol's productions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Attempt {
    /// Context-sensitive productions, right contexts along the axis.
    Axis,
    /// Productions with a right context, which may now enter branches.
    Branches,
    /// Context-free productions.
    Free,
}

/// What one rewriting pass over a word uses: its rules, its name in messages, its random
/// stream, the module limit and each symbol's number of parameters.
struct Pass<'a> {
    rules: &'a Rules,
    stage: Stage,
    key: u64,
    max: usize,
    arities: &'a [usize],
}

/// What applying productions to the modules of one step needs.
struct Applier<'a> {
    system: &'a LSystem,
    rules: &'a Rules,
    input: &'a Word,
    structure: Structure<'a>,
    offsets: &'a [u32],
    arities: &'a [usize],
    key: u64,
    stage: Stage,
    variables: &'a mut Vec<f64>,
    stack: &'a mut Vec<f64>,
    found_left: &'a mut Vec<usize>,
    found_right: &'a mut Vec<usize>,
    backtrack: &'a mut Vec<(usize, usize)>,
}

impl Applier<'_> {
    /// Applies the first production of `list` that matches the module at `at`; false when none
    /// does. Context-sensitive productions come first, with right contexts read along the axis;
    /// then, if none matched, again with right contexts that may enter branches (the paper's
    /// reading); then the context-free ones.
    fn apply(
        &mut self,
        list: &[u32],
        at: usize,
        params: &[f64],
        out: &mut Word,
    ) -> Result<bool, Error> {
        for attempt in [Attempt::Axis, Attempt::Branches, Attempt::Free] {
            for &index in list {
                let production = &self.rules.productions[index as usize];
                let eligible = match attempt {
                    Attempt::Axis => production.has_context(),
                    Attempt::Branches => !production.right.is_empty(),
                    Attempt::Free => !production.has_context(),
                };
                if !eligible || !self.bind(production, at, params, attempt == Attempt::Branches) {
                    continue;
                }
                if self.rewrite(production, at, params, out)? {
                    return Ok(true);
                }
            }
        }
        Ok(false)
    }

    /// Applies `production` (whose contexts matched, variables bound) unless its condition is
    /// false; whether it applied.
    fn rewrite(
        &mut self,
        production: &Production,
        at: usize,
        params: &[f64],
        out: &mut Word,
    ) -> Result<bool, Error> {
        if let Some(condition) = &production.condition {
            let value = condition.eval(self.variables, self.stack);
            if !value.is_finite() {
                return Err(Error::at(
                    condition.position,
                    format!(
                        "{}: the condition cannot be evaluated for {} (it divides by zero, overflows or leaves a function's domain)",
                        self.stage,
                        self.module_text(at, params)
                    ),
                ));
            }
            if value == 0.0 {
                return Ok(false);
            }
        }
        let alternatives = &production.alternatives;
        let chosen = if alternatives.len() == 1 {
            &alternatives[0]
        } else {
            let u = rng::draw(self.key, at);
            alternatives
                .iter()
                .find(|a| u < a.cumulative)
                .unwrap_or(&alternatives[alternatives.len() - 1])
        };
        for module in &chosen.modules {
            out.symbols.push(module.symbol);
            for arg in &module.args {
                let value = arg.eval(self.variables, self.stack);
                if !value.is_finite() {
                    return Err(Error::at(
                        arg.position,
                        format!(
                            "{}: the parameter is {value}, not a finite number, when rewriting {}",
                            self.stage,
                            self.module_text(at, params)
                        ),
                    ));
                }
                out.params.push(value);
            }
        }
        Ok(true)
    }

    /// Checks the contexts of `production` at `at` and binds its variables; false when a
    /// context does not match.
    fn bind(&mut self, production: &Production, at: usize, params: &[f64], enter: bool) -> bool {
        self.variables.clear();
        self.variables.extend_from_slice(params);
        self.variables.resize(production.variables, 0.0);
        if !production.left.is_empty() {
            self.found_left.resize(production.left.len(), 0);
            if !self
                .structure
                .matches_left(at, &production.left, self.found_left)
            {
                return false;
            }
            for (k, &base) in production.left_vars.iter().enumerate() {
                self.copy_params(self.found_left[k], production.left[k], base);
            }
        }
        if !production.right.is_empty() {
            self.found_right.resize(production.right.len(), 0);
            if !self.structure.matches_right(
                at,
                &production.right,
                self.found_right,
                self.backtrack,
                enter,
            ) {
                return false;
            }
            for (k, &base) in production.right_vars.iter().enumerate() {
                self.copy_params(self.found_right[k], production.right[k], base);
            }
        }
        true
    }

    /// Copies the parameters of the module at `position` (a `symbol`) to the variables from
    /// `base`.
    fn copy_params(&mut self, position: usize, symbol: SymbolId, base: u16) {
        let arity = self.arities[symbol as usize];
        if arity == 0 {
            return;
        }
        let offset = self.offsets[position] as usize;
        let base = base as usize;
        self.variables[base..base + arity]
            .copy_from_slice(&self.input.params[offset..offset + arity]);
    }

    /// A module as text, for messages.
    fn module_text(&self, at: usize, params: &[f64]) -> String {
        let symbol = self.system.alphabet.symbol(self.input.symbols[at]);
        let mut text = symbol.name.to_string();
        if !params.is_empty() {
            text.push('(');
            for (k, &v) in params.iter().enumerate() {
                if k > 0 {
                    text.push(',');
                }
                push_number(&mut text, v);
            }
            text.push(')');
        }
        text
    }
}
