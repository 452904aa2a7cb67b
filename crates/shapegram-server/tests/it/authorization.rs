//! Every route × {anonymous, stranger, friend, owner, revoked token}: the expected status, and
//! that lists never show what the caller may not see. Every operation of the OpenAPI document
//! must have a case here.

use crate::common;

use std::collections::BTreeSet;

use axum::http::{Method, StatusCode};
use common::{App, WOOD};
use serde_json::{Value, json};

const ACTORS: [&str; 5] = ["anonymous", "stranger", "friend", "owner", "revoked"];

struct World {
    app: App,
    /// Tokens by actor (none for the anonymous caller).
    tokens: [Option<String>; 5],
    /// An unrevoked token of the owner's, other than the one the owner calls with.
    spare_id: i64,
}

async fn world(app: App) -> World {
    let owner = app.user("olga").await;
    let friend = app.user("fred").await;
    let stranger = app.user("sam").await;
    let revoked = app.user("rita").await;
    app.befriend(("olga", &owner), ("fred", &friend)).await;
    // Rita is a friend too, so that only the revocation explains her 401s.
    app.befriend(("olga", &owner), ("rita", &revoked)).await;
    for (name, visibility) in [("pub", "public"), ("fri", "friends"), ("pri", "private")] {
        let (status, body) = app
            .publish(&owner, &format!("olga/{name}"), WOOD, Some(visibility))
            .await;
        assert_eq!(status, StatusCode::CREATED, "{body}");
    }
    let (_, tokens) = app.get("/api/v1/tokens", Some(&revoked)).await;
    let id = tokens[0]["id"].as_i64().unwrap();
    let (status, _) = app
        .call(
            Method::DELETE,
            &format!("/api/v1/tokens/{id}"),
            Some(&revoked),
            None,
        )
        .await;
    assert_eq!(status, StatusCode::NO_CONTENT);
    let (_, spare) = app
        .call(
            Method::POST,
            "/api/v1/tokens",
            Some(&owner),
            Some(json!({"name": "spare"})),
        )
        .await;
    World {
        app,
        tokens: [
            None,
            Some(stranger),
            Some(friend),
            Some(owner),
            Some(revoked),
        ],
        spare_id: spare["id"].as_i64().unwrap(),
    }
}

/// One route's case: the OpenAPI operation it covers, the request, and a status per actor.
struct Case {
    operation: (&'static str, &'static str),
    method: Method,
    uri: String,
    body: Option<Value>,
    expect: [u16; 5],
}

fn case(
    operation: (&'static str, &'static str),
    uri: impl Into<String>,
    body: Option<Value>,
    expect: [u16; 5],
) -> Case {
    let method = Method::from_bytes(operation.0.to_uppercase().as_bytes()).unwrap();
    Case {
        operation,
        method,
        uri: uri.into(),
        body,
        expect,
    }
}

const GRAMMAR: &str = "/api/v1/grammars/{owner}/{name}";
const VERSIONS: &str = "/api/v1/grammars/{owner}/{name}/versions";
const VERSION: &str = "/api/v1/grammars/{owner}/{name}/versions/{version}";
const RULES: &str = "/api/v1/grammars/{owner}/{name}/versions/{version}/rules";
const PREVIEW: &str = "/api/v1/grammars/{owner}/{name}/versions/{version}/preview";
const YANK: &str = "/api/v1/grammars/{owner}/{name}/versions/{version}/yank";
const UNYANK: &str = "/api/v1/grammars/{owner}/{name}/versions/{version}/unyank";

/// Reads of each grammar: public to all, friends-only to friend and owner, private to owner;
/// a revoked token is refused whatever it asks.
fn read_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for (name, expect) in [
        ("pub", [200, 200, 200, 200, 401]),
        ("fri", [404, 404, 200, 200, 401]),
        ("pri", [404, 404, 404, 200, 401]),
        // A grammar that does not exist answers as an invisible one.
        ("none", [404, 404, 404, 404, 401]),
    ] {
        let base = format!("/api/v1/grammars/olga/{name}");
        cases.push(case(("get", GRAMMAR), base.clone(), None, expect));
        cases.push(case(
            ("get", VERSIONS),
            format!("{base}/versions"),
            None,
            expect,
        ));
        cases.push(case(
            ("get", VERSION),
            format!("{base}/versions/1"),
            None,
            expect,
        ));
        cases.push(case(
            ("get", RULES),
            format!("{base}/versions/1/rules"),
            None,
            expect,
        ));
        // This server makes no previews: what may be seen says so, the rest is not found.
        cases.push(case(
            ("get", PREVIEW),
            format!("{base}/versions/1/preview"),
            None,
            expect.map(|status| if status == 200 { 503 } else { status }),
        ));
    }
    let all = [200, 200, 200, 200, 401];
    cases.push(case(
        ("get", "/api/v1/grammars"),
        "/api/v1/grammars",
        None,
        all,
    ));
    cases.push(case(
        ("get", "/api/v1/grammars"),
        "/api/v1/grammars?owner=olga",
        None,
        all,
    ));
    cases.push(case(
        ("get", "/api/v1/search"),
        "/api/v1/search?goal=wooden",
        None,
        all,
    ));
    let signed = [401, 200, 200, 200, 401];
    // Every grammar of the world has this text; one of them is public.
    let texts = ("get", "/api/v1/texts/{sha256}");
    let wood = shapegram_server::tokens::sha256_hex(WOOD.as_bytes());
    cases.push(case(texts, format!("/api/v1/texts/{wood}"), None, all));
    let nobodys = "0".repeat(64);
    let none = [404, 404, 404, 404, 401];
    cases.push(case(texts, format!("/api/v1/texts/{nobodys}"), None, none));
    let query = |link: &str| Some(json!({"link": link, "queries": [{"goals": ["wooden"]}]}));
    let queries = ("post", "/api/v1/queries");
    cases.push(case(queries, "/api/v1/queries", query("all"), all));
    cases.push(case(queries, "/api/v1/queries", query("friends"), signed));
    cases.push(case(queries, "/api/v1/queries", query("mine"), signed));
    cases.push(case(("get", "/api/v1/me"), "/api/v1/me", None, signed));
    cases.push(case(
        ("get", "/api/v1/tokens"),
        "/api/v1/tokens",
        None,
        signed,
    ));
    cases.push(case(
        ("get", "/api/v1/friends"),
        "/api/v1/friends",
        None,
        signed,
    ));
    cases
}

/// Yanking and unyanking: the owner alone; a caller who sees the grammar but does not own it
/// is forbidden, one who does not see it finds nothing.
fn yank_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    for (name, expect) in [
        ("pub", [401, 403, 403, 200, 401]),
        ("fri", [401, 404, 403, 200, 401]),
        ("pri", [401, 404, 404, 200, 401]),
        ("none", [401, 404, 404, 404, 401]),
    ] {
        for (operation, action) in [(YANK, "yank"), (UNYANK, "unyank")] {
            cases.push(case(
                ("post", operation),
                format!("/api/v1/grammars/olga/{name}/versions/1/{action}"),
                None,
                expect,
            ));
        }
    }
    cases
}

fn write_cases(spare_id: i64) -> Vec<Case> {
    let wood = || Some(json!({"text": WOOD}));
    let mut cases = yank_cases();
    cases.extend([
        // Only the owner publishes under her name, new grammar or existing (even private).
        case(
            ("post", VERSIONS),
            "/api/v1/grammars/olga/new/versions",
            wood(),
            [401, 403, 403, 201, 401],
        ),
        case(
            ("post", VERSIONS),
            "/api/v1/grammars/olga/pri/versions",
            wood(),
            [401, 403, 403, 201, 401],
        ),
        case(
            ("post", VERSIONS),
            "/api/v1/grammars/olga/fri/versions",
            wood(),
            [401, 403, 403, 201, 401],
        ),
        case(
            ("post", "/api/v1/tokens"),
            "/api/v1/tokens",
            Some(json!({"name": "t"})),
            [401, 201, 201, 201, 401],
        ),
        // Another's token is not found; the owner's own revocation works.
        case(
            ("delete", "/api/v1/tokens/{id}"),
            format!("/api/v1/tokens/{spare_id}"),
            None,
            [401, 404, 404, 204, 401],
        ),
        // The stranger asks Olga; the friend is one already; Olga cannot befriend herself.
        case(
            ("post", "/api/v1/friends/{user}"),
            "/api/v1/friends/olga",
            None,
            [401, 200, 200, 404, 401],
        ),
        // Nobody has a pending request from Olga.
        case(
            ("post", "/api/v1/friends/{user}/accept"),
            "/api/v1/friends/olga/accept",
            None,
            [401, 404, 404, 404, 401],
        ),
        // The stranger withdraws the request; the friend ends the friendship.
        case(
            ("delete", "/api/v1/friends/{user}"),
            "/api/v1/friends/olga",
            None,
            [401, 204, 204, 404, 401],
        ),
        // Sign-up and login take no token: a revoked one is not looked at.
        case(
            ("post", "/api/v1/accounts"),
            "/api/v1/accounts",
            Some(json!({"name": "x", "password": "12345678"})),
            [201, 409, 409, 409, 409],
        ),
        case(
            ("post", "/api/v1/login"),
            "/api/v1/login",
            Some(json!({"name": "x", "password": "12345678"})),
            [200, 200, 200, 200, 200],
        ),
    ]);
    // Renames last, since they change the names the cases above use: the owner alone. (The
    // friend ended the friendship above: Olga's friends-only grammar is no longer theirs to see.)
    for (name, expect) in [
        ("pub", [401, 403, 403, 200, 401]),
        ("fri", [401, 404, 404, 200, 401]),
        ("pri", [401, 404, 404, 200, 401]),
        ("none", [401, 404, 404, 404, 401]),
    ] {
        cases.push(case(
            ("post", "/api/v1/grammars/{owner}/{name}/rename"),
            format!("/api/v1/grammars/olga/{name}/rename"),
            Some(json!({"name": format!("{name}-renamed")})),
            expect,
        ));
    }
    cases
}

async fn run(world: &World, cases: &[Case]) -> Vec<String> {
    let mut failures = Vec::new();
    for c in cases {
        for (a, actor) in ACTORS.iter().enumerate() {
            let token = world.tokens[a].as_deref();
            let (status, body) = world
                .app
                .call(c.method.clone(), &c.uri, token, c.body.clone())
                .await;
            if status.as_u16() != c.expect[a] {
                failures.push(format!(
                    "{} {} as {actor}: {status}, expected {} ({body})",
                    c.method, c.uri, c.expect[a]
                ));
            }
            if !status.is_success() {
                assert!(body["error"].is_string(), "{} {}: {body}", c.method, c.uri);
            }
        }
    }
    failures
}

async fn every_route_answers_every_kind_of_caller_as_expected(app: App) {
    let world = world(app).await;
    let reads = read_cases();
    let writes = write_cases(world.spare_id);
    let mut failures = run(&world, &reads).await;
    failures.extend(run(&world, &writes).await);
    assert!(failures.is_empty(), "{}", failures.join("\n"));

    // Every operation of the OpenAPI document has a case.
    let (_, doc) = world.app.get("/openapi.json", None).await;
    let mut operations = BTreeSet::new();
    for (path, item) in doc["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            operations.insert((method.clone(), path.clone()));
        }
    }
    let covered: BTreeSet<(String, String)> = reads
        .iter()
        .chain(&writes)
        .map(|c| (c.operation.0.to_owned(), c.operation.1.to_owned()))
        .collect();
    let missing: Vec<_> = operations.difference(&covered).collect();
    assert!(
        missing.is_empty(),
        "operations without an authorization case: {missing:?}"
    );
    let unknown: Vec<_> = covered.difference(&operations).collect();
    assert!(
        unknown.is_empty(),
        "cases for operations not in the document: {unknown:?}"
    );
}

fn names(list: &Value) -> Vec<String> {
    list.as_array()
        .unwrap()
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

async fn lists_show_only_what_the_caller_may_see(app: App) {
    let world = world(app).await;
    let app = &world.app;
    // Another owner's private grammar, to make sure the owner's view is hers alone.
    let sam = world.tokens[1].as_deref().unwrap();
    app.publish(sam, "sam/secret", WOOD, Some("private")).await;
    for (a, expect) in [
        (0, vec!["olga/pub"]),
        (1, vec!["olga/pub", "sam/secret"]),
        (2, vec!["olga/fri", "olga/pub"]),
        (3, vec!["olga/fri", "olga/pri", "olga/pub"]),
    ] {
        let token = world.tokens[a].as_deref();
        let (status, list) = app.get("/api/v1/grammars", token).await;
        assert_eq!(status, StatusCode::OK);
        assert_eq!(names(&list), expect, "{}", ACTORS[a]);
        // Rule queries offer the same grammars, no more.
        let (status, found) = app
            .call(
                Method::POST,
                "/api/v1/queries",
                token,
                Some(json!({"queries": [{"goals": ["wooden"]}]})),
            )
            .await;
        assert_eq!(status, StatusCode::OK, "{found}");
        assert_eq!(names(&found["grammars"]), expect, "{}", ACTORS[a]);
        // Search applies the same rule: every grammar here provides the goal `wooden`.
        let (status, found) = app.get("/api/v1/search?goal=wooden", token).await;
        assert_eq!(status, StatusCode::OK);
        assert_eq!(names(&found["grammars"]), expect, "search as {}", ACTORS[a]);
        let (_, list) = app.get("/api/v1/grammars?owner=olga", token).await;
        let olga: Vec<String> = expect
            .iter()
            .filter(|n| n.starts_with("olga/"))
            .map(|s| s.to_string())
            .collect();
        assert_eq!(names(&list), olga, "{}", ACTORS[a]);
    }
    // A friend request that is not accepted shows nothing.
    let (status, _) = app
        .call(Method::POST, "/api/v1/friends/olga", Some(sam), None)
        .await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(
        names(&app.get("/api/v1/grammars?owner=olga", Some(sam)).await.1),
        ["olga/pub"]
    );
    assert_eq!(
        names(
            &app.get("/api/v1/search?goal=wooden&owner=olga", Some(sam))
                .await
                .1["grammars"]
        ),
        ["olga/pub"]
    );
}

on_both_backends!(
    every_route_answers_every_kind_of_caller_as_expected,
    lists_show_only_what_the_caller_may_see,
);
