//! `POST /api/derive`: grammar text derived by the [`Engine`] as the file it is edited in (its
//! kind from the extension, assets and imports beside it), answered with the GLB (base64, or an
//! SVG for a 2D drawing) and the diagnostics, counts and time.
//!
//! Typing sends a request per pause, so requests for one file are serialised and superseded:
//! each takes a generation number; one derivation per file runs at a time, and a request whose
//! generation is no longer the newest when its turn comes (or when its derivation ends) is
//! answered 409 without its model. A newer request cancels the derivation running for the file
//! through its [`DeriveControl`], so that one answers 409 within about a millisecond instead of
//! running on to its end or to the studio's time budget.
//!
//! The request may carry attribute values, a seed and a lot; the answer reports the grammar's
//! attributes (see [`StudioAttr`]) and any value it dropped. `POST /api/export` derives the same
//! way and answers with the model as GLB, OBJ (with its MTL) or STL files.

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
use shapegram_eval::DeriveControl;

use super::StudioState;
use super::files::Source;
use super::packages::PackagedRule;
use crate::error::ApiError;
use crate::extract::JsonBody;

/// What derives grammar text for the studio (the `shapegram` crate's engine glue).
pub trait Engine: Send + Sync + 'static {
    /// Derives `job.text` as the content of the file `job.path`.
    fn derive(&self, job: &DeriveJob) -> Derived;
}

/// One derivation to make.
pub struct DeriveJob {
    /// The file the text is edited in (canonical): its kind and where assets are. For a rule
    /// file inside a package, its path as the API names it (`/folder/town.rpk!/rules/a.cga`).
    pub path: PathBuf,
    /// The rule file inside a rule package the text is edited in: its imports and assets are
    /// read from the package.
    pub package: Option<PackagedRule>,
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
    /// The seed.
    pub seed: u64,
    /// The user's attribute values by name (JSON numbers, strings and booleans), which override
    /// the grammar's defaults as `--attr` does; values that no longer fit are dropped.
    pub attrs: Vec<(String, serde_json::Value)>,
    /// The lot; `None`: the default lot.
    pub lot: Option<LotRequest>,
    /// Cancelled when a newer request for the same file arrives.
    pub control: Arc<DeriveControl>,
    /// Write the model in this format into [`Derived::files`] instead of the GLB.
    pub export: Option<ExportFormat>,
}

/// A lot the page sends.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum LotRequest {
    /// A polygon drawn on the ground: `[x, z]` corners.
    Polygon {
        /// The corners, in either winding.
        points: Vec<[f64; 2]>,
    },
    /// A GeoJSON (`.geojson`, `.json`) or OBJ file's text, read as `shapegram derive --lots`
    /// reads such a file: every polygon or face a lot.
    File {
        /// The file's name, for its kind and for messages.
        name: String,
        /// Its text.
        text: String,
    },
}

/// The model formats `POST /api/export` writes.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum ExportFormat {
    /// Binary glTF.
    Glb,
    /// Wavefront OBJ and its MTL.
    Obj,
    /// Binary STL.
    Stl,
}

/// An attribute of the grammar as the panel shows it: its name, type, default and value on the
/// first lot, and what its annotations ask for (see `shapegram_eval::AttrAnnotations`).
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct StudioAttr {
    pub name: String,
    /// `number`, `string`, `boolean` or `array`: the default's type.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// What the declaration evaluates to with the user's other values.
    pub default: serde_json::Value,
    /// What the derivation used: the user's value when set, else the default.
    pub value: serde_json::Value,
    /// Whether the user's value was used.
    pub user: bool,
    /// `@Range`: `{min, max, step}` (step 0: none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub range: Option<serde_json::Value>,
    /// `@Enum` (or `@Range` of strings): the choices.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub choices: Option<Vec<serde_json::Value>>,
    /// Whether values outside the range or choices are refused.
    pub restricted: bool,
    /// `@Color`.
    pub color: bool,
    /// `@Group`: the nested groups, outermost first.
    pub group: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub group_order: Option<f64>,
    /// `@Order`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub order: Option<f64>,
    /// `@Hidden`.
    pub hidden: bool,
    /// `@Description`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// `@DisplayName`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub display_name: Option<String>,
    /// `angle`, `distance` or `percent`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<&'static str>,
    /// The annotations' names as written.
    pub annotations: Vec<String>,
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
    /// The grammar's attributes; `None` when it did not compile (the panel keeps what it has).
    pub attrs: Option<Vec<StudioAttr>>,
    /// The user's attribute values that were dropped (no such attribute, or a value of another
    /// type), by name.
    pub dropped: Vec<String>,
    /// Notes for the user: why a value was dropped, parts of a lot file that were skipped.
    pub notes: Vec<String>,
    /// The lots derived.
    pub lots: usize,
    /// With [`DeriveJob::export`]: the files written, by name (`model.obj`, `model.mtl`).
    pub files: Vec<(String, Vec<u8>)>,
}

/// Per file, the newest generation asked for and the lock of the one running.
#[derive(Default)]
pub struct Generations(Mutex<HashMap<PathBuf, Arc<Slot>>>);

/// One file's derivations.
#[derive(Default)]
pub struct Slot {
    newest: AtomicU64,
    running: tokio::sync::Mutex<()>,
    /// The control of the derivation running, which a newer request cancels.
    current: Mutex<Option<Arc<DeriveControl>>>,
}

impl Slot {
    fn set_current(&self, control: Option<Arc<DeriveControl>>) {
        *self.current.lock().unwrap_or_else(PoisonError::into_inner) = control;
    }

    fn cancel_current(&self) {
        if let Some(control) = &*self.current.lock().unwrap_or_else(PoisonError::into_inner) {
            control.cancel();
        }
    }
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
    /// The seed (0 when absent).
    #[serde(default)]
    pub seed: u64,
    /// Attribute values by name.
    #[serde(default)]
    pub attrs: serde_json::Map<String, serde_json::Value>,
    /// The lot (absent: the default lot).
    #[serde(default)]
    pub lot: Option<LotRequest>,
}

/// The body of `POST /api/export`: what to derive, as for `POST /api/derive`, and the format.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportRequest {
    pub path: String,
    pub text: String,
    #[serde(default)]
    pub seed: u64,
    #[serde(default)]
    pub attrs: serde_json::Map<String, serde_json::Value>,
    #[serde(default)]
    pub lot: Option<LotRequest>,
    /// The generation slider's position, as for `POST /api/derive`.
    #[serde(default)]
    pub generations: Option<u32>,
    /// The joints' pose, as for `POST /api/derive`.
    #[serde(default)]
    pub pose: Option<serde_json::Value>,
    pub format: ExportFormat,
}

/// One file of `POST /api/export`'s answer.
#[derive(Serialize)]
pub struct ExportFile {
    /// The name to save it as.
    pub name: String,
    /// Its bytes, base64-encoded.
    pub data: String,
    pub bytes: usize,
}

/// The answer of `POST /api/export`.
#[derive(Serialize)]
pub struct ExportAnswer {
    /// The model's files: one, or an OBJ and its MTL.
    pub files: Vec<ExportFile>,
    pub notes: Vec<String>,
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
    /// The grammar's attributes (absent when it did not compile).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attrs: Option<Vec<StudioAttr>>,
    /// The user's values that were dropped, by name; `notes` says why.
    pub dropped: Vec<String>,
    pub notes: Vec<String>,
    pub lots: usize,
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
    let (path, package) = source_job(state.folders.resolve_source(&request.path)?);
    let slot = state.generations.slot(&path);
    let generation = slot.newest.fetch_add(1, Ordering::SeqCst) + 1;
    slot.cancel_current();
    let superseded = || {
        ApiError::new(
            StatusCode::CONFLICT,
            format!("derivation {generation} of this file was superseded by a newer one"),
        )
    };
    let _running = slot.running.lock().await;
    let control = Arc::new(DeriveControl::new());
    // Published before the check: a request counted after it cancels this derivation.
    slot.set_current(Some(control.clone()));
    if slot.newest.load(Ordering::SeqCst) != generation {
        slot.set_current(None);
        return Err(superseded());
    }
    let job = DeriveJob {
        path,
        package,
        text: request.text,
        time_budget: state.time_budget,
        tree: request.tree,
        generations: request.generations,
        pose: request.pose,
        seed: request.seed,
        attrs: request.attrs.into_iter().collect(),
        lot: request.lot,
        control,
        export: None,
    };
    let derived = run(&state, job).await;
    slot.set_current(None);
    let derived = derived?;
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
        attrs: derived.attrs,
        dropped: derived.dropped,
        notes: derived.notes,
        lots: derived.lots,
    }))
}

/// The path and package of a job on `source`.
fn source_job(source: Source) -> (PathBuf, Option<PackagedRule>) {
    match source {
        Source::File(path) => (path, None),
        Source::Packaged(rule) => (PathBuf::from(rule.path()), Some(rule)),
    }
}

/// Runs the engine on a blocking thread.
async fn run(state: &StudioState, job: DeriveJob) -> Result<Derived, ApiError> {
    let engine = state.engine.clone();
    tokio::task::spawn_blocking(move || engine.derive(&job))
        .await
        .map_err(|e| ApiError::internal(format!("the derivation panicked: {e}")))
}

/// `POST /api/export`: the model of the text, attributes, seed and lot given, as files. Not
/// numbered with the previews: a download is never superseded.
pub async fn export(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ExportRequest>,
) -> Result<Json<ExportAnswer>, ApiError> {
    let (path, package) = source_job(state.folders.resolve_source(&request.path)?);
    let job = DeriveJob {
        path,
        package,
        text: request.text,
        time_budget: state.time_budget,
        seed: request.seed,
        attrs: request.attrs.into_iter().collect(),
        lot: request.lot,
        control: Arc::new(DeriveControl::new()),
        export: Some(request.format),
        tree: false,
        generations: request.generations.map(|g| g.min(MAX_GENERATIONS)),
        pose: request.pose,
    };
    let derived = run(&state, job).await?;
    if derived.files.is_empty() {
        let mut message = derived
            .error
            .or_else(|| {
                derived
                    .diagnostics
                    .iter()
                    .find(|d| d.severity == "error")
                    .map(|d| format!("{}:{}: {}", d.line, d.column, d.message))
            })
            .unwrap_or_else(|| "the grammar gives no model to export".to_owned());
        for hint in &derived.hints {
            message.push_str(&format!(" (hint: {hint})"));
        }
        return Err(ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, message));
    }
    Ok(Json(ExportAnswer {
        files: derived
            .files
            .into_iter()
            .map(|(name, bytes)| ExportFile {
                name,
                bytes: bytes.len(),
                data: base64::engine::general_purpose::STANDARD.encode(bytes),
            })
            .collect(),
        notes: derived.notes,
    }))
}
