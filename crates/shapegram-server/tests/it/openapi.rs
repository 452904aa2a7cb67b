//! The OpenAPI document says what the extractors and handlers do, so that clients generated from
//! it (and Schemathesis, `schemathesis/run.sh`) send what the server takes.

use crate::common;

use common::{App, Backend};
use serde_json::{Value, json};

async fn document() -> Value {
    let app = App::on(Backend::Sqlite)
        .await
        .expect("SQLite is always there");
    let (status, doc) = app.get("/openapi.json", None).await;
    assert_eq!(status, 200);
    doc
}

fn parameter<'a>(doc: &'a Value, method: &str, path: &str, name: &str) -> &'a Value {
    doc["paths"][path][method]["parameters"]
        .as_array()
        .unwrap_or_else(|| panic!("{method} {path} has parameters"))
        .iter()
        .find(|p| p["name"] == name)
        .unwrap_or_else(|| panic!("{method} {path} has the parameter {name}"))
}

/// Found by Schemathesis: the query parameters were documented as required path parameters.
#[tokio::test]
async fn query_parameters_are_optional_and_in_the_query() {
    let doc = document().await;
    let preview = "/api/v1/grammars/{owner}/{name}/versions/{version}/preview";
    for (path, name) in [
        ("/api/v1/grammars", "owner"),
        ("/api/v1/search", "goal"),
        ("/api/v1/search", "tag"),
        ("/api/v1/search", "q"),
        ("/api/v1/search", "owner"),
        ("/api/v1/search", "page"),
        ("/api/v1/search", "per_page"),
        (preview, "seed"),
    ] {
        let p = parameter(&doc, "get", path, name);
        assert_eq!(
            (&p["in"], &p["required"]),
            (&json!("query"), &json!(false)),
            "{path} {name}"
        );
    }
    let per_page = &parameter(&doc, "get", "/api/v1/search", "per_page")["schema"];
    assert_eq!(
        (&per_page["minimum"], &per_page["maximum"]),
        (&json!(1), &json!(100))
    );
    let seed = &parameter(&doc, "get", preview, "seed")["schema"];
    assert_eq!(
        (&seed["minimum"], &seed["maximum"]),
        (&json!(0), &json!(u64::MAX))
    );
}

/// Found by Schemathesis: limits the handlers enforce with a 400 were not in the document, so
/// data it called valid was refused.
#[tokio::test]
async fn limits_the_handlers_enforce_are_documented() {
    let doc = document().await;
    let schemas = &doc["components"]["schemas"];
    let credentials = &schemas["Credentials"]["properties"];
    assert_eq!(credentials["name"]["maxLength"], json!(39));
    assert_eq!(
        credentials["name"]["pattern"],
        json!("^[A-Za-z][A-Za-z0-9_-]*$")
    );
    assert_eq!(
        (
            &credentials["password"]["minLength"],
            &credentials["password"]["maxLength"]
        ),
        (&json!(8), &json!(1024))
    );
    assert_eq!(
        schemas["TokenRequest"]["properties"]["name"]["minLength"],
        json!(1)
    );
    let goals = &schemas["ShapeQuery"]["properties"]["goals"];
    assert_eq!(
        (&goals["minItems"], &goals["maxItems"]),
        (&json!(1), &json!(100))
    );
    assert_eq!(goals["items"]["maxLength"], json!(200));
    assert_eq!(
        schemas["QueryRequest"]["properties"]["queries"]["maxItems"],
        json!(1000)
    );
    assert_eq!(
        schemas["RenameRequest"]["properties"]["name"]["maxLength"],
        json!(64)
    );
    let sha256 = parameter(&doc, "get", "/api/v1/texts/{sha256}", "sha256");
    assert_eq!(sha256["schema"]["pattern"], json!("^[0-9A-Fa-f]{64}$"));
    for (method, path) in [
        ("get", "/api/v1/grammars/{owner}/{name}/versions/{version}"),
        (
            "get",
            "/api/v1/grammars/{owner}/{name}/versions/{version}/rules",
        ),
        (
            "get",
            "/api/v1/grammars/{owner}/{name}/versions/{version}/preview",
        ),
        (
            "post",
            "/api/v1/grammars/{owner}/{name}/versions/{version}/yank",
        ),
        (
            "post",
            "/api/v1/grammars/{owner}/{name}/versions/{version}/unyank",
        ),
    ] {
        assert_eq!(
            parameter(&doc, method, path, "version")["schema"]["minimum"],
            json!(1),
            "{path}"
        );
    }
}

/// Found by Schemathesis: the yank body was documented as required, and bodies over the limit
/// answered an undocumented 413.
#[tokio::test]
async fn request_bodies_document_whether_required_and_the_size_limit() {
    let doc = document().await;
    let mut bodies = 0;
    for (path, item) in doc["paths"].as_object().unwrap() {
        for (method, operation) in item.as_object().unwrap() {
            let Some(body) = operation.get("requestBody") else {
                continue;
            };
            bodies += 1;
            let optional = path.ends_with("/yank");
            assert_eq!(
                body.get("required").is_none_or(|r| r == false),
                optional,
                "{method} {path}"
            );
            assert!(
                operation["responses"].get("413").is_some(),
                "{method} {path} documents 413"
            );
        }
    }
    assert_eq!(bodies, 7);
}
