//! From parsed lines to an L-system: interning symbols, evaluating the axiom, grouping
//! productions with the same left side into stochastic alternatives, checking contexts.

use rustc_hash::FxHashMap;

use super::production::{PatternModule, RawModule, RawProduction};
use crate::alphabet::{Alphabet, Symbol, SymbolId};
use crate::error::{Error, Position};
use crate::system::{Alternative, Production, SuccessorModule};
use crate::word::Word;

/// Interns the axiom's modules and evaluates their (constant) parameters.
pub(super) fn build_axiom(modules: &[RawModule], alphabet: &mut Alphabet) -> Result<Word, Error> {
    let mut word = Word::default();
    for module in modules {
        word.symbols.push(intern(
            alphabet,
            module.name,
            module.args.len(),
            module.position,
        )?);
        for arg in &module.args {
            let value = arg.constant().unwrap_or(f64::NAN);
            if !value.is_finite() {
                return Err(Error::at(arg.position, "the value is not a finite number"));
            }
            word.params.push(value);
        }
    }
    Ok(word)
}

/// The id of a symbol, or an error when the alphabet is full.
fn intern(
    alphabet: &mut Alphabet,
    name: char,
    arity: usize,
    position: Position,
) -> Result<SymbolId, Error> {
    alphabet
        .intern(Symbol {
            name,
            arity: arity as u8,
        })
        .ok_or_else(|| Error::at(position, "too many different symbols (at most 65,535)"))
}

/// Every symbol a word can hold: the axiom's and the successors'.
pub(super) fn produced<'a>(
    axiom: &[RawModule],
    raws: impl Iterator<Item = &'a RawProduction>,
) -> Vec<Symbol> {
    let symbol = |m: &RawModule| Symbol {
        name: m.name,
        arity: m.args.len() as u8,
    };
    let mut produced: Vec<Symbol> = axiom.iter().map(symbol).collect();
    for raw in raws {
        produced.extend(raw.successor.iter().map(symbol));
    }
    produced.sort_unstable_by_key(|s| (s.name, s.arity));
    produced.dedup();
    produced
}

/// Groups productions with the same left side (stochastic alternatives), interns their symbols
/// and checks that contexts can ever match (`produced`: the symbols words can hold; `ignored`:
/// the symbols context matching skips).
pub(super) fn group(
    raws: Vec<RawProduction>,
    alphabet: &mut Alphabet,
    produced: &[Symbol],
    ignored: &[char],
) -> Result<Vec<Production>, Error> {
    let mut order: Vec<String> = Vec::new();
    let mut groups: FxHashMap<String, Vec<RawProduction>> = FxHashMap::default();
    for raw in raws {
        if !groups.contains_key(&raw.key) {
            order.push(raw.key.clone());
        }
        groups.entry(raw.key.clone()).or_default().push(raw);
    }

    let mut productions = Vec::with_capacity(order.len());
    for key in order {
        let members = groups.remove(&key).unwrap_or_default();
        if members.len() > 1 {
            // Point at a later line when possible: the first one is usually the intended rule.
            let unweighted = (1..members.len())
                .chain([0])
                .find(|&k| members[k].weight.is_none());
            if let Some(k) = unweighted {
                let other = if k == 0 { 1 } else { 0 };
                return Err(Error::at(
                    members[k].position,
                    format!(
                        "another production with the same left side is on line {}: give each alternative a weight, as in `{} (0.5) -> …`",
                        members[other].position.line, members[k].predecessor.name
                    ),
                ));
            }
        }
        productions.push(build_production(members, alphabet, produced, ignored)?);
    }
    Ok(productions)
}

/// One production from its alternatives (all with the same left side).
fn build_production(
    members: Vec<RawProduction>,
    alphabet: &mut Alphabet,
    produced: &[Symbol],
    ignored: &[char],
) -> Result<Production, Error> {
    let first = &members[0];
    let pattern_id = |alphabet: &mut Alphabet, module: &PatternModule, context: bool| {
        let symbol = Symbol {
            name: module.name,
            arity: module.formals.len() as u8,
        };
        let structural = module.name == '[' || module.name == ']';
        if context && ignored.contains(&module.name) {
            return Err(Error::at(
                module.position,
                format!(
                    "'{}' is in the ignore set, which context matching skips, so this context could never match (drop it from the context or from `ignore:`)",
                    module.name
                ),
            ));
        }
        if context && !structural && !produced.contains(&symbol) {
            let mut arities: Vec<u8> = produced
                .iter()
                .filter(|s| s.name == symbol.name)
                .map(|s| s.arity)
                .collect();
            arities.sort_unstable();
            arities.dedup();
            let others: Vec<String> = arities.iter().map(u8::to_string).collect();
            return Err(Error::at(
                module.position,
                if others.is_empty() {
                    format!(
                        "unknown symbol '{}' in a context: it is in neither the axiom nor any successor, so the production could never apply",
                        module.name
                    )
                } else {
                    format!(
                        "'{}' never has {} parameter{} in a word (it has {}), so this context could never match",
                        module.name,
                        symbol.arity,
                        if symbol.arity == 1 { "" } else { "s" },
                        others.join(" or ")
                    )
                },
            ));
        }
        intern(alphabet, module.name, module.formals.len(), module.position)
    };
    let predecessor = pattern_id(alphabet, &first.predecessor, false)?;
    let mut variables = first.predecessor.formals.len();
    let mut context = |alphabet: &mut Alphabet, modules: &[PatternModule]| {
        let mut ids = Vec::with_capacity(modules.len());
        let mut bases = Vec::with_capacity(modules.len());
        for module in modules {
            ids.push(pattern_id(alphabet, module, true)?);
            bases.push(variables as u16);
            variables += module.formals.len();
        }
        Ok::<_, Error>((ids, bases))
    };
    let (left, left_vars) = context(alphabet, &first.left)?;
    let (right, right_vars) = context(alphabet, &first.right)?;

    let total: f64 = members.iter().map(|m| m.weight.unwrap_or(1.0)).sum();
    let mut cumulative = 0.0;
    let mut alternatives = Vec::with_capacity(members.len());
    let count = members.len();
    let condition = first.condition.clone();
    for (k, member) in members.into_iter().enumerate() {
        cumulative += member.weight.unwrap_or(1.0) / total;
        let mut modules = Vec::with_capacity(member.successor.len());
        for module in member.successor {
            modules.push(SuccessorModule {
                symbol: intern(alphabet, module.name, module.args.len(), module.position)?,
                args: module.args,
            });
        }
        alternatives.push(Alternative {
            // The last alternative takes every draw below 1, whatever the rounding.
            cumulative: if k + 1 == count { 1.0 } else { cumulative },
            modules,
        });
    }
    Ok(Production {
        predecessor,
        left,
        left_vars,
        right,
        right_vars,
        condition,
        alternatives,
        variables,
    })
}
