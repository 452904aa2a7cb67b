//! The grammar repository behind `shapegram serve`: accounts, API tokens, friends, and goal
//! grammars published as immutable, checked versions, over a JSON API described by an OpenAPI
//! document (`/openapi.json`). See `docs/repository.md`.
//!
//! | module | concern |
//! | --- | --- |
//! | [`store`] | the `Store` trait every backend implements, and its types |
//! | [`sqlite`] | the embedded SQLite store |
//! | [`postgres`] | the PostgreSQL store, for several servers on one database |
//! | [`migrations`] | versioned schema migrations, one folder per backend |
//! | [`names`] | renaming grammars, versions by the hash of their text |
//! | [`accounts`] | name rules, argon2id password hashing |
//! | [`tokens`] | API tokens: generation, form, hashing |
//! | [`grammars`] | checking uploads with the engine, the rule index |
//! | [`policy`] | who may see and do what |
//! | [`preview`] | previews of versions, derived by a worker process under limits |
//! | [`queries`] | procedural rule queries |
//! | [`ratelimit`] | rate limits per token and address, counted in the database |
//! | [`routes`] | the HTTP handlers |
//! | [`openapi`] | the OpenAPI document |
//! | [`error`] | errors as JSON answers |
//! | [`failpoint`] | fail points in a publish, for the crash test |
//! | [`studio`] | Shapegram Studio: the single-user local mode (`shapegram studio`) |
//! | [`testing`] | throwaway PostgreSQL databases for the test suites |

pub mod accounts;
pub mod error;
pub mod extract;
pub mod failpoint;
pub mod grammars;
pub mod migrations;
pub mod names;
pub mod openapi;
pub mod policy;
pub mod postgres;
pub mod preview;
pub mod queries;
pub mod ratelimit;
pub mod routes;
pub mod sqlite;
pub mod store;
pub mod studio;
pub mod testing;
pub mod tokens;

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Arc;

use axum::Json;
use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::http::StatusCode;
use axum::routing::{get, post};

use sqlx::postgres::PgConnectOptions;

use crate::error::ApiError;
use crate::failpoint::FailPoints;
use crate::preview::{PreviewConfig, Previews};
use crate::ratelimit::{RateLimiter, RateLimits};
use crate::store::Store;

/// Largest request body, in bytes (a grammar of 256 KiB, escaped as JSON, fits).
pub const MAX_BODY_BYTES: usize = 1024 * 1024;

/// What the handlers share.
#[derive(Clone)]
pub struct AppState {
    pub store: Arc<dyn Store>,
    pub passwords: accounts::Passwords,
    /// Previews of versions; `None`: previews are off.
    pub previews: Option<Arc<Previews>>,
    /// Counts requests against the rate limits (none by default).
    pub limiter: Arc<RateLimiter>,
}

impl AppState {
    /// The state over `store`, without previews or rate limits.
    pub fn new(store: Arc<dyn Store>) -> AppState {
        AppState {
            store,
            // Each hash takes 19 MiB and a core for tens of milliseconds.
            passwords: accounts::Passwords::new(2),
            previews: None,
            limiter: Arc::new(RateLimiter::new(RateLimits::OFF, ratelimit::system_clock())),
        }
    }

    /// The same state, with previews made by the worker `config` names.
    pub fn with_previews(mut self, config: PreviewConfig) -> AppState {
        self.previews = Some(Arc::new(Previews::new(config)));
        self
    }

    /// The same state, limiting requests with `limiter`.
    pub fn with_limiter(self, limiter: RateLimiter) -> AppState {
        AppState {
            limiter: Arc::new(limiter),
            ..self
        }
    }
}

/// How `shapegram serve` runs, besides where.
#[derive(Clone, Debug)]
pub struct ServeOptions {
    /// Requests per token or address, and sign-ins per address.
    pub rate_limits: RateLimits,
    /// How previews are made; `None`: previews are off.
    pub previews: Option<PreviewConfig>,
}

/// The application: every route, the body limit, and JSON answers for unknown routes and
/// methods.
pub fn router(state: AppState) -> Router {
    use routes::*;
    Router::new()
        .route("/openapi.json", get(|| async { Json(openapi::document()) }))
        .route("/api/v1/accounts", post(sign_up))
        .route("/api/v1/login", post(login))
        .route("/api/v1/me", get(me))
        .route("/api/v1/tokens", get(list_tokens).post(create_token))
        .route("/api/v1/tokens/{id}", axum::routing::delete(revoke_token))
        .route("/api/v1/friends", get(friends))
        .route(
            "/api/v1/friends/{user}",
            post(request_friend).delete(remove_friend),
        )
        .route("/api/v1/friends/{user}/accept", post(accept_friend))
        .route("/api/v1/grammars", get(list_grammars))
        .route("/api/v1/search", get(search))
        .route("/api/v1/grammars/{owner}/{name}", get(grammar))
        .route(
            "/api/v1/grammars/{owner}/{name}/versions",
            get(versions).post(publish),
        )
        .route(
            "/api/v1/grammars/{owner}/{name}/versions/{version}",
            get(version),
        )
        .route(
            "/api/v1/grammars/{owner}/{name}/versions/{version}/rules",
            get(version_rules),
        )
        .route("/api/v1/queries", post(queries::query_rules))
        .route(
            "/api/v1/grammars/{owner}/{name}/rename",
            post(names::rename),
        )
        .route("/api/v1/texts/{sha256}", get(names::text_by_sha256))
        .route(
            "/api/v1/grammars/{owner}/{name}/versions/{version}/preview",
            get(version_preview),
        )
        .route(
            "/api/v1/grammars/{owner}/{name}/versions/{version}/yank",
            post(yank),
        )
        .route(
            "/api/v1/grammars/{owner}/{name}/versions/{version}/unyank",
            post(unyank),
        )
        .fallback(|| async { ApiError::not_found() })
        .method_not_allowed_fallback(|| async {
            ApiError::new(StatusCode::METHOD_NOT_ALLOWED, "method not allowed")
        })
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            ratelimit::limit,
        ))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(state)
}

/// The application over the SQLite database at `path` (created and migrated as needed).
pub async fn sqlite_app(path: &Path) -> Result<Router, store::StoreError> {
    let store = sqlite::SqliteStore::open(path).await?;
    Ok(router(AppState::new(Arc::new(store))))
}

/// Where the repository keeps its data.
#[derive(Clone, Debug)]
pub enum Database {
    /// A SQLite database file, created on first start.
    Sqlite(PathBuf),
    /// A PostgreSQL database, which must exist (`postgres://user:password@host:port/name`).
    Postgres(Box<PgConnectOptions>),
}

impl Database {
    /// A PostgreSQL database from its URL (`postgres://` or `postgresql://`); the error says
    /// what is wrong with the URL.
    pub fn postgres(url: &str) -> Result<Database, String> {
        if !(url.starts_with("postgres://") || url.starts_with("postgresql://")) {
            return Err("a PostgreSQL URL starts with postgres:// or postgresql://".to_owned());
        }
        PgConnectOptions::from_str(url)
            .map(|options| Database::Postgres(Box::new(options)))
            .map_err(|e| e.to_string())
    }

    /// Opens the store (migrating its schema), stopping at `fail_points` during a publish
    /// (the crash test; [`FailPoints::from_env`] reads `SHAPEGRAM_FAILPOINT`).
    pub async fn open(&self, fail_points: FailPoints) -> Result<Arc<dyn Store>, store::StoreError> {
        Ok(match self {
            Database::Sqlite(path) => Arc::new(
                sqlite::SqliteStore::open(path)
                    .await?
                    .with_fail_points(fail_points),
            ),
            Database::Postgres(options) => Arc::new(
                postgres::PgStore::connect_with((**options).clone())
                    .await?
                    .with_fail_points(fail_points),
            ),
        })
    }
}

/// The file name, or the PostgreSQL URL without its password.
impl std::fmt::Display for Database {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Database::Sqlite(path) => write!(f, "{}", path.display()),
            Database::Postgres(options) => {
                let (user, host, port) = (
                    options.get_username(),
                    options.get_host(),
                    options.get_port(),
                );
                let name = options.get_database().unwrap_or_default();
                if let Some(socket) = options.get_socket() {
                    return write!(
                        f,
                        "postgres:///{name}?host={}&user={user}",
                        socket.display()
                    );
                }
                write!(f, "postgres://")?;
                if !user.is_empty() {
                    write!(f, "{user}@")?;
                }
                if host.contains(':') && !host.starts_with('[') {
                    write!(f, "[{host}]:{port}")?;
                } else {
                    write!(f, "{host}:{port}")?;
                }
                if !name.is_empty() {
                    write!(f, "/{name}")?;
                }
                Ok(())
            }
        }
    }
}

/// Serves the repository in `store` on `listen` (`127.0.0.1:8080`; port 0 picks a free port),
/// with the rate limits and previews `options` set; `ready` gets the address once it accepts
/// connections. Runs until SIGINT or SIGTERM, then stops accepting connections, lets requests in
/// flight finish and returns.
pub async fn serve(
    store: Arc<dyn Store>,
    listen: &str,
    options: ServeOptions,
    ready: impl FnOnce(SocketAddr),
) -> Result<(), String> {
    let limiter = RateLimiter::new(options.rate_limits, ratelimit::system_clock());
    let mut state = AppState::new(store).with_limiter(limiter);
    if let Some(config) = options.previews {
        state = state.with_previews(config);
    }
    let app = router(state);
    let listener = tokio::net::TcpListener::bind(listen)
        .await
        .map_err(|e| format!("cannot listen on {listen}: {e}"))?;
    let addr = listener.local_addr().map_err(|e| e.to_string())?;
    ready(addr);
    axum::serve(
        listener,
        app.into_make_service_with_connect_info::<SocketAddr>(),
    )
    .with_graceful_shutdown(shutdown_signal())
    .await
    .map_err(|e| e.to_string())
}

/// SIGINT (Ctrl-C) or, on Unix, SIGTERM.
pub(crate) async fn shutdown_signal() {
    let interrupt = async {
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = interrupt => {}
        () = terminate => {}
    }
}

#[cfg(test)]
mod tests {
    use super::Database;

    #[test]
    fn a_postgres_database_is_named_without_its_password() {
        let named = |url: &str| Database::postgres(url).unwrap().to_string();
        assert_eq!(
            named("postgres://ana:secret@db.example:6543/grammars"),
            "postgres://ana@db.example:6543/grammars"
        );
        assert_eq!(
            named("postgresql://ana:secret@[::1]:5432/grammars?sslmode=disable"),
            "postgres://ana@[::1]:5432/grammars"
        );
        assert_eq!(
            named("postgres:///grammars?host=/var/run/postgresql&user=ana&password=secret"),
            "postgres:///grammars?host=/var/run/postgresql&user=ana"
        );
        assert_eq!(
            Database::postgres("mysql://ana@db/grammars").unwrap_err(),
            "a PostgreSQL URL starts with postgres:// or postgresql://"
        );
        assert!(Database::postgres("postgres://ana@db:port/grammars").is_err());
    }
}
