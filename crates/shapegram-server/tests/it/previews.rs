//! The server's side of previews, with a stand-in worker (a shell script) whose behaviour the
//! published text picks: what the worker is given (request, limits, environment, folder), the
//! cache, and how each way a worker can end is answered. The real worker is tested end to end
//! in the `shapegram` crate (`tests/preview.rs`).

#![cfg(unix)]

use crate::common;

use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::App;
use http_body_util::BodyExt;
use serde_json::{Value, json};
use shapegram_server::preview::{PreviewConfig, PreviewLimits};
use shapegram_server::{AppState, sqlite::SqliteStore};
use tower::ServiceExt;

/// What the stand-in does, by a marker in the grammar's text; it logs each run, its request,
/// arguments, environment and folder in `dir`.
fn script(dir: &Path) -> String {
    let d = dir.display();
    format!(
        r#"echo run >> {d}/runs
cat > {d}/request.json
echo "$@" > {d}/args
env > {d}/env
pwd > {d}/pwd
case "$(cat {d}/request.json)" in
  *REFUSE*) printf '{{"error":"x does not derive: no","diagnostics":[{{"message":"no","line":2,"column":5,"hints":["try"]}}]}}'; exit 3 ;;
  *MEMORY*) echo "memory allocation of 96 bytes failed" >&2; kill -ABRT $$ ;;
  *CPU*) kill -XCPU $$ ;;
  *PANIC*) echo "thread 'main' panicked" >&2; exit 101 ;;
  *HANG*) echo $$ > {d}/pid; exec sleep 30 ;;
  *HUGE*) printf glTF; exec head -c 70000000 /dev/zero ;;
  *GARBAGE*) printf 'not a model' ;;
  *) printf 'glTF fake model' ;;
esac
"#
    )
}

/// The time limit of tests that are not about time: long enough for a shell to start on a busy
/// machine.
const AMPLE: Duration = Duration::from_secs(30);

/// A repository whose previews the stand-in makes: 64 MiB, 500 steps, 1 worker.
async fn app(worker: Option<&str>, timeout: Duration) -> App {
    let dir = tempfile::tempdir().unwrap();
    let store = SqliteStore::open(&dir.path().join("repo.db"))
        .await
        .unwrap();
    let script = script(dir.path());
    let config = PreviewConfig {
        worker: worker.unwrap_or("/bin/sh").into(),
        args: vec!["-c".into(), script.into(), "worker".into()],
        limits: PreviewLimits {
            timeout,
            memory_mib: 64,
            steps: 500,
            workers: 1,
        },
    };
    let state = AppState::new(Arc::new(store)).with_previews(config);
    App::sqlite(dir, state)
}

/// The status, content type and body of the preview of a version (`owner/name/versions/N`,
/// perhaps with `?seed=S`).
async fn preview(app: &App, version: &str) -> (StatusCode, String, Vec<u8>) {
    let (version, seed) = match version.split_once('?') {
        Some((version, query)) => (version, format!("?{query}")),
        None => (version, String::new()),
    };
    let request = Request::get(format!("/api/v1/grammars/{version}/preview{seed}"))
        .body(Body::empty())
        .unwrap();
    let response = app.router.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let content_type = response.headers()["content-type"]
        .to_str()
        .unwrap()
        .to_owned();
    let body = response.into_body().collect().await.unwrap().to_bytes();
    (status, content_type, body.to_vec())
}

/// The JSON error of a failed preview.
async fn error(app: &App, uri: &str) -> (StatusCode, Value) {
    let (status, content_type, body) = preview(app, uri).await;
    assert_eq!(content_type, "application/json");
    (status, serde_json::from_slice(&body).unwrap())
}

fn read(app: &App, file: &str) -> String {
    std::fs::read_to_string(app.dir().join(file)).unwrap_or_default()
}

fn runs(app: &App) -> usize {
    read(app, "runs").lines().count()
}

/// A publishable grammar carrying `marker` in a comment.
fn grammar(marker: &str) -> String {
    format!("// {marker}\nfulfills(wooden) --> color(\"#8b5a2b\")\n")
}

#[tokio::test]
async fn the_worker_gets_the_request_and_limits_and_nothing_of_the_servers() {
    let app = app(None, AMPLE).await;
    let ana = app.user("ana").await;
    let text = grammar("OK");
    app.publish(&ana, "ana/Wood", &text, None).await;
    let (status, content_type, body) = preview(&app, "ana/wood/versions/1?seed=7").await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(content_type, "model/gltf-binary");
    assert_eq!(body, b"glTF fake model");
    let request: Value = serde_json::from_str(&read(&app, "request.json")).unwrap();
    assert_eq!(
        request,
        json!({"name": "Wood", "text": text, "seed": 7, "max_steps": 500})
    );
    assert_eq!(
        read(&app, "args"),
        "--memory-mib 64 --cpu-seconds 32 --max-output-mib 64\n"
    );
    assert_eq!(read(&app, "pwd"), "/\n");
    let env = read(&app, "env");
    assert!(
        !env.contains("CARGO") && !env.contains("HOME="),
        "the environment is cleared: {env}"
    );
}

#[tokio::test]
async fn previews_are_kept_per_text_and_seed() {
    let app = app(None, AMPLE).await;
    let ana = app.user("ana").await;
    let text = grammar("OK");
    app.publish(&ana, "ana/wood", &text, None).await;
    app.publish(&ana, "ana/same", &text, None).await;
    for (uri, runs_after) in [
        ("ana/wood/versions/1", 1),
        ("ana/wood/versions/1", 1),
        ("ana/wood/versions/1?seed=1", 2),
        // Another grammar with the same text: the same model.
        ("ana/same/versions/1", 2),
    ] {
        let (status, _, body) = preview(&app, uri).await;
        assert_eq!(
            (status, body.as_slice()),
            (StatusCode::OK, &b"glTF fake model"[..])
        );
        assert_eq!(runs(&app), runs_after, "{uri}");
    }
    // A refusal is kept as well; a memory kill is not (it depends on the machine).
    app.publish(&ana, "ana/refused", &grammar("REFUSE"), None)
        .await;
    app.publish(&ana, "ana/memory", &grammar("MEMORY"), None)
        .await;
    for _ in 0..2 {
        assert_eq!(
            error(&app, "ana/refused/versions/1").await.0,
            StatusCode::UNPROCESSABLE_ENTITY
        );
        assert_eq!(
            error(&app, "ana/memory/versions/1").await.0,
            StatusCode::SERVICE_UNAVAILABLE
        );
    }
    assert_eq!(runs(&app), 2 + 1 + 2);
}

#[tokio::test]
async fn each_end_of_a_worker_has_its_answer() {
    let app = app(None, AMPLE).await;
    let ana = app.user("ana").await;
    let cases = [
        (
            "REFUSE",
            422,
            json!({"error": "x does not derive: no", "diagnostics": [
                {"severity": "error", "message": "no", "line": 2, "column": 5, "hints": ["try"]}]}),
        ),
        (
            "MEMORY",
            503,
            json!({"error": "the preview needed more than 64 MiB of memory (the memory limit): stopped"}),
        ),
        (
            "CPU",
            503,
            json!({"error": "the preview used more than 32 s of CPU time (the CPU limit): stopped"}),
        ),
        (
            "PANIC",
            422,
            json!({"error": "panic does not derive: the engine failed on it (a bug, logged on the server)"}),
        ),
        (
            "HUGE",
            503,
            json!({"error": "the preview is larger than 64 MiB (the size limit): stopped"}),
        ),
        ("GARBAGE", 500, json!({"error": "internal error"})),
    ];
    for (marker, status, body) in cases {
        let name = marker.to_lowercase();
        app.publish(&ana, &format!("ana/{name}"), &grammar(marker), None)
            .await;
        let answer = error(&app, &format!("ana/{name}/versions/1")).await;
        assert_eq!((answer.0.as_u16(), answer.1), (status, body), "{marker}");
    }
}

#[tokio::test]
async fn a_worker_past_the_deadline_is_killed_and_reaped() {
    let app = app(None, Duration::from_secs(1)).await;
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/hang", &grammar("HANG"), None).await;
    let started = Instant::now();
    let (status, body) = error(&app, "ana/hang/versions/1").await;
    let took = started.elapsed();
    assert_eq!(status, StatusCode::SERVICE_UNAVAILABLE);
    assert_eq!(
        body["error"],
        "the preview took longer than 1 s (the time limit): stopped"
    );
    // Killed at the deadline, not when its 30 s sleep ended.
    assert!(took < Duration::from_secs(20), "{took:?}");
    let pid = read(&app, "pid");
    let pid = pid.trim();
    assert!(!pid.is_empty());
    // Neither running nor a zombie: killed and waited for.
    assert!(
        !Path::new(&format!("/proc/{pid}")).exists(),
        "worker {pid} is still there"
    );
}

#[tokio::test]
async fn a_worker_that_cannot_start_is_an_internal_error() {
    let app = app(Some("/nonexistent/shapegram"), AMPLE).await;
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/wood", &grammar("OK"), None).await;
    let (status, body) = error(&app, "ana/wood/versions/1").await;
    assert_eq!(status, StatusCode::INTERNAL_SERVER_ERROR);
    assert_eq!(body["error"], "internal error");
}
