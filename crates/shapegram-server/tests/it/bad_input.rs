//! Bad input gets a 4xx answer with a JSON message, never a 500 or a crash.

use crate::common;

use axum::http::{Method, StatusCode};
use common::{App, WOOD};
use serde_json::json;

async fn malformed_bodies_are_client_errors_with_messages(app: App) {
    let ana = app.user("ana").await;
    let publish = "/api/v1/grammars/ana/paint/versions";
    let cases: Vec<(&str, Vec<u8>, StatusCode)> = vec![
        ("empty body", Vec::new(), StatusCode::BAD_REQUEST),
        ("not JSON", b"text: hello".to_vec(), StatusCode::BAD_REQUEST),
        (
            "truncated JSON",
            br#"{"text": "fulfills(w"#.to_vec(),
            StatusCode::BAD_REQUEST,
        ),
        ("an array", b"[1, 2]".to_vec(), StatusCode::BAD_REQUEST),
        (
            "unknown field",
            json!({"text": WOOD, "owner": "bo"})
                .to_string()
                .into_bytes(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "wrong type",
            br#"{"text": 12}"#.to_vec(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "unknown visibility",
            json!({"text": WOOD, "visibility": "everyone"})
                .to_string()
                .into_bytes(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "huge number",
            br#"{"text": "x", "visibility": 1e999999}"#.to_vec(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "invalid UTF-8",
            b"{\"text\": \"fulfills(w\xff\xfe) --> color(1)\"}".to_vec(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "lone surrogate escape",
            br#"{"text": "\ud800"}"#.to_vec(),
            StatusCode::BAD_REQUEST,
        ),
        (
            "too large a body",
            format!("{{\"text\": \"{}\"}}", "x".repeat(2 * 1024 * 1024)).into_bytes(),
            StatusCode::PAYLOAD_TOO_LARGE,
        ),
        (
            "too large a grammar",
            json!({"text": format!("{WOOD}//{}", "x".repeat(300 * 1024))})
                .to_string()
                .into_bytes(),
            StatusCode::PAYLOAD_TOO_LARGE,
        ),
        (
            "deep nesting",
            format!("{}{}", "[".repeat(100_000), "]".repeat(100_000)).into_bytes(),
            StatusCode::BAD_REQUEST,
        ),
    ];
    for (what, body, expected) in cases {
        let (status, answer) = app.raw(Method::POST, publish, Some(&ana), body).await;
        assert_eq!(status, expected, "{what}: {answer}");
        assert!(
            answer["error"].as_str().is_some_and(|m| !m.is_empty()),
            "{what}: {answer}"
        );
    }
    // Nothing was published.
    assert_eq!(app.get("/api/v1/grammars", Some(&ana)).await.1, json!([]));

    let (status, answer) = app
        .raw(
            Method::POST,
            "/api/v1/accounts",
            None,
            br#"{"name": "bo", "password": "12345678", "admin": true}"#.to_vec(),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        answer["error"].as_str().unwrap().contains("unknown field"),
        "{answer}"
    );
}

async fn odd_paths_queries_and_methods_are_client_errors(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/paint", WOOD, None).await;
    for (method, uri, expected) in [
        (Method::GET, "/nowhere", StatusCode::NOT_FOUND),
        (Method::GET, "/api/v1/grammars/ana", StatusCode::NOT_FOUND),
        (
            Method::GET,
            "/api/v1/grammars/ana/paint/versions/99999999999999999999999",
            StatusCode::NOT_FOUND,
        ),
        (
            Method::GET,
            "/api/v1/grammars/ana/paint/versions/-1",
            StatusCode::NOT_FOUND,
        ),
        (
            Method::GET,
            "/api/v1/grammars/ana/pa%FFint",
            StatusCode::BAD_REQUEST,
        ),
        (
            Method::GET,
            "/api/v1/grammars/ana/..%2F..%2Fetc",
            StatusCode::NOT_FOUND,
        ),
        (
            Method::GET,
            "/api/v1/grammars?owner=ana&limit=3",
            StatusCode::BAD_REQUEST,
        ),
        (
            Method::DELETE,
            "/api/v1/tokens/99999999999999999999999",
            StatusCode::NOT_FOUND,
        ),
        (Method::DELETE, "/api/v1/tokens/abc", StatusCode::NOT_FOUND),
        (
            Method::PUT,
            "/api/v1/grammars/ana/paint",
            StatusCode::METHOD_NOT_ALLOWED,
        ),
        (
            Method::DELETE,
            "/api/v1/grammars/ana/paint/versions/1",
            StatusCode::METHOD_NOT_ALLOWED,
        ),
    ] {
        let (status, answer) = app.call(method.clone(), uri, Some(&ana), None).await;
        assert_eq!(status, expected, "{method} {uri}: {answer}");
        assert!(answer["error"].is_string(), "{method} {uri}: {answer}");
    }
    // Publishing under an invalid grammar name is a 400 with the rule.
    let (status, answer) = app.publish(&ana, "ana/1paint", WOOD, None).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert!(
        answer["error"].as_str().unwrap().contains("letter"),
        "{answer}"
    );
    // A grammar that fails the checker in odd ways is still a 422, not a crash.
    for text in [
        "",
        "\0\0\0",
        "fulfills(",
        "fulfills(a) --> split(x) { ~1e308 : +b }* ",
        "axiom a size(1e999, 1, 1)",
    ] {
        let (status, answer) = app.publish(&ana, "ana/odd", text, None).await;
        assert!(
            status == StatusCode::UNPROCESSABLE_ENTITY || status == StatusCode::CREATED,
            "{text:?}: {status} {answer}"
        );
    }
}

/// Found by Schemathesis: serde reads a struct from an array of its fields in order, so
/// `["text"]` published a grammar and `[null]` yanked a version; a body over the limit answered
/// with axum's own message.
async fn bodies_are_json_objects_and_too_large_ones_name_the_limit(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/paint", WOOD, None).await;
    let not_object = json!({"error": "invalid JSON body: expected an object `{…}`"});
    for (uri, body) in [
        ("/api/v1/grammars/ana/paint/versions", json!([WOOD, null])),
        ("/api/v1/grammars/ana/paint/versions/1/yank", json!([null])),
        ("/api/v1/tokens", json!(["laptop"])),
        ("/api/v1/queries", json!("queries")),
    ] {
        let (status, answer) = app.call(Method::POST, uri, Some(&ana), Some(body)).await;
        assert_eq!(
            (status, &answer),
            (StatusCode::BAD_REQUEST, &not_object),
            "{uri}"
        );
    }
    assert_eq!(
        app.get("/api/v1/tokens", Some(&ana))
            .await
            .1
            .as_array()
            .unwrap()
            .len(),
        1
    );
    // `null` is the optional yank body left out.
    let (status, answer) = app
        .raw(
            Method::POST,
            "/api/v1/grammars/ana/paint/versions/1/yank",
            Some(&ana),
            b" null ".to_vec(),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    assert_eq!(answer["yank"]["reason"], json!(null));

    let (status, answer) = app
        .raw(
            Method::POST,
            "/api/v1/queries",
            None,
            vec![b' '; 2 * 1024 * 1024],
        )
        .await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    assert_eq!(
        answer,
        json!({"error": "a request body has at most 1048576 bytes"})
    );
}

/// Found by hand: `?q=%FF` was read as U+FFFD and answered 200.
async fn query_strings_that_are_not_utf8_are_refused(app: App) {
    for uri in [
        "/api/v1/search?q=%FF",
        "/api/v1/search?goal=wood%C3",
        "/api/v1/grammars?owner=an%E2%82a",
        "/api/v1/grammars/ana/paint/versions/1/preview?seed=1&x=%80",
    ] {
        let (status, answer) = app.get(uri, None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{uri}: {answer}");
        assert_eq!(
            answer,
            json!({"error": "the query string is not UTF-8 once percent-decoded"}),
            "{uri}"
        );
    }
    // Percent-encoded UTF-8 and `+` for a space are fine.
    let (status, answer) = app.get("/api/v1/search?q=h%C3%A9+llo", None).await;
    assert_eq!(status, StatusCode::OK, "{answer}");
}

/// Found by hand: rule queries took names with control characters (search refused them), and
/// counted bytes where the message and the OpenAPI document say characters.
async fn rule_query_names_are_characters_without_control_characters(app: App) {
    let query = |goal: String| json!({"queries": [{"goals": [goal]}]});
    for (goal, expected) in [
        (
            "a\0b".to_owned(),
            "query 0: goals have no control characters",
        ),
        (
            "wood\u{85}".to_owned(),
            "query 0: goals have no control characters",
        ),
        (
            "é".repeat(201),
            "query 0: goals have 1 to 200 characters, not 201",
        ),
    ] {
        let (status, answer) = app
            .call(Method::POST, "/api/v1/queries", None, Some(query(goal)))
            .await;
        assert_eq!(status, StatusCode::BAD_REQUEST);
        assert_eq!(answer, json!({"error": expected}));
    }
    // 200 characters of 2 bytes each are 400 bytes, and allowed.
    let (status, answer) = app
        .call(
            Method::POST,
            "/api/v1/queries",
            None,
            Some(query("é".repeat(200))),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    assert_eq!(answer["answers"], json!([[]]));
}

/// Found by hand: `versions/+1` and `versions/01` were version 1 under other URLs.
async fn version_numbers_have_one_spelling(app: App) {
    let ana = app.user("ana").await;
    app.publish(&ana, "ana/paint", WOOD, None).await;
    let (status, _) = app.get("/api/v1/grammars/ana/paint/versions/1", None).await;
    assert_eq!(status, StatusCode::OK);
    for version in ["+1", "01", "1.0", "0", "-1", " 1", "99999999999999999999"] {
        let uri = format!(
            "/api/v1/grammars/ana/paint/versions/{}/rules",
            version.replace(' ', "%20")
        );
        let (status, answer) = app.get(&uri, None).await;
        assert_eq!(
            (status, answer),
            (StatusCode::NOT_FOUND, json!({"error": "not found"})),
            "{uri}"
        );
    }
}

/// Found by Schemathesis: the password's upper bound counted bytes, its message characters.
async fn passwords_are_bounded_in_characters(app: App) {
    let sign_up = |name: &str, password: String| json!({"name": name, "password": password});
    let (status, answer) = app
        .call(
            Method::POST,
            "/api/v1/accounts",
            None,
            Some(sign_up("ana", "é".repeat(1024))),
        )
        .await;
    assert_eq!(status, StatusCode::CREATED, "{answer}");
    let (status, answer) = app
        .call(
            Method::POST,
            "/api/v1/login",
            None,
            Some(sign_up("ana", "é".repeat(1024))),
        )
        .await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    let (status, answer) = app
        .call(
            Method::POST,
            "/api/v1/accounts",
            None,
            Some(sign_up("bo", "é".repeat(1025))),
        )
        .await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(
        answer,
        json!({"error": "a password has 8 to 1024 characters"})
    );
}

on_both_backends!(
    malformed_bodies_are_client_errors_with_messages,
    odd_paths_queries_and_methods_are_client_errors,
    bodies_are_json_objects_and_too_large_ones_name_the_limit,
    query_strings_that_are_not_utf8_are_refused,
    rule_query_names_are_characters_without_control_characters,
    version_numbers_have_one_spelling,
    passwords_are_bounded_in_characters,
);
