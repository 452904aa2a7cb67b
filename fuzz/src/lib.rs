//! What the fuzz targets share: small limits, and the steps every model takes on its way out
//! (measured as `shapegram info` measures it, written in every format, read back).

use std::io::Cursor;
use std::time::Duration;

use shapegram_eval::{DeriveOptions, InitialShape, Program};
use shapegram_export::{ExportOptions, read_glb, write_glb_to, write_obj_to, write_stl_to};
use shapegram_geom::{DVec2, Model};
use shapegram_syntax::{Diagnostic, SourceFile};

/// Derivation limits small enough that a fuzz input runs in milliseconds, yet deep enough for
/// every operation to be reached.
pub fn small_limits() -> DeriveOptions {
    DeriveOptions {
        max_shapes: 2_000,
        max_depth: 64,
        time_budget: Some(Duration::from_secs(2)),
        implicit_cell: Some(0.5),
        ..DeriveOptions::default()
    }
}

/// The CLI's default lot: 20 × 30 m, facing up.
pub fn default_lot() -> InitialShape {
    let corners = [(0.0, 0.0), (20.0, 0.0), (20.0, 30.0), (0.0, 30.0)];
    InitialShape::from_xz(&corners.map(|(x, z)| DVec2::new(x, z))).expect("a lot with area")
}

/// Parses and compiles a grammar as `shapegram derive` does, rendering every diagnostic;
/// `None` when it has errors.
pub fn compile(source: &SourceFile) -> Option<Program> {
    let parsed = shapegram_syntax::parse(source);
    render(source, &parsed.diagnostics);
    if parsed.diagnostics.iter().any(Diagnostic::is_error) {
        return None;
    }
    let (program, diagnostics) = Program::compile(&parsed.grammar);
    render(source, &diagnostics);
    program
}

/// Renders diagnostics (spans must lie on character boundaries inside the text).
pub fn render(source: &SourceFile, diagnostics: &[Diagnostic]) {
    let text = source.text();
    for d in diagnostics {
        let (start, end) = (d.span.start as usize, d.span.end as usize);
        assert!(
            start <= end && end <= text.len(),
            "span out of range: {:?}",
            d.span
        );
        assert!(text.is_char_boundary(start) && text.is_char_boundary(end));
        source.render(d);
    }
}

/// Derives `program` on `lots` under [`small_limits`]; a derived model goes through
/// [`finish`], an error is rendered.
pub fn derive(source: &SourceFile, program: &Program, lots: &[InitialShape]) {
    match shapegram_eval::derive(program, lots, &small_limits()) {
        Ok(derivation) => finish(&derivation.to_model()),
        Err(error) => {
            if let Some(diagnostic) = error.to_diagnostic() {
                render(source, &[diagnostic]);
            }
        }
    }
}

/// What happens to every model: measured as `shapegram info` does, written as GLB, OBJ and
/// STL, and the GLB read back with as many parts.
pub fn finish(model: &Model) {
    measure(model);
    let options = ExportOptions::default();
    let mut glb = Vec::new();
    write_glb_to(model, &options, &mut glb).expect("a GLB written to memory");
    let mut obj = Vec::new();
    write_obj_to(model, &options, "fuzz.mtl", &mut obj).expect("an OBJ written to memory");
    let mut stl = Cursor::new(Vec::new());
    write_stl_to(model, &mut stl).expect("an STL written to memory");
    read_glb(&glb).expect("the GLB we wrote reads back");
}

/// The measurements of `shapegram info`: welded parts, triangles, edges, area and volume.
pub fn measure(model: &Model) {
    let tolerance = 1e-9 * model.bounds().map_or(0.0, |b| b.diagonal());
    for part in &model.parts {
        let welded = part.mesh.welded(tolerance);
        let _ = welded.triangulate();
        let _ = welded.edge_report().is_watertight();
        let _ = (welded.area(), welded.signed_volume());
    }
}

/// Generates a topological grammar from its first symbol as `shapegram topo` does (eight
/// generations, at most 2,000 shapes) and finishes its model.
pub fn generate(grammar: &shapegram_topo::Grammar) {
    let Some(symbol) = grammar.symbol_names().first().map(|s| (*s).to_owned()) else {
        return;
    };
    let mut state = match shapegram_topo::GrammarState::new(grammar, &symbol) {
        Ok(state) => state.with_seed(0x2a).with_generations(8),
        Err(error) => return drop(error.to_string()),
    };
    state.max_shapes = 2_000;
    if let Err(error) = state.generate_all() {
        return drop(error.to_string());
    }
    finish(&shapegram_topo::GrammarMesh::new(&state).to_model());
}
