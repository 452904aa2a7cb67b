//! End to end: `shapegram serve` as a child process on a free port, over real HTTP: it creates
//! the database, a restart on the same file keeps every published version as it was, and two
//! servers on one database (a SQLite file, or PostgreSQL when `SHAPEGRAM_TEST_POSTGRES` names a
//! server) see each other's publishes.

use std::process::Command;

use crate::common;

use common::{Server, TempDir, http, sign_up, start_server as start, start_server_with};
use serde_json::json;
use shapegram_server::testing::TestDatabase;

/// `shapegram serve` on a free port over the PostgreSQL database at `url`.
fn start_on(url: &str) -> Server {
    common::start_server_over(&["--database".as_ref(), url.as_ref()], None, &[])
}

#[test]
fn serve_creates_the_database_and_keeps_versions_across_restarts() {
    let dir = TempDir::new("serve");
    let db = dir.path("repo.db");
    let wood = "fulfills(wooden) --> color(\"#8b5a2b\")\n";
    let (hash, token) = {
        let server = start(&db);
        assert!(db.exists());
        let token = sign_up(&server, "ana");
        let (status, published) = http(
            &server,
            "POST",
            "/api/v1/grammars/ana/paint/versions",
            Some(&token),
            Some(json!({"text": wood, "visibility": "private"})),
        );
        assert_eq!(status, 201, "{published}");
        let (status, doc) = http(&server, "GET", "/openapi.json", None, None);
        assert_eq!(status, 200);
        assert!(doc["paths"]["/api/v1/grammars/{owner}/{name}/versions"]["post"].is_object());
        (published["sha256"].clone(), token)
    };
    // Killed and started again on the same file: migrations are not re-applied, data is there.
    let server = start(&db);
    assert_eq!(
        http(
            &server,
            "GET",
            "/api/v1/grammars/ana/paint/versions/1",
            None,
            None
        )
        .0,
        404
    );
    let (status, version) = http(
        &server,
        "GET",
        "/api/v1/grammars/ana/paint/versions/1",
        Some(&token),
        None,
    );
    assert_eq!(status, 200, "{version}");
    assert_eq!(
        (&version["text"], &version["sha256"]),
        (&json!(wood), &hash)
    );
}

#[test]
fn serve_reports_an_address_in_use() {
    let dir = TempDir::new("serve-busy");
    let first = start(&dir.path("a.db"));
    let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["serve", "--listen", &first.addr, "--data"])
        .arg(dir.path("b.db"))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(stderr.starts_with("error: cannot listen on"), "{stderr}");
}

#[test]
fn two_servers_on_one_database_publish_consecutive_versions() {
    let dir = TempDir::new("serve-two");
    let db = dir.path("repo.db");
    two_servers_publish_consecutive_versions([start(&db), start(&db)]);
}

#[test]
fn two_servers_on_one_postgres_database_publish_consecutive_versions() {
    let Some(database) = TestDatabase::create() else {
        return;
    };
    let url = database.url();
    let servers = [start_on(url), start_on(url)];
    two_servers_publish_consecutive_versions(servers);
}

/// Publishes of one grammar, alternately through each server and all at once, become versions
/// 1 to 8, and each server sees all of them.
fn two_servers_publish_consecutive_versions(servers: [Server; 2]) {
    let credentials = json!({"name": "ana", "password": "ana's password"});
    assert_eq!(
        http(
            &servers[0],
            "POST",
            "/api/v1/accounts",
            None,
            Some(credentials.clone())
        )
        .0,
        201
    );
    let (_, login) = http(
        &servers[1],
        "POST",
        "/api/v1/login",
        None,
        Some(credentials),
    );
    let token = login["token"].as_str().unwrap().to_owned();
    let mut versions: Vec<i64> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..8)
            .map(|i| {
                let (server, token) = (&servers[i % 2], &token);
                scope.spawn(move || {
                    let text = format!("fulfills(wooden) --> color(\"#8b5a2b\")\n// {i}\n");
                    let (status, body) = http(
                        server,
                        "POST",
                        "/api/v1/grammars/ana/paint/versions",
                        Some(token),
                        Some(json!({"text": text})),
                    );
                    assert_eq!(status, 201, "{body}");
                    body["version"].as_i64().unwrap()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    versions.sort();
    assert_eq!(versions, (1..=8).collect::<Vec<_>>());
    // Each server sees the other's publishes.
    for server in &servers {
        let (_, list) = http(
            server,
            "GET",
            "/api/v1/grammars/ana/paint/versions",
            None,
            None,
        );
        assert_eq!(list.as_array().unwrap().len(), 8);
    }
}

#[test]
fn serve_stops_cleanly_on_sigterm() {
    let dir = TempDir::new("serve-term");
    let mut server = start(&dir.path("repo.db"));
    assert_eq!(http(&server, "GET", "/api/v1/grammars", None, None).0, 200);
    let pid = server.child.id().to_string();
    let sent = Command::new("kill").args(["-TERM", &pid]).status().unwrap();
    assert!(sent.success());
    let status = server.child.wait().unwrap();
    assert!(status.success(), "{status:?}");
}

#[test]
fn serve_limits_requests_per_address_and_token() {
    let dir = TempDir::new("serve-limits");
    // A day's window: the test cannot straddle two.
    let options = ["--rate-limit", "3/day", "--sign-in-rate-limit", "off"];
    let server = start_server_with(&dir.path("repo.db"), None, &options);
    let token = &sign_up(&server, "ana");
    for _ in 0..3 {
        assert_eq!(http(&server, "GET", "/api/v1/grammars", None, None).0, 200);
    }
    let (status, body) = http(&server, "GET", "/api/v1/grammars", None, None);
    assert_eq!(status, 429);
    let message = body["error"].as_str().unwrap();
    assert!(
        message.starts_with(
            "too many requests from this address without a token: at most 3/day; retry in "
        ),
        "{message}"
    );
    // The token has its own count.
    assert_eq!(http(&server, "GET", "/api/v1/me", Some(token), None).0, 200);
}

#[test]
fn serve_refuses_a_malformed_rate_limit() {
    let dir = TempDir::new("serve-bad-limit");
    let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["serve", "--rate-limit", "600", "--data"])
        .arg(dir.path("repo.db"))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        String::from_utf8(output.stderr).unwrap(),
        "error: --rate-limit: \"600\" is no rate limit: write N/s, N/min, N/h or N/day, or off\n"
    );
    assert!(!dir.path("repo.db").exists());
}

#[test]
fn serve_names_a_postgres_database_without_its_password() {
    let Some(database) = TestDatabase::create() else {
        return;
    };
    let url = database.url();
    let server = start_on(url);
    let options = database.options();
    let expected = format!(
        "shapegram serve: listening on http://{} (database postgres://{}@{}:{}/{})\n",
        server.addr,
        options.get_username(),
        options.get_host(),
        options.get_port(),
        options.get_database().unwrap()
    );
    // The URL carries a password (user:password@), which the line leaves out.
    let user = format!("//{}:", options.get_username());
    assert!(url.contains(&user) && url.contains('@'), "{url}");
    assert_eq!(server.first_line, expected);
    assert_eq!(http(&server, "GET", "/api/v1/grammars", None, None).0, 200);
}

#[test]
fn serve_refuses_bad_database_settings_with_exit_code_2() {
    let run = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_shapegram"))
            .args(["serve", "--listen", "127.0.0.1:0"])
            .args(args)
            .output()
            .unwrap();
        (
            output.status.code(),
            String::from_utf8(output.stderr).unwrap(),
        )
    };
    let (code, stderr) = run(&["--database", "mysql://ana:secret@localhost/repo"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(
        stderr,
        "error: --database mysql://ana:***@localhost/repo: a PostgreSQL URL starts with postgres:// or postgresql://\n"
    );
    let (code, stderr) = run(&["--database", "postgres://ana:secret@localhost:port/repo"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.starts_with("error: --database postgres://ana:***@localhost:port/repo: "),
        "{stderr}"
    );
    // Nothing listens on port 1: the message names the database, without the password.
    let (code, stderr) = run(&["--database", "postgres://ana:secret@127.0.0.1:1/repo"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.starts_with("error: cannot open postgres://ana@127.0.0.1:1/repo: "),
        "{stderr}"
    );
    assert!(!stderr.contains("secret"), "{stderr}");
    let (code, stderr) = run(&["--data", "x.db", "--database", "postgres://localhost/repo"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}
