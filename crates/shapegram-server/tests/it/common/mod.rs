//! A fresh repository, on SQLite in a temporary directory or in a PostgreSQL database of its
//! own, driven through the router without sockets. [`on_both_backends!`] runs each test on
//! both.

#![allow(dead_code)]

use std::sync::Arc;

use axum::Router;
use axum::body::Body;
use axum::http::{Method, Request, StatusCode};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use shapegram_server::postgres::PgStore;
use shapegram_server::sqlite::SqliteStore;
use shapegram_server::store::Store;
use shapegram_server::testing::TestDatabase;
use shapegram_server::{AppState, router};
use tower::ServiceExt;

/// Where a test's repository lives.
#[derive(Clone, Copy, Debug)]
pub enum Backend {
    Sqlite,
    Postgres,
}

/// A repository for one test; clones share it. Its database goes with the last clone.
#[derive(Clone)]
pub struct App {
    pub router: Router,
    /// The store the router uses, for what the API does not show.
    pub store: Arc<dyn Store>,
    /// Declared last, so dropped after the store's connections.
    database: Arc<Database>,
}

/// What holds the database: a temporary directory, or a database dropped afterwards.
enum Database {
    Sqlite(tempfile::TempDir),
    Postgres(Box<TestDatabase>),
}

/// Declares a `sqlite` and a `postgres` module with one test per named function, which takes
/// a fresh [`App`] on that backend. The PostgreSQL tests are skipped (one line on stderr) when
/// `SHAPEGRAM_TEST_POSTGRES` is not set, and fail then under `CI=true`.
#[macro_export]
macro_rules! on_both_backends {
    ($($test:ident),+ $(,)?) => {
        mod sqlite {
            $(
                #[tokio::test]
                async fn $test() {
                    let app = $crate::common::App::on($crate::common::Backend::Sqlite).await;
                    super::$test(app.expect("SQLite is always there")).await;
                }
            )+
        }
        mod postgres {
            $(
                #[tokio::test]
                async fn $test() {
                    if let Some(app) = $crate::common::App::on($crate::common::Backend::Postgres).await {
                        super::$test(app).await;
                    }
                }
            )+
        }
    };
}

/// A grammar that compiles on its own (a library grammar: rules, no axiom).
pub const WOOD: &str = "// Wooden things are brown.\nfulfills(wooden) --> color(\"#8b5a2b\")\n";

/// A grammar with an axiom, local goals, `using` blocks and negations.
pub const CHAIR: &str = r#"local "split-legs"
axiom chair, wooden size(0.4, 0.8, 0.4)
fulfills(chair) --> split(y) { ~0.4 : set(@Leg.Size, 0.04) +support | ~0.05 : +seat | ~0.55 : +lean }
using is(chair) {
    fulfills(support) --> split(x) { @Leg.Size : +"split-legs" | ~1 : void | @Leg.Size : +"split-legs" }
    fulfills("split-legs") --> split(z) { @Leg.Size : +leg | ~1 : void | @Leg.Size : +leg }
    fulfills(lean) !has(Cushion) --> s('1, '1, 0.04)
}
"#;

impl App {
    /// A fresh repository; `None` when PostgreSQL tests are skipped.
    pub async fn on(backend: Backend) -> Option<App> {
        let (store, database): (Arc<dyn Store>, Database) = match backend {
            Backend::Sqlite => {
                let dir = tempfile::tempdir().expect("a temporary directory");
                let store = SqliteStore::open(&dir.path().join("repo.db"))
                    .await
                    .expect("the repository opens");
                (Arc::new(store), Database::Sqlite(dir))
            }
            Backend::Postgres => {
                let database = TestDatabase::create()?;
                let store = PgStore::connect_with(database.options())
                    .await
                    .expect("the repository opens");
                (Arc::new(store), Database::Postgres(Box::new(database)))
            }
        };
        Some(App {
            router: router(AppState::new(store.clone())),
            store,
            database: Arc::new(database),
        })
    }

    /// A repository over `state`, whose SQLite store lives in `dir` (for tests that set the
    /// state up themselves).
    pub fn sqlite(dir: tempfile::TempDir, state: AppState) -> App {
        App {
            store: state.store.clone(),
            router: router(state),
            database: Arc::new(Database::Sqlite(dir)),
        }
    }

    /// The temporary directory of a repository on SQLite.
    pub fn dir(&self) -> &std::path::Path {
        match &*self.database {
            Database::Sqlite(dir) => dir.path(),
            Database::Postgres(_) => panic!("a repository on PostgreSQL has no directory"),
        }
    }

    /// Sends raw bytes; the answer's status and JSON body (`null` when empty).
    pub async fn raw(
        &self,
        method: Method,
        uri: &str,
        token: Option<&str>,
        body: Vec<u8>,
    ) -> (StatusCode, Value) {
        let mut request = Request::builder().method(method).uri(uri);
        if let Some(token) = token {
            request = request.header("authorization", format!("Bearer {token}"));
        }
        if !body.is_empty() {
            request = request.header("content-type", "application/json");
        }
        let request = request.body(Body::from(body)).expect("a request");
        self.send(request).await
    }

    pub async fn send(&self, request: Request<Body>) -> (StatusCode, Value) {
        let response = self
            .router
            .clone()
            .oneshot(request)
            .await
            .expect("an answer");
        let status = response.status();
        let bytes = response
            .into_body()
            .collect()
            .await
            .expect("a body")
            .to_bytes();
        let value = if bytes.is_empty() {
            Value::Null
        } else {
            serde_json::from_slice(&bytes).unwrap_or_else(|e| {
                panic!(
                    "{status}: the answer is not JSON ({e}): {}",
                    String::from_utf8_lossy(&bytes)
                )
            })
        };
        (status, value)
    }

    pub async fn call(
        &self,
        method: Method,
        uri: &str,
        token: Option<&str>,
        body: Option<Value>,
    ) -> (StatusCode, Value) {
        let bytes = body.map(|b| b.to_string().into_bytes()).unwrap_or_default();
        self.raw(method, uri, token, bytes).await
    }

    pub async fn get(&self, uri: &str, token: Option<&str>) -> (StatusCode, Value) {
        self.call(Method::GET, uri, token, None).await
    }

    /// Signs `name` up and logs in: a token.
    pub async fn user(&self, name: &str) -> String {
        let credentials = json!({"name": name, "password": format!("{name} password")});
        let (status, body) = self
            .call(
                Method::POST,
                "/api/v1/accounts",
                None,
                Some(credentials.clone()),
            )
            .await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
        let (status, body) = self
            .call(Method::POST, "/api/v1/login", None, Some(credentials))
            .await;
        assert_eq!(status, StatusCode::OK, "{body}");
        body["token"].as_str().expect("a token").to_owned()
    }

    /// Publishes `text` as `owner/name`: the status and answer.
    pub async fn publish(
        &self,
        token: &str,
        grammar: &str,
        text: &str,
        visibility: Option<&str>,
    ) -> (StatusCode, Value) {
        let mut body = json!({"text": text});
        if let Some(v) = visibility {
            body["visibility"] = json!(v);
        }
        self.call(
            Method::POST,
            &format!("/api/v1/grammars/{grammar}/versions"),
            Some(token),
            Some(body),
        )
        .await
    }

    /// Yanks (`action` `yank`) or unyanks (`unyank`) version `version` of `owner/name`.
    pub async fn yank(&self, token: &str, grammar: &str, version: i64, action: &str) {
        let (status, body) = self
            .call(
                Method::POST,
                &format!("/api/v1/grammars/{grammar}/versions/{version}/{action}"),
                Some(token),
                None,
            )
            .await;
        assert_eq!(status, StatusCode::OK, "{body}");
        assert_eq!(body["yanked"], json!(action == "yank"));
    }

    /// `a` asks `b` to be friends and `b` accepts.
    pub async fn befriend(&self, a: (&str, &str), b: (&str, &str)) {
        let (status, body) = self
            .call(
                Method::POST,
                &format!("/api/v1/friends/{}", b.0),
                Some(a.1),
                None,
            )
            .await;
        assert_eq!(
            (status, &body["state"]),
            (StatusCode::OK, &json!("requested"))
        );
        let (status, body) = self
            .call(
                Method::POST,
                &format!("/api/v1/friends/{}/accept", a.0),
                Some(b.1),
                None,
            )
            .await;
        assert_eq!(
            (status, &body["state"]),
            (StatusCode::OK, &json!("friends"))
        );
    }
}
