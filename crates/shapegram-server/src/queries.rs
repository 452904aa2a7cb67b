//! Procedural rule queries (`POST /api/v1/queries`): which published rules may apply to shapes
//! with these goals, tags and attributes. The engine asks once per distinct combination its
//! shapes sought and found no local rule for, in batches; the store answers from the rule index
//! (see [`crate::store::Store::query_rules`]) and the engine evaluates the rest of each rule's
//! predicates (`if(…)`) itself, once it has the grammar.

use axum::Json;
use axum::extract::State;
use serde::Deserialize;
use utoipa::ToSchema;
use utoipa::openapi::schema::{Array, ArrayBuilder, ObjectBuilder, Type};

use crate::AppState;
use crate::error::{ApiError, ErrorBody};
use crate::extract::{Caller, JsonBody};
use crate::store::{Link, QueryAnswers, Viewer};

/// Most queries in one request.
pub const MAX_QUERIES: usize = 1000;
/// Most names in one list of a query.
pub const MAX_NAMES: usize = 100;
/// Longest goal, tag or attribute name, in characters.
pub const MAX_NAME_CHARS: usize = 200;

/// A batch of rule queries.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct QueryRequest {
    /// Whose grammars: `all` (the default: every grammar the caller may see), `friends` (the
    /// caller's and their friends'), `mine`. The last two need a token.
    #[serde(default)]
    pub link: Link,
    /// At most 1,000.
    #[schema(max_items = 1000)]
    pub queries: Vec<ShapeQuery>,
}

/// What one kind of shape has: rules are found whose goal, tag and attribute predicates hold.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ShapeQuery {
    /// Its open goals: 1 to 100 names.
    #[schema(schema_with = goal_names)]
    pub goals: Vec<String>,
    /// The goals it fulfilled: at most 100 names.
    #[serde(default)]
    #[schema(schema_with = names)]
    pub tags: Vec<String>,
    /// The names of its attributes: at most 100.
    #[serde(default)]
    #[schema(schema_with = names)]
    pub attributes: Vec<String>,
}

/// A list of at least `min_items` and at most [`MAX_NAMES`] names of 1 to [`MAX_NAME_CHARS`]
/// characters, none a control character.
fn name_list(min_items: usize) -> Array {
    let name = ObjectBuilder::new()
        .schema_type(Type::String)
        .min_length(Some(1))
        .max_length(Some(MAX_NAME_CHARS))
        .pattern(Some("^[^\\u0000-\\u001F\\u007F-\\u009F]*$"));
    ArrayBuilder::new()
        .items(name)
        .min_items(Some(min_items))
        .max_items(Some(MAX_NAMES))
        .build()
}

fn goal_names() -> Array {
    name_list(1)
}

fn names() -> Array {
    name_list(0)
}

impl ShapeQuery {
    /// The index keys of the query (see `docs/repository.md`, "The rule index").
    fn keys(&self) -> Vec<String> {
        let prefixed = |prefix: &'static str, names: &[String]| {
            names
                .iter()
                .map(move |n| format!("{prefix}:{n}"))
                .collect::<Vec<_>>()
        };
        let mut keys = prefixed("g", &self.goals);
        keys.extend(prefixed("t", &self.tags));
        keys.extend(prefixed("a", &self.attributes));
        keys.sort();
        keys.dedup();
        keys
    }

    fn check(&self, at: usize) -> Result<(), ApiError> {
        if self.goals.is_empty() {
            return Err(ApiError::bad_request(format!(
                "query {at} has no goals: rules are found for shapes with open goals"
            )));
        }
        for (what, names) in [
            ("goals", &self.goals),
            ("tags", &self.tags),
            ("attributes", &self.attributes),
        ] {
            if names.len() > MAX_NAMES {
                return Err(ApiError::bad_request(format!(
                    "query {at} has {} {what}; at most {MAX_NAMES}",
                    names.len()
                )));
            }
            if let Some(n) = names
                .iter()
                .map(|n| n.chars().count())
                .find(|n| !(1..=MAX_NAME_CHARS).contains(n))
            {
                return Err(ApiError::bad_request(format!(
                    "query {at}: {what} have 1 to {MAX_NAME_CHARS} characters, not {n}"
                )));
            }
            if names.iter().any(|n| n.chars().any(char::is_control)) {
                return Err(ApiError::bad_request(format!(
                    "query {at}: {what} have no control characters"
                )));
            }
        }
        Ok(())
    }
}

/// Finds the published rules that may apply to shapes: per query, the grammars (their current
/// versions: the newest not yanked) with rules whose goal, tag and attribute predicates hold for it, among those the
/// caller may see and the link mode admits.
#[utoipa::path(post, path = "/api/v1/queries", tag = "queries", request_body = QueryRequest,
    responses((status = 200, body = QueryAnswers), (status = 400, body = ErrorBody),
        (status = 401, description = "`friends` or `mine` without a token", body = ErrorBody),
        (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn query_rules(
    State(state): State<AppState>,
    Caller(caller): Caller,
    JsonBody(request): JsonBody<QueryRequest>,
) -> Result<Json<QueryAnswers>, ApiError> {
    if request.queries.len() > MAX_QUERIES {
        return Err(ApiError::bad_request(format!(
            "{} queries in one request; at most {MAX_QUERIES}",
            request.queries.len()
        )));
    }
    if caller.is_none() && request.link != Link::All {
        return Err(ApiError::unauthorized(format!(
            "link `{}` needs a token: it is about whose grammars are yours",
            request.link.as_str()
        )));
    }
    let mut keys = Vec::with_capacity(request.queries.len());
    for (at, query) in request.queries.iter().enumerate() {
        query.check(at)?;
        keys.push(query.keys());
    }
    let answers = state
        .store
        .query_rules(Viewer::of(caller.as_ref()), request.link, &keys)
        .await?;
    Ok(Json(answers))
}
