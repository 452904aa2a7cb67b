//! Procedural rule queries: which grammars have rules for shapes with these goals, tags and
//! attributes, by the rule index, the newest versions, negations and link modes.

use crate::common;

use axum::http::{Method, StatusCode};
use common::{App, CHAIR, WOOD};
use serde_json::{Value, json};

async fn query(app: &App, token: Option<&str>, body: Value) -> (StatusCode, Value) {
    app.call(Method::POST, "/api/v1/queries", token, Some(body))
        .await
}

/// Per query, the `owner/name@version: rules` it found.
fn found(answer: &Value) -> Vec<Vec<String>> {
    let grammars = answer["grammars"].as_array().unwrap();
    answer["answers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|matches| {
            matches
                .as_array()
                .unwrap()
                .iter()
                .map(|m| {
                    let g = &grammars[m["grammar"].as_u64().unwrap() as usize];
                    format!(
                        "{}/{}@{}: {}",
                        g["owner"].as_str().unwrap(),
                        g["name"].as_str().unwrap(),
                        g["version"],
                        m["rules"]
                    )
                })
                .collect()
        })
        .collect()
}

async fn published(app: &App, token: &str, grammar: &str, text: &str, visibility: &str) {
    let (status, body) = app.publish(token, grammar, text, Some(visibility)).await;
    assert_eq!(status, StatusCode::CREATED, "{grammar}: {body}");
}

const PAINTS: &str = r##"
fulfills(wooden) !is(chair) --> color("#aa2020")
fulfills(wooden) is(chair) has(Leg.Size) --> color("#20aa20")
fulfills(leg) --> s('0.5, '1, '0.5)
"##;

async fn rules_are_found_by_goals_tags_and_attributes_and_negations_rule_some_out(app: App) {
    let ana = app.user("ana").await;
    published(&app, &ana, "ana/wood", WOOD, "public").await;
    published(&app, &ana, "ana/paints", PAINTS, "public").await;
    published(&app, &ana, "ana/chair", CHAIR, "public").await;
    let (status, answer) = query(
        &app,
        None,
        json!({"queries": [
            {"goals": ["wooden"]},
            {"goals": ["wooden", "leg"], "tags": ["chair", "support"], "attributes": ["Leg.Size"]},
            {"goals": ["wooden"], "tags": ["chair"]},
            {"goals": ["support"], "tags": ["chair"], "attributes": ["Leg.Size"]},
            {"goals": ["support"], "tags": ["chair"]},
            {"goals": ["nothing"]},
        ]}),
    )
    .await;
    assert_eq!(status, StatusCode::OK, "{answer}");
    assert_eq!(
        found(&answer),
        [
            vec!["ana/paints@1: [0]", "ana/wood@1: [0]"],
            vec!["ana/paints@1: [1,2]", "ana/wood@1: [0]"],
            // A chair without the attribute: neither paint (one needs it, one refuses chairs).
            vec!["ana/wood@1: [0]"],
            // The chair's support rule asks for `is(chair)` (its `using` block) and reads the
            // attribute.
            vec!["ana/chair@1: [1]"],
            vec![],
            vec![],
        ]
    );
    // The grammars come sorted, each once, with the version's hash.
    let grammars = answer["grammars"].as_array().unwrap();
    assert_eq!(grammars.len(), 3);
    assert_eq!(grammars[0]["name"], "chair");
    assert_eq!(grammars[0]["sha256"].as_str().unwrap().len(), 64);
    assert_eq!(answer["as_of"], 3);
}

async fn only_the_newest_version_answers_and_local_goals_are_never_offered(app: App) {
    let ana = app.user("ana").await;
    published(&app, &ana, "ana/wood", WOOD, "public").await;
    // Version 2 makes oak instead.
    let oak = "fulfills(oak) --> color(\"#806040\")";
    published(&app, &ana, "ana/wood", oak, "public").await;
    let body = json!({"queries": [{"goals": ["wooden"]}, {"goals": ["oak"]}]});
    let (_, answer) = query(&app, None, body.clone()).await;
    assert_eq!(found(&answer), [vec![], vec!["ana/wood@2: [0]"]]);
    // The chair's `split-legs` is local to it: no query, by that name or any other, finds it.
    published(&app, &ana, "ana/chair", CHAIR, "public").await;
    let (_, answer) = query(
        &app,
        None,
        json!({"queries": [{"goals": ["split-legs"], "tags": ["chair", "support"]}]}),
    )
    .await;
    assert_eq!(found(&answer), [Vec::<String>::new()]);
}

async fn the_newest_version_not_yanked_answers(app: App) {
    let ana = app.user("ana").await;
    published(&app, &ana, "ana/wood", WOOD, "public").await;
    published(
        &app,
        &ana,
        "ana/wood",
        "fulfills(oak) --> color(\"#806040\")",
        "public",
    )
    .await;
    let body = json!({"queries": [{"goals": ["wooden"]}, {"goals": ["oak"]}]});
    let answers = || async { found(&query(&app, None, body.clone()).await.1) };
    // Version 2 yanked: version 1 answers again, as if 2 had never been published.
    app.yank(&ana, "ana/wood", 2, "yank").await;
    assert_eq!(answers().await, [vec!["ana/wood@1: [0]"], vec![]]);
    // Every version yanked: the grammar answers nothing.
    app.yank(&ana, "ana/wood", 1, "yank").await;
    assert_eq!(answers().await, [Vec::<String>::new(), vec![]]);
    app.yank(&ana, "ana/wood", 2, "unyank").await;
    assert_eq!(answers().await, [vec![], vec!["ana/wood@2: [0]"]]);
}

async fn link_modes_choose_whose_grammars_answer(app: App) {
    let ana = app.user("ana").await;
    let bob = app.user("bob").await;
    let eve = app.user("eve").await;
    app.befriend(("ana", &ana), ("bob", &bob)).await;
    published(&app, &ana, "ana/wood", WOOD, "private").await;
    published(&app, &bob, "bob/wood", WOOD, "friends").await;
    published(&app, &eve, "eve/wood", WOOD, "public").await;
    let body = |link: &str| json!({"link": link, "queries": [{"goals": ["wooden"]}]});
    let mut seen = Vec::new();
    for link in ["all", "friends", "mine"] {
        let (status, answer) = query(&app, Some(&ana), body(link)).await;
        assert_eq!(status, StatusCode::OK, "{answer}");
        seen.push(found(&answer).remove(0));
    }
    assert_eq!(
        seen,
        [
            vec!["ana/wood@1: [0]", "bob/wood@1: [0]", "eve/wood@1: [0]"],
            vec!["ana/wood@1: [0]", "bob/wood@1: [0]"],
            vec!["ana/wood@1: [0]"],
        ]
    );
    // Eve, no friend of Ana's or Bob's, sees neither of their grammars, even asking for all.
    let (_, answer) = query(&app, Some(&eve), body("all")).await;
    assert_eq!(found(&answer), [vec!["eve/wood@1: [0]"]]);
    // Without a token, only `all`.
    let (status, answer) = query(&app, None, body("mine")).await;
    assert_eq!(status, StatusCode::UNAUTHORIZED);
    assert_eq!(
        answer["error"],
        "link `mine` needs a token: it is about whose grammars are yours"
    );
}

async fn malformed_queries_are_refused_with_a_message(app: App) {
    for (body, message) in [
        (
            json!({"queries": [{"goals": []}]}),
            "query 0 has no goals: rules are found for shapes with open goals",
        ),
        (
            json!({"queries": [{"goals": ["a"]}, {"goals": ["b"], "tags": [""]}]}),
            "query 1: tags have 1 to 200 characters, not 0",
        ),
        (
            json!({"queries": [{"goals": ["a"], "colour": "red"}]}),
            "unknown field `colour`",
        ),
        (
            json!({"link": "this", "queries": []}),
            "unknown variant `this`",
        ),
    ] {
        let (status, answer) = query(&app, None, body.clone()).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}: {answer}");
        let error = answer["error"].as_str().unwrap();
        assert!(error.contains(message), "{body}: {error}");
    }
    let many: Vec<Value> = (0..1001).map(|_| json!({"goals": ["a"]})).collect();
    let (status, answer) = query(&app, None, json!({ "queries": many })).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(answer["error"], "1001 queries in one request; at most 1000");
    let (status, answer) = query(&app, None, json!({"queries": []})).await;
    assert_eq!(
        (status, answer["answers"].clone()),
        (StatusCode::OK, json!([]))
    );
}

on_both_backends!(
    rules_are_found_by_goals_tags_and_attributes_and_negations_rule_some_out,
    only_the_newest_version_answers_and_local_goals_are_never_offered,
    the_newest_version_not_yanked_answers,
    link_modes_choose_whose_grammars_answer,
    malformed_queries_are_refused_with_a_message,
);
