//! Yanking: owner only, recorded beside the immutable versions, still fetchable by number,
//! never the current version.

use crate::common;

use axum::http::{Method, StatusCode};
use common::{App, WOOD};
use serde_json::{Value, json};

async fn post(app: &App, uri: &str, token: &str, body: Option<Value>) -> (StatusCode, Value) {
    app.call(Method::POST, uri, Some(token), body).await
}

async fn current(app: &App, token: Option<&str>) -> Value {
    let (status, body) = app.get("/api/v1/grammars/ana/wood", token).await;
    assert_eq!(status, StatusCode::OK, "{body}");
    body["current_version"].clone()
}

async fn a_yanked_version_is_fetchable_but_not_current(app: App) {
    let ana = app.user("ana").await;
    for i in 1..=3 {
        let (status, body) = app
            .publish(&ana, "ana/wood", &format!("{WOOD}// {i}\n"), None)
            .await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
        assert_eq!(body["yanked"], json!(false));
    }
    assert_eq!(current(&app, None).await, json!(3));

    let (status, yanked) = post(
        &app,
        "/api/v1/grammars/ana/wood/versions/3/yank",
        &ana,
        Some(json!({"reason": "paints metal brown"})),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{yanked}");
    assert_eq!(yanked["version"], json!(3));
    assert_eq!(yanked["yanked"], json!(true));
    assert_eq!(yanked["yank"]["by"], json!("ana"));
    assert_eq!(yanked["yank"]["reason"], json!("paints metal brown"));
    let at = yanked["yank"]["at"].as_i64().unwrap();
    assert!(at > 1_700_000_000, "{at}");

    // Still fetchable by its number, text and hash unchanged, and marked.
    let (status, v3) = app.get("/api/v1/grammars/ana/wood/versions/3", None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(v3["text"], json!(format!("{WOOD}// 3\n")));
    assert_eq!(v3["sha256"], yanked["sha256"]);
    assert_eq!(v3["yanked"], json!(true));
    let (status, rules) = app
        .get("/api/v1/grammars/ana/wood/versions/3/rules", None)
        .await;
    assert_eq!(
        (status, rules.as_array().unwrap().len()),
        (StatusCode::OK, 1)
    );

    // The current version is the newest not yanked; the latest is still the latest.
    let (_, grammar) = app.get("/api/v1/grammars/ana/wood", None).await;
    assert_eq!(
        (&grammar["latest_version"], &grammar["current_version"]),
        (&json!(3), &json!(2))
    );
    let (_, versions) = app.get("/api/v1/grammars/ana/wood/versions", None).await;
    let flags: Vec<&Value> = versions
        .as_array()
        .unwrap()
        .iter()
        .map(|v| &v["yanked"])
        .collect();
    assert_eq!(flags, [&json!(false), &json!(false), &json!(true)]);
    assert!(versions[0].get("yank").is_none(), "{versions}");

    // Yanking again keeps the first yank; an empty body is no reason.
    let (status, again) = post(
        &app,
        "/api/v1/grammars/ana/wood/versions/3/yank",
        &ana,
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(again["yank"], yanked["yank"]);
    let (status, no_reason) = post(
        &app,
        "/api/v1/grammars/ana/wood/versions/1/yank",
        &ana,
        None,
    )
    .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(no_reason["yank"]["reason"], Value::Null);
    assert_eq!(current(&app, None).await, json!(2));

    // Every version yanked: no current version, the grammar is still listed for its owner.
    post(
        &app,
        "/api/v1/grammars/ana/wood/versions/2/yank",
        &ana,
        None,
    )
    .await;
    assert_eq!(current(&app, None).await, Value::Null);
    let (_, list) = app.get("/api/v1/grammars", None).await;
    assert_eq!(list[0]["current_version"], Value::Null);

    // Unyanking offers a version again; unyanking twice changes nothing.
    for _ in 0..2 {
        let (status, back) = post(
            &app,
            "/api/v1/grammars/ana/wood/versions/3/unyank",
            &ana,
            None,
        )
        .await;
        assert_eq!(status, StatusCode::OK, "{back}");
        assert_eq!(back["yanked"], json!(false));
        assert!(back.get("yank").is_none());
    }
    assert_eq!(current(&app, None).await, json!(3));

    // A new version is current and not yanked, whatever came before.
    let (_, v4) = app.publish(&ana, "ana/wood", WOOD, None).await;
    assert_eq!((&v4["version"], &v4["yanked"]), (&json!(4), &json!(false)));
    assert_eq!(current(&app, None).await, json!(4));
}

async fn only_the_owner_yanks(app: App) {
    let ana = app.user("ana").await;
    let bob = app.user("bob").await;
    app.publish(&ana, "ana/wood", WOOD, Some("public")).await;
    app.publish(&ana, "ana/secret", WOOD, Some("private")).await;
    let yank = "/api/v1/grammars/ana/wood/versions/1/yank";

    // Visible to bob: 403; invisible or absent: 404, the same answer.
    let (status, body) = post(&app, yank, &bob, None).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    assert_eq!(
        body["error"],
        json!("only the grammar's owner yanks its versions, and bob is not")
    );
    for uri in [
        "/api/v1/grammars/ana/secret/versions/1/yank",
        "/api/v1/grammars/ana/nothing/versions/1/yank",
        "/api/v1/grammars/ana/secret/versions/1/unyank",
    ] {
        let (status, body) = post(&app, uri, &bob, None).await;
        assert_eq!(
            (status, &body["error"]),
            (StatusCode::NOT_FOUND, &json!("not found")),
            "{uri}"
        );
    }
    let (status, _) = post(
        &app,
        "/api/v1/grammars/ana/wood/versions/1/unyank",
        &bob,
        None,
    )
    .await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    // Without a token: 401. A version that does not exist: 404.
    let (status, _) = app.call(Method::POST, yank, None, None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    for version in ["2", "0", "x"] {
        let (status, _) = post(
            &app,
            &format!("/api/v1/grammars/ana/wood/versions/{version}/yank"),
            &ana,
            None,
        )
        .await;
        assert_eq!(status, StatusCode::NOT_FOUND, "{version}");
    }
    // Nothing was yanked by any of this.
    let (_, v1) = app.get("/api/v1/grammars/ana/wood/versions/1", None).await;
    assert_eq!(v1["yanked"], json!(false));
}

async fn bad_yank_bodies_are_refused(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/wood", WOOD, None).await;
    let yank = "/api/v1/grammars/ana/wood/versions/1/yank";
    let long = "x".repeat(1001);
    for (body, message) in [
        (
            json!({"reason": long}),
            "a yank reason has at most 1000 characters and no control characters but line breaks",
        ),
        (
            json!({"reason": "bell\u{7}"}),
            "a yank reason has at most 1000 characters and no control characters but line breaks",
        ),
    ] {
        let (status, answer) = post(&app, yank, &ana, Some(body)).await;
        assert_eq!(
            (status, &answer["error"]),
            (StatusCode::BAD_REQUEST, &json!(message))
        );
    }
    let (status, answer) = post(&app, yank, &ana, Some(json!({"why": "no"}))).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        answer["error"]
            .as_str()
            .unwrap()
            .contains("unknown field `why`"),
        "{answer}"
    );
    let (status, _) = app
        .raw(Method::POST, yank, Some(&ana), b"{\"reason\": ".to_vec())
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    let (_, v1) = app.get("/api/v1/grammars/ana/wood/versions/1", None).await;
    assert_eq!(v1["yanked"], json!(false));
    // A reason with line breaks is fine.
    let (status, answer) = post(&app, yank, &ana, Some(json!({"reason": "one\ntwo"}))).await;
    assert_eq!(
        (status, &answer["yank"]["reason"]),
        (StatusCode::OK, &json!("one\ntwo"))
    );
}

/// Publishes and yanks of one grammar at once leave it with the right current version, the
/// newest not yanked (on PostgreSQL a yank locks the grammar's row before it looks).
async fn concurrent_yanks_and_publishes_keep_the_current_version(app: App) {
    let ana = app.user("ana").await;
    for i in 1..=4 {
        let (status, body) = app
            .publish(&ana, "ana/wood", &format!("{WOOD}// {i}\n"), None)
            .await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
    }
    let mut tasks = Vec::new();
    for i in 1..=4 {
        let (yanker, token) = (app.clone(), ana.clone());
        tasks.push(tokio::spawn(async move {
            yanker.yank(&token, "ana/wood", i, "yank").await;
        }));
        let (app, ana) = (app.clone(), ana.clone());
        tasks.push(tokio::spawn(async move {
            let text = format!("{WOOD}// {}\n", i + 4);
            let (status, body) = app.publish(&ana, "ana/wood", &text, None).await;
            assert_eq!(status, StatusCode::CREATED, "{body}");
        }));
    }
    for task in tasks {
        task.await.unwrap();
    }
    assert_eq!(current(&app, None).await, json!(8));
    assert_eq!(app.store.audit().await.unwrap(), Vec::<String>::new());
}

on_both_backends!(
    a_yanked_version_is_fetchable_but_not_current,
    only_the_owner_yanks,
    bad_yank_bodies_are_refused,
    concurrent_yanks_and_publishes_keep_the_current_version,
);
