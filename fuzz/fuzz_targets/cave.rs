//! A `.cave` file as `shapegram cave` takes it: parsed, its productions run, the solid meshed
//! (at a coarse level of detail) with gradient normals, the model measured and written.

#![no_main]

use libfuzzer_sys::fuzz_target;
use shapegram_geom::{Color, Model};
use shapegram_implicit::{MeshOptions, mesh, surface_normals, text};

fuzz_target!(|source: &str| {
    let program = match text::parse(source) {
        Ok(program) => program,
        Err(error) => return drop(error.to_string()),
    };
    let run = match program.run(None) {
        Ok(run) => run,
        Err(error) => return drop(error.to_string()),
    };
    let lod = program.lod.unwrap_or(2).min(2);
    let options = MeshOptions::with_cell_size(1.0 / f64::from(lod));
    let meshing = match mesh(run.builder.solid(), &options) {
        Ok(meshing) => meshing,
        Err(error) => return drop(error.to_string()),
    };
    let mut model = Model::single("cave", Color::rgb(0.55, 0.48, 0.42), meshing.mesh.clone());
    model.parts[0].normals =
        surface_normals(run.builder.solid(), &meshing.mesh, options.cell_size / 2.0);
    shapegram_fuzz::finish(&model);
});
