//! Renaming a grammar, and reading a version by the hash of its text. Derivations find rules by
//! goals, not names, and lock files fetch their versions by hash (`GET /api/v1/texts/{sha256}`),
//! so a rename breaks no one: not a future resolution, not an existing lock.

use axum::Json;
use axum::extract::State;
use serde::Deserialize;
use utoipa::ToSchema;

use crate::AppState;
use crate::accounts::{self, MAX_GRAMMAR_NAME};
use crate::error::{ApiError, ErrorBody};
use crate::extract::{ApiPath, Caller, JsonBody, Signed};
use crate::policy::Action;
use crate::routes::owned_grammar;
use crate::store::{GrammarSummary, VersionText, Viewer};

/// A grammar's new name.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RenameRequest {
    /// ASCII letters, digits, `-` and `_`, starting with a letter; at most 64 characters.
    #[schema(min_length = 1, max_length = 64, pattern = "^[A-Za-z][A-Za-z0-9_-]*$")]
    pub name: String,
}

/// Renames a grammar. Its versions keep their numbers, texts and hashes; rule queries and lock
/// files never went by its name.
#[utoipa::path(post, path = "/api/v1/grammars/{owner}/{name}/rename", tag = "grammars",
    security(("bearer" = [])), request_body = RenameRequest,
    params(("owner" = String, Path), ("name" = String, Path)),
    responses((status = 200, body = GrammarSummary), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody),
        (status = 403, description = "not the grammar's owner", body = ErrorBody),
        (status = 404, body = ErrorBody),
        (status = 409, description = "the owner has a grammar of that name", body = ErrorBody),
        (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn rename(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath((owner, name)): ApiPath<(String, String)>,
    JsonBody(request): JsonBody<RenameRequest>,
) -> Result<Json<GrammarSummary>, ApiError> {
    let canon = owned_grammar(&state, &account, &owner, &name, |owner_canon| {
        Action::Rename { owner_canon }
    })
    .await?;
    let new_canon = accounts::canonical_name("grammar", &request.name, MAX_GRAMMAR_NAME)
        .map_err(ApiError::bad_request)?;
    state
        .store
        .rename_grammar(&account, &canon, &request.name, &new_canon)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// The newest version the caller may see whose text has this SHA-256, under its grammar's
/// present name: how lock files fetch what they pin.
#[utoipa::path(get, path = "/api/v1/texts/{sha256}", tag = "grammars",
    security((), ("bearer" = [])),
    params(("sha256" = String, Path, description = "64 hexadecimal digits",
        pattern = "^[0-9A-Fa-f]{64}$")),
    responses((status = 200, body = VersionText), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody), (status = 404, body = ErrorBody)))]
pub async fn text_by_sha256(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath(sha256): ApiPath<String>,
) -> Result<Json<VersionText>, ApiError> {
    if sha256.len() != 64 || !sha256.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(ApiError::bad_request("a SHA-256 is 64 hexadecimal digits"));
    }
    state
        .store
        .version_by_sha256(Viewer::of(caller.as_ref()), &sha256.to_ascii_lowercase())
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}
