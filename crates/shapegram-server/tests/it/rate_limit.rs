//! Rate limits, counted in the database: exact counts per window (the clock is moved, not
//! waited for), per token, per address without one and for sign-ins, shared by two servers on
//! one database, and a revoked token answered 401 rather than 429.

use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicI64, Ordering};

use axum::Router;
use axum::body::Body;
use axum::extract::ConnectInfo;
use axum::http::{HeaderMap, Method, Request, StatusCode};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use shapegram_server::postgres::PgStore;
use shapegram_server::ratelimit::{Limit, RateLimiter, RateLimits};
use shapegram_server::sqlite::SqliteStore;
use shapegram_server::store::Store;
use shapegram_server::testing::TestDatabase;
use shapegram_server::{AppState, router};
use tower::ServiceExt;

/// A repository whose limiter reads `time`.
struct Limited {
    router: Router,
    store: SqliteStore,
    time: Arc<AtomicI64>,
}

const MINUTE: u32 = 60;

async fn limited(db: &Path, requests: Option<u32>, sign_in: Option<u32>, start: i64) -> Limited {
    let store = SqliteStore::open(db).await.unwrap();
    let time = Arc::new(AtomicI64::new(start));
    let clock = {
        let time = time.clone();
        Arc::new(move || time.load(Ordering::Relaxed))
    };
    let limit = |n: Option<u32>| {
        n.map(|requests| Limit {
            requests,
            window: MINUTE,
        })
    };
    let limits = RateLimits {
        requests: limit(requests),
        sign_in: limit(sign_in),
    };
    let state =
        AppState::new(Arc::new(store.clone())).with_limiter(RateLimiter::new(limits, clock));
    Limited {
        router: router(state),
        store,
        time,
    }
}

impl Limited {
    async fn call(
        &self,
        method: Method,
        uri: &str,
        token: Option<&str>,
        from: [u8; 4],
        body: Option<Value>,
    ) -> (StatusCode, HeaderMap, Value) {
        let mut request = Request::builder().method(method).uri(uri);
        if let Some(token) = token {
            request = request.header("authorization", format!("Bearer {token}"));
        }
        let body = body.map(|b| b.to_string()).unwrap_or_default();
        let mut request = request
            .header("content-type", "application/json")
            .body(Body::from(body))
            .unwrap();
        request
            .extensions_mut()
            .insert(ConnectInfo(SocketAddr::from((from, 40000))));
        let response = self.router.clone().oneshot(request).await.unwrap();
        let status = response.status();
        let headers = response.headers().clone();
        let bytes = response.into_body().collect().await.unwrap().to_bytes();
        let value = if bytes.is_empty() {
            Value::Null
        } else {
            serde_json::from_slice(&bytes).unwrap()
        };
        (status, headers, value)
    }

    async fn get(&self, uri: &str, token: Option<&str>, from: [u8; 4]) -> StatusCode {
        self.call(Method::GET, uri, token, from, None).await.0
    }

    /// Signs `name` up and logs in from `from`: a token.
    async fn user(&self, name: &str, from: [u8; 4]) -> String {
        let credentials = json!({"name": name, "password": format!("{name} password")});
        let (status, _, _) = self
            .call(
                Method::POST,
                "/api/v1/accounts",
                None,
                from,
                Some(credentials),
            )
            .await;
        assert_eq!(status, StatusCode::CREATED);
        self.login(name, from).await
    }

    /// Logs `name` in from `from`: a new token.
    async fn login(&self, name: &str, from: [u8; 4]) -> String {
        let credentials = json!({"name": name, "password": format!("{name} password")});
        let (status, _, body) = self
            .call(Method::POST, "/api/v1/login", None, from, Some(credentials))
            .await;
        assert_eq!(status, StatusCode::OK, "{body}");
        body["token"].as_str().unwrap().to_owned()
    }

    fn set_time(&self, t: i64) {
        self.time.store(t, Ordering::Relaxed);
    }
}

const HOME: [u8; 4] = [10, 0, 0, 1];
const AWAY: [u8; 4] = [10, 0, 0, 2];

#[tokio::test]
async fn a_token_gets_its_limit_per_window_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let app = limited(&dir.path().join("repo.db"), Some(3), None, 6000).await;
    let ana = app.user("ana", HOME).await;
    let bob = app.user("bob", HOME).await;
    app.set_time(6010);
    for _ in 0..3 {
        assert_eq!(
            app.get("/api/v1/me", Some(&ana), HOME).await,
            StatusCode::OK
        );
    }
    let (status, headers, body) = app
        .call(Method::GET, "/api/v1/me", Some(&ana), HOME, None)
        .await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(headers["retry-after"], "50");
    assert_eq!(
        body,
        json!({"error": "too many requests with this token: at most 3/min; retry in 50 s"})
    );
    // Every route counts, and a 429 is not answered by the route.
    assert_eq!(
        app.get("/api/v1/grammars", Some(&ana), HOME).await,
        StatusCode::TOO_MANY_REQUESTS
    );
    // Another token, or no token, from the same address is counted apart.
    assert_eq!(
        app.get("/api/v1/me", Some(&bob), HOME).await,
        StatusCode::OK
    );
    assert_eq!(
        app.get("/api/v1/grammars", None, HOME).await,
        StatusCode::OK
    );
    // The last second of the window is still refused; the next window starts afresh.
    app.set_time(6059);
    let (status, headers, _) = app
        .call(Method::GET, "/api/v1/me", Some(&ana), HOME, None)
        .await;
    assert_eq!(
        (status, &headers["retry-after"]),
        (StatusCode::TOO_MANY_REQUESTS, &"1".parse().unwrap())
    );
    app.set_time(6060);
    for _ in 0..3 {
        assert_eq!(
            app.get("/api/v1/me", Some(&ana), HOME).await,
            StatusCode::OK
        );
    }
    assert_eq!(
        app.get("/api/v1/me", Some(&ana), HOME).await,
        StatusCode::TOO_MANY_REQUESTS
    );
}

#[tokio::test]
async fn anonymous_callers_are_limited_by_address() {
    let dir = tempfile::tempdir().unwrap();
    let app = limited(&dir.path().join("repo.db"), Some(2), None, 0).await;
    let ana = app.user("ana", HOME).await;
    for _ in 0..2 {
        assert_eq!(
            app.get("/api/v1/grammars", None, HOME).await,
            StatusCode::OK
        );
    }
    let (status, headers, body) = app
        .call(Method::GET, "/api/v1/grammars", None, HOME, None)
        .await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(headers["retry-after"], "60");
    assert_eq!(
        body["error"],
        json!("too many requests from this address without a token: at most 2/min; retry in 60 s")
    );
    // Unknown routes count too: the limit comes before routing.
    assert_eq!(
        app.get("/nothing", None, HOME).await,
        StatusCode::TOO_MANY_REQUESTS
    );
    assert_eq!(
        app.get("/api/v1/grammars", None, AWAY).await,
        StatusCode::OK
    );
    assert_eq!(
        app.get("/api/v1/me", Some(&ana), HOME).await,
        StatusCode::OK
    );
}

#[tokio::test]
async fn sign_in_attempts_are_limited_by_address() {
    let dir = tempfile::tempdir().unwrap();
    let app = limited(&dir.path().join("repo.db"), None, Some(3), 0).await;
    // Sign-up and a login: two attempts.
    let ana = app.user("ana", HOME).await;
    let wrong = json!({"name": "ana", "password": "not ana's password"});
    let (status, _, _) = app
        .call(
            Method::POST,
            "/api/v1/login",
            None,
            HOME,
            Some(wrong.clone()),
        )
        .await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    // The fourth attempt is refused before the password is looked at, right or wrong.
    let right = json!({"name": "ana", "password": "ana password"});
    let (status, _, body) = app
        .call(
            Method::POST,
            "/api/v1/login",
            None,
            HOME,
            Some(right.clone()),
        )
        .await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(
        body["error"],
        json!(
            "too many sign-up and login attempts from this address: at most 3/min; retry in 60 s"
        )
    );
    let (status, _, _) = app
        .call(
            Method::POST,
            "/api/v1/accounts",
            None,
            HOME,
            Some(json!({"name": "bob", "password": "bob password"})),
        )
        .await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    // Another address may, and the token keeps working (requests are unlimited here).
    let (status, _, _) = app
        .call(Method::POST, "/api/v1/login", None, AWAY, Some(right))
        .await;
    assert_eq!(status, StatusCode::OK);
    for _ in 0..10 {
        assert_eq!(
            app.get("/api/v1/me", Some(&ana), HOME).await,
            StatusCode::OK
        );
    }
}

#[tokio::test]
async fn a_revoked_token_is_refused_with_401_not_429() {
    let dir = tempfile::tempdir().unwrap();
    let app = limited(&dir.path().join("repo.db"), Some(2), None, 0).await;
    let ana = app.user("ana", HOME).await;
    let ana_again = app.login("ana", HOME).await;
    for expected in [
        StatusCode::OK,
        StatusCode::OK,
        StatusCode::TOO_MANY_REQUESTS,
    ] {
        assert_eq!(app.get("/api/v1/me", Some(&ana), HOME).await, expected);
    }
    // The other token revokes the first with its two requests of this window.
    let (_, _, tokens) = app
        .call(Method::GET, "/api/v1/tokens", Some(&ana_again), HOME, None)
        .await;
    let id = tokens[0]["id"].as_i64().unwrap();
    let (status, _, _) = app
        .call(
            Method::DELETE,
            &format!("/api/v1/tokens/{id}"),
            Some(&ana_again),
            HOME,
            None,
        )
        .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    // Over its limit in this window: still 401, however often it asks.
    for _ in 0..3 {
        let (status, _, body) = app
            .call(Method::GET, "/api/v1/me", Some(&ana), HOME, None)
            .await;
        assert_eq!(
            (status, &body["error"]),
            (
                StatusCode::UNAUTHORIZED,
                &json!("unknown or revoked API token")
            )
        );
    }
}

#[tokio::test]
async fn two_servers_on_one_database_share_the_counts_and_prune_them() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("repo.db");
    let one = limited(&db, Some(4), None, 0).await;
    let two = limited(&db, Some(4), None, 0).await;
    for app in [&one, &two, &one, &two] {
        assert_eq!(
            app.get("/api/v1/grammars", None, HOME).await,
            StatusCode::OK
        );
    }
    for app in [&one, &two] {
        assert_eq!(
            app.get("/api/v1/grammars", None, HOME).await,
            StatusCode::TOO_MANY_REQUESTS
        );
    }
    let windows = || async {
        sqlx::query_scalar::<_, i64>("SELECT window_start FROM rate_limit ORDER BY window_start")
            .fetch_all(one.store.pool())
            .await
            .unwrap()
    };
    assert_eq!(windows().await, [0]);
    // Two windows later the first has ended and is forgotten.
    for app in [&one, &two] {
        app.set_time(125);
    }
    assert_eq!(
        one.get("/api/v1/grammars", None, HOME).await,
        StatusCode::OK
    );
    assert_eq!(windows().await, [120]);
}

/// Concurrent checks from 16 tasks lose no count; the time per check is printed (the figures in
/// docs/repository.md come from `cargo test --release -p shapegram-server --test rate_limit
/// concurrent -- --nocapture`).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn concurrent_checks_lose_no_count() {
    let dir = tempfile::tempdir().unwrap();
    let store = SqliteStore::open(&dir.path().join("repo.db"))
        .await
        .unwrap();
    concurrent_checks(Arc::new(store)).await;
}

/// The same on PostgreSQL, where the counts of several servers meet.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn concurrent_checks_lose_no_count_on_postgres() {
    let Some(database) = TestDatabase::create() else {
        return;
    };
    let store = PgStore::connect_with(database.options()).await.unwrap();
    concurrent_checks(Arc::new(store)).await;
}

async fn concurrent_checks(store: Arc<dyn Store>) {
    let started = std::time::Instant::now();
    let tasks: Vec<_> = (0..16)
        .map(|task| {
            let store = store.clone();
            tokio::spawn(async move {
                let mut last = Vec::new();
                for i in 0..100 {
                    let key = format!("token:{}", (task + i) % 4);
                    last.push(store.rate_limit_hit(&key, 60).await.unwrap());
                }
                last
            })
        })
        .collect();
    let mut counts = Vec::new();
    for task in tasks {
        counts.extend(task.await.unwrap());
    }
    let elapsed = started.elapsed();
    println!(
        "1,600 checks from 16 tasks: {:.0} µs each, {:.0} checks/s",
        elapsed.as_secs_f64() * 1e6 / 1600.0,
        1600.0 / elapsed.as_secs_f64()
    );
    // Every count from 1 to 400 was handed out exactly once per key.
    counts.sort_unstable();
    let expected: Vec<i64> = (1..=400).flat_map(|n| [n; 4]).collect();
    assert_eq!(counts, expected);
}
