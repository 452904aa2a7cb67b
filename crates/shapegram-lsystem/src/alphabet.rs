//! The modules an L-system is made of: a one-character name with a fixed number of parameters.
//!
//! `F` and `F(l)` are different symbols (as in L-Py, productions match name and parameter count);
//! both draw a line, the second with its own length.

use rustc_hash::FxHashMap;

/// The index of a [`Symbol`] in its [`Alphabet`]; words are arrays of these.
pub type SymbolId = u16;

/// A kind of module: its name and how many parameters it carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Symbol {
    /// The one-character name, e.g. `F` or `+`.
    pub name: char,
    /// The number of parameters, 0 for plain symbols.
    pub arity: u8,
}

/// The symbols of one L-system, numbered in order of first appearance in the file.
#[derive(Clone, Debug, Default)]
pub struct Alphabet {
    symbols: Vec<Symbol>,
    ids: FxHashMap<Symbol, SymbolId>,
}

impl Alphabet {
    /// The id of `symbol`, adding it if new; `None` when the alphabet is full (65,535 symbols).
    pub(crate) fn intern(&mut self, symbol: Symbol) -> Option<SymbolId> {
        if let Some(&id) = self.ids.get(&symbol) {
            return Some(id);
        }
        let id = SymbolId::try_from(self.symbols.len())
            .ok()
            .filter(|&id| id < SymbolId::MAX)?;
        self.symbols.push(symbol);
        self.ids.insert(symbol, id);
        Some(id)
    }

    /// The id of `symbol`, if the L-system uses it.
    pub fn id(&self, name: char, arity: u8) -> Option<SymbolId> {
        self.ids.get(&Symbol { name, arity }).copied()
    }

    /// The symbol with id `id`.
    ///
    /// # Panics
    /// If `id` is not from this alphabet.
    pub fn symbol(&self, id: SymbolId) -> Symbol {
        self.symbols[id as usize]
    }

    /// All symbols, indexed by id.
    pub fn symbols(&self) -> &[Symbol] {
        &self.symbols
    }

    /// The number of symbols.
    pub fn len(&self) -> usize {
        self.symbols.len()
    }

    /// Whether there are no symbols.
    pub fn is_empty(&self) -> bool {
        self.symbols.is_empty()
    }
}
