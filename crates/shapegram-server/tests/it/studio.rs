//! The studio's API through its router, without sockets, with an engine that only counts: the
//! Host and Origin guard, paths that try to leave the folders, saving in the encoding a file was
//! read in, and derivations superseded by newer ones.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use shapegram_server::studio::{self, DeriveJob, Derived, Engine, Folders, StudioState};
use tower::ServiceExt;

const PORT: u16 = 7370;
const ORIGIN: &str = "http://127.0.0.1:7370";

/// An engine whose model is the text's length in shapes, counting its derivations and noting
/// the path and packaged rule file of each. `spin` runs until it is cancelled; `hold` notes
/// when it is cancelled and then waits for `release` to end normally (each at most 10 s).
#[derive(Default)]
struct Counting {
    runs: AtomicUsize,
    jobs: Mutex<Vec<(PathBuf, Option<String>)>>,
    cancel_noticed: AtomicBool,
    release: AtomicBool,
}

/// Waits, at most 10 s, for `done`.
fn wait_for(done: impl Fn() -> bool) {
    let started = Instant::now();
    while !done() && started.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Waits, at most 10 s, for `done` without holding up the runtime's other tasks.
async fn until(done: impl Fn() -> bool) {
    let started = Instant::now();
    while !done() && started.elapsed() < Duration::from_secs(10) {
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
}

impl Engine for Counting {
    fn derive(&self, job: &DeriveJob) -> Derived {
        self.runs.fetch_add(1, Ordering::SeqCst);
        self.jobs.lock().unwrap().push((
            job.path.clone(),
            job.package.as_ref().map(|p| p.entry.clone()),
        ));
        if job.text == "hold" {
            wait_for(|| job.control.is_cancelled());
            self.cancel_noticed.store(true, Ordering::SeqCst);
            wait_for(|| self.release.load(Ordering::SeqCst));
        }
        if job.text == "spin" {
            wait_for(|| job.control.is_cancelled());
            return Derived {
                error: Some("the derivation was cancelled".to_owned()),
                ..Derived::default()
            };
        }
        Derived {
            glb: Some(b"glTF".to_vec()),
            shapes: job.text.len(),
            ..Derived::default()
        }
    }
}

struct Studio {
    router: Router,
    engine: Arc<Counting>,
    dir: tempfile::TempDir,
}

impl Studio {
    /// A studio given `house.cga` (UTF-8) in a fresh folder that also holds `old.cga`
    /// (Windows-1252, CR LF), `notes.txt`, and a link `escape.cga` to a grammar outside.
    fn new() -> Studio {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("project");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("house.cga"), "Lot --> extrude(10) Mass.\n").unwrap();
        std::fs::write(folder.join("old.cga"), b"// caf\xe9\r\nLot --> X.\r\n").unwrap();
        std::fs::write(folder.join("notes.txt"), "not a grammar").unwrap();
        std::fs::write(dir.path().join("outside.cga"), "Lot --> Secret.\n").unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(dir.path().join("outside.cga"), folder.join("escape.cga"))
            .unwrap();
        Studio::serve(dir, &["house.cga"])
    }

    /// A studio over the folder of [`Studio::new`] with rule packages beside its files: the
    /// given `town.rpk` (a main rule file compiled, another not, an asset), `broken.rpk` (not an
    /// archive) and `compiled.rpk` (compiled rules only).
    fn with_packages() -> Studio {
        let studio = Studio::new();
        let folder = studio.path("");
        std::fs::write(
            folder.join("town.rpk"),
            archive(&[
                ("rules/town.cga", TOWN.as_bytes()),
                ("rules/flat.cga", b"Lot --> Flat.\n"),
                ("bin/town.cgb", b"compiled"),
                ("assets/box.obj", b"v 0 0 0\n"),
            ]),
        )
        .unwrap();
        std::fs::write(folder.join("broken.rpk"), b"Lot --> X.\n").unwrap();
        std::fs::write(
            folder.join("compiled.rpk"),
            archive(&[("bin/main.cgb", b"compiled")]),
        )
        .unwrap();
        Studio::serve(studio.dir, &["house.cga", "town.rpk"])
    }

    /// A studio given the files `given` of the folder `project` in `dir`.
    fn serve(dir: tempfile::TempDir, given: &[&str]) -> Studio {
        let folder = dir.path().join("project");
        let given: Vec<PathBuf> = given.iter().map(|name| folder.join(name)).collect();
        let folders = Folders::new(&given).unwrap();
        let engine = Arc::new(Counting::default());
        let state = StudioState::new(folders, engine.clone(), PORT);
        Studio {
            router: studio::router(state),
            engine,
            dir,
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        std::fs::canonicalize(self.dir.path())
            .unwrap()
            .join("project")
            .join(name)
    }

    async fn send(
        &self,
        method: &str,
        uri: &str,
        host: &str,
        origin: Option<&str>,
        body: Option<Value>,
    ) -> (StatusCode, Value) {
        let mut request = Request::builder()
            .method(method)
            .uri(uri)
            .header("host", host);
        if let Some(origin) = origin {
            request = request.header("origin", origin);
        }
        let body = match body {
            Some(body) => {
                request = request.header("content-type", "application/json");
                Body::from(body.to_string())
            }
            None => Body::empty(),
        };
        let response = self
            .router
            .clone()
            .oneshot(request.body(body).unwrap())
            .await
            .unwrap();
        let status = response.status();
        let bytes = response.into_body().collect().await.unwrap().to_bytes();
        let value = serde_json::from_slice(&bytes).unwrap_or(Value::Null);
        (status, value)
    }

    async fn get(&self, uri: &str) -> (StatusCode, Value) {
        self.send("GET", uri, "127.0.0.1:7370", None, None).await
    }

    async fn write(&self, method: &str, uri: &str, body: Value) -> (StatusCode, Value) {
        self.send(method, uri, "127.0.0.1:7370", Some(ORIGIN), Some(body))
            .await
    }

    async fn read(&self, path: &Path) -> (StatusCode, Value) {
        let query = format!("/api/file?path={}", path.display()).replace(' ', "%20");
        self.get(&query).await
    }
}

/// The main rule file of `town.rpk`.
const TOWN: &str = "attr height = 9\nLot --> extrude(height) Mass.\n";

/// A 7-Zip archive of `files` (path, contents), as CityEngine writes rule packages.
fn archive(files: &[(&str, &[u8])]) -> Vec<u8> {
    let mut writer = sevenz_rust2::ArchiveWriter::new(std::io::Cursor::new(Vec::new())).unwrap();
    for (name, bytes) in files {
        writer
            .push_archive_entry(sevenz_rust2::ArchiveEntry::new_file(name), Some(*bytes))
            .unwrap();
    }
    writer.finish().unwrap().into_inner()
}

#[tokio::test]
async fn a_foreign_host_is_refused_on_every_route() {
    let studio = Studio::new();
    for host in [
        "evil.example:7370",
        "127.0.0.1:80",
        "127.0.0.1",
        "localhost:7371",
    ] {
        let (status, body) = studio.send("GET", "/api/files", host, None, None).await;
        assert_eq!(status, StatusCode::FORBIDDEN, "{host}");
        assert_eq!(
            body["error"],
            format!("the Host `{host}` is not this studio's (127.0.0.1:7370 or localhost:7370)")
        );
    }
    let (status, _) = studio
        .send("GET", "/", "evil.example:7370", None, None)
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let (status, list) = studio
        .send("GET", "/api/files", "localhost:7370", None, None)
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(list["files"].as_array().unwrap().len(), 2);
}

#[tokio::test]
async fn writes_need_the_studios_origin() {
    let studio = Studio::new();
    let house = studio.path("house.cga");
    let save = json!({"path": house, "text": "Lot --> X.\n"});
    let cases = [
        (
            None,
            "a request that changes something must carry the Origin of the studio's page",
        ),
        (
            Some("http://evil.example"),
            "the Origin `http://evil.example` is not this studio's page: only the studio may change files",
        ),
        (
            Some("http://127.0.0.1:7371"),
            "the Origin `http://127.0.0.1:7371` is not this studio's page: only the studio may change files",
        ),
        (
            Some("null"),
            "the Origin `null` is not this studio's page: only the studio may change files",
        ),
    ];
    for (origin, message) in cases {
        for (method, uri) in [("PUT", "/api/file"), ("POST", "/api/derive")] {
            let (status, body) = studio
                .send(method, uri, "127.0.0.1:7370", origin, Some(save.clone()))
                .await;
            assert_eq!(status, StatusCode::FORBIDDEN, "{method} {origin:?}");
            assert_eq!(body["error"], message);
        }
    }
    assert_eq!(
        std::fs::read_to_string(&house).unwrap(),
        "Lot --> extrude(10) Mass.\n"
    );
    assert_eq!(studio.engine.runs.load(Ordering::SeqCst), 0);
    let (status, saved) = studio
        .send(
            "PUT",
            "/api/file",
            "localhost:7370",
            Some("http://localhost:7370"),
            Some(save),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_eq!(
        saved,
        json!({"path": house, "bytes": 11, "encoding": "utf-8", "line_endings": "lf"})
    );
    assert_eq!(std::fs::read_to_string(&house).unwrap(), "Lot --> X.\n");
}

#[tokio::test]
async fn the_list_has_the_given_file_first_then_the_folders_grammars() {
    let studio = Studio::new();
    let (status, list) = studio.get("/api/files").await;
    assert_eq!(status, StatusCode::OK);
    let names: Vec<(&str, bool)> = list["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["name"].as_str().unwrap(), f["given"].as_bool().unwrap()))
        .collect();
    // Not `notes.txt`, nor the link `escape.cga`: links are not listed.
    assert_eq!(names, [("house.cga", true), ("old.cga", false)]);
    assert_eq!(list["files"][0]["path"], json!(studio.path("house.cga")));
}

#[tokio::test]
async fn paths_that_leave_the_folders_are_refused() {
    let studio = Studio::new();
    let project = studio.path("");
    let outside = project.parent().unwrap().join("outside.cga");
    let climbing = format!("{}/../outside.cga", project.display());
    let cases: Vec<(String, StatusCode, String)> = vec![
        (
            climbing.clone(),
            StatusCode::FORBIDDEN,
            format!("`{climbing}` goes up with `..`"),
        ),
        (
            outside.display().to_string(),
            StatusCode::FORBIDDEN,
            format!(
                "`{}` is outside the folders of the files the studio was given",
                outside.display()
            ),
        ),
        (
            studio.path("escape.cga").display().to_string(),
            StatusCode::FORBIDDEN,
            format!(
                "`{}` is outside the folders of the files the studio was given",
                studio.path("escape.cga").display()
            ),
        ),
        (
            studio.path("notes.txt").display().to_string(),
            StatusCode::FORBIDDEN,
            format!(
                "`{}` is not a grammar file (.cga, .mul, .sgl, .goal, .lsys, .cave, .grammar) or a rule file of a rule package (.rpk!/rules/…)",
                studio.path("notes.txt").display()
            ),
        ),
        (
            "house.cga".to_owned(),
            StatusCode::BAD_REQUEST,
            "`house.cga` is not an absolute path (GET /api/files lists the files)".to_owned(),
        ),
        (
            studio.path("missing.cga").display().to_string(),
            StatusCode::NOT_FOUND,
            format!("no file `{}`", studio.path("missing.cga").display()),
        ),
    ];
    for (path, status, message) in cases {
        let (got, body) = studio.read(Path::new(&path)).await;
        assert_eq!((got, body["error"].as_str().unwrap()), (status, &*message));
        for (method, uri) in [("PUT", "/api/file"), ("POST", "/api/derive")] {
            let (got, body) = studio
                .write(
                    method,
                    uri,
                    json!({"path": path, "text": "Lot --> Hacked.\n"}),
                )
                .await;
            assert_eq!(
                (got, body["error"].as_str().unwrap()),
                (status, &*message),
                "{method} {path}"
            );
        }
    }
    assert_eq!(
        std::fs::read_to_string(&outside).unwrap(),
        "Lot --> Secret.\n"
    );
    assert_eq!(studio.engine.runs.load(Ordering::SeqCst), 0);
}

#[tokio::test]
async fn a_rule_packages_rule_files_are_listed_read_and_derived_but_never_written() {
    let studio = Studio::with_packages();
    let town = studio.path("town.rpk");
    let (status, list) = studio.get("/api/files").await;
    assert_eq!(status, StatusCode::OK);
    let files: Vec<(&str, bool, bool)> = list["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            (
                f["name"].as_str().unwrap(),
                f["given"].as_bool().unwrap(),
                f["read_only"].as_bool().unwrap(),
            )
        })
        .collect();
    // The given files first, the package's main rule file (the one PRT runs) before its other;
    // packages without rule files to run as themselves.
    assert_eq!(
        files,
        [
            ("house.cga", true, false),
            ("town.rpk!/rules/town.cga", true, true),
            ("town.rpk!/rules/flat.cga", true, true),
            ("broken.rpk", false, false),
            ("compiled.rpk", false, false),
            ("old.cga", false, false),
        ]
    );
    let main = format!("{}!/rules/town.cga", town.display());
    assert_eq!(list["files"][1]["path"], json!(main));

    // Read from the archive; the package's own path reads its main rule file.
    for asked in [main.clone(), town.display().to_string()] {
        let (status, file) = studio.read(Path::new(&asked)).await;
        assert_eq!(status, StatusCode::OK, "{file}");
        assert_eq!(file["text"], json!(TOWN));
        assert_eq!(file["path"], json!(main));
        assert_eq!(file["read_only"], json!(true));
    }

    // Derived as the rule file of its package.
    let (status, answer) = studio
        .write(
            "POST",
            "/api/derive",
            json!({"path": main, "text": "Lot --> X.\n"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    assert_eq!(
        studio.engine.jobs.lock().unwrap().as_slice(),
        [(PathBuf::from(&main), Some("rules/town.cga".to_owned()))]
    );

    // Never written: the archive stays as it was.
    let before = std::fs::read(&town).unwrap();
    let (status, body) = studio
        .write(
            "PUT",
            "/api/file",
            json!({"path": main, "text": "Lot --> Hacked.\n"}),
        )
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    assert_eq!(
        body["error"],
        json!(format!(
            "`{main}` is inside the rule package {}, which the studio does not write: edits derive, but are not saved",
            town.display()
        ))
    );
    assert_eq!(std::fs::read(&town).unwrap(), before);
}

#[tokio::test]
async fn packages_that_cannot_be_used_say_why() {
    let studio = Studio::with_packages();
    let town = studio.path("town.rpk").display().to_string();
    let broken = studio.path("broken.rpk").display().to_string();
    let compiled = studio.path("compiled.rpk").display().to_string();
    let cases = [
        (
            broken.clone(),
            StatusCode::UNPROCESSABLE_ENTITY,
            format!("{broken} is not a readable rule package (a 7-Zip archive): "),
        ),
        (
            compiled.clone(),
            StatusCode::UNPROCESSABLE_ENTITY,
            format!(
                "{compiled} holds only compiled rules (bin/main.cgb) and no CGA source: Shapegram runs CGA source, not CityEngine's compiled .cgb files (use a package that includes its rules/*.cga files"
            ),
        ),
        (
            format!("{town}!/rules/missing.cga"),
            StatusCode::UNPROCESSABLE_ENTITY,
            format!(
                "{town} has no rule file `rules/missing.cga`; its rule files are rules/flat.cga, rules/town.cga"
            ),
        ),
        (
            format!("{town}!/assets/box.obj"),
            StatusCode::UNPROCESSABLE_ENTITY,
            format!(
                "{town} has no rule file `assets/box.obj`; its rule files are rules/flat.cga, rules/town.cga"
            ),
        ),
        (
            format!("{town}!/rules/../rules/town.cga"),
            StatusCode::FORBIDDEN,
            format!("`{town}!/rules/../rules/town.cga` goes up with `..`"),
        ),
        (
            format!("{}!/rules/town.cga", studio.path("gone.rpk").display()),
            StatusCode::NOT_FOUND,
            format!("no file `{}`", studio.path("gone.rpk").display()),
        ),
    ];
    for (path, status, message) in cases {
        let (got, body) = studio.read(Path::new(&path)).await;
        let error = body["error"].as_str().unwrap();
        assert_eq!(got, status, "{path}: {error}");
        assert!(error.starts_with(&message), "{path}: {error}");
        let (got, body) = studio
            .write(
                "POST",
                "/api/derive",
                json!({"path": path, "text": "Lot --> X.\n"}),
            )
            .await;
        assert_eq!((got, &body["error"]), (status, &json!(error)), "{path}");
    }
    assert_eq!(studio.engine.runs.load(Ordering::SeqCst), 0);
}

#[tokio::test]
async fn a_windows_1252_file_is_saved_back_in_windows_1252_with_its_line_endings() {
    let studio = Studio::new();
    let old = studio.path("old.cga");
    let (status, file) = studio.read(&old).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        file,
        json!({"path": old, "text": "// café\r\nLot --> X.\r\n", "encoding": "windows-1252", "line_endings": "crlf", "read_only": false})
    );
    // An editor gives lines ending in LF.
    let (status, saved) = studio
        .write(
            "PUT",
            "/api/file",
            json!({"path": old, "text": "// café €\nLot --> Y.\n"}),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{saved}");
    assert_eq!(
        saved,
        json!({"path": old, "bytes": 23, "encoding": "windows-1252", "line_endings": "crlf"})
    );
    assert_eq!(
        std::fs::read(&old).unwrap(),
        b"// caf\xe9 \x80\r\nLot --> Y.\r\n"
    );
    let (status, again) = studio.read(&old).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(again["text"], "// café €\r\nLot --> Y.\r\n");
    // A character Windows-1252 lacks is refused, and the file stays as it was.
    let (status, refused) = studio
        .write(
            "PUT",
            "/api/file",
            json!({"path": old, "text": "// 中\nLot --> Z.\n"}),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        refused["error"],
        "line 1: `中` (U+4E2D) cannot be written in Windows-1252, the file's encoding"
    );
    assert_eq!(
        std::fs::read(&old).unwrap(),
        b"// caf\xe9 \x80\r\nLot --> Y.\r\n"
    );
    // No temporary file is left beside it.
    let mut names: Vec<String> = std::fs::read_dir(studio.path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["escape.cga", "house.cga", "notes.txt", "old.cga"]);
}

#[tokio::test]
async fn a_derivation_waiting_behind_a_newer_one_is_dropped_unrun() {
    let studio = Arc::new(Studio::new());
    let house = studio.path("house.cga");
    let request = |text: &str| {
        let studio = studio.clone();
        let body = json!({"path": house, "text": text});
        async move { studio.write("POST", "/api/derive", body).await }
    };
    // Each request is sent once the one before is under way, so they take their numbers in order.
    let engine = &studio.engine;
    let first = tokio::spawn(request("hold"));
    until(|| engine.runs.load(Ordering::SeqCst) == 1).await;
    // The second cancels the first as it takes its number, then waits for it to end.
    let second = tokio::spawn(request("Lot --> Y."));
    until(|| engine.cancel_noticed.load(Ordering::SeqCst)).await;
    let third = tokio::spawn(request("Lot --> X."));
    // On this one-thread runtime the third runs up to its wait before this task goes on.
    tokio::time::sleep(Duration::from_millis(50)).await;
    engine.release.store(true, Ordering::SeqCst);
    let (first, second, third) = (
        first.await.unwrap(),
        second.await.unwrap(),
        third.await.unwrap(),
    );
    // The first ran to its end, but a newer request had come: its model is not sent.
    assert_eq!(first.0, StatusCode::CONFLICT);
    assert_eq!(
        first.1["error"],
        "derivation 1 of this file was superseded by a newer one"
    );
    assert_eq!(second.0, StatusCode::CONFLICT);
    assert_eq!(
        second.1["error"],
        "derivation 2 of this file was superseded by a newer one"
    );
    assert_eq!(third.0, StatusCode::OK, "{}", third.1);
    assert_eq!(
        (&third.1["generation"], &third.1["shapes"], &third.1["glb"]),
        (&json!(3), &json!(10), &json!("Z2xURg=="))
    );
    // The second never ran.
    assert_eq!(studio.engine.runs.load(Ordering::SeqCst), 2);
}

#[tokio::test]
async fn a_newer_request_cancels_the_running_derivation_which_is_answered_409_at_once() {
    let studio = Arc::new(Studio::new());
    let house = studio.path("house.cga");
    let request = |text: &str| {
        let studio = studio.clone();
        let body = json!({"path": house, "text": text});
        async move {
            let started = Instant::now();
            let answer = studio.write("POST", "/api/derive", body).await;
            (answer, started.elapsed())
        }
    };
    let first = tokio::spawn(request("spin"));
    tokio::time::sleep(Duration::from_millis(100)).await;
    let ((status, answer), second_time) = request("Lot --> X.").await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    let ((status, answer), first_time) = first.await.unwrap();
    assert_eq!(status, StatusCode::CONFLICT, "{answer}");
    assert_eq!(
        answer["error"],
        "derivation 1 of this file was superseded by a newer one"
    );
    // Without the cancel, the first would have spun for 10 s and the second waited for it.
    assert!(first_time < Duration::from_secs(5), "{first_time:?}");
    assert!(second_time < Duration::from_secs(5), "{second_time:?}");
    assert_eq!(studio.engine.runs.load(Ordering::SeqCst), 2);
}

#[tokio::test]
async fn bad_lots_seeds_and_formats_are_refused() {
    let studio = Studio::new();
    let house = studio.path("house.cga");
    for (body, error) in [
        (
            json!({"path": house, "text": "x", "lot": {"kind": "circle"}}),
            "unknown variant `circle`",
        ),
        (
            json!({"path": house, "text": "x", "seed": -1}),
            "invalid value",
        ),
        (
            json!({"path": house, "text": "x", "format": "stl"}),
            "unknown field `format`",
        ),
    ] {
        let (status, answer) = studio.write("POST", "/api/derive", body).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{answer}");
        assert!(
            answer["error"].as_str().unwrap().contains(error),
            "{answer}"
        );
    }
    let (status, answer) = studio
        .write(
            "POST",
            "/api/export",
            json!({"path": house, "text": "x", "format": "ply"}),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{answer}");
    assert!(
        answer["error"]
            .as_str()
            .unwrap()
            .contains("unknown variant `ply`"),
        "{answer}"
    );
    // The counting engine writes no export files: the export says there is no model.
    let (status, answer) = studio
        .write(
            "POST",
            "/api/export",
            json!({"path": house, "text": "x", "format": "obj"}),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{answer}");
    assert_eq!(answer["error"], "the grammar gives no model to export");
}

#[tokio::test]
async fn the_page_and_its_assets_are_served() {
    let studio = Studio::new();
    let response = studio
        .router
        .clone()
        .oneshot(
            Request::builder()
                .uri("/")
                .header("host", "127.0.0.1:7370")
                .body(Body::empty())
                .unwrap(),
        )
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    assert_eq!(
        response.headers()["content-type"],
        "text/html; charset=utf-8"
    );
    assert_eq!(response.headers()["x-frame-options"], "DENY");
    let page = response.into_body().collect().await.unwrap().to_bytes();
    let page = String::from_utf8(page.to_vec()).unwrap();
    assert!(page.contains(r#"<script type="module" src="/assets/studio.js">"#));
    for (asset, kind) in [
        ("studio.js", "text/javascript; charset=utf-8"),
        ("studio.css", "text/css; charset=utf-8"),
    ] {
        let response = studio
            .router
            .clone()
            .oneshot(
                Request::builder()
                    .uri(format!("/assets/{asset}"))
                    .header("host", "127.0.0.1:7370")
                    .body(Body::empty())
                    .unwrap(),
            )
            .await
            .unwrap();
        assert_eq!(response.status(), StatusCode::OK);
        assert_eq!(response.headers()["content-type"], kind);
    }
    let (status, body) = studio.get("/assets/secret.js").await;
    assert_eq!(
        (status, &body["error"]),
        (StatusCode::NOT_FOUND, &json!("not found"))
    );
}

/// The vocabulary comes from the engine's tables: operations with their signatures and
/// support, built-in functions with theirs, shape queries.
#[tokio::test]
async fn the_vocabulary_is_the_engines() {
    let studio = Studio::new();
    let (status, vocabulary) = studio.get("/api/vocabulary").await;
    assert_eq!(status, StatusCode::OK);
    let find = |list: &str, name: &str| {
        vocabulary[list]
            .as_array()
            .unwrap()
            .iter()
            .find(|w| w["name"] == name)
            .cloned()
            .unwrap_or(Value::Null)
    };
    assert_eq!(
        find("operations", "roofHip"),
        json!({"name": "roofHip", "signature": "roofHip([byAngle | byHeight,] value [, overhang [, even]])", "support": "implemented"})
    );
    assert_eq!(
        find("operations", "softenNormals"),
        json!({"name": "softenNormals", "support": "visual-only"})
    );
    assert_eq!(
        find("operations", "reduceGeometry"),
        json!({"name": "reduceGeometry", "support": "unsupported"})
    );
    // Names that are no CityEngine operation are not offered as operations.
    assert_eq!(find("operations", "fill"), Value::Null);
    assert_eq!(
        find("functions", "rand"),
        json!({"name": "rand", "signature": "rand() | rand(max) | rand(min, max)"})
    );
    assert_eq!(find("functions", "sin"), json!({"name": "sin"}));
    assert_eq!(find("queries", "scope.sx"), json!({"name": "scope.sx"}));
    let implemented = vocabulary["operations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["support"] == "implemented")
        .count();
    // Every implemented operation has its signature.
    let signed = vocabulary["operations"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["signature"].is_string())
        .count();
    assert_eq!(signed, implemented);
    assert_eq!(implemented, 85);
    // A foreign page cannot read it either.
    let (status, _) = studio
        .send("GET", "/api/vocabulary", "evil.example:7370", None, None)
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
}
