//! An `.lsys` file as `shapegram lsystem` takes it: parsed, derived (at most 12 steps and
//! 20,000 modules), interpreted and drawn as tubes and as lines, every error rendered.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_lsystem::{
    DeriveOptions, LSystem, drawing_to_lines_within, drawing_to_model_within, interpret,
};

const MAX_VERTICES: usize = 200_000;

fuzz_target!(|text: &str| {
    let system = match LSystem::parse(text) {
        Ok(system) => system,
        Err(error) => {
            error.render("fuzz.lsys", text);
            return;
        }
    };
    let options = DeriveOptions {
        iterations: Some(system.settings.iterations.min(12)),
        seed: None,
        max_modules: 20_000,
    };
    let drawn = system
        .derive(&options)
        .and_then(|word| {
            system
                .interpretation(&word, &options)
                .map(|w| w.into_owned())
        })
        .map(|word| interpret(&system, &word));
    let drawing = match drawn {
        Ok(drawing) => drawing,
        Err(error) => {
            error.render("fuzz.lsys", text);
            return;
        }
    };
    for build in [drawing_to_model_within, drawing_to_lines_within] {
        match build(&drawing, &system.settings, MAX_VERTICES) {
            Ok(model) => shapegram_fuzz::finish(&model),
            Err(error) => {
                error.render("fuzz.lsys", text);
            }
        }
    }
});
