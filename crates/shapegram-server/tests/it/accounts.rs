//! Sign-up, login and API tokens.

use crate::common;

use axum::http::{Method, StatusCode};
use common::App;
use serde_json::json;

async fn sign_up_login_and_token_flow(app: App) {
    let token = app.user("Ana_M").await;
    assert!(token.starts_with("sgr_") && token.len() == 42, "{token}");

    // The name is unique in its canonical form (case, `-` and `_`).
    let (status, body) = app
        .call(
            Method::POST,
            "/api/v1/accounts",
            None,
            Some(json!({"name": "ana-m", "password": "another password"})),
        )
        .await;
    assert_eq!(status, StatusCode::CONFLICT, "{body}");
    assert!(body["error"].as_str().unwrap().contains("taken"));

    // Login is by canonical name too; a wrong password or unknown name is 401 alike.
    let (status, _) = app
        .call(
            Method::POST,
            "/api/v1/login",
            None,
            Some(json!({"name": "ANA-M", "password": "Ana_M password"})),
        )
        .await;
    assert_eq!(status, StatusCode::OK);
    for (name, password) in [("ana_m", "wrong password"), ("nobody", "Ana_M password")] {
        let (status, body) = app
            .call(
                Method::POST,
                "/api/v1/login",
                None,
                Some(json!({"name": name, "password": password})),
            )
            .await;
        assert_eq!(status, StatusCode::UNAUTHORIZED, "{name}");
        assert_eq!(body["error"], "wrong name or password");
    }

    let (status, body) = app.get("/api/v1/me", Some(&token)).await;
    assert_eq!((status, &body["name"]), (StatusCode::OK, &json!("Ana_M")));

    // A named token for the CLI, shown once.
    let (status, created) = app
        .call(
            Method::POST,
            "/api/v1/tokens",
            Some(&token),
            Some(json!({"name": "laptop"})),
        )
        .await;
    assert_eq!(status, StatusCode::CREATED, "{created}");
    let laptop = created["token"].as_str().unwrap().to_owned();
    assert_eq!(created["prefix"], json!(&laptop[..8]));

    // Listed without secrets.
    let (status, list) = app.get("/api/v1/tokens", Some(&laptop)).await;
    assert_eq!(status, StatusCode::OK);
    let list = list.as_array().unwrap();
    assert_eq!(list.len(), 3, "two logins and the laptop's: {list:?}");
    let text = serde_json::to_string(list).unwrap();
    assert!(!text.contains(&laptop) && !text.contains(&token));
    assert!(
        list.iter()
            .all(|t| t.get("token").is_none() && t.get("hash").is_none())
    );

    // Revoked: fails at once, and stays listed as revoked.
    let id = created["id"].as_i64().unwrap();
    let (status, _) = app
        .call(
            Method::DELETE,
            &format!("/api/v1/tokens/{id}"),
            Some(&token),
            None,
        )
        .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    let (status, body) = app.get("/api/v1/me", Some(&laptop)).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    assert_eq!(body["error"], "unknown or revoked API token");
    // Even on routes anonymous callers may use.
    let (status, _) = app.get("/api/v1/grammars", Some(&laptop)).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    let (_, list) = app.get("/api/v1/tokens", Some(&token)).await;
    let revoked: Vec<bool> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["revoked"].as_bool().unwrap())
        .collect();
    assert_eq!(revoked, [false, false, true]);
    // Another account cannot revoke Ana's tokens: to it they do not exist.
    let bo = app.user("bo").await;
    let first = list[0]["id"].as_i64().unwrap();
    let (status, _) = app
        .call(
            Method::DELETE,
            &format!("/api/v1/tokens/{first}"),
            Some(&bo),
            None,
        )
        .await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(app.get("/api/v1/me", Some(&token)).await.0, StatusCode::OK);
}

async fn malformed_tokens_and_headers_are_refused(app: App) {
    let token = app.user("ana").await;
    // A changed character breaks the checksum: refused before any lookup.
    let mut bad = token.clone().into_bytes();
    bad[12] = if bad[12] == b'a' { b'b' } else { b'a' };
    let bad = String::from_utf8(bad).unwrap();
    let (status, body) = app.get("/api/v1/me", Some(&bad)).await;
    assert_eq!(
        (status, &body["error"]),
        (StatusCode::UNAUTHORIZED, &json!("malformed API token"))
    );
    // Well formed but never issued.
    let unknown = shapegram_server::tokens::generate().unwrap();
    assert_eq!(
        app.get("/api/v1/me", Some(&unknown)).await.0,
        StatusCode::UNAUTHORIZED
    );
    // Not a bearer header.
    let request = axum::http::Request::builder()
        .uri("/api/v1/me")
        .header("authorization", format!("Basic {token}"))
        .body(axum::body::Body::empty())
        .unwrap();
    let (status, body) = app.send(request).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED, "{body}");
    // No header on a route that needs one.
    let (status, _) = app.get("/api/v1/me", None).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
}

async fn names_and_passwords_are_checked(app: App) {
    for (name, password) in [
        ("1ana", "long enough"),
        ("ana/b", "long enough"),
        ("", "long enough"),
        ("ana", "short"),
        (&*"a".repeat(40), "long enough"),
    ] {
        let (status, body) = app
            .call(
                Method::POST,
                "/api/v1/accounts",
                None,
                Some(json!({"name": name, "password": password})),
            )
            .await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{name}: {body}");
        assert!(body["error"].is_string());
    }
}

async fn login_rehashes_a_password_stored_with_weaker_parameters(app: App) {
    use argon2::password_hash::{PasswordHasher, SaltString};

    // An account from a time of weaker parameters, written through the store.
    let weak = argon2::Argon2::new(
        argon2::Algorithm::Argon2id,
        argon2::Version::V0x13,
        argon2::Params::new(8, 1, 1, None).unwrap(),
    )
    .hash_password(
        b"old password",
        &SaltString::encode_b64(b"0123456789abcdef").unwrap(),
    )
    .unwrap()
    .to_string();
    app.store.create_account("old", "old", &weak).await.unwrap();

    let login = json!({"name": "old", "password": "old password"});
    let (status, _) = app
        .call(Method::POST, "/api/v1/login", None, Some(login.clone()))
        .await;
    assert_eq!(status, StatusCode::OK);
    let (_, stored) = app.store.account_for_login("old").await.unwrap().unwrap();
    assert!(
        stored.starts_with("$argon2id$v=19$m=19456,t=2,p=1$"),
        "{stored}"
    );
    // The same password still logs in.
    let (status, _) = app
        .call(Method::POST, "/api/v1/login", None, Some(login))
        .await;
    assert_eq!(status, StatusCode::OK);
}

on_both_backends!(
    sign_up_login_and_token_flow,
    malformed_tokens_and_headers_are_refused,
    names_and_passwords_are_checked,
    login_rehashes_a_password_stored_with_weaker_parameters,
);
