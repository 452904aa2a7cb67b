//! The crash test: `shapegram serve` killed with SIGKILL in the middle of a publish, at each fail
//! point (`SHAPEGRAM_FAILPOINT`, see `shapegram_server::failpoint`), then started again on the
//! same database. Every version committed before is intact, the interrupted one is there whole
//! (killed after COMMIT) or not at all, the database passes its audit, and the next publish
//! takes the next number.

#![cfg(unix)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::os::unix::process::ExitStatusExt;
use std::sync::mpsc;
use std::time::Duration;

use crate::common;

use common::TempDir;
use common::{Server, http, sign_up, start_server as start, start_server_with as start_with};
use serde_json::json;
use shapegram_server::failpoint::FailPoint;
use shapegram_server::sqlite::SqliteStore;
use shapegram_server::store::Store;
use shapegram_server::tokens::sha256_hex;

const WOOD: &str = "fulfills(wooden) --> color(\"#8b5a2b\")\n";
const METAL: &str = "fulfills(metal) --> color(\"#aaaaaa\")\nfulfills(shiny) --> set(@Metal, 1) color(\"#eeeeee\")\nfulfills(polished) has(Metal) --> color(\"#ffffff\")\nfulfills(rusty) !is(steel) --> color(\"#8b4000\")\n";
const GLASS: &str =
    "fulfills(glass) --> color(\"#ddeeff\")\nfulfills(frosted) --> color(\"#f0f0f0\")\n";

/// A published version as the test remembers it: text, hash, number of rules.
struct Kept {
    text: &'static str,
    sha256: String,
    rules: usize,
}

fn publish(server: &Server, token: &str, text: &str) -> (i64, String, usize) {
    let (status, body) = http(
        server,
        "POST",
        "/api/v1/grammars/ana/paint/versions",
        Some(token),
        Some(json!({"text": text})),
    );
    assert_eq!(status, 201, "{body}");
    (
        body["version"].as_i64().unwrap(),
        body["sha256"].as_str().unwrap().to_owned(),
        body["rules"].as_u64().unwrap() as usize,
    )
}

/// Sends a publish whose answer never comes (the server is killed): the bytes it got back.
fn publish_unanswered(addr: String, token: String, text: &str) -> std::thread::JoinHandle<String> {
    let body = json!({"text": text}).to_string();
    std::thread::spawn(move || {
        let mut stream = TcpStream::connect(&addr).unwrap();
        write!(
            stream,
            "POST /api/v1/grammars/ana/paint/versions HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\nAuthorization: Bearer {token}\r\n\r\n{body}",
            body.len()
        )
        .unwrap();
        let mut answer = Vec::new();
        // A reset connection is what a killed server gives.
        let _ = stream.read_to_end(&mut answer);
        String::from_utf8_lossy(&answer).into_owned()
    })
}

/// Waits until the server says it reached `point` (at most 60 s).
fn wait_for(server: &mut Server, point: FailPoint) {
    let stderr = server.stderr.take().expect("stderr piped");
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            if send.send(line).is_err() {
                break;
            }
        }
    });
    let expected = format!("shapegram serve: fail point {point} reached");
    loop {
        let line = receive
            .recv_timeout(Duration::from_secs(60))
            .unwrap_or_else(|e| panic!("the server never said {expected:?}: {e}"));
        if line == expected {
            return;
        }
    }
}

fn audit(db: &std::path::Path) -> Vec<String> {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap()
        .block_on(async {
            let store = SqliteStore::open(db).await.unwrap();
            store.audit().await.unwrap()
        })
}

fn crash_at(point: FailPoint) {
    let dir = TempDir::new(&format!("crash-{}", point.name().replace(':', "-")));
    let db = dir.path("repo.db");
    // Two versions committed by a server that then stops.
    let mut kept = Vec::new();
    let token = {
        let server = start(&db);
        let token = sign_up(&server, "ana");
        for (n, text) in [(1, WOOD), (2, METAL)] {
            let (version, sha256, rules) = publish(&server, &token, text);
            assert_eq!(version, n);
            kept.push(Kept {
                text,
                sha256,
                rules,
            });
        }
        token
    };
    assert_eq!(kept[1].rules, 4);

    // A server that stops at the fail point in the third publish, killed there with SIGKILL.
    let mut server = start_with(&db, Some(point.name()), &[]);
    let request = publish_unanswered(server.addr.clone(), token.clone(), GLASS);
    wait_for(&mut server, point);
    server.child.kill().unwrap();
    let status = server.child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "{status:?}");
    let answer = request.join().unwrap();
    assert!(
        !answer.contains("201"),
        "a killed server answered: {answer}"
    );
    drop(server);

    // Restarted on the same database: the committed versions as they were, the third whole
    // exactly when COMMIT had returned, nothing half written.
    let server = start(&db);
    if point == FailPoint::AfterCommit {
        kept.push(Kept {
            text: GLASS,
            sha256: sha256_hex(GLASS.as_bytes()),
            rules: 2,
        });
    }
    let (status, versions) = http(
        &server,
        "GET",
        "/api/v1/grammars/ana/paint/versions",
        Some(&token),
        None,
    );
    assert_eq!(status, 200, "{versions}");
    let numbers: Vec<i64> = versions
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["version"].as_i64().unwrap())
        .collect();
    assert_eq!(numbers, (1..=kept.len() as i64).collect::<Vec<_>>());
    for (i, k) in kept.iter().enumerate() {
        let uri = format!("/api/v1/grammars/ana/paint/versions/{}", i + 1);
        let (status, version) = http(&server, "GET", &uri, Some(&token), None);
        assert_eq!(status, 200, "{version}");
        assert_eq!(version["text"], json!(k.text));
        assert_eq!(version["sha256"], json!(k.sha256));
        assert_eq!(sha256_hex(k.text.as_bytes()), k.sha256);
        let (status, rules) = http(&server, "GET", &format!("{uri}/rules"), Some(&token), None);
        assert_eq!(status, 200);
        assert_eq!(rules.as_array().unwrap().len(), k.rules, "{uri}: {rules}");
    }
    let (_, grammar) = http(
        &server,
        "GET",
        "/api/v1/grammars/ana/paint",
        Some(&token),
        None,
    );
    assert_eq!(grammar["latest_version"], json!(kept.len()));
    assert_eq!(audit(&db), Vec::<String>::new());

    // Publishing works again and takes the next number.
    let (version, _, _) = publish(&server, &token, GLASS);
    assert_eq!(version, kept.len() as i64 + 1);
    drop(server);
    assert_eq!(audit(&db), Vec::<String>::new());
}

#[test]
fn sigkill_before_the_transaction() {
    crash_at(FailPoint::BeforeTransaction);
}

#[test]
fn sigkill_after_inserting_the_version() {
    crash_at(FailPoint::AfterInsertVersion);
}

#[test]
fn sigkill_after_the_rule_index() {
    crash_at(FailPoint::AfterRuleIndex);
}

#[test]
fn sigkill_just_before_commit() {
    crash_at(FailPoint::BeforeCommit);
}

#[test]
fn sigkill_after_commit_before_the_answer() {
    crash_at(FailPoint::AfterCommit);
}

#[test]
fn an_unknown_fail_point_refuses_to_start() {
    let dir = TempDir::new("crash-unknown");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["serve", "--listen", "127.0.0.1:0", "--data"])
        .arg(dir.path("repo.db"))
        .env("SHAPEGRAM_FAILPOINT", "publish:after-comit")
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(
        stderr.starts_with("error: SHAPEGRAM_FAILPOINT=publish:after-comit is no fail point (known: publish:before-transaction, "),
        "{stderr}"
    );
}
