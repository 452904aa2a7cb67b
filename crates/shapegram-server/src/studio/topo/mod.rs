//! The studio's editor of topological split grammars (the Shape Grammar Editor, thesis 3.1): an
//! open `.sgproj.json` project lives here as an editing session of shapegram-topo's [`Editor`],
//! and the page sends it authoring steps ([`action`]), undo and redo, and asks for what to draw
//! ([`view`]). Saving writes the project atomically; compiling writes the `.grammar` beside it;
//! the tester and the anchor preview generate with shapegram-topo's interpreter. The geometry is
//! all here: the page only draws and picks.

pub mod action;
pub mod pending;
pub mod view;

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use serde::{Deserialize, Serialize};
use shapegram_topo::{
    Assignment, Editor, GrammarMesh, GrammarState, NodeId, NodeKind, Project, compile,
};

use super::StudioState;
use crate::error::ApiError;
use crate::extract::JsonBody;
use action::{Action, Made};
use view::{MeshView, ProjectView};

/// The file name ending of topological grammar projects.
pub const PROJECT_SUFFIX: &str = ".sgproj.json";

/// Most generations the tester and the preview run (each multiplies the shapes).
pub const MAX_GENERATIONS: u32 = 64;

/// The open projects, by canonical path.
#[derive(Default)]
pub struct Sessions(Mutex<HashMap<PathBuf, Session>>);

/// One open project: its editor, the project as last saved, and the sub-shapes hidden in the
/// edit view (rule, node), which are the view's and not undone.
struct Session {
    editor: Editor,
    saved: Project,
    hidden: BTreeSet<(u32, NodeId)>,
}

/// Which rule (or else symbol) the edit view shows.
#[derive(Deserialize, Default, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct ViewChoice {
    pub rule: Option<u32>,
    pub symbol: Option<u32>,
}

/// A request naming the project and the view to answer with.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProjectRequest {
    pub path: String,
    #[serde(default)]
    pub view: ViewChoice,
}

/// The body of `POST /api/topo/action`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActionRequest {
    pub path: String,
    pub action: Action,
    #[serde(default)]
    pub view: ViewChoice,
}

/// The body of `POST /api/topo/visibility`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VisibilityRequest {
    pub path: String,
    pub rule: u32,
    pub node: NodeId,
    pub visible: bool,
    #[serde(default)]
    pub view: ViewChoice,
}

/// The answer of an authoring step: what it made and the new state.
#[derive(Serialize)]
pub struct Applied {
    pub made: Made,
    pub state: ProjectView,
}

impl Sessions {
    /// Runs `f` on the session of `path`, if the project is open.
    fn with<T>(
        &self,
        path: &Path,
        f: impl FnOnce(&mut Session) -> Result<T, ApiError>,
    ) -> Result<T, ApiError> {
        let mut sessions = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let session = sessions.get_mut(path).ok_or_else(|| {
            ApiError::new(
                StatusCode::CONFLICT,
                format!(
                    "`{}` is not open: POST /api/topo/open first",
                    path.display()
                ),
            )
        })?;
        f(session)
    }
}

impl Session {
    fn state(&self, path: &Path, choice: ViewChoice) -> ProjectView {
        let project = self.editor.project();
        let (symbols, rules) = view::symbols_and_rules(project);
        ProjectView {
            path: path.display().to_string(),
            symbols,
            rules,
            undo: self.editor.undo_depth(),
            redo: self.editor.redo_depth(),
            dirty: *project != self.saved,
            materials: view::materials(project),
            edit: view::edit_view(project, choice.rule, choice.symbol, &self.hidden),
        }
    }
}

/// The project file `path` names, if the studio may touch it.
fn project_path(state: &StudioState, path: &str) -> Result<PathBuf, ApiError> {
    state.folders.resolve_project(path)
}

fn unprocessable(message: impl std::fmt::Display) -> ApiError {
    ApiError::new(StatusCode::UNPROCESSABLE_ENTITY, message.to_string())
}

/// `POST /api/topo/open`: reads the project (a blank file is a new, empty project) into a fresh
/// session, replacing one open before.
pub async fn open(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<ProjectView>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let text = std::fs::read_to_string(&real)
        .map_err(|e| ApiError::bad_request(format!("cannot read `{}`: {e}", request.path)))?;
    let project = if text.trim().is_empty() {
        Project::new()
    } else {
        Project::from_json(&text).map_err(|e| unprocessable(format!("{}: {e}", request.path)))?
    };
    let session = Session {
        editor: Editor::new(project.clone()),
        saved: project,
        hidden: BTreeSet::new(),
    };
    let answer = session.state(&real, request.view);
    state
        .topo
        .0
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .insert(real, session);
    Ok(Json(answer))
}

/// `POST /api/topo/state`: the open project and the edit view asked for.
pub async fn current(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<ProjectView>, ApiError> {
    let real = project_path(&state, &request.path)?;
    state
        .topo
        .with(&real, |s| Ok(Json(s.state(&real, request.view))))
}

/// `POST /api/topo/action`: one authoring step (undoable); a refused step changes nothing and
/// answers 422 with the reason.
pub async fn apply(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ActionRequest>,
) -> Result<Json<Applied>, ApiError> {
    let real = project_path(&state, &request.path)?;
    state.topo.with(&real, |session| {
        let made = session
            .editor
            .apply(|project| request.action.run(project))
            .map_err(unprocessable)?;
        Ok(Json(Applied {
            made,
            state: session.state(&real, request.view),
        }))
    })
}

/// `POST /api/topo/undo`.
pub async fn undo(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<ProjectView>, ApiError> {
    step(&state, request, Editor::undo, "nothing to undo")
}

/// `POST /api/topo/redo`.
pub async fn redo(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<ProjectView>, ApiError> {
    step(&state, request, Editor::redo, "nothing to redo")
}

fn step(
    state: &StudioState,
    request: ProjectRequest,
    go: fn(&mut Editor) -> bool,
    none: &str,
) -> Result<Json<ProjectView>, ApiError> {
    let real = project_path(state, &request.path)?;
    state.topo.with(&real, |session| {
        if !go(&mut session.editor) {
            return Err(ApiError::new(StatusCode::CONFLICT, none));
        }
        Ok(Json(session.state(&real, request.view)))
    })
}

/// `POST /api/topo/visibility`: shows or hides a sub-shape in the edit view.
pub async fn visibility(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<VisibilityRequest>,
) -> Result<Json<ProjectView>, ApiError> {
    let real = project_path(&state, &request.path)?;
    state.topo.with(&real, |session| {
        let rule = session
            .editor
            .project()
            .rule(request.rule)
            .map_err(unprocessable)?;
        rule.tree.node(request.node).map_err(unprocessable)?;
        let key = (request.rule, request.node);
        if request.visible {
            session.hidden.remove(&key);
        } else {
            session.hidden.insert(key);
        }
        Ok(Json(session.state(&real, request.view)))
    })
}

/// The answer of `POST /api/topo/save` and `POST /api/topo/compile`.
#[derive(Serialize)]
pub struct Written {
    pub path: String,
    pub bytes: usize,
}

/// `POST /api/topo/save`: writes the project to its file atomically (a crash leaves the old
/// file or the new one, never half of one).
pub async fn save(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<Written>, ApiError> {
    let real = project_path(&state, &request.path)?;
    state.topo.with(&real, |session| {
        let project = session.editor.project().clone();
        let text = project.to_json();
        write_file(&real, &text, &request.path)?;
        session.saved = project;
        Ok(Json(Written {
            path: request.path.clone(),
            bytes: text.len(),
        }))
    })
}

/// `POST /api/topo/compile`: compiles the project and writes the `.grammar` beside it
/// (`house.sgproj.json` → `house.grammar`).
pub async fn compile_project(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<ProjectRequest>,
) -> Result<Json<Written>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let project = state.topo.with(&real, |s| Ok(s.editor.project().clone()))?;
    let grammar = compile(&project).map_err(unprocessable)?;
    let target = beside(&real, "grammar");
    let text = grammar.to_json();
    write_file(&target, &text, &target.display().to_string())?;
    Ok(Json(Written {
        path: target.display().to_string(),
        bytes: text.len(),
    }))
}

/// `POST /api/topo/export`: the tester's model (the body of `POST /api/topo/test`) written as
/// GLB beside the project (`house.sgproj.json` → `house.glb`), textures read beside it.
pub async fn export(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<TestRequest>,
) -> Result<Json<Written>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let project = state.topo.with(&real, |s| Ok(s.editor.project().clone()))?;
    let name = project
        .symbol(request.symbol)
        .map_err(unprocessable)?
        .name
        .clone();
    let target = beside(&real, "glb");
    let folder = real.parent().map(Path::to_path_buf).unwrap_or_default();
    let run = Run {
        name,
        shape: None,
        seed: request.seed,
        generations: request.generations,
    };
    run.generated(project, move |state| {
        let model =
            GrammarMesh::new(state).to_model_with(|texture| texture_beside(&folder, texture));
        shapegram_export::save(&model, &target, &shapegram_export::ExportOptions::default())
            .map_err(|e| ApiError::new(StatusCode::CONFLICT, e.to_string()))?;
        let bytes = std::fs::metadata(&target).map_or(0, |m| m.len() as usize);
        Ok(Json(Written {
            path: target.display().to_string(),
            bytes,
        }))
    })
    .await
}

/// The file beside a project with its name and another extension (`house.sgproj.json` →
/// `house.grammar`).
fn beside(project: &Path, extension: &str) -> PathBuf {
    let stem = project
        .file_name()
        .and_then(|n| n.to_str())
        .and_then(|n| n.strip_suffix(PROJECT_SUFFIX))
        .unwrap_or("project");
    project.with_file_name(format!("{stem}.{extension}"))
}

/// Writes `text` to `path` atomically; a failure is a conflict naming the file as `shown`.
fn write_file(path: &Path, text: &str, shown: &str) -> Result<(), ApiError> {
    super::files::write_atomically(path, text.as_bytes())
        .map_err(|e| ApiError::new(StatusCode::CONFLICT, format!("cannot write `{shown}`: {e}")))
}

/// A texture's image, read only from within the project's folder (a project file must not make
/// the studio copy files from elsewhere into an export); `None` draws its faces in colour.
fn texture_beside(folder: &Path, texture: &str) -> Option<std::sync::Arc<[u8]>> {
    let relative = Path::new(texture);
    let inside = relative
        .components()
        .all(|c| matches!(c, std::path::Component::Normal(_)));
    if !inside {
        return None;
    }
    std::fs::read(folder.join(relative)).ok().map(Into::into)
}

/// The body of `POST /api/topo/test`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TestRequest {
    pub path: String,
    /// The symbol to start from.
    pub symbol: u32,
    #[serde(default)]
    pub seed: u64,
    pub generations: u32,
}

/// The body of `POST /api/topo/preview`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreviewRequest {
    pub path: String,
    pub rule: u32,
    /// A sub-shape with a symbol.
    pub node: NodeId,
    #[serde(default)]
    pub seed: u64,
    /// Generations of the assigned symbol's rules (default 1).
    pub generations: Option<u32>,
}

/// A generated model.
#[derive(Serialize)]
pub struct Generated {
    pub generation: u32,
    pub terminals: usize,
    pub non_terminals: usize,
    pub triangles: usize,
    pub parts: Vec<MeshView>,
}

/// `POST /api/topo/test`: the tester: `generations` generations from a symbol's prototype.
pub async fn test(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<TestRequest>,
) -> Result<Json<Generated>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let project = state.topo.with(&real, |s| Ok(s.editor.project().clone()))?;
    let name = project
        .symbol(request.symbol)
        .map_err(unprocessable)?
        .name
        .clone();
    generate(project, name, None, request.seed, request.generations).await
}

/// `POST /api/topo/preview`: the anchor preview: the assigned symbol's rules applied to a
/// sub-shape, its vertices ordered from the anchor, so the user sees which way the symbol
/// stands.
pub async fn preview(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<PreviewRequest>,
) -> Result<Json<Generated>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let project = state.topo.with(&real, |s| Ok(s.editor.project().clone()))?;
    let node = project
        .rule(request.rule)
        .and_then(|r| r.tree.node(request.node))
        .map_err(unprocessable)?;
    let NodeKind::Leaf(Assignment::Symbol { symbol, anchor }) = node.kind else {
        return Err(unprocessable(format!(
            "sub-shape {} has no symbol to preview",
            request.node
        )));
    };
    let vertices = view::anchored_vertices(&node.shape, anchor)
        .ok_or_else(|| unprocessable("the anchor is not on the sub-shape"))?;
    let name = project.symbols[symbol as usize].name.clone();
    let generations = request.generations.unwrap_or(1);
    generate(project, name, Some(vertices), request.seed, generations).await
}

/// Compiles `project` and runs `generations` generations from symbol `name` (from `shape`, or
/// its prototype) on a blocking thread, reported as the tester shows it.
async fn generate(
    project: Project,
    name: String,
    shape: Option<Vec<shapegram_geom::DVec3>>,
    seed: u64,
    generations: u32,
) -> Result<Json<Generated>, ApiError> {
    let run = Run {
        name,
        shape,
        seed,
        generations,
    };
    run.generated(project, |state| {
        let mesh = GrammarMesh::new(state);
        Ok(Json(Generated {
            generation: state.generation(),
            terminals: state.terminals().len(),
            non_terminals: state.non_terminals().len(),
            triangles: mesh.triangle_count(),
            parts: view::mesh_view(&mesh),
        }))
    })
    .await
}

/// A run of a project's compiled grammar, as the tester, the preview and the export ask for it.
struct Run {
    /// The symbol it starts from.
    name: String,
    /// The start shape's vertices, or the symbol's prototype.
    shape: Option<Vec<shapegram_geom::DVec3>>,
    seed: u64,
    generations: u32,
}

impl Run {
    /// Compiles `project`, runs the generations on a blocking thread and hands the final state
    /// to `then`; more than [`MAX_GENERATIONS`] is refused before any work.
    async fn generated<T: Send + 'static>(
        self,
        project: Project,
        then: impl FnOnce(&GrammarState) -> Result<T, ApiError> + Send + 'static,
    ) -> Result<T, ApiError> {
        if self.generations > MAX_GENERATIONS {
            return Err(ApiError::bad_request(format!(
                "at most {MAX_GENERATIONS} generations, not {}",
                self.generations
            )));
        }
        tokio::task::spawn_blocking(move || {
            let grammar = compile(&project).map_err(unprocessable)?;
            let mut state = GrammarState::new(&grammar, &self.name)
                .map_err(unprocessable)?
                .with_seed(self.seed)
                .with_generations(self.generations);
            if let Some(shape) = self.shape {
                state = state.with_initial_shape(shape).map_err(unprocessable)?;
            }
            state.generate_all().map_err(unprocessable)?;
            then(&state)
        })
        .await
        .map_err(ApiError::internal)?
    }
}
