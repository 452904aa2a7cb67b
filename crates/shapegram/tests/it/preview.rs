//! Previews end to end: `shapegram serve` as a child process with small limits, its
//! `preview-worker` deriving published grammars: the GLB equals `shapegram derive`'s, and step,
//! memory and time limits, refused file reads and visibility answer as documented.

#![cfg(unix)]

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

use crate::common;

use common::{Answer, Server, TempDir, request as http, sign_up as user};
use serde_json::{Value, json};

/// A server on a fresh database with the preview flags given.
fn start(dir: &TempDir, flags: &[&str]) -> Server {
    common::start_server_with(&dir.path("repo.db"), None, flags)
}

/// Publishes `text` as `owner/name` (version 1 for a new grammar).
fn publish(server: &Server, token: &str, path: &str, text: &str, visibility: &str) {
    let answer = http(
        server,
        "POST",
        &format!("/api/v1/grammars/{path}/versions"),
        Some(token),
        Some(json!({"text": text, "visibility": visibility})),
    );
    assert_eq!(answer.status, 201, "{}", answer.json());
}

/// The preview of a version (`owner/name/versions/N`), with a query (`?seed=3`) after `?`.
fn preview(server: &Server, version: &str, token: Option<&str>) -> Answer {
    let (version, query) = version.split_once('?').unwrap_or((version, ""));
    let query = if query.is_empty() {
        String::new()
    } else {
        format!("?{query}")
    };
    http(
        server,
        "GET",
        &format!("/api/v1/grammars/{version}/preview{query}"),
        token,
        None,
    )
}

/// Small limits, so that the tests run fast: the debug binary derives the chair in
/// milliseconds and fills 128 MiB in well under a second.
const LIMITS: [&str; 8] = [
    "--preview-timeout",
    "3",
    "--preview-memory",
    "128",
    "--preview-steps",
    "1000",
    "--preview-workers",
    "2",
];

/// A grammar whose rules call each other forever, each step doubling the shapes: the step
/// limit ends it long before the depth limit.
const FOREVER: &str = "axiom a size(1, 1, 1)\n\
    fulfills(a) --> split(x) { ~1 : +b | ~1 : +b }\n\
    fulfills(b) --> split(x) { ~1 : +a | ~1 : +a }\n";

/// A thousand steps that each make a million parts, all kept: gigabytes within the step and
/// shape limits.
const BOMB: &str = "axiom a size(1, 1, 1)\n\
    fulfills(a) --> split(x) { { 0.001 : +b }* }\n\
    fulfills(b) --> split(y) { { 0.000001 : +c }* }\n";

/// 999 steps that each build two cylinders of 100,000 sides and drop them: minutes of work in
/// constant memory and within every count limit.
const SLOW: &str = "axiom a size(1, 1, 1)\n\
    fulfills(a) --> split(x) { { 0.001 : +b }* }\n\
    fulfills(b) --> primitiveCylinder(100000) primitiveCylinder(100000) primitiveCube()\n";

/// `shapegram derive` of `grammar` (a file) with `args`, into `output`.
fn derive(grammar: &Path, output: &Path, args: &[&str]) {
    let result = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .arg("derive")
        .arg(grammar)
        .arg("-o")
        .arg(output)
        .args(args)
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
}

/// The triangles of a model file, by `shapegram info`.
fn triangles(file: &Path) -> u64 {
    let result = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["info", "--json"])
        .arg(file)
        .output()
        .unwrap();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let info: Value = serde_json::from_slice(&result.stdout).unwrap();
    info["triangles"].as_u64().unwrap()
}

#[test]
fn a_published_chair_previews_as_derive_writes_it() {
    let dir = TempDir::new("preview-chair");
    let server = start(&dir, &LIMITS);
    let ana = user(&server, "ana");
    let text = std::fs::read_to_string(common::example("chairs/chair.goal")).unwrap();
    publish(&server, &ana, "ana/chair", &text, "public");
    let file = dir.path("chair.goal");
    std::fs::write(&file, &text).unwrap();

    let mut previews = Vec::new();
    for seed in [None, Some("3")] {
        let path = match seed {
            None => "ana/chair/versions/1".to_owned(),
            Some(seed) => format!("ana/chair/versions/1?seed={seed}"),
        };
        let started = Instant::now();
        let answer = preview(&server, &path, None);
        assert_eq!(
            answer.status,
            200,
            "{}",
            String::from_utf8_lossy(&answer.body)
        );
        assert_eq!(answer.header("content-type"), Some("model/gltf-binary"));
        let expected = dir.path("derived.glb");
        derive(&file, &expected, &["--seed", seed.unwrap_or("0")]);
        assert_eq!(
            answer.body,
            std::fs::read(&expected).unwrap(),
            "seed {seed:?}"
        );
        let written = dir.path("preview.glb");
        std::fs::write(&written, &answer.body).unwrap();
        assert_eq!(triangles(&written), 72, "a seat, a back and four legs");
        // Asked again: the same bytes, from the cache.
        let again = preview(&server, &path, None);
        assert_eq!(again.body, answer.body);
        eprintln!(
            "seed {seed:?}: {:?} for the first preview",
            started.elapsed()
        );
        previews.push(answer.body);
    }
    assert_ne!(previews[0], previews[1], "the seed draws the legs' size");
}

#[test]
fn a_grammar_that_recurses_forever_is_refused_at_the_step_limit() {
    let dir = TempDir::new("preview-steps");
    let server = start(&dir, &LIMITS);
    let ana = user(&server, "ana");
    publish(&server, &ana, "ana/forever", FOREVER, "public");
    let answer = preview(&server, "ana/forever/versions/1", None);
    assert_eq!(answer.status, 422);
    let body = answer.json();
    let error = body["error"].as_str().unwrap();
    assert!(
        error.starts_with("forever does not derive: the derivation took more than 1000 steps"),
        "{body}"
    );
    let place = &body["diagnostics"][0];
    assert_eq!(
        (&place["line"], &place["column"]),
        (&json!(3), &json!(1)),
        "{body}"
    );
    assert!(
        place["hints"].as_array().unwrap().contains(&json!(
            "previews stop after 1000 steps (the server's --preview-steps)"
        )),
        "{body}"
    );
}

#[test]
fn a_memory_bomb_is_stopped_by_the_memory_limit_while_the_server_answers() {
    let dir = TempDir::new("preview-memory");
    let server = start(&dir, &LIMITS);
    let ana = user(&server, "ana");
    publish(&server, &ana, "ana/bomb", BOMB, "public");
    let started = Instant::now();
    let (answer, others) = std::thread::scope(|scope| {
        let bomb = scope.spawn(|| preview(&server, "ana/bomb/versions/1", None));
        // Meanwhile other requests are answered at once.
        let mut others = Vec::new();
        while !bomb.is_finished() {
            let asked = Instant::now();
            let list = http(&server, "GET", "/api/v1/grammars", None, None);
            assert_eq!(list.status, 200);
            others.push(asked.elapsed());
            std::thread::sleep(Duration::from_millis(20));
        }
        (bomb.join().unwrap(), others)
    });
    let took = started.elapsed();
    assert_eq!(answer.status, 503, "{}", answer.json());
    assert_eq!(
        answer.json()["error"],
        "the preview needed more than 128 MiB of memory (the memory limit): stopped"
    );
    // The error names the memory limit, not the 3 s deadline; times are printed, not asserted,
    // as they depend on the machine's load.
    let slowest = others.iter().max().copied().unwrap_or_default();
    eprintln!(
        "the bomb was stopped after {took:?}; {} other requests answered meanwhile, the slowest in {slowest:?}",
        others.len()
    );
    // The server goes on making previews.
    publish(&server, &ana, "ana/forever", FOREVER, "public");
    assert_eq!(preview(&server, "ana/forever/versions/1", None).status, 422);
}

#[test]
fn a_slow_grammar_is_killed_at_the_deadline_and_busy_workers_answer_503() {
    let dir = TempDir::new("preview-time");
    // Memory to spare: the limit is of address space, which the binary itself takes a good
    // part of (93 MiB in a debug build), and this test is about time.
    let server = start(
        &dir,
        &[
            "--preview-timeout",
            "2",
            "--preview-memory",
            "512",
            "--preview-steps",
            "1000",
            "--preview-workers",
            "1",
        ],
    );
    let ana = user(&server, "ana");
    publish(&server, &ana, "ana/slow", SLOW, "public");
    publish(&server, &ana, "ana/forever", FOREVER, "public");
    // One worker: the first slow preview holds it for 2 s, the second waits for it and holds it
    // 2 s more, and a third request gives up waiting after 2 s.
    let started = Instant::now();
    let answers = std::thread::scope(|scope| {
        let first = scope.spawn(|| preview(&server, "ana/slow/versions/1", None));
        std::thread::sleep(Duration::from_millis(500));
        let second = scope.spawn(|| preview(&server, "ana/slow/versions/1?seed=1", None));
        std::thread::sleep(Duration::from_millis(500));
        let third = scope.spawn(|| {
            (
                preview(&server, "ana/forever/versions/1", None),
                started.elapsed(),
            )
        });
        [first, second]
            .map(|h| (h.join().unwrap(), started.elapsed()))
            .into_iter()
            .chain([third.join().unwrap()])
            .collect::<Vec<_>>()
    });
    for (answer, _) in &answers[..2] {
        assert_eq!(answer.status, 503);
        assert_eq!(
            answer.json()["error"],
            "the preview took longer than 2 s (the time limit): stopped"
        );
    }
    let (busy, at) = &answers[2];
    assert_eq!(busy.status, 503, "{}", busy.json());
    assert_eq!(
        busy.json()["error"],
        "every preview worker is busy: try again later"
    );
    assert_eq!(busy.header("retry-after"), Some("2"));
    // Sent 1 s in, it waited its 2 s for a worker; had it waited longer it would have had one
    // and been answered 422 (asserted above).
    assert!(
        *at >= Duration::from_millis(2_900),
        "the third request waited 2 s: {at:?}"
    );
}

#[test]
fn file_reads_are_refused_with_the_path_and_the_file_is_never_opened() {
    let dir = TempDir::new("preview-files");
    let server = start(&dir, &LIMITS);
    let ana = user(&server, "ana");
    let passwd = "axiom a size(1, 1, 1)\nfulfills(a) --> i(\"/etc/passwd\")\n";
    publish(&server, &ana, "ana/passwd", passwd, "public");
    let answer = preview(&server, "ana/passwd/versions/1", None);
    assert_eq!(answer.status, 422);
    assert_eq!(
        answer.json()["error"],
        "passwd does not derive: cannot insert `/etc/passwd`: previews read no files"
    );

    // A relative path to a file that exists and parses: `shapegram derive` reads it, the worker
    // does not even open it (its access time stays as set, where derive's read moves it).
    let secret_text = "axiom a size(1, 1, 1)\nfulfills(a) --> i(\"../../secret.obj\")\n";
    publish(&server, &ana, "ana/secret", secret_text, "public");
    let folder = dir.path("project/rules");
    std::fs::create_dir_all(&folder).unwrap();
    let secret = dir.path("secret.obj");
    std::fs::write(&secret, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let grammar = folder.join("secret.goal");
    std::fs::write(&grammar, secret_text).unwrap();
    let long_ago = SystemTime::UNIX_EPOCH + Duration::from_secs(946_684_800);
    let set_atime = || {
        std::fs::File::options()
            .write(true)
            .open(&secret)
            .unwrap()
            .set_times(std::fs::FileTimes::new().set_accessed(long_ago))
            .unwrap();
    };
    let atime = || std::fs::metadata(&secret).unwrap().accessed().unwrap();

    set_atime();
    let request = json!({"name": "secret", "text": secret_text, "seed": 0, "max_steps": 1000});
    let mut worker = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(["preview-worker", "--memory-mib", "128"])
        .current_dir(&folder)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    worker
        .stdin
        .take()
        .unwrap()
        .write_all(request.to_string().as_bytes())
        .unwrap();
    let output = worker.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(3));
    let failure: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(
        failure["error"],
        "secret does not derive: cannot insert `../../secret.obj`: previews read no files"
    );
    assert_eq!(atime(), long_ago, "the worker did not open the file");

    // The control: derive reads the same file from the same folder, and its access time moves.
    derive(&grammar, &dir.path("secret.glb"), &[]);
    assert_eq!(triangles(&dir.path("secret.glb")), 1, "the file parses");
    assert_ne!(
        atime(),
        long_ago,
        "reading a file moves its access time here"
    );

    let answer = preview(&server, "ana/secret/versions/1", None);
    assert_eq!(answer.status, 422);
    let body = answer.json();
    assert_eq!(
        body["error"],
        "secret does not derive: cannot insert `../../secret.obj`: previews read no files"
    );
    assert_eq!(
        (
            &body["diagnostics"][0]["line"],
            &body["diagnostics"][0]["column"]
        ),
        (&json!(2), &json!(19))
    );
}

#[test]
fn previews_follow_the_versions_visibility() {
    let dir = TempDir::new("preview-visibility");
    let server = start(&dir, &LIMITS);
    let ana = user(&server, "ana");
    let sam = user(&server, "sam");
    let text = std::fs::read_to_string(common::example("chairs/chair.goal")).unwrap();
    publish(&server, &ana, "ana/hidden", &text, "private");
    for token in [None, Some(sam.as_str())] {
        let answer = preview(&server, "ana/hidden/versions/1", token);
        assert_eq!(answer.status, 404);
        assert_eq!(answer.json()["error"], "not found");
    }
    let answer = preview(&server, "ana/hidden/versions/1", Some(&ana));
    assert_eq!(answer.status, 200);
    assert!(answer.body.starts_with(b"glTF"));
    assert_eq!(
        preview(&server, "ana/hidden/versions/2", Some(&ana)).status,
        404
    );
    assert_eq!(
        preview(&server, "ana/hidden/versions/1?seed=x", Some(&ana)).status,
        400
    );
}

#[test]
fn previews_are_off_without_workers() {
    let dir = TempDir::new("preview-off");
    let server = start(&dir, &["--preview-workers", "0"]);
    let ana = user(&server, "ana");
    let text = std::fs::read_to_string(common::example("chairs/chair.goal")).unwrap();
    publish(&server, &ana, "ana/chair", &text, "public");
    let answer = preview(&server, "ana/chair/versions/1", None);
    assert_eq!(answer.status, 503);
    assert_eq!(answer.json()["error"], "previews are off");
    assert_eq!(preview(&server, "ana/none/versions/1", None).status, 404);
}
