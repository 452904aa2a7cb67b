//! Per-call times of the C ABI from a warm handle (the grammar loaded, one derivation done):
//! `sg_state_derive` + `sg_state_mesh` of `examples/house.cga` and of the topological houses.
//! Then the same split in two through the Rust API: deriving (a model, or a topological
//! grammar's triangles, made afresh and dropped each time) and filling the buffers. Prints; asserts nothing. Run with
//! `cargo run --release -p shapegram-ffi --example bench` (one thread: `RAYON_NUM_THREADS=1`).

use std::ffi::CString;
use std::time::Instant;

use shapegram_export::Buffers;
use shapegram_ffi::*;
use shapegram_runtime::{Grammar, Settings};

/// The median of `runs` timings of `call`, in milliseconds.
fn median_ms(runs: usize, mut call: impl FnMut()) -> f64 {
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let started = Instant::now();
            call();
            started.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[runs / 2]
}

fn main() {
    let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/");
    for (file, kind, target_ms) in [
        ("house.cga", SG_KIND_AUTO, 3.0),
        ("topo_house.grammar", SG_KIND_AUTO, 0.2),
        ("topo_pyramid.grammar", SG_KIND_AUTO, 0.2),
        ("topo_brick_house.grammar", SG_KIND_AUTO, 0.2),
    ] {
        let path = CString::new(format!("{examples}{file}")).expect("no NUL in the path");
        let state = sg_state_new();
        assert_eq!(
            sg_state_load_file(state, path.as_ptr(), kind),
            sg_status::SG_OK
        );
        let mut mesh = std::mem::MaybeUninit::<sg_mesh>::uninit();
        let mut call = || {
            assert_eq!(sg_state_derive(state), sg_status::SG_OK);
            assert_eq!(sg_state_mesh(state, mesh.as_mut_ptr()), sg_status::SG_OK);
        };
        call();
        // About a second of calls, at least ten.
        let started = Instant::now();
        call();
        let once = started.elapsed().as_secs_f64();
        let runs = ((1.0 / once.max(1e-6)) as usize).clamp(10, 100_000);
        let mut times = Vec::with_capacity(runs);
        for _ in 0..runs {
            let started = Instant::now();
            call();
            times.push(started.elapsed().as_secs_f64() * 1e3);
        }
        times.sort_by(f64::total_cmp);
        // SAFETY: the last call succeeded and wrote the mesh.
        let mesh = unsafe { mesh.assume_init() };
        println!(
            "{file}: derive + mesh {:.3} ms median, {:.3} ms min, {:.3} ms p95 over {runs} calls \
             (target {target_ms} ms); {} vertices, {} triangles, {} parts",
            times[runs / 2],
            times[0],
            times[runs * 95 / 100],
            mesh.vertex_count,
            mesh.index_count / 3,
            mesh.part_count
        );
        assert_eq!(sg_state_free(state), sg_status::SG_OK);

        // By its path, so that what it reads beside it (textures) is found.
        let path = format!("{examples}{file}");
        let text = std::fs::read_to_string(&path).expect("the example");
        let grammar = Grammar::load(&path, &text, None).expect("the example loads");
        let settings = Settings {
            seed: 0,
            attrs: Vec::new(),
            lots: Vec::new(),
            generations: None,
            control: Default::default(),
        };
        let derived = grammar.derive(&settings).expect("the example derives");
        let derive = median_ms(runs, || drop(grammar.derive(&settings)));
        let mut buffers = Buffers::default();
        let mesh = median_ms(runs, || derived.fill(&mut buffers));
        println!("  split: derive {derive:.3} ms (a fresh result each time), buffers {mesh:.3} ms");
    }
}
