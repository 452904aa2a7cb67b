//! Publishing: checked, immutable, consecutive versions; the rule index; friends.

use crate::common;

use axum::http::{Method, StatusCode};
use common::{App, CHAIR, WOOD};
use serde_json::json;
use sha2::{Digest, Sha256};

fn sha256(text: &str) -> String {
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

async fn versions_are_immutable_and_numbered(app: App) {
    let ana = app.user("ana").await;
    let (status, first) = app.publish(&ana, "ana/paint", WOOD, None).await;
    assert_eq!(status, StatusCode::CREATED, "{first}");
    assert_eq!(first["version"], 1);
    assert_eq!(first["sha256"], json!(sha256(WOOD)));
    assert_eq!(first["rules"], 1);

    let v1 = app.get("/api/v1/grammars/ana/paint/versions/1", None).await;
    assert_eq!(v1.0, StatusCode::OK);

    // Publishing the same or another text makes version n+1; version 1 never changes.
    let second_text = format!("{WOOD}fulfills(metallic) --> color(\"#9aa4ad\")\n");
    let (_, second) = app.publish(&ana, "ana/paint", &second_text, None).await;
    assert_eq!(second["version"], 2);
    let (_, third) = app.publish(&ana, "ANA/Paint", WOOD, None).await;
    assert_eq!(third["version"], 3, "names are canonical");
    assert_eq!(third["sha256"], first["sha256"]);

    assert_eq!(
        app.get("/api/v1/grammars/ana/paint/versions/1", None).await,
        v1
    );
    let (_, v1) = v1;
    assert_eq!(v1["text"], WOOD);
    assert_eq!(v1["sha256"], json!(sha256(WOOD)));
    assert_eq!(
        (&v1["owner"], &v1["name"], &v1["version"]),
        (&json!("ana"), &json!("paint"), &json!(1))
    );
    let (_, v2) = app.get("/api/v1/grammars/ana/paint/versions/2", None).await;
    assert_eq!(v2["text"], json!(second_text));
    assert_eq!(v2["sha256"], json!(sha256(&second_text)));

    let (status, versions) = app.get("/api/v1/grammars/ana/paint/versions", None).await;
    assert_eq!(status, StatusCode::OK);
    let numbers: Vec<i64> = versions
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["version"].as_i64().unwrap())
        .collect();
    assert_eq!(numbers, [1, 2, 3]);
    let (_, grammar) = app.get("/api/v1/grammars/ana/paint", None).await;
    assert_eq!(grammar["latest_version"], 3);
    assert_eq!(grammar["visibility"], "public");
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint/versions/4", None)
            .await
            .0,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint/versions/0", None)
            .await
            .0,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint/versions/x", None)
            .await
            .0,
        StatusCode::NOT_FOUND
    );
}

async fn compile_errors_come_back_with_lines_and_columns(app: App) {
    let ana = app.user("ana").await;
    let text =
        "fulfills(wooden) --> color(\"#8b5a2b\")\n\nfulfills(metal) --> split(x) { ~1 : +a\n";
    let (status, body) = app.publish(&ana, "ana/broken", text, None).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
    assert!(body["error"].as_str().unwrap().contains("does not compile"));
    let first = &body["diagnostics"][0];
    assert_eq!(first["severity"], "error");
    assert!(first["message"].as_str().unwrap().len() > 3);
    // The unclosed `{` of line 3.
    assert_eq!(
        (&first["line"], &first["column"]),
        (&json!(3), &json!(30)),
        "{body}"
    );

    // Compiler errors (not only the parser's): an unknown function, with its place.
    let text = "fulfills(wooden) -->\n    color(nosuch(1))\n";
    let (status, body) = app.publish(&ana, "ana/broken", text, None).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");
    assert_eq!(
        (
            &body["diagnostics"][0]["line"],
            &body["diagnostics"][0]["column"]
        ),
        (&json!(2), &json!(11)),
        "{body}"
    );

    // A symbol grammar is not a goal grammar.
    let (status, body) = app
        .publish(&ana, "ana/lot", "Lot --> extrude(10) Mass", None)
        .await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY, "{body}");

    // Nothing was stored.
    assert_eq!(
        app.get("/api/v1/grammars/ana/broken", Some(&ana)).await.0,
        StatusCode::NOT_FOUND
    );
    assert_eq!(app.get("/api/v1/grammars", Some(&ana)).await.1, json!([]));
}

async fn the_rule_index_holds_goals_tags_attributes_and_negations(app: App) {
    let ana = app.user("ana").await;
    // The paper's notation is detected too.
    let (status, body) = app.publish(&ana, "ana/chair", CHAIR, Some("public")).await;
    assert_eq!(status, StatusCode::CREATED, "{body}");
    let (status, rules) = app
        .get("/api/v1/grammars/ana/chair/versions/1/rules", None)
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        rules,
        json!([
            {"index": 0, "positive": ["g:chair"], "negative": [], "local": false, "conditional": false},
            {"index": 1, "positive": ["a:Leg.Size", "g:support", "t:chair"], "negative": [], "local": false, "conditional": false},
            {"index": 2, "positive": ["a:Leg.Size", "lg:split-legs", "t:chair"], "negative": [], "local": true, "conditional": false},
            {"index": 3, "positive": ["g:lean", "t:chair"], "negative": [["a:Cushion"]], "local": false, "conditional": false},
        ])
    );
}

async fn concurrent_publishes_become_consecutive_versions(app: App) {
    let ana = app.user("ana").await;
    let mut tasks = Vec::new();
    for i in 0..8 {
        let (app, ana) = (app.clone(), ana.clone());
        tasks.push(tokio::spawn(async move {
            let text = format!("{WOOD}// copy {i}\n");
            let (status, body) = app.publish(&ana, "ana/paint", &text, None).await;
            assert_eq!(status, StatusCode::CREATED, "{body}");
            (body["version"].as_i64().unwrap(), text)
        }));
    }
    let mut published = Vec::new();
    for t in tasks {
        published.push(t.await.unwrap());
    }
    published.sort();
    let numbers: Vec<i64> = published.iter().map(|(v, _)| *v).collect();
    assert_eq!(numbers, (1..=8).collect::<Vec<_>>());
    for (v, text) in &published {
        let (_, body) = app
            .get(&format!("/api/v1/grammars/ana/paint/versions/{v}"), None)
            .await;
        assert_eq!(body["text"], json!(text));
    }
}

async fn visibility_changes_with_a_publish_and_friendship_needs_acceptance(app: App) {
    let ana = app.user("ana").await;
    let bo = app.user("bo").await;
    app.publish(&ana, "ana/paint", WOOD, Some("friends")).await;
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&bo)).await.0,
        StatusCode::NOT_FOUND
    );

    // A request alone shows nothing.
    let (status, _) = app
        .call(Method::POST, "/api/v1/friends/ana", Some(&bo), None)
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&bo)).await.0,
        StatusCode::NOT_FOUND
    );
    let (_, friends) = app.get("/api/v1/friends", Some(&ana)).await;
    assert_eq!(
        friends,
        json!({"friends": [], "incoming": ["bo"], "outgoing": []})
    );
    // Asking back accepts.
    let (_, state) = app
        .call(Method::POST, "/api/v1/friends/bo", Some(&ana), None)
        .await;
    assert_eq!(state["state"], "friends");
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&bo)).await.0,
        StatusCode::OK
    );
    let (_, friends) = app.get("/api/v1/friends", Some(&bo)).await;
    assert_eq!(
        friends,
        json!({"friends": ["ana"], "incoming": [], "outgoing": []})
    );

    // Private from version 2 on hides every version from the friend.
    app.publish(&ana, "ana/paint", WOOD, Some("private")).await;
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint/versions/1", Some(&bo))
            .await
            .0,
        StatusCode::NOT_FOUND
    );
    // Omitted visibility keeps it.
    app.publish(&ana, "ana/paint", WOOD, None).await;
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&ana)).await.1["visibility"],
        "private"
    );

    // Unfriending ends what friends see.
    app.publish(&ana, "ana/paint", WOOD, Some("friends")).await;
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&bo)).await.0,
        StatusCode::OK
    );
    let (status, _) = app
        .call(Method::DELETE, "/api/v1/friends/ana", Some(&bo), None)
        .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    assert_eq!(
        app.get("/api/v1/grammars/ana/paint", Some(&bo)).await.0,
        StatusCode::NOT_FOUND
    );
    // No self-friendship, no unknown accounts.
    assert_eq!(
        app.call(Method::POST, "/api/v1/friends/ana", Some(&ana), None)
            .await
            .0,
        StatusCode::NOT_FOUND
    );
    assert_eq!(
        app.call(Method::POST, "/api/v1/friends/nobody", Some(&ana), None)
            .await
            .0,
        StatusCode::NOT_FOUND
    );
}

/// Two accounts asking each other at the same moment become friends, as they do one after the
/// other: one request is recorded, the other finds it and accepts.
async fn crossing_friend_requests_make_friends(app: App) {
    let mut pairs = Vec::new();
    for i in 0..6 {
        let (a, b) = (format!("a{i}"), format!("b{i}"));
        let (ta, tb) = (app.user(&a).await, app.user(&b).await);
        pairs.push(((a, ta), (b, tb)));
    }
    let mut tasks = Vec::new();
    for ((a, ta), (b, tb)) in &pairs {
        for (to, token) in [(b, ta), (a, tb)] {
            let (app, uri, token) = (app.clone(), format!("/api/v1/friends/{to}"), token.clone());
            tasks.push(tokio::spawn(async move {
                let (status, body) = app.call(Method::POST, &uri, Some(&token), None).await;
                assert_eq!(status, StatusCode::OK, "{body}");
                body["state"].as_str().unwrap().to_owned()
            }));
        }
    }
    let mut states = Vec::new();
    for task in tasks {
        states.push(task.await.unwrap());
    }
    for (pair, answers) in pairs.iter().zip(states.chunks(2)) {
        let mut answers = answers.to_vec();
        answers.sort();
        assert_eq!(answers, ["friends", "requested"], "{}", pair.0.0);
        let ((a, ta), (b, _)) = pair;
        let (_, friends) = app.get("/api/v1/friends", Some(ta)).await;
        assert_eq!(
            friends,
            json!({"friends": [b], "incoming": [], "outgoing": []}),
            "{a}"
        );
    }
}

on_both_backends!(
    versions_are_immutable_and_numbered,
    compile_errors_come_back_with_lines_and_columns,
    the_rule_index_holds_goals_tags_attributes_and_negations,
    concurrent_publishes_become_consecutive_versions,
    visibility_changes_with_a_publish_and_friendship_needs_acceptance,
    crossing_friend_requests_make_friends,
);
