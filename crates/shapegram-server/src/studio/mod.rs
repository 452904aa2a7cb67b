//! Shapegram Studio's server: the single-user, local mode of this crate (`shapegram studio`),
//! beside the multi-user repository of [`crate::router`]. See `docs/studio.md`.
//!
//! It serves the page (built from `studio/` and embedded, [`assets`]) and a JSON API over the
//! grammar files it was given and the grammar files in their folders ([`files`]), and the rule
//! files inside rule packages ([`packages`]): list, read, save, and derive text with the engine
//! ([`derive`]); and the engine's vocabulary for completion ([`vocabulary`]). Because the page
//! writes files, every request passes [`guard`] first: the Host must be this server's loopback
//! address (against DNS rebinding) and a request that is not a GET must come from the studio's
//! own page (its Origin), so that no other site can write through the user's browser.
//!
//! Deriving is the engine's business, which lives in the `shapegram` crate with the command line
//! (assets, imports, goal libraries, GLB export): it comes in as an [`Engine`].

pub mod assets;
pub mod derive;
pub mod files;
pub mod guard;
pub mod packages;
pub mod topo;
pub mod tree;
pub mod vocabulary;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::routing::{get, post};

use crate::error::ApiError;

pub use derive::{
    DeriveJob, Derived, Engine, ExportFormat, LotRequest, StudioAttr, StudioDiagnostic,
};
pub use files::{Folders, Source};
pub use packages::PackagedRule;
pub use tree::{DerivationTree, PrimitiveNodes, RuleInfo, RulePlace};

/// What the studio's handlers share.
#[derive(Clone)]
pub struct StudioState {
    /// The files given and the folders they are in.
    pub folders: Arc<Folders>,
    /// Derives grammar text.
    pub engine: Arc<dyn Engine>,
    /// The port the server listens on: the only one the Host and Origin may name.
    pub port: u16,
    /// How long one derivation may run before the engine stops it.
    pub time_budget: Duration,
    /// Per file, the newest derivation asked for and the one running.
    pub generations: Arc<derive::Generations>,
    /// How each file was read, so that saving writes it back the same way.
    pub formats: Arc<files::Formats>,
    /// The topological grammar projects open in the editor.
    pub topo: Arc<topo::Sessions>,
}

impl StudioState {
    /// The state for the studio on `port` over `folders`.
    pub fn new(folders: Folders, engine: Arc<dyn Engine>, port: u16) -> StudioState {
        StudioState {
            folders: Arc::new(folders),
            engine,
            port,
            time_budget: Duration::from_secs(10),
            generations: Arc::default(),
            formats: Arc::default(),
            topo: Arc::default(),
        }
    }
}

/// The studio's application: the page, its assets and the API, behind the Host/Origin guard.
pub fn router(state: StudioState) -> Router {
    Router::new()
        .route("/", get(assets::index))
        .route("/topo", get(assets::topo))
        .route("/assets/{name}", get(assets::asset))
        .route("/api/files", get(files::list))
        .route("/api/file", get(files::read).put(files::save))
        .route("/api/derive", post(derive::derive))
        .route("/api/vocabulary", get(vocabulary::vocabulary))
        .route("/api/export", post(derive::export))
        .route("/api/topo/open", post(topo::open))
        .route("/api/topo/state", post(topo::current))
        .route("/api/topo/action", post(topo::apply))
        .route("/api/topo/undo", post(topo::undo))
        .route("/api/topo/redo", post(topo::redo))
        .route("/api/topo/visibility", post(topo::visibility))
        .route("/api/topo/save", post(topo::save))
        .route("/api/topo/compile", post(topo::compile_project))
        .route("/api/topo/export", post(topo::export))
        .route("/api/topo/test", post(topo::test))
        .route("/api/topo/preview", post(topo::preview))
        .route("/api/topo/sections", post(topo::pending::sections))
        .route("/api/topo/texture", get(topo::pending::texture))
        .fallback(|| async { ApiError::not_found() })
        .method_not_allowed_fallback(|| async {
            ApiError::new(StatusCode::METHOD_NOT_ALLOWED, "method not allowed")
        })
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            guard::check,
        ))
        .layer(DefaultBodyLimit::max(crate::MAX_BODY_BYTES))
        .with_state(state)
}

/// How `shapegram studio` runs.
pub struct StudioOptions {
    /// The grammar files given on the command line (none: the current folder's).
    pub files: Vec<PathBuf>,
    /// A loopback address and port (port 0: any free port).
    pub listen: String,
    /// How long one derivation may run.
    pub time_budget: Duration,
}

/// Serves the studio until SIGINT or SIGTERM; `ready` gets the address once it accepts
/// connections. Refuses addresses that are not loopback: the studio reads and writes the
/// user's files and has no accounts.
pub async fn serve(
    options: StudioOptions,
    engine: Arc<dyn Engine>,
    ready: impl FnOnce(SocketAddr),
) -> Result<(), String> {
    let listen: SocketAddr = options
        .listen
        .parse()
        .map_err(|_| format!("--listen {}: expected 127.0.0.1:PORT", options.listen))?;
    if !listen.ip().is_loopback() {
        return Err(format!(
            "--listen {listen}: the studio listens on a loopback address only (127.0.0.1), since it writes your files"
        ));
    }
    let folders = Folders::new(&options.files)?;
    let listener = tokio::net::TcpListener::bind(listen)
        .await
        .map_err(|e| format!("cannot listen on {listen}: {e}"))?;
    let addr = listener.local_addr().map_err(|e| e.to_string())?;
    let mut state = StudioState::new(folders, engine, addr.port());
    state.time_budget = options.time_budget;
    ready(addr);
    axum::serve(listener, router(state))
        .with_graceful_shutdown(crate::shutdown_signal())
        .await
        .map_err(|e| e.to_string())
}
