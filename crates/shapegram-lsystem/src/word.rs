//! Words: the strings an L-system rewrites, stored flat for speed.

use crate::alphabet::{Alphabet, Symbol, SymbolId};

/// A word: one symbol id per module, and all parameters back to back in a separate array (module
/// `i` owns the next `arity` values). No module owns a heap allocation, so a word of 10⁸ modules
/// is two arrays.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Word {
    pub(crate) symbols: Vec<SymbolId>,
    pub(crate) params: Vec<f64>,
}

impl Word {
    /// The number of modules.
    pub fn len(&self) -> usize {
        self.symbols.len()
    }

    /// Whether the word has no modules.
    pub fn is_empty(&self) -> bool {
        self.symbols.is_empty()
    }

    /// The symbol ids, one per module.
    pub fn symbols(&self) -> &[SymbolId] {
        &self.symbols
    }

    /// All parameters, module after module.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The modules with their parameters, in order.
    pub fn modules<'a>(
        &'a self,
        alphabet: &'a Alphabet,
    ) -> impl Iterator<Item = (Symbol, &'a [f64])> + 'a {
        let mut offset = 0;
        self.symbols.iter().map(move |&id| {
            let symbol = alphabet.symbol(id);
            let params = &self.params[offset..offset + symbol.arity as usize];
            offset += symbol.arity as usize;
            (symbol, params)
        })
    }

    /// The word as text: no spaces, parameters as `A(8,7)`, numbers in their shortest
    /// round-trip decimal form (`0.1`, `8`, never `-0`).
    pub fn to_text(&self, alphabet: &Alphabet) -> String {
        let mut text = String::with_capacity(self.symbols.len() + self.params.len() * 4);
        for (symbol, params) in self.modules(alphabet) {
            text.push(symbol.name);
            if symbol.arity > 0 {
                text.push('(');
                for (k, &value) in params.iter().enumerate() {
                    if k > 0 {
                        text.push(',');
                    }
                    push_number(&mut text, value);
                }
                text.push(')');
            }
        }
        text
    }
}

/// Appends `value` in the shortest decimal form that reads back as the same `f64`: plain
/// digits, or an exponent (`1e-300`, `2.5e22`) for magnitudes below 10⁻⁶ or from 10²¹ on, where
/// plain digits would run to hundreds of zeros.
pub(crate) fn push_number(text: &mut String, value: f64) {
    use std::fmt::Write;
    // -0 and 0 are the same parameter value; printing "-0" would only confuse.
    let value = if value == 0.0 { 0.0 } else { value };
    let magnitude = value.abs();
    let _ = if value != 0.0 && !(1e-6..1e21).contains(&magnitude) {
        write!(text, "{value:e}")
    } else {
        write!(text, "{value}")
    };
}
