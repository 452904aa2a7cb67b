//! Bad input gets a 4xx answer with a JSON message, never a 500 or a crash.

mod common;

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

on_both_backends!(
    malformed_bodies_are_client_errors_with_messages,
    odd_paths_queries_and_methods_are_client_errors,
);
