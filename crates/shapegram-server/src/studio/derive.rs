//! `POST /api/derive`: grammar text derived by the [`Engine`] as the file it is edited in (its
//! kind from the extension, assets and imports beside it), answered with the GLB (base64, or an
//! SVG for a 2D drawing) and the diagnostics, counts and time.
//!
//! Typing sends a request per pause, so requests for one file are serialised and superseded:
//! each takes a generation number; one derivation per file runs at a time, and a request whose
//! generation is no longer the newest when its turn comes (or when its derivation ends) is
//! answered 409 without its model. A derivation already running is not interrupted (the engine
//! has no cancel hook), but it runs under the studio's time budget, after which the engine stops
//! it with an error.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use base64::Engine as _;
use serde::{Deserialize, Serialize};

use super::StudioState;
use crate::error::ApiError;
use crate::extract::JsonBody;

/// What derives grammar text for the studio (the `shapegram` crate's engine glue).
pub trait Engine: Send + Sync + 'static {
    /// Derives `job.text` as the content of the file `job.path`.
    fn derive(&self, job: &DeriveJob) -> Derived;
}

/// One derivation to make.
pub struct DeriveJob {
    /// The file the text is edited in (canonical): its kind and where assets are.
    pub path: PathBuf,
    /// The text, perhaps not saved yet.
    pub text: String,
    /// How long the derivation may take before the engine stops it.
    pub time_budget: Duration,
    /// Whether to send the derivation tree (visual debugging).
    pub tree: bool,
    /// Rewrite in parallel generations and stop after this many (the generation slider).
    pub generations: Option<u32>,
    /// Joints posed by section name after deriving, as `derive --pose` reads them
    /// (`{"Boom": {"rotation": [x, y, z], "translation": [x, y, z]}}`).
    pub pose: Option<serde_json::Value>,
}

/// A diagnostic with its place as lines and columns (1-based, columns in characters; the end
/// is exclusive).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct StudioDiagnostic {
    /// `error` or `warning`.
    pub severity: &'static str,
    pub message: String,
    /// The text shown at the span, if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
    pub hints: Vec<String>,
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
    /// The imported file it is in; `None`: the file being edited.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

/// What a derivation gave.
#[derive(Default)]
pub struct Derived {
    /// The model as GLB; `None` when the grammar does not compile or derive.
    pub glb: Option<Vec<u8>>,
    /// Parse, compile and derivation diagnostics, errors and warnings.
    pub diagnostics: Vec<StudioDiagnostic>,
    /// A failure without a place in the text (a limit, a missing start rule, an unsupported
    /// kind of file).
    pub error: Option<String>,
    /// Hints for `error`.
    pub hints: Vec<String>,
    /// What `print` wrote.
    pub prints: Vec<String>,
    /// Shapes made and leaves left.
    pub shapes: usize,
    pub leaves: usize,
    /// Compiling and deriving, in milliseconds.
    pub derive_ms: f64,
    /// Writing the GLB, in milliseconds.
    pub export_ms: f64,
    /// A 2D drawing (a flat L-system) as SVG, shown instead of a model.
    pub svg: Option<String>,
    /// What was made, in the words of the grammar's kind (`3 steps, 3803 modules, …`), for
    /// kinds whose shapes and leaves say little.
    pub summary: Option<String>,
    /// The derivation tree, when the job asked for it and there is a model.
    pub tree: Option<super::DerivationTree>,
}

/// Per file, the newest generation asked for and the lock of the one running.
#[derive(Default)]
pub struct Generations(Mutex<HashMap<PathBuf, Arc<Slot>>>);

/// One file's derivations.
#[derive(Default)]
pub struct Slot {
    newest: AtomicU64,
    running: tokio::sync::Mutex<()>,
}

impl Generations {
    fn slot(&self, path: &Path) -> Arc<Slot> {
        let mut slots = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        slots.entry(path.to_path_buf()).or_default().clone()
    }
}

/// The body of `POST /api/derive`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeriveRequest {
    /// The file the text is edited in (as `GET /api/files` names it).
    pub path: String,
    pub text: String,
    /// Send the derivation tree with the model.
    #[serde(default)]
    pub tree: bool,
    /// Stop after this many generations (at most 10,000).
    #[serde(default)]
    pub generations: Option<u32>,
    /// Pose joints by section name, as `derive --pose` does.
    #[serde(default)]
    pub pose: Option<serde_json::Value>,
}

/// The answer of `POST /api/derive`.
#[derive(Serialize)]
pub struct DeriveAnswer {
    /// Whether there is a model.
    pub ok: bool,
    /// This request's generation for the file.
    pub generation: u64,
    /// The GLB, base64-encoded.
    pub glb: Option<String>,
    pub glb_bytes: usize,
    pub diagnostics: Vec<StudioDiagnostic>,
    pub error: Option<String>,
    pub hints: Vec<String>,
    pub prints: Vec<String>,
    pub shapes: usize,
    pub leaves: usize,
    pub derive_ms: f64,
    pub export_ms: f64,
    /// A 2D drawing as SVG (then there is no GLB).
    pub svg: Option<String>,
    /// What was made, for grammars that are not CGA-style.
    pub summary: Option<String>,
    /// The derivation tree, when asked for (`"tree": true`) and there is a model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tree: Option<super::DerivationTree>,
}

/// The most generations a request may ask for: deeper derivations are refused by the engine's
/// depth limit long before.
const MAX_GENERATIONS: u32 = 10_000;

/// `POST /api/derive`.
pub async fn derive(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<DeriveRequest>,
) -> Result<Json<DeriveAnswer>, ApiError> {
    if let Some(n) = request.generations.filter(|&n| n > MAX_GENERATIONS) {
        return Err(ApiError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("generations: {n} is more than the {MAX_GENERATIONS} a derivation may have"),
        ));
    }
    let path = state.folders.resolve(&request.path)?;
    let slot = state.generations.slot(&path);
    let generation = slot.newest.fetch_add(1, Ordering::SeqCst) + 1;
    let superseded = || {
        ApiError::new(
            StatusCode::CONFLICT,
            format!("derivation {generation} of this file was superseded by a newer one"),
        )
    };
    let _running = slot.running.lock().await;
    if slot.newest.load(Ordering::SeqCst) != generation {
        return Err(superseded());
    }
    let engine = state.engine.clone();
    let job = DeriveJob {
        path,
        text: request.text,
        time_budget: state.time_budget,
        tree: request.tree,
        generations: request.generations,
        pose: request.pose,
    };
    let derived = tokio::task::spawn_blocking(move || engine.derive(&job))
        .await
        .map_err(|e| ApiError::internal(format!("the derivation panicked: {e}")))?;
    if slot.newest.load(Ordering::SeqCst) != generation {
        return Err(superseded());
    }
    Ok(Json(DeriveAnswer {
        ok: derived.glb.is_some() || derived.svg.is_some(),
        generation,
        glb_bytes: derived.glb.as_ref().map_or(0, Vec::len),
        glb: derived
            .glb
            .map(|g| base64::engine::general_purpose::STANDARD.encode(g)),
        diagnostics: derived.diagnostics,
        error: derived.error,
        hints: derived.hints,
        prints: derived.prints,
        shapes: derived.shapes,
        leaves: derived.leaves,
        derive_ms: derived.derive_ms,
        export_ms: derived.export_ms,
        svg: derived.svg,
        summary: derived.summary,
        tree: derived.tree,
    }))
}
