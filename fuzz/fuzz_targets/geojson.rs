//! A GeoJSON lot file as `shapegram derive --lots` takes it: its polygons become lots, and a
//! small grammar (mass, facades, floors, roof) is derived on every one.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_eval::InitialShape;
use shapegram_fuzz::{compile, derive};
use shapegram_syntax::SourceFile;

const GRAMMAR: &str = "Lot --> extrude(9) Mass
Mass --> comp(f) { side : Facade | top : roofHip(30) Roof. | bottom : NIL }
Facade --> split(y) { ~3 : Floor }*
Floor --> split(x) { ~1 : Wall. | 1.2 : Window. | ~1 : Wall. }
";

fuzz_target!(|text: &str| {
    let Ok(found) = shapegram_export::read_geojson(text) else {
        return;
    };
    let lots: Vec<InitialShape> = found
        .rings
        .iter()
        .filter_map(|r| InitialShape::from_xz(r))
        .collect();
    if lots.is_empty() || lots.len() > 16 {
        return;
    }
    let source = SourceFile::new("lots.cga", GRAMMAR);
    let program = compile(&source).expect("the lot grammar compiles");
    derive(&source, &program, &lots);
});
