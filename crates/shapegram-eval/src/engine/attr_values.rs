//! The attributes' values as a derivation starts a lot: what an editor shows beside each
//! attribute, and the default it falls back to when the user's value is cleared.

use super::derive::{initial_shape, overrides};
use super::{DeriveOptions, InitialShape};
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::program::Program;
use crate::rng::child_seed;
use crate::shape::State;
use crate::value::Value;

/// One attribute on one lot.
#[derive(Clone, Debug, PartialEq)]
pub struct AttrValue {
    /// The attribute's name (imported ones with their namespace, `id.name`).
    pub name: String,
    /// The value the derivation starts with: the override when there is one, else the default.
    pub value: Value,
    /// The value of the declaration's expression with the other overrides in place: what the
    /// attribute takes when its own override is dropped.
    pub default: Value,
}

/// Every attribute of `program` (in declaration order) on lot number `index`, as
/// [`super::derive()`] with `options` starts it: the same seed, overrides and random stream,
/// so defaults that call `rand` give the derivation's numbers. An override naming no attribute
/// is the derivation's error.
pub fn attr_values(
    program: &Program,
    lot: &InitialShape,
    index: usize,
    options: &DeriveOptions,
) -> Result<Vec<AttrValue>, DeriveError> {
    let given = overrides(program, options)?;
    let values = evaluate(program, lot, index, options, &given)?;
    let mut defaults = values.clone();
    // An overridden attribute's default needs a run without its own override.
    for (k, (attr, _)) in given.iter().enumerate() {
        let mut others = given.clone();
        others.remove(k);
        let without = evaluate(program, lot, index, options, &others)?;
        defaults[*attr as usize] = without[*attr as usize].clone();
    }
    Ok(program
        .attr_names()
        .zip(values.into_iter().zip(defaults))
        .map(|(name, (value, default))| AttrValue {
            name: name.to_owned(),
            value,
            default,
        })
        .collect())
}

/// The initial attribute values of one lot, as `derive_lot` evaluates them.
fn evaluate(
    program: &Program,
    lot: &InitialShape,
    index: usize,
    options: &DeriveOptions,
    given: &[(u32, Value)],
) -> Result<Vec<Value>, DeriveError> {
    let (scope, geometry) = initial_shape(&lot.footprint)?;
    let number = lot.index.unwrap_or(index as u64);
    let seed = child_seed(options.seed, number);
    let symbol = program
        .start_rule
        .map_or(0, |rule| program.rules[rule as usize].symbol);
    let mut state = State::initial(symbol, scope, geometry, seed);
    let mut ev = Evaluator::new(program, seed, scope.origin);
    ev.assets = options.assets.as_deref();
    ev.lot = index as u32;
    ev.lot_number = number;
    ev.initial_attrs(&mut state, given)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::DVec2;

    fn program(text: &str) -> Program {
        let source = shapegram_syntax::SourceFile::new("t.cga", text);
        let parsed = shapegram_syntax::parse(&source);
        Program::compile(&parsed.grammar).0.expect("compiles")
    }

    fn lot() -> InitialShape {
        let corners = [(0.0, 0.0), (10.0, 0.0), (10.0, 20.0), (0.0, 20.0)];
        InitialShape::from_xz(&corners.map(|(x, z)| DVec2::new(x, z))).unwrap()
    }

    #[test]
    fn defaults_read_the_lot_and_other_attributes_and_overrides_keep_their_own_default() {
        let p = program(
            "attr floorH = 3\nattr ground = floorH + 1\nattr width = scope.sx\nattr name = \"a\"\nLot --> X",
        );
        let options = DeriveOptions {
            attrs: vec![
                ("floorH".to_owned(), Value::Number(4.0)),
                ("ground".to_owned(), Value::Number(9.0)),
            ],
            ..DeriveOptions::default()
        };
        let values = attr_values(&p, &lot(), 0, &options).unwrap();
        let got: Vec<(&str, Value, Value)> = values
            .iter()
            .map(|a| (a.name.as_str(), a.value.clone(), a.default.clone()))
            .collect();
        assert_eq!(
            got,
            [
                ("floorH", Value::Number(4.0), Value::Number(3.0)),
                // Without its own override, `ground` reads the user's floorH.
                ("ground", Value::Number(9.0), Value::Number(5.0)),
                ("width", Value::Number(10.0), Value::Number(10.0)),
                ("name", Value::string("a"), Value::string("a")),
            ]
        );
    }

    #[test]
    fn random_defaults_are_the_derivations_numbers() {
        let p = program("attr h = rand(10, 20)\nLot --> extrude(h) X.");
        for seed in [0, 7] {
            let options = DeriveOptions {
                seed,
                ..DeriveOptions::default()
            };
            let h = attr_values(&p, &lot(), 0, &options).unwrap()[0]
                .value
                .clone();
            let derived = crate::derive(&p, &[lot()], &options).unwrap();
            let Value::Number(h) = h else { panic!("{h:?}") };
            assert!((derived.leaves[0].scope.size.y - h).abs() < 1e-9);
        }
    }

    #[test]
    fn an_unknown_override_is_the_derivations_error() {
        let p = program("attr height = 3\nLot --> X");
        let options = DeriveOptions {
            attrs: vec![("heigth".to_owned(), Value::Number(1.0))],
            ..DeriveOptions::default()
        };
        let e = attr_values(&p, &lot(), 0, &options).unwrap_err();
        assert_eq!(e.message, "the grammar has no attribute `heigth`");
    }
}
