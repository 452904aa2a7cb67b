//! The runtime's vertex count of a grammar for each seed, which the Godot test compares with
//! the `GrammarMesh`'s: `cargo run --example counts -- FILE SEED…` prints `SEED=VERTICES …`.

use shapegram_export::Buffers;
use shapegram_runtime::{Grammar, Settings};

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: counts FILE SEED…")?;
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let grammar = Grammar::load(&path, &text, None).map_err(|e| e.message)?;
    let mut counts = Vec::new();
    for seed in args {
        let seed: u64 = seed.parse().map_err(|e| format!("seed {seed}: {e}"))?;
        let settings = Settings {
            seed,
            ..Settings::default()
        };
        let mut buffers = Buffers::default();
        grammar
            .derive(&settings)
            .map_err(|e| e.message)?
            .fill(&mut buffers);
        counts.push(format!("{seed}={}", buffers.positions.len()));
    }
    println!("{}", counts.join(" "));
    Ok(())
}
