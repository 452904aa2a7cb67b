//! Renaming grammars and reading versions by the hash of their text.

use crate::common;

use axum::http::{Method, StatusCode};
use common::{App, WOOD};
use serde_json::json;

fn sha256(text: &str) -> String {
    shapegram_server::tokens::sha256_hex(text.as_bytes())
}

async fn a_renamed_grammar_keeps_its_versions_and_answers_queries_under_its_new_name(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/wood", WOOD, None).await;
    app.publish(
        &ana,
        "ana/oak",
        "fulfills(oak) --> color(\"#806040\")",
        None,
    )
    .await;
    let rename = async |from: &str, to: &str| {
        let uri = format!("/api/v1/grammars/ana/{from}/rename");
        app.call(Method::POST, &uri, Some(&ana), Some(json!({ "name": to })))
            .await
    };
    let (status, body) = rename("wood", "Timber").await;
    assert_eq!(status, StatusCode::OK, "{body}");
    assert_eq!(
        (&body["name"], &body["latest_version"]),
        (&json!("Timber"), &json!(1))
    );
    let (status, _) = app.get("/api/v1/grammars/ana/wood", None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, version) = app
        .get("/api/v1/grammars/ana/timber/versions/1", None)
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(version["text"], WOOD);
    assert_eq!(version["sha256"], sha256(WOOD));
    // Queries find it by its goal, under its new name.
    let (_, found) = app
        .call(
            Method::POST,
            "/api/v1/queries",
            None,
            Some(json!({"queries": [{"goals": ["wooden"]}]})),
        )
        .await;
    assert_eq!(found["grammars"][0]["name"], "Timber");
    // A name taken, spelt otherwise, is a conflict; a bad one a bad request.
    let (status, body) = rename("timber", "OAK").await;
    assert_eq!(status, StatusCode::CONFLICT, "{body}");
    assert_eq!(body["error"], "ana/OAK exists already");
    let (status, _) = rename("timber", "9lives").await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    // Another spelling of its own name is fine.
    let (status, body) = rename("timber", "TIMBER").await;
    assert_eq!((status, &body["name"]), (StatusCode::OK, &json!("TIMBER")));
}

async fn texts_are_found_by_their_hash_by_whoever_may_see_one_of_their_versions(app: App) {
    let ana = app.user("ana").await;
    let bob = app.user("bob").await;
    let secret = "fulfills(secret) --> color(\"#123456\")\n";
    app.publish(&ana, "ana/hidden", secret, Some("private"))
        .await;
    let uri = format!("/api/v1/texts/{}", sha256(secret));
    let (status, _) = app.get(&uri, Some(&bob)).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, _) = app.get(&uri, None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    let (status, found) = app.get(&uri, Some(&ana)).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        (&found["name"], &found["text"]),
        (&json!("hidden"), &json!(secret))
    );
    // Bob publishes the same text in public: everyone finds it, as Bob's.
    app.publish(&bob, "bob/copy", secret, None).await;
    let (status, found) = app.get(&uri, None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        (&found["owner"], &found["name"]),
        (&json!("bob"), &json!("copy"))
    );
    // Upper case hex is the same hash; anything else is refused.
    let (status, _) = app
        .get(
            &uri.to_ascii_uppercase()
                .replace("/API/V1/TEXTS/", "/api/v1/texts/"),
            None,
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    for bad in ["abc", &"g".repeat(64), &"0".repeat(65)] {
        let (status, body) = app.get(&format!("/api/v1/texts/{bad}"), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{bad}");
        assert_eq!(body["error"], "a SHA-256 is 64 hexadecimal digits");
    }
}

/// Publishes into a grammar's name while it is renamed away all land: before the rename in the
/// renamed grammar, after it in a new grammar of the old name, each numbered without gaps.
async fn publishes_during_a_rename_all_land(app: App) {
    let ana = app.user("ana").await;
    for round in 0..4 {
        let (old, new) = (format!("g{round}"), format!("h{round}"));
        let (status, body) = app.publish(&ana, &format!("ana/{old}"), WOOD, None).await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
        let mut tasks = Vec::new();
        for i in 0..4 {
            let (app, ana, uri) = (app.clone(), ana.clone(), format!("ana/{old}"));
            tasks.push(tokio::spawn(async move {
                let text = format!("{WOOD}// {i}\n");
                let (status, body) = app.publish(&ana, &uri, &text, None).await;
                assert_eq!(status, StatusCode::CREATED, "{body}");
            }));
        }
        let uri = format!("/api/v1/grammars/ana/{old}/rename");
        let (status, body) = app
            .call(Method::POST, &uri, Some(&ana), Some(json!({ "name": new })))
            .await;
        assert_eq!(status, StatusCode::OK, "{body}");
        for task in tasks {
            task.await.unwrap();
        }
        let mut total = 0;
        for name in [&old, &new] {
            let (status, versions) = app
                .get(&format!("/api/v1/grammars/ana/{name}/versions"), None)
                .await;
            let numbers: Vec<i64> = match status {
                StatusCode::OK => versions
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|v| v["version"].as_i64().unwrap())
                    .collect(),
                _ => Vec::new(),
            };
            assert_eq!(numbers, (1..=numbers.len() as i64).collect::<Vec<_>>());
            total += numbers.len();
        }
        assert_eq!(total, 5, "round {round}");
    }
    assert_eq!(app.store.audit().await.unwrap(), Vec::<String>::new());
}

on_both_backends!(
    a_renamed_grammar_keeps_its_versions_and_answers_queries_under_its_new_name,
    texts_are_found_by_their_hash_by_whoever_may_see_one_of_their_versions,
    publishes_during_a_rename_all_land,
);
