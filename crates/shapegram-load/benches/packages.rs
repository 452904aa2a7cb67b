//! The rule packages benchmark: the public CityEngine rule packages Candler,
//! complexpatterns_01 and envelope2002 derived straight from their `.rpk` archives, on PRT's
//! initial shape (a 20 × 30 m lot, seed 0), with their textures read and UVs projected as the
//! rules ask, into the model a host exports (derive and mesh; the GLB is not written). One core
//! (a one-thread pool). Each package is opened and compiled once and its assets are read once
//! and cached, as a host that keeps a package loaded does; prints models per second and
//! triangles per second per package and for the three in turns.
//!
//! The packages come from the CityEngine corpus (`SHAPEGRAM_CORPUS`, else `../shared/anchors`
//! beside the checkout; see `shapegram-corpus`). Without it the benchmark says so and exits 0.
//!
//!     cargo bench -p shapegram-load --bench packages

use std::hint::black_box;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use shapegram_eval::{DeriveOptions, InitialShape, Program, derive};
use shapegram_geom::{DVec2, Model};
use shapegram_load::{FileAssets, Files, MissingAssets, RulePackage};

/// The packages, as the corpus names their archives.
const PACKAGES: [&str; 3] = [
    "palladio__candler.rpk",
    "rhino__complexpatterns_01.rpk",
    "pyprt__envelope2002.rpk",
];

/// How long each package is derived over and over.
const MEASURE: Duration = Duration::from_secs(3);

/// A package ready to derive: compiled, with its assets.
struct Loaded {
    name: &'static str,
    program: Program,
    options: DeriveOptions,
}

fn main() -> ExitCode {
    let corpus = match shapegram_corpus::locate() {
        Ok(Some(corpus)) => corpus,
        Ok(None) => {
            println!(
                "packages benchmark skipped: no CityEngine corpus (set {} to the folder that holds cityengine-cga and cityengine-rpk)",
                shapegram_corpus::SETTING
            );
            return ExitCode::SUCCESS;
        }
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let loaded: Vec<Loaded> = PACKAGES
        .iter()
        .map(|name| load(name, &corpus.rpk().join(name)))
        .collect();
    let lot = [prt_lot()];
    pool.install(|| {
        let mut total = (0usize, 0usize, Duration::ZERO);
        for package in &loaded {
            let model = model(package, &lot);
            let triangles = triangles(&model);
            let textured = model.parts.iter().filter(|p| p.texture.is_some()).count();
            let (runs, time) = measure(|| {
                black_box(self::model(package, &lot));
            });
            println!(
                "{}: {triangles} triangles in {} parts ({textured} textured); {:.1} models/s, {:.2} M triangles/s ({runs} models in {:.2} s)",
                package.name,
                model.parts.len(),
                runs as f64 / time.as_secs_f64(),
                (runs * triangles) as f64 / time.as_secs_f64() / 1e6,
                time.as_secs_f64()
            );
            total = (total.0 + 1, total.1 + triangles, total.2);
        }
        // The three in turns, as a host deriving a mixed city would.
        let (runs, time) = measure(|| {
            for package in &loaded {
                black_box(model(package, &lot));
            }
        });
        println!(
            "all three in turns: {:.1} models/s, {:.2} M triangles/s",
            (runs * total.0) as f64 / time.as_secs_f64(),
            (runs * total.1) as f64 / time.as_secs_f64() / 1e6,
        );
    });
    ExitCode::SUCCESS
}

/// Opens and compiles the package at `path`, its rule file chosen as PRT chooses it.
fn load(name: &'static str, path: &Path) -> Loaded {
    let package = Arc::new(RulePackage::open(path).unwrap_or_else(|e| panic!("{e}")));
    let entry = package.rule_file(None).unwrap_or_else(|e| panic!("{e}"));
    let files = Files::Package(Arc::clone(&package));
    let read = shapegram_load::read_in(&files, Path::new(&entry)).expect("the rule file");
    let compiled = shapegram_load::compile_in(&read.source, None, &files, Path::new(&entry));
    let program = compiled
        .program
        .unwrap_or_else(|| panic!("{name} compiles: {:?}", compiled.diagnostics));
    // envelope2002's ESRI.lib plant loader reads a vegetation table the package lacks; PRT goes
    // on with an empty table, and so does this.
    let assets = FileAssets::in_package(package, &entry, MissingAssets::Skip);
    let options = DeriveOptions {
        assets: Some(Arc::new(assets)),
        ..DeriveOptions::default()
    };
    Loaded {
        name,
        program,
        options,
    }
}

/// One model of the package on `lots`.
fn model(package: &Loaded, lots: &[InitialShape]) -> Model {
    derive(&package.program, lots, &package.options)
        .unwrap_or_else(|e| panic!("{} derives: {}", package.name, e.message))
        .to_model()
}

/// PRT's initial shape: x from 0 to 20, z from 0 to 30, facing up.
fn prt_lot() -> InitialShape {
    let corners = [(0.0, 0.0), (20.0, 0.0), (20.0, 30.0), (0.0, 30.0)];
    InitialShape::from_xz(&corners.map(|(x, z)| DVec2::new(x, z))).expect("a lot")
}

fn triangles(model: &Model) -> usize {
    model.parts.iter().map(|p| p.mesh.triangulate().len()).sum()
}

/// Runs `work` for at least [`MEASURE`] (and at least three times): the runs and the time.
fn measure(mut work: impl FnMut()) -> (usize, Duration) {
    let started = Instant::now();
    let mut runs = 0;
    while runs < 3 || started.elapsed() < MEASURE {
        work();
        runs += 1;
    }
    (runs, started.elapsed())
}
