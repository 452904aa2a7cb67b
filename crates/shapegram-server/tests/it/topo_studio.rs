//! The studio's editor of topological split grammars through its router: opening a project,
//! authoring steps with undo and redo, the edit view's meshes, saving and compiling to files,
//! the tester and the anchor preview, the guard, and bad requests answered with reasons.

use std::path::PathBuf;
use std::sync::Arc;

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use http_body_util::BodyExt;
use serde_json::{Value, json};
use shapegram_server::studio::{self, DeriveJob, Derived, Engine, Folders, StudioState};
use shapegram_topo::{Assignment, NodeKind, Project};
use tower::ServiceExt;

const PORT: u16 = 7370;
const ORIGIN: &str = "http://127.0.0.1:7370";

/// The editor never derives grammar text.
struct NoEngine;

impl Engine for NoEngine {
    fn derive(&self, _: &DeriveJob) -> Derived {
        Derived::default()
    }
}

struct Studio {
    router: Router,
    project: PathBuf,
    _dir: tempfile::TempDir,
}

impl Studio {
    /// A studio given `pyramid.sgproj.json`, holding `text`.
    fn new(text: &str) -> Studio {
        let dir = tempfile::tempdir().unwrap();
        let folder = std::fs::canonicalize(dir.path()).unwrap();
        let project = folder.join("pyramid.sgproj.json");
        std::fs::write(&project, text).unwrap();
        std::fs::write(folder.join("notes.json"), "{}").unwrap();
        let folders = Folders::new(std::slice::from_ref(&project)).unwrap();
        let state = StudioState::new(folders, Arc::new(NoEngine), PORT);
        Studio {
            router: studio::router(state),
            project,
            _dir: dir,
        }
    }

    async fn send(&self, uri: &str, origin: Option<&str>, body: Value) -> (StatusCode, Value) {
        let mut request = Request::builder()
            .method("POST")
            .uri(uri)
            .header("host", "127.0.0.1:7370")
            .header("content-type", "application/json");
        if let Some(origin) = origin {
            request = request.header("origin", origin);
        }
        let response = self
            .router
            .clone()
            .oneshot(request.body(Body::from(body.to_string())).unwrap())
            .await
            .unwrap();
        let status = response.status();
        let bytes = response.into_body().collect().await.unwrap().to_bytes();
        (
            status,
            serde_json::from_slice(&bytes).unwrap_or(Value::Null),
        )
    }

    async fn post(&self, uri: &str, body: Value) -> (StatusCode, Value) {
        self.send(uri, Some(ORIGIN), body).await
    }

    fn path(&self) -> String {
        self.project.display().to_string()
    }

    async fn open(&self) -> Value {
        let (status, state) = self
            .post("/api/topo/open", json!({ "path": self.path() }))
            .await;
        assert_eq!(status, StatusCode::OK, "{state}");
        state
    }

    /// Applies `action` showing rule 0; the answer must be 200.
    async fn act(&self, action: Value) -> Value {
        let (status, answer) = self
            .post(
                "/api/topo/action",
                json!({ "path": self.path(), "action": action, "view": { "rule": 0 } }),
            )
            .await;
        assert_eq!(status, StatusCode::OK, "{answer}");
        answer
    }

    fn saved(&self) -> Project {
        Project::from_json(&std::fs::read_to_string(&self.project).unwrap()).unwrap()
    }
}

#[tokio::test]
async fn a_blank_file_opens_as_an_empty_project_and_a_rule_is_cut_saved_and_compiled() {
    let studio = Studio::new("");
    let state = studio.open().await;
    assert_eq!(state["symbols"], json!([]));
    assert_eq!(
        (state["undo"].clone(), state["dirty"].clone()),
        (json!(0), json!(false))
    );

    let made = studio
        .act(json!({ "kind": "add_symbol", "name": "Pyramid", "size": [16, 8, 16] }))
        .await;
    assert_eq!(made["made"]["index"], 0);
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "tier" }))
        .await;
    // The edit view of the new rule: one sub-shape, a box of 6 faces, 12 triangles.
    let answer = studio
        .act(json!({ "kind": "face_cut", "rule": 0, "node": 0, "face": 3, "distance": 2.0 }))
        .await;
    assert_eq!(answer["made"]["nodes"], json!([2, 1]));
    let state = &answer["state"];
    assert_eq!(state["undo"], 3);
    assert_eq!(state["dirty"], true);
    assert_eq!(
        state["rules"][0]["tree"],
        json!({ "node": 0, "kind": "cut", "children": [
            { "node": 1, "kind": "terminal" }, { "node": 2, "kind": "terminal" }] })
    );
    let parts = state["edit"]["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 2);
    for part in parts {
        assert_eq!(part["triangle_faces"].as_array().unwrap().len(), 12);
        assert_eq!(part["positions"].as_array().unwrap().len(), 12 * 9);
        assert_eq!(part["faces"].as_array().unwrap().len(), 6);
    }
    // The slice (node 2) is the top 2 units: its corners lie between y = 6 and y = 8.
    let ys: Vec<f64> = parts[1]["faces"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|f| f.as_array().unwrap().iter().map(|p| p[1].as_f64().unwrap()))
        .collect();
    assert_eq!(parts[1]["node"], 2);
    assert_eq!(ys.iter().cloned().fold(f64::MAX, f64::min), 6.0);
    assert_eq!(ys.iter().cloned().fold(f64::MIN, f64::max), 8.0);
    assert_ne!(parts[0]["color"], parts[1]["color"]);

    studio
        .act(json!({ "kind": "assign", "rule": 0, "node": 2, "to": "epsilon" }))
        .await;
    let (status, written) = studio
        .post("/api/topo/save", json!({ "path": studio.path() }))
        .await;
    assert_eq!(status, StatusCode::OK, "{written}");
    let saved = studio.saved();
    assert_eq!(saved.symbols.len(), 1);
    assert_eq!(saved.rules[0].name, "tier");
    assert_eq!(
        saved.rules[0].tree.nodes()[2].kind,
        NodeKind::Leaf(Assignment::Epsilon)
    );
    assert_eq!(
        written["bytes"],
        std::fs::metadata(&studio.project).unwrap().len()
    );
    let (_, state) = studio
        .post("/api/topo/state", json!({ "path": studio.path() }))
        .await;
    assert_eq!(state["dirty"], false);

    let (status, compiled) = studio
        .post("/api/topo/compile", json!({ "path": studio.path() }))
        .await;
    assert_eq!(status, StatusCode::OK, "{compiled}");
    let grammar_path = studio.project.with_file_name("pyramid.grammar");
    assert_eq!(compiled["path"], grammar_path.display().to_string());
    let grammar =
        shapegram_topo::Grammar::from_json(&std::fs::read_to_string(grammar_path).unwrap())
            .unwrap();
    assert_eq!(grammar.symbol_names(), ["Pyramid"]);
}

#[tokio::test]
async fn undo_and_redo_walk_the_steps_and_a_refused_step_changes_nothing() {
    let studio = Studio::new("");
    studio.open().await;
    studio
        .act(json!({ "kind": "add_symbol", "name": "A", "size": [4, 1, 4] }))
        .await;
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "r" }))
        .await;
    studio
        .act(json!({ "kind": "multi_cut", "rule": 0, "node": 0, "face": 0, "cuts": 3 }))
        .await;
    let body = json!({ "path": studio.path(), "view": { "rule": 0 } });
    let (status, state) = studio.post("/api/topo/undo", body.clone()).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(state["edit"]["parts"].as_array().unwrap().len(), 1);
    assert_eq!(
        (state["undo"].clone(), state["redo"].clone()),
        (json!(2), json!(1))
    );
    let (_, state) = studio.post("/api/topo/redo", body.clone()).await;
    assert_eq!(state["edit"]["parts"].as_array().unwrap().len(), 4);
    let (status, error) = studio.post("/api/topo/redo", body.clone()).await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert_eq!(error["error"], "nothing to redo");

    // Node 0 is cut now: cutting it again is refused with the reason, and not recorded.
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action":
                { "kind": "face_cut", "rule": 0, "node": 0, "face": 0, "distance": 1.0 } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        error["error"],
        "node 0 is already cut; cut one of its sub-shapes"
    );
    let (_, state) = studio.post("/api/topo/state", body).await;
    assert_eq!(state["undo"], 3);
}

#[tokio::test]
async fn every_tool_and_explorer_step_runs_through_the_api() {
    let studio = Studio::new("");
    studio.open().await;
    for action in [
        json!({ "kind": "add_symbol", "name": "Box", "size": [4, 4, 4] }),
        json!({ "kind": "add_symbol", "name": "Slab", "size": [4, 1, 4] }),
        json!({ "kind": "add_rule", "symbol": 0, "name": "cuts", "weight": 2.0 }),
        json!({ "kind": "rename_rule", "rule": 0, "name": "carve" }),
        json!({ "kind": "rename_symbol", "symbol": 1, "name": "Floor" }),
        json!({ "kind": "set_color", "symbol": 1, "color": "#336699" }),
        // Prism cut on the bottom face (2) at 0.3 of the height, snapped to 0.5: 1.0 up.
        json!({ "kind": "prism_cut", "rule": 0, "node": 0, "face": 2, "fraction": 0.3, "grid": 0.5 }),
    ] {
        studio.act(action).await;
    }
    let state = studio
        .act(json!({ "kind": "assign", "rule": 0, "node": 2, "to": { "symbol": { "symbol": 1 } } }))
        .await["state"]
        .clone();
    assert_eq!(state["rules"][0]["name"], "carve");
    assert_eq!(state["rules"][0]["weight"], 2.0);
    assert_eq!(state["symbols"][1]["name"], "Floor");
    assert_eq!(state["symbols"][1]["color"], "#336699");
    assert_eq!(state["symbols"][0]["rules"], json!([0]));
    let floor = &state["rules"][0]["tree"]["children"][1];
    assert_eq!(
        (floor["node"].clone(), floor["kind"].clone()),
        (json!(2), json!("symbol"))
    );
    let part = &state["edit"]["parts"][1];
    assert_eq!(part["color"], "#336699");
    assert!(part["anchor"]["from"].is_array());

    // The anchor turns round its face and comes back after four turns.
    let anchor = floor["anchor"].clone();
    let mut turned = Value::Null;
    for _ in 0..4 {
        turned = studio
            .act(json!({ "kind": "turn_anchor", "rule": 0, "node": 2, "clockwise": true }))
            .await["state"]["rules"][0]["tree"]["children"][1]["anchor"]
            .clone();
    }
    assert_eq!(turned, anchor);

    // The anchor moves to another face of the sub-shape; one that is not there is refused.
    let moved = studio
        .act(json!({ "kind": "place_anchor", "rule": 0, "node": 2, "face": 0, "corner": 1 }))
        .await["state"]["rules"][0]["tree"]["children"][1]["anchor"]
        .clone();
    assert_eq!(moved, json!([0, 1]));
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action":
                { "kind": "place_anchor", "rule": 0, "node": 2, "face": 9, "corner": 0 } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        error["error"],
        "the anchor (face 9, corner 0) is not on the shape"
    );
    let (status, _) = studio
        .post("/api/topo/undo", json!({ "path": studio.path() }))
        .await;
    assert_eq!(status, StatusCode::OK);

    // The anchor preview: the Floor symbol has no rule, so one generation leaves it whole.
    let (status, preview) = studio
        .post(
            "/api/topo/preview",
            json!({ "path": studio.path(), "rule": 0, "node": 2 }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{preview}");
    assert_eq!(
        (preview["terminals"].clone(), preview["triangles"].clone()),
        (json!(1), json!(12))
    );

    // 3-point cut through the rest (node 1, 4 × 3 × 4 from y = 1): the diagonal plane x = z
    // through the corners (0, 4, 0), (0, 1, 0) and (4, 1, 4) makes two triangular prisms.
    let answer = studio
        .act(json!({ "kind": "three_point_cut", "rule": 0, "points": [
            { "node": 1, "face": 0, "corner": 2, "fraction": 0.0 },
            { "node": 1, "face": 0, "corner": 3, "fraction": 0.0 },
            { "node": 1, "face": 1, "corner": 3, "fraction": 0.0 }] }))
        .await;
    let nodes = answer["made"]["nodes"].as_array().unwrap().clone();
    assert_eq!(nodes.len(), 2, "{answer}");
    let faces: Vec<usize> = answer["state"]["edit"]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| nodes.contains(&p["node"]))
        .map(|p| p["faces"].as_array().unwrap().len())
        .collect();
    assert_eq!(faces, [5, 5]);

    // A sub-shape becomes a new symbol of its own shape (a triangular prism), assigned to it.
    let answer = studio
        .act(json!({ "kind": "symbol_from_leaf", "rule": 0, "node": nodes[0].clone(), "name": "Wedge" }))
        .await;
    assert_eq!(answer["made"]["index"], 2);
    let wedge = &answer["state"]["symbols"][2];
    assert_eq!(
        (
            wedge["name"].clone(),
            wedge["vertices"].clone(),
            wedge["faces"].clone()
        ),
        (json!("Wedge"), json!(6), json!(5))
    );
    studio
        .post("/api/topo/undo", json!({ "path": studio.path() }))
        .await;
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action": { "kind": "set_weight", "rule": 0, "weight": 0.0 } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        error["error"],
        "a rule weight must be a positive number, not 0"
    );

    // Global face cut over both prisms: each is cut in two.
    let answer = studio
        .act(
            json!({ "kind": "face_cut", "rule": 0, "node": nodes[0], "face": 0,
            "distance": 1.0, "global": true }),
        )
        .await;
    assert_eq!(answer["made"]["nodes"].as_array().unwrap().len(), 4);

    // Hiding a sub-shape is the view's: it is flagged and not an undo step.
    let (status, state) = studio
        .post(
            "/api/topo/visibility",
            json!({ "path": studio.path(), "rule": 0, "node": 2, "visible": false, "view": { "rule": 0 } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    let hidden: Vec<&Value> = state["edit"]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["hidden"] == true)
        .map(|p| &p["node"])
        .collect();
    assert_eq!(hidden, [&json!(2)]);

    // Deleting a symbol another rule assigns is refused; deleting the rule first lets it go.
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action": { "kind": "delete_symbol", "symbol": 1 } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        error["error"],
        "symbol 'Floor' is used by rule 'carve' of symbol 'Box'; assign something else there first"
    );
    studio
        .act(json!({ "kind": "delete_rule", "rule": 0 }))
        .await;
    let state = studio
        .act(json!({ "kind": "delete_symbol", "symbol": 1 }))
        .await["state"]
        .clone();
    assert_eq!(state["symbols"].as_array().unwrap().len(), 1);
    assert_eq!(state["rules"], json!([]));
}

#[tokio::test]
async fn the_tester_generates_the_saved_pyramid() {
    let project = shapegram_topo::demos::mayan_pyramid().unwrap();
    let studio = Studio::new(&project.to_json());
    studio.open().await;
    let test = |generations: u32| json!({ "path": studio.path(), "symbol": 0, "seed": 7, "generations": generations });
    let (status, one) = studio.post("/api/topo/test", test(1)).await;
    assert_eq!(status, StatusCode::OK, "{one}");
    // One tier: the slab and the stairs are terminal, the smaller pyramid is not.
    assert_eq!(
        (
            one["generation"].clone(),
            one["terminals"].clone(),
            one["non_terminals"].clone()
        ),
        (json!(1), json!(2), json!(1))
    );
    let (_, three) = studio.post("/api/topo/test", test(3)).await;
    assert_eq!(
        (three["terminals"].clone(), three["non_terminals"].clone()),
        (json!(6), json!(1))
    );
    let triangles: usize = three["parts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["positions"].as_array().unwrap().len() / 9)
        .sum();
    assert_eq!(json!(triangles), three["triangles"]);
    // Generating is deterministic: the same request, the same model.
    let (_, again) = studio.post("/api/topo/test", test(3)).await;
    assert_eq!(again, three);
    let (status, error) = studio.post("/api/topo/test", test(1000)).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(error["error"], "at most 64 generations, not 1000");
}

#[tokio::test]
async fn bad_requests_get_reasons_and_other_sites_are_refused() {
    let studio = Studio::new("{ not json");
    let path = studio.path();
    let (status, error) = studio.post("/api/topo/open", json!({ "path": path })).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert!(
        error["error"]
            .as_str()
            .unwrap()
            .starts_with(&format!("{path}: ")),
        "{error}"
    );

    let studio = Studio::new("");
    let (status, error) = studio
        .post("/api/topo/state", json!({ "path": studio.path() }))
        .await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert_eq!(
        error["error"],
        format!("`{}` is not open: POST /api/topo/open first", studio.path())
    );
    let other = studio.project.with_file_name("notes.json");
    let (status, _) = studio
        .post(
            "/api/topo/open",
            json!({ "path": other.display().to_string() }),
        )
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    let (status, error) = studio
        .send(
            "/api/topo/open",
            Some("http://evil.example"),
            json!({ "path": studio.path() }),
        )
        .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    assert!(error["error"].as_str().unwrap().contains("evil.example"));
    studio.open().await;
    for (action, message) in [
        (
            json!({ "kind": "add_rule", "symbol": 5, "name": "r" }),
            "there is no symbol 5",
        ),
        (
            json!({ "kind": "add_symbol", "name": " " }),
            "a symbol name must be 1 to 200 characters, not blank",
        ),
        (
            json!({ "kind": "add_symbol", "name": "A", "size": [1, -1, 1] }),
            "a box symbol's sides must be positive numbers up to 1000000",
        ),
        (
            json!({ "kind": "set_color", "symbol": 0, "color": "red" }),
            "`red` is not a colour (#rrggbb)",
        ),
    ] {
        let (status, error) = studio
            .post(
                "/api/topo/action",
                json!({ "path": studio.path(), "action": action }),
            )
            .await;
        assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{error}");
        assert_eq!(error["error"], message);
    }
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action": { "kind": "explode" } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        error["error"].as_str().unwrap().contains("explode"),
        "{error}"
    );
    // Nothing was saved: the file is as blank as it was.
    assert_eq!(std::fs::read_to_string(&studio.project).unwrap(), "");
}

#[tokio::test]
async fn the_editor_page_and_its_bundle_are_served() {
    let studio = Studio::new("");
    for (uri, kind, marker) in [
        (
            "/topo?path=/x.sgproj.json",
            "text/html; charset=utf-8",
            "/assets/topo.js",
        ),
        (
            "/assets/topo.js",
            "text/javascript; charset=utf-8",
            "/api/topo/",
        ),
        ("/assets/topo.css", "text/css; charset=utf-8", "#toolbar"),
    ] {
        let response = studio
            .router
            .clone()
            .oneshot(
                Request::builder()
                    .uri(uri)
                    .header("host", "127.0.0.1:7370")
                    .body(Body::empty())
                    .unwrap(),
            )
            .await
            .unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{uri}");
        assert_eq!(response.headers()["content-type"], kind, "{uri}");
        let bytes = response.into_body().collect().await.unwrap().to_bytes();
        assert!(String::from_utf8_lossy(&bytes).contains(marker), "{uri}");
    }
}

#[tokio::test]
async fn a_version_1_project_opens_and_is_saved_as_version_2() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let version_1 = std::fs::read_to_string(format!(
        "{root}/crates/shapegram-topo/tests/version1/topo_pyramid.sgproj.json"
    ))
    .unwrap();
    assert!(version_1.contains("\"version\": 1,"));
    let studio = Studio::new(&version_1);
    let state = studio.open().await;
    let names: Vec<&str> = state["symbols"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["Pyramid", "Stone", "Stairs"]);
    assert_eq!(state["dirty"], false);
    let (status, written) = studio
        .post("/api/topo/save", json!({ "path": studio.path() }))
        .await;
    assert_eq!(status, StatusCode::OK, "{written}");
    // docs/topo.md: saving always writes version 2; nothing else of the project changes, so
    // the file is the committed example, which is the same project written by this build.
    let saved = std::fs::read_to_string(&studio.project).unwrap();
    let example =
        std::fs::read_to_string(format!("{root}/examples/topo_pyramid.sgproj.json")).unwrap();
    assert_eq!(saved, example);
    assert_eq!(
        saved,
        version_1.replacen("\"version\": 1,", "\"version\": 2,", 1)
    );
}

/// The triangles of a generated model, each as its corners rounded to 1e-4 and turned to start
/// at its smallest corner (so the winding is kept), sorted.
fn triangles(generated: &Value) -> Vec<[[i64; 3]; 3]> {
    let mut all = Vec::new();
    for part in generated["parts"].as_array().unwrap() {
        let numbers: Vec<i64> = part["positions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| (v.as_f64().unwrap() * 1e4).round() as i64)
            .collect();
        for t in numbers.chunks(9) {
            let corners = [[t[0], t[1], t[2]], [t[3], t[4], t[5]], [t[6], t[7], t[8]]];
            let first = (0..3).min_by_key(|&i| corners[i]).unwrap();
            all.push([0, 1, 2].map(|k| corners[(first + k) % 3]));
        }
    }
    all.sort();
    all
}

#[tokio::test]
async fn the_anchor_preview_is_what_the_interpreter_makes_of_the_sub_shape() {
    let project = shapegram_topo::demos::mayan_pyramid().unwrap();
    let inner = project.rules[0]
        .tree
        .nodes()
        .iter()
        .position(|n| matches!(n.kind, NodeKind::Leaf(Assignment::Symbol { symbol: 0, .. })))
        .unwrap();
    let studio = Studio::new(&project.to_json());
    studio.open().await;
    let (status, preview) = studio
        .post(
            "/api/topo/preview",
            json!({ "path": studio.path(), "rule": 0, "node": inner }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{preview}");
    assert_eq!(
        (
            preview["terminals"].clone(),
            preview["non_terminals"].clone()
        ),
        (json!(2), json!(1))
    );
    // The interpreter from the prototype: after one generation the inner pyramid is the only
    // `Pyramid`; the second generation replaces it by exactly what the preview shows.
    let test = |generations: u32| json!({ "path": studio.path(), "symbol": 0, "seed": 0, "generations": generations });
    let (_, one) = studio.post("/api/topo/test", test(1)).await;
    let (_, two) = studio.post("/api/topo/test", test(2)).await;
    let mut one_without_inner = one.clone();
    one_without_inner["parts"] = Value::Array(
        one["parts"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["name"] != "Pyramid")
            .cloned()
            .collect(),
    );
    let mut expected = triangles(&one_without_inner);
    expected.extend(triangles(&preview));
    expected.sort();
    assert_eq!(triangles(&two), expected);
    assert_eq!(triangles(&preview).len(), 12 + 8 + 12);
}

#[tokio::test]
async fn the_symmetric_cut_makes_equal_outer_parts_and_undoes_in_one_step() {
    let studio = Studio::new("");
    studio.open().await;
    studio
        .act(json!({ "kind": "add_symbol", "name": "Wall", "size": [10, 4, 1] }))
        .await;
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "bays" }))
        .await;
    // Face 0 is the box's side at x = 0: margins of 0.25 × 10 at both ends.
    let answer = studio
        .act(json!({ "kind": "symmetric_cut", "rule": 0, "node": 0, "face": 0, "margin": 0.25 }))
        .await;
    let made = answer["made"]["nodes"].as_array().unwrap().clone();
    assert_eq!(made.len(), 3);
    let parts = answer["state"]["edit"]["parts"].as_array().unwrap();
    let span = |node: &Value| {
        let part = parts.iter().find(|p| &p["node"] == node).unwrap();
        let xs: Vec<f64> = part["faces"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|f| f.as_array().unwrap().iter().map(|p| p[0].as_f64().unwrap()))
            .collect();
        (
            xs.iter().cloned().fold(f64::MAX, f64::min),
            xs.iter().cloned().fold(f64::MIN, f64::max),
        )
    };
    assert_eq!(
        made.iter().map(span).collect::<Vec<_>>(),
        [(0.0, 2.5), (2.5, 7.5), (7.5, 10.0)]
    );
    let body = json!({ "path": studio.path(), "view": { "rule": 0 } });
    let (_, state) = studio.post("/api/topo/undo", body.clone()).await;
    assert_eq!(state["edit"]["parts"].as_array().unwrap().len(), 1);
    let (_, state) = studio.post("/api/topo/redo", body).await;
    assert_eq!(state["edit"]["parts"].as_array().unwrap().len(), 3);
    let (status, error) = studio
        .post(
            "/api/topo/action",
            json!({ "path": studio.path(), "action":
                { "kind": "symmetric_cut", "rule": 0, "node": 1, "face": 0, "margin": 0.5 } }),
        )
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(
        error["error"],
        "the margin 0.5 must lie strictly between 0 and 0.5 of the height"
    );
}

#[tokio::test]
async fn a_face_gets_a_material_and_a_cut_keeps_an_absolute_distance() {
    let studio = Studio::new("");
    studio.open().await;
    studio
        .act(json!({ "kind": "add_symbol", "name": "Block", "size": [4, 3, 4] }))
        .await;
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "walls" }))
        .await;
    // Face 1 is the side at x = 4: a wall 0.3 m thick inside it, in metres.
    let answer = studio
        .act(json!({ "kind": "face_cut", "rule": 0, "node": 0, "face": 1, "distance": 0.3, "absolute": true }))
        .await;
    let wall = answer["made"]["nodes"][0].clone();
    let brick =
        json!({ "name": "brick", "color": "#aa5533", "texture": "brick.png", "tile": [0.5, 0.25] });
    let answer = studio
        .act(json!({ "kind": "face_material", "rule": 0, "node": wall, "face": 1, "material": brick }))
        .await;
    assert_eq!(answer["made"]["index"], 0);
    let state = &answer["state"];
    assert_eq!(
        state["materials"],
        json!([{ "name": "brick", "color": "#aa5533", "surface": "#aa5533",
                 "texture": "brick.png", "tile": [0.5, 0.25] }])
    );
    let part = state["edit"]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["node"] == wall)
        .unwrap();
    let mut expected = vec![Value::Null; 6];
    expected[1] = json!(0);
    assert_eq!(part["face_materials"], Value::Array(expected));
    // The same name again updates the material rather than adding one.
    let answer = studio
        .act(
            json!({ "kind": "face_material", "rule": 0, "node": wall, "face": 0,
                     "material": { "name": "brick", "color": "#bb6644", "tile": [1, 1] } }),
        )
        .await;
    assert_eq!(answer["state"]["materials"].as_array().unwrap().len(), 1);
    assert_eq!(answer["state"]["materials"][0]["color"], "#bb6644");
    studio
        .post("/api/topo/save", json!({ "path": studio.path() }))
        .await;
    let saved = studio.saved();
    let rule = &saved.rules[0];
    assert_eq!(
        rule.tree.nodes()[0].offset.map(|o| (o.face, o.distance)),
        Some((1, 0.3))
    );
    let node = &rule.tree.nodes()[wall.as_u64().unwrap() as usize];
    assert_eq!(node.face_materials[..2], [Some(0), Some(0)]);
    assert!(
        std::fs::read_to_string(&studio.project)
            .unwrap()
            .contains("\"version\": 2")
    );
    // Undo takes back the second material step alone.
    let body = json!({ "path": studio.path(), "view": { "rule": 0 } });
    let (_, state) = studio.post("/api/topo/undo", body).await;
    assert_eq!(state["materials"][0]["color"], "#aa5533");

    for (action, reason) in [
        (
            json!({ "kind": "face_cut", "rule": 0, "node": 1, "face": 1, "distance": 0.3, "absolute": true, "global": true }),
            "a cut at an absolute distance cuts one sub-shape, not globally",
        ),
        (
            json!({ "kind": "face_material", "rule": 0, "node": 1, "face": 0,
                    "material": { "name": "x", "color": "red", "tile": [1, 1] } }),
            "`red` is not a colour (#rrggbb)",
        ),
    ] {
        let (status, error) = studio
            .post(
                "/api/topo/action",
                json!({ "path": studio.path(), "action": action }),
            )
            .await;
        assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
        assert_eq!(error["error"], reason);
    }
}

#[tokio::test]
async fn the_tester_model_is_exported_as_glb_beside_the_project() {
    let project = shapegram_topo::demos::mayan_pyramid().unwrap();
    let studio = Studio::new(&project.to_json());
    studio.open().await;
    let (status, written) = studio
        .post(
            "/api/topo/export",
            json!({ "path": studio.path(), "symbol": 0, "seed": 3, "generations": 3 }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{written}");
    let glb = studio.project.with_file_name("pyramid.glb");
    assert_eq!(written["path"], glb.display().to_string());
    let bytes = std::fs::read(&glb).unwrap();
    assert_eq!(written["bytes"], bytes.len());
    assert_eq!(&bytes[..4], b"glTF");
    // The same model as the tester's: its triangles, counted from the file.
    let model = shapegram_export::load(&glb).unwrap();
    let (_, tested) = studio
        .post(
            "/api/topo/test",
            json!({ "path": studio.path(), "symbol": 0, "seed": 3, "generations": 3 }),
        )
        .await;
    let faces: usize = model.parts.iter().map(|p| p.mesh.face_count()).sum();
    assert_eq!(json!(faces), tested["triangles"]);
}

/// A polygon's corners rounded to 1e-9 and sorted, for comparing sections.
fn corners(polygon: &Value) -> Vec<[i64; 3]> {
    let mut corners: Vec<[i64; 3]> = polygon
        .as_array()
        .unwrap()
        .iter()
        .map(|p| std::array::from_fn(|i| (p[i].as_f64().unwrap() * 1e9).round() as i64))
        .collect();
    corners.sort();
    corners
}

#[tokio::test]
async fn a_pending_cut_answers_its_exact_sections_and_changes_nothing() {
    let studio = Studio::new("");
    studio.open().await;
    studio
        .act(json!({ "kind": "add_symbol", "name": "Steps" }))
        .await;
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "slabs" }))
        .await;
    // Face 3 is the top: three cuts from it make four slabs; pending, they are three squares
    // across the cube.
    let path = studio.path();
    let multi = json!({ "kind": "multi_cut", "rule": 0, "node": 0, "face": 3, "cuts": 3 });
    let (status, pending) = studio
        .post(
            "/api/topo/sections",
            json!({ "path": path, "action": multi }),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{pending}");
    let square = |y: i64| {
        let mut c = vec![
            [0, y, 0],
            [1_000_000_000, y, 0],
            [1_000_000_000, y, 1_000_000_000],
            [0, y, 1_000_000_000],
        ];
        c.sort();
        c
    };
    let mut squares: Vec<_> = pending["sections"]
        .as_array()
        .unwrap()
        .iter()
        .map(corners)
        .collect();
    squares.sort();
    assert_eq!(
        squares,
        [
            square(250_000_000),
            square(500_000_000),
            square(750_000_000)
        ]
    );
    let answer = studio.act(multi).await;
    let top = answer["made"]["nodes"][0].clone();
    let undo = answer["state"]["undo"].clone();
    let part = answer["state"]["edit"]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["node"] == top)
        .unwrap();
    let front = part["normals"]
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n[2].as_f64().unwrap() > 0.99)
        .unwrap();
    // A global face cut half way into the top slab's front face crosses all four slabs: four
    // rectangles at z = 0.5, where the face alone would give one.
    let global = json!({ "kind": "face_cut", "rule": 0, "node": top, "face": front, "distance": 0.5, "global": true });
    let (_, pending) = studio
        .post(
            "/api/topo/sections",
            json!({ "path": path, "action": global }),
        )
        .await;
    let sections = pending["sections"].as_array().unwrap();
    assert_eq!(sections.len(), 4);
    for section in sections {
        let c = corners(section);
        assert!(c.iter().all(|p| p[2] == 500_000_000), "{c:?}");
        assert_eq!(c.len(), 4);
    }
    let (_, pending) = studio
        .post(
            "/api/topo/sections",
            json!({ "path": path, "action": { "kind": "face_cut", "rule": 0, "node": top, "face": front, "distance": 0.5 } }),
        )
        .await;
    assert_eq!(pending["sections"].as_array().unwrap().len(), 1);
    // Nothing was cut: the session is as the multi-cut left it.
    let (_, state) = studio
        .post(
            "/api/topo/state",
            json!({ "path": path, "view": { "rule": 0 } }),
        )
        .await;
    assert_eq!(
        (
            state["undo"].clone(),
            state["edit"]["parts"].as_array().unwrap().len()
        ),
        (undo, 4)
    );
    // A cut that would be refused has no sections and says why; a step that is no cut is a
    // bad request.
    let (status, pending) = studio
        .post(
            "/api/topo/sections",
            json!({ "path": path, "action": { "kind": "prism_cut", "rule": 0, "node": top, "face": 3, "fraction": 1.5 } }),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        pending,
        json!({ "sections": [],
                "refused": "a prism cut's fraction 1.5 must lie strictly between 0 and 1" })
    );
    let (status, error) = studio
        .post(
            "/api/topo/sections",
            json!({ "path": path, "action": { "kind": "rename_rule", "rule": 0, "name": "x" } }),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(error["error"], "only a cut has sections");
}

#[tokio::test]
async fn a_textured_face_has_texture_coordinates_and_its_image_is_served() {
    let studio = Studio::new("");
    studio.open().await;
    studio
        .act(json!({ "kind": "add_symbol", "name": "Wall", "size": [4, 3, 1] }))
        .await;
    studio
        .act(json!({ "kind": "add_rule", "symbol": 0, "name": "bricks" }))
        .await;
    let image = b"\x89PNG\r\n\x1a\n not really an image".to_vec();
    let folder = studio.project.parent().unwrap().to_path_buf();
    std::fs::create_dir(folder.join("textures")).unwrap();
    std::fs::write(folder.join("textures/brick.png"), &image).unwrap();
    // Face 5 is the front (+z), 4 × 3 m: in tiles of 0.5 × 0.25 m, u runs along x and v up y.
    let brick = json!({ "name": "brick", "texture": "textures/brick.png", "tile": [0.5, 0.25] });
    let answer = studio
        .act(json!({ "kind": "face_material", "rule": 0, "node": 0, "face": 5, "material": brick }))
        .await;
    let part = &answer["state"]["edit"]["parts"][0];
    let positions = part["positions"].as_array().unwrap();
    let uvs = part["uvs"].as_array().unwrap();
    assert_eq!(uvs.len(), positions.len() / 3 * 2);
    let faces = part["triangle_faces"].as_array().unwrap();
    for (t, face) in faces.iter().enumerate() {
        for k in 0..3 {
            let corner = 3 * t + k;
            let (u, v) = (
                uvs[2 * corner].as_f64().unwrap(),
                uvs[2 * corner + 1].as_f64().unwrap(),
            );
            if face == 5 {
                let (x, y) = (
                    positions[3 * corner].as_f64().unwrap(),
                    positions[3 * corner + 1].as_f64().unwrap(),
                );
                assert_eq!((u, v), (x / 0.5, y / 0.25));
            } else {
                assert_eq!((u, v), (0.0, 0.0));
            }
        }
    }
    let get = |query: String| {
        let router = studio.router.clone();
        async move {
            let response = router
                .oneshot(
                    Request::builder()
                        .uri(format!("/api/topo/texture?{query}"))
                        .header("host", "127.0.0.1:7370")
                        .body(Body::empty())
                        .unwrap(),
                )
                .await
                .unwrap();
            let status = response.status();
            let kind = response.headers().get("content-type").cloned();
            let bytes = response.into_body().collect().await.unwrap().to_bytes();
            (status, kind, bytes.to_vec())
        }
    };
    let project = studio.path().replace('/', "%2F");
    let (status, kind, bytes) = get(format!("path={project}&texture=textures%2Fbrick.png")).await;
    assert_eq!((status, bytes), (StatusCode::OK, image));
    assert_eq!(kind.unwrap(), "image/png");
    // Only files inside the project's folder, and only those that exist.
    for texture in [
        "..%2Fpyramid.sgproj.json",
        "%2Fetc%2Fpasswd",
        "textures%2Fnone.png",
    ] {
        let (status, _, _) = get(format!("path={project}&texture={texture}")).await;
        assert_eq!(status, StatusCode::NOT_FOUND, "{texture}");
    }
}
