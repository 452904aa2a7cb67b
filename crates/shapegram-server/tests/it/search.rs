//! `GET /api/v1/search`: by the goals and tags of a grammar's latest version, by name and
//! owner, page by page; what the caller may not see is never found (see also
//! `authorization.rs`).

use crate::common;

use axum::http::StatusCode;
use common::{App, CHAIR, WOOD};
use serde_json::Value;

const PAINT: &str = "fulfills(painted) --> color(\"#c02020\")\n";

/// `owner/name` of each grammar found, in order.
fn found(results: &Value) -> Vec<String> {
    results["grammars"]
        .as_array()
        .unwrap_or_else(|| panic!("no grammars in {results}"))
        .iter()
        .map(|g| {
            format!(
                "{}/{}",
                g["owner"].as_str().unwrap(),
                g["name"].as_str().unwrap()
            )
        })
        .collect()
}

async fn search(app: &App, query: &str, token: Option<&str>) -> Vec<String> {
    let (status, results) = app.get(&format!("/api/v1/search?{query}"), token).await;
    assert_eq!(status, StatusCode::OK, "{query}: {results}");
    found(&results)
}

async fn search_finds_grammars_by_goal_tag_name_and_owner(app: App) {
    let ana = app.user("ana").await;
    let bob = app.user("bob").await;
    for (token, grammar, text) in [
        (&ana, "ana/wood", WOOD),
        (&ana, "ana/Chair_Parts", CHAIR),
        (&bob, "bob/paint", PAINT),
        (&bob, "bob/oak", WOOD),
    ] {
        let (status, body) = app.publish(token, grammar, text, None).await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
    }
    assert_eq!(
        search(&app, "goal=wooden", None).await,
        ["ana/wood", "bob/oak"]
    );
    assert_eq!(search(&app, "goal=chair", None).await, ["ana/Chair_Parts"]);
    assert_eq!(search(&app, "goal=lean", None).await, ["ana/Chair_Parts"]);
    // `is(chair)` is a tag, not a goal; a local goal is not searchable.
    assert_eq!(search(&app, "tag=chair", None).await, ["ana/Chair_Parts"]);
    assert!(search(&app, "goal=split-legs", None).await.is_empty());
    assert!(search(&app, "tag=wooden", None).await.is_empty());
    // Goal names are exact.
    assert!(search(&app, "goal=Wooden", None).await.is_empty());
    // Both filters must hold (here by different rules of one grammar).
    assert_eq!(
        search(&app, "goal=support&tag=chair", None).await,
        ["ana/Chair_Parts"]
    );
    assert!(search(&app, "goal=wooden&tag=chair", None).await.is_empty());
    assert_eq!(
        search(&app, "goal=wooden&owner=BOB", None).await,
        ["bob/oak"]
    );
    assert!(
        search(&app, "goal=wooden&owner=nobody", None)
            .await
            .is_empty()
    );
    assert!(search(&app, "owner=not%20a%20name", None).await.is_empty());
    // The name: a substring, case and `-`/`_` alike; LIKE's wildcards are plain characters.
    assert_eq!(search(&app, "q=AIR-P", None).await, ["ana/Chair_Parts"]);
    assert_eq!(search(&app, "q=o", None).await, ["ana/wood", "bob/oak"]);
    assert!(search(&app, "q=%25", None).await.is_empty());
    assert!(search(&app, "q=w_d", None).await.is_empty());
    // No filter: everything, by owner and name.
    assert_eq!(
        search(&app, "", None).await,
        ["ana/Chair_Parts", "ana/wood", "bob/oak", "bob/paint"]
    );
}

async fn search_looks_at_the_latest_version_only(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/finish", WOOD, None).await;
    assert_eq!(search(&app, "goal=wooden", None).await, ["ana/finish"]);
    let (status, _) = app.publish(&ana, "ana/finish", PAINT, None).await;
    assert_eq!(status, StatusCode::CREATED);
    assert!(search(&app, "goal=wooden", None).await.is_empty());
    assert_eq!(search(&app, "goal=painted", None).await, ["ana/finish"]);
}

async fn search_skips_yanked_versions(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/finish", WOOD, None).await;
    app.publish(&ana, "ana/finish", PAINT, None).await;
    app.yank(&ana, "ana/finish", 2, "yank").await;
    assert_eq!(search(&app, "goal=wooden", None).await, ["ana/finish"]);
    assert!(search(&app, "goal=painted", None).await.is_empty());
    // Every version yanked: found by nothing, not even its name.
    app.yank(&ana, "ana/finish", 1, "yank").await;
    assert!(search(&app, "goal=wooden", None).await.is_empty());
    assert!(search(&app, "q=finish", None).await.is_empty());
    app.yank(&ana, "ana/finish", 1, "unyank").await;
    assert_eq!(search(&app, "q=finish", None).await, ["ana/finish"]);
}

async fn search_pages_are_stable_and_bounded(app: App) {
    let ana = app.user("ana").await;
    let names = ["e", "a", "d", "b", "c"];
    for name in names {
        app.publish(&ana, &format!("ana/{name}"), WOOD, None).await;
    }
    let mut all = Vec::new();
    for (page, next) in [(1, Value::from(2)), (2, Value::from(3)), (3, Value::Null)] {
        let (status, results) = app
            .get(
                &format!("/api/v1/search?goal=wooden&per_page=2&page={page}"),
                None,
            )
            .await;
        assert_eq!(status, StatusCode::OK, "{results}");
        assert_eq!(
            (&results["page"], &results["per_page"]),
            (&Value::from(page), &Value::from(2))
        );
        assert_eq!(results["next_page"], next, "page {page}");
        all.extend(found(&results));
    }
    assert_eq!(all, ["ana/a", "ana/b", "ana/c", "ana/d", "ana/e"]);
    let (_, past) = app.get("/api/v1/search?page=4&per_page=2", None).await;
    assert_eq!((found(&past).len(), &past["next_page"]), (0, &Value::Null));
    let (_, default) = app.get("/api/v1/search", None).await;
    assert_eq!(default["per_page"], 50);

    for (query, message) in [
        ("page=0", "page is a number from 1 to 10000"),
        ("page=10001", "page is a number from 1 to 10000"),
        ("per_page=0", "per_page is a number from 1 to 100"),
        ("per_page=101", "per_page is a number from 1 to 100"),
        (
            "goal=",
            "a goal name has 1 to 100 characters, none a control character",
        ),
        (
            "tag=%0A",
            "a tag name has 1 to 100 characters, none a control character",
        ),
    ] {
        let (status, body) = app.get(&format!("/api/v1/search?{query}"), None).await;
        assert_eq!(
            (status, body["error"].as_str()),
            (StatusCode::BAD_REQUEST, Some(message)),
            "{query}"
        );
    }
    for query in [
        "page=x",
        "per_page=-1",
        "goals=wooden",
        &format!("q={}", "a".repeat(65)),
    ] {
        let (status, body) = app.get(&format!("/api/v1/search?{query}"), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{query}: {body}");
        assert!(body["error"].is_string(), "{body}");
    }
}

on_both_backends!(
    search_finds_grammars_by_goal_tag_name_and_owner,
    search_looks_at_the_latest_version_only,
    search_skips_yanked_versions,
    search_pages_are_stable_and_bounded,
);
