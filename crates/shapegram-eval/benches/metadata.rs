//! The cost of `--metadata` on a big model: 100 lots of the city benchmark's grammar (about
//! 153,000 leaves) with a `report()` per floor and per window, as `shapegram derive --metadata`
//! writes them (a node per leaf and per lot). Prints, best of three on one thread, the time to
//! build the model's parts with and without metadata, the time to write the GLB and its size,
//! so the metadata's share can be read off against the same model without it
//! (`docs/output.md`, "Metadata on big models").

mod city_lots;

use std::hint::black_box;
use std::time::Instant;

use shapegram_eval::{DeriveOptions, MetadataScope, ModelOptions, Program, derive};
use shapegram_export::{ExportOptions, write_glb};
use shapegram_syntax::{SourceFile, parse};

const CITY: &str = r##"
attr floors = floor(rand(5, 21))
const floorH = 3.2

@StartRule
Lot --> extrude(floors * floorH) Mass
Mass --> comp(f) { side : Facade | top : Roof | bottom : NIL }
Facade --> split(y) { 4 : Ground | { ~floorH : Floor }* }
Floor --> report("floor.area", scope.sx * scope.sy)
          split(x) { 0.5 : Wall | { ~2.8 : Tile }* | 0.5 : Wall }
Tile --> split(x) { ~1 : Wall | 1.4 : Window | ~1 : Wall }
Window --> report("windows", 1) Pane
Pane --> 40% : color("#5d7fa3") Glass.
         30% : color("#34495e") Glass.
         else : split(y) { 0.9 : Wall | ~1 : color("#8fb3d9") Glass. | 0.4 : Wall }
Ground --> split(x) { { ~5 : Shop }* }
Shop --> split(x) { 0.4 : Wall | ~1 : color("#a0c4e8") Glass. | 0.4 : Wall }
Roof --> color("#777777")
Wall --> color("#d9d4c7")
"##;

/// The fastest of three runs of `f`, in seconds, and its last result.
fn best_of_three<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut result = None;
    for _ in 0..3 {
        // The last result is let go before the clock starts.
        drop(result.take());
        let started = Instant::now();
        let made = black_box(f());
        best = best.min(started.elapsed().as_secs_f64());
        result = Some(made);
    }
    (best, result.expect("ran three times"))
}

fn main() {
    let parsed = parse(&SourceFile::new("metadata.cga", CITY));
    let program = Program::compile(&parsed.grammar)
        .0
        .expect("the benchmark grammar compiles");
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let derivation = derive(&program, &city_lots::lots(100), &options).expect("the city derives");
    let attr_names: Vec<String> = program.attr_names().map(str::to_owned).collect();
    let export = ExportOptions::default();
    for (label, metadata) in [
        ("without metadata", MetadataScope::None),
        ("with metadata per leaf", MetadataScope::Leaf),
    ] {
        let model_options = ModelOptions {
            metadata,
            attr_names: attr_names.clone(),
            ..ModelOptions::default()
        };
        let (model_time, model) = best_of_three(|| derivation.to_model_with(&model_options));
        let (write_time, glb) = best_of_three(|| write_glb(&model, &export));
        println!(
            "metadata city, {label}: 100 lots, {} leaves, {} parts; model built in {:.0} ms, \
             GLB of {:.1} MB written in {:.0} ms",
            derivation.stats.leaves,
            model.parts.len(),
            model_time * 1e3,
            glb.len() as f64 / 1e6,
            write_time * 1e3,
        );
    }
}
