//! Shared setup for the side-by-side benchmarks of Shapegram and peer engines.
//!
//! The "hello house" grammar, written once per engine as literally as the two languages allow:
//! a 20 × 30 m lot is extruded to `floors` floors of 3 m, its four side faces become facades,
//! facades split into floors, floors into repeated 2.5 m window tiles, and each tile into
//! wall | window | wall. The tile and floor sizes divide the facades exactly, so both engines'
//! repeat rules (Shapegram rounds, symbios-shape floors) give the same counts: per lot and floor
//! 2 × 8 + 2 × 12 = 40 tiles, 120 terminals.
//!
//! Nothing here builds meshes: Shapegram's leaves are implicit boxes (a scope and
//! [`shapegram_eval::Geometry::Box`]), symbios-shape's terminals are oriented boxes with a mesh
//! id.

use shapegram_eval::{DeriveOptions, InitialShape, Program, Value, derive};
use shapegram_geom::DVec2;
use shapegram_syntax::{SourceFile, parse};
use symbios_shape::grammar::parse_statement;
use symbios_shape::{Interpreter, Quat, Scope, Vec3};

/// The house in Shapegram's CGA-style syntax. `Wall.` and `Window.` are leaves at once.
pub const SHAPEGRAM_HOUSE: &str = r#"
attr floors = 10

@StartRule
Lot --> extrude(floors * 3) comp(f) { side : Facade }
Facade --> split(y) { { ~3 : Floor }* }
Floor --> split(x) { { ~2.5 : Tile }* }
Tile --> split(x) { ~1 : Wall. | 1.2 : Window. | ~1 : Wall. }
"#;

/// The same house in symbios-shape's syntax, one statement a line. `Wall` and `Window` have no
/// rule, so each becomes an implicit terminal (`I("Wall")`) without a mesh.
pub const SYMBIOS_HOUSE: &str = r#"
attr Floors = 10
Lot --> Extrude(Floors * 3) Comp(Faces) { Side: Facade }
Facade --> Split(Y) { { ~3: Floor }* }
Floor --> Split(X) { { ~2.5: Tile }* }
Tile --> Split(X) { ~1: Wall | 1.2: Window | ~1: Wall }
"#;

/// Terminals each engine derives from one lot with `floors` floors.
pub fn terminals_per_lot(floors: u32) -> usize {
    // Four facades: two 20 m wide (8 tiles), two 30 m wide (12 tiles); three parts a tile.
    floors as usize * (2 * 8 + 2 * 12) * 3
}

/// Corner `(x, z)` of lot `i`: rows of 40 lots, 5 m apart.
fn lot_corner(i: usize) -> (f64, f64) {
    ((i % 40) as f64 * 25.0, (i / 40) as f64 * 35.0)
}

/// Shapegram's compiled house and the options that set its floor count.
pub struct ShapegramHouse {
    /// The compiled grammar.
    pub program: Program,
    /// Derivation options (the `floors` attribute).
    pub options: DeriveOptions,
    /// The lots.
    pub lots: Vec<InitialShape>,
}

impl ShapegramHouse {
    /// Compiles the grammar and lays out `lots` lots of 20 × 30 m.
    pub fn new(lots: usize, floors: u32) -> Self {
        let parsed = parse(&SourceFile::new("house.cga", SHAPEGRAM_HOUSE));
        assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
        let (program, diagnostics) = Program::compile(&parsed.grammar);
        let program = program.unwrap_or_else(|| panic!("house compiles: {diagnostics:?}"));
        let options = DeriveOptions {
            attrs: vec![("floors".into(), Value::Number(f64::from(floors)))],
            ..DeriveOptions::default()
        };
        let lots = (0..lots)
            .map(|i| {
                let (x, z) = lot_corner(i);
                InitialShape::from_xz(&[
                    DVec2::new(x, z),
                    DVec2::new(x + 20.0, z),
                    DVec2::new(x + 20.0, z + 30.0),
                    DVec2::new(x, z + 30.0),
                ])
                .expect("a rectangle is a lot")
            })
            .collect();
        Self {
            program,
            options,
            lots,
        }
    }

    /// Derives every lot; returns the number of leaves.
    pub fn derive(&self) -> usize {
        derive(&self.program, &self.lots, &self.options)
            .expect("the house derives")
            .leaves
            .len()
    }
}

/// symbios-shape's house: an interpreter with the rules and the lots as root scopes.
pub struct SymbiosHouse {
    /// The interpreter holding the rules.
    pub interpreter: Interpreter,
    /// The lots (footprint scopes in the xz-plane; `Extrude` sets y).
    pub lots: Vec<Scope>,
}

impl SymbiosHouse {
    /// Loads the grammar and lays out `lots` lots of 20 × 30 m.
    pub fn new(lots: usize, floors: u32) -> Self {
        let mut interpreter = Interpreter::new();
        for line in SYMBIOS_HOUSE.lines().filter(|l| !l.trim().is_empty()) {
            let statement = parse_statement(line).unwrap_or_else(|e| panic!("{line}: {e}"));
            interpreter
                .add_statement(statement)
                .unwrap_or_else(|e| panic!("{line}: {e}"));
        }
        interpreter.set_attr("Floors", f64::from(floors));
        let lots = (0..lots)
            .map(|i| {
                let (x, z) = lot_corner(i);
                Scope::new(
                    Vec3::new(x, 0.0, z),
                    Quat::IDENTITY,
                    Vec3::new(20.0, 0.0, 30.0),
                )
            })
            .collect();
        Self { interpreter, lots }
    }

    /// Derives every lot (the interpreter takes one root scope per call); returns the number of
    /// terminals.
    pub fn derive(&self) -> usize {
        self.lots
            .iter()
            .map(|&lot| {
                self.interpreter
                    .derive(lot, "Lot")
                    .expect("the house derives")
                    .terminals
                    .len()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_engines_derive_the_same_terminals() {
        for floors in [1, 4, 10] {
            let expected = 3 * terminals_per_lot(floors);
            assert_eq!(ShapegramHouse::new(3, floors).derive(), expected);
            assert_eq!(SymbiosHouse::new(3, floors).derive(), expected);
        }
    }

    #[test]
    fn the_terminals_are_the_same_boxes() {
        // Same names and the same total area in both engines (windows 1.2 × 3 m each).
        let sg = ShapegramHouse::new(1, 2);
        let d = derive(&sg.program, &sg.lots, &sg.options).unwrap();
        let sy = SymbiosHouse::new(1, 2);
        let m = sy.interpreter.derive(sy.lots[0], "Lot").unwrap();
        for name in ["Wall", "Window"] {
            let a = d.leaves.iter().filter(|l| d.name(l.name) == name).count();
            let b = m.terminals.iter().filter(|t| t.mesh_id == name).count();
            assert_eq!(a, b, "{name}");
        }
        assert!(
            d.leaves
                .iter()
                .all(|l| l.geometry == shapegram_eval::Geometry::Box)
        );
        let area_sg: f64 = d
            .leaves
            .iter()
            .filter(|l| d.name(l.name) == "Window")
            .map(|l| l.scope.size.x * l.scope.size.y)
            .sum();
        let area_sy: f64 = m
            .terminals
            .iter()
            .filter(|t| t.mesh_id == "Window")
            .map(|t| t.scope.size.x * t.scope.size.y)
            .sum();
        assert!((area_sg - area_sy).abs() < 1e-6, "{area_sg} vs {area_sy}");
        assert!((area_sg - 80.0 * 1.2 * 3.0).abs() < 1e-6, "{area_sg}");
    }
}
