//! Procedural rule queries (`POST /api/v1/queries`): which published rules may apply to shapes
//! with these goals, tags and attributes. The engine asks once per distinct combination its
//! shapes sought and found no local rule for, in batches; the store answers from the rule index
//! (see [`crate::store::Store::query_rules`]) and the engine evaluates the rest of each rule's
//! predicates (`if(…)`) itself, once it has the grammar.

use axum::Json;
use axum::extract::State;
use serde::Deserialize;
use utoipa::ToSchema;

use crate::AppState;
use crate::error::{ApiError, ErrorBody};
use crate::extract::{Caller, JsonBody};
use crate::store::{Link, QueryAnswers, Viewer};

/// Most queries in one request.
pub const MAX_QUERIES: usize = 1000;
/// Most names in one list of a query.
pub const MAX_NAMES: usize = 100;
/// Longest goal, tag or attribute name, in bytes.
pub const MAX_NAME_BYTES: usize = 200;

/// A batch of rule queries.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct QueryRequest {
    /// Whose grammars: `all` (the default: every grammar the caller may see), `friends` (the
    /// caller's and their friends'), `mine`. The last two need a token.
    #[serde(default)]
    pub link: Link,
    /// At most 1,000.
    pub queries: Vec<ShapeQuery>,
}

/// What one kind of shape has: rules are found whose goal, tag and attribute predicates hold.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ShapeQuery {
    /// Its open goals (at least one).
    pub goals: Vec<String>,
    /// The goals it fulfilled.
    #[serde(default)]
    pub tags: Vec<String>,
    /// The names of its attributes.
    #[serde(default)]
    pub attributes: Vec<String>,
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
            if let Some(bad) = names
                .iter()
                .find(|n| n.is_empty() || n.len() > MAX_NAME_BYTES)
            {
                return Err(ApiError::bad_request(format!(
                    "query {at}: {what} have 1 to {MAX_NAME_BYTES} bytes, not {}",
                    bad.len()
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
        (status = 401, description = "`friends` or `mine` without a token", body = ErrorBody)))]
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
