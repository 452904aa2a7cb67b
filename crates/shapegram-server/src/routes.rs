//! The HTTP API (`/api/v1/…`): handlers, their request and answer bodies, and their OpenAPI
//! descriptions.

use axum::Json;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use utoipa::openapi::schema::{Object, ObjectBuilder, Type};
use utoipa::{IntoParams, ToSchema};

use crate::AppState;
use crate::accounts::{self, MAX_ACCOUNT_NAME, MAX_GRAMMAR_NAME, MAX_PASSWORD, MIN_PASSWORD};
use crate::error::{ApiError, ErrorBody};
use crate::extract::{ApiPath, ApiQuery, Caller, JsonBody, OptionalJsonBody, Signed};
use crate::grammars::{self, MAX_GRAMMAR_BYTES, Problem};
use crate::policy::{self, Action};
use crate::preview::{Glb, PreviewError};
use crate::store::*;
use crate::tokens;

type ApiResult<T> = Result<T, ApiError>;

/// The canonical form of an account's name (valid since sign-up).
fn canon(account: &Account) -> String {
    accounts::canon(&account.name)
}

/// The canonical owner and grammar names of a path; names that cannot exist are not found.
fn grammar_path(owner: &str, name: &str) -> ApiResult<(String, String)> {
    let owner = accounts::canonical_name("account", owner, MAX_ACCOUNT_NAME)
        .map_err(|_| ApiError::not_found())?;
    let name = accounts::canonical_name("grammar", name, MAX_GRAMMAR_NAME)
        .map_err(|_| ApiError::not_found())?;
    Ok((owner, name))
}

/// A version's number, written as the API writes it (`+1` and `01` are not version 1).
fn version_number(version: &str) -> ApiResult<i64> {
    if version.starts_with('0') || !version.bytes().all(|b| b.is_ascii_digit()) {
        return Err(ApiError::not_found());
    }
    version.parse().map_err(|_| ApiError::not_found())
}

// ---------------------------------------------------------------------------------------------
// Accounts and tokens

/// Name and password, to sign up or log in.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct Credentials {
    /// ASCII letters, digits, `-` and `_`, starting with a letter; at most 39 characters.
    #[schema(min_length = 1, max_length = 39, pattern = "^[A-Za-z][A-Za-z0-9_-]*$")]
    pub name: String,
    /// 8 to 1,024 characters.
    #[schema(min_length = 8, max_length = 1024)]
    pub password: String,
}

/// An account.
#[derive(Serialize, ToSchema)]
pub struct AccountBody {
    pub name: String,
}

/// A token's name, to create one.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct TokenRequest {
    /// What the token is for (`laptop`, `ci`): 1 to 100 characters, none a control character.
    #[schema(
        min_length = 1,
        max_length = 100,
        pattern = "^[^\\u0000-\\u001F\\u007F-\\u009F]*$"
    )]
    pub name: String,
}

/// A new token: the secret is shown this once and never again.
#[derive(Serialize, ToSchema)]
pub struct NewTokenBody {
    /// The secret: send it as `Authorization: Bearer <token>`.
    pub token: String,
    #[serde(flatten)]
    pub info: TokenInfo,
}

/// Signs up: creates an account.
#[utoipa::path(post, path = "/api/v1/accounts", tag = "accounts", request_body = Credentials,
    responses((status = 201, body = AccountBody), (status = 400, body = ErrorBody),
        (status = 409, description = "the name is taken", body = ErrorBody),
        (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn sign_up(
    State(state): State<AppState>,
    JsonBody(c): JsonBody<Credentials>,
) -> ApiResult<(StatusCode, Json<AccountBody>)> {
    let canon = accounts::canonical_name("account", &c.name, MAX_ACCOUNT_NAME)
        .map_err(ApiError::bad_request)?;
    if !(MIN_PASSWORD..=MAX_PASSWORD).contains(&c.password.chars().count()) {
        return Err(ApiError::bad_request(format!(
            "a password has {MIN_PASSWORD} to {MAX_PASSWORD} characters"
        )));
    }
    let hash = state
        .passwords
        .hash(c.password)
        .await
        .map_err(ApiError::internal)?;
    let account = state.store.create_account(&c.name, &canon, &hash).await?;
    Ok((
        StatusCode::CREATED,
        Json(AccountBody { name: account.name }),
    ))
}

async fn new_token(state: &AppState, account: &Account, name: &str) -> ApiResult<NewTokenBody> {
    let token = tokens::generate().map_err(ApiError::internal)?;
    let prefix = tokens::display_prefix(&token);
    let info = state
        .store
        .create_token(NewToken {
            account: account.id,
            name,
            hash: tokens::hash(&token),
            prefix: &prefix,
        })
        .await?;
    Ok(NewTokenBody { token, info })
}

/// Logs in: checks the password and gives a new API token (named `login`).
#[utoipa::path(post, path = "/api/v1/login", tag = "accounts", request_body = Credentials,
    responses((status = 200, body = NewTokenBody), (status = 400, body = ErrorBody),
        (status = 401, description = "wrong name or password", body = ErrorBody),
        (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn login(
    State(state): State<AppState>,
    JsonBody(c): JsonBody<Credentials>,
) -> ApiResult<Json<NewTokenBody>> {
    let wrong = || ApiError::unauthorized("wrong name or password");
    let canon = accounts::canonical_name("account", &c.name, MAX_ACCOUNT_NAME).ok();
    let found = match &canon {
        Some(canon) if c.password.chars().count() <= MAX_PASSWORD => {
            state.store.account_for_login(canon).await?
        }
        _ => return Err(wrong()),
    };
    let (account, phc) = match found {
        Some((account, phc)) => (Some(account), Some(phc)),
        None => (None, None),
    };
    let rehash = phc.as_deref().is_some_and(accounts::needs_rehash);
    if !state.passwords.verify(c.password.clone(), phc).await {
        return Err(wrong());
    }
    let account = account.ok_or_else(wrong)?;
    if rehash {
        // Stored with weaker parameters than today's: hash again while the password is known.
        let hash = state
            .passwords
            .hash(c.password)
            .await
            .map_err(ApiError::internal)?;
        state.store.set_password_hash(account.id, &hash).await?;
    }
    Ok(Json(new_token(&state, &account, "login").await?))
}

/// The account of the token.
#[utoipa::path(get, path = "/api/v1/me", tag = "accounts", security(("bearer" = [])),
    responses((status = 200, body = AccountBody), (status = 401, body = ErrorBody)))]
pub async fn me(Signed(account): Signed) -> Json<AccountBody> {
    Json(AccountBody { name: account.name })
}

/// Creates an API token.
#[utoipa::path(post, path = "/api/v1/tokens", tag = "accounts", security(("bearer" = [])),
    request_body = TokenRequest,
    responses((status = 201, body = NewTokenBody), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody), (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn create_token(
    State(state): State<AppState>,
    Signed(account): Signed,
    JsonBody(request): JsonBody<TokenRequest>,
) -> ApiResult<(StatusCode, Json<NewTokenBody>)> {
    let n = request.name.chars().count();
    if n == 0 || n > 100 || request.name.chars().any(char::is_control) {
        return Err(ApiError::bad_request(
            "a token name has 1 to 100 characters, none a control character",
        ));
    }
    let body = new_token(&state, &account, &request.name).await?;
    Ok((StatusCode::CREATED, Json(body)))
}

/// The caller's tokens, without their secrets.
#[utoipa::path(get, path = "/api/v1/tokens", tag = "accounts", security(("bearer" = [])),
    responses((status = 200, body = Vec<TokenInfo>), (status = 401, body = ErrorBody)))]
pub async fn list_tokens(
    State(state): State<AppState>,
    Signed(account): Signed,
) -> ApiResult<Json<Vec<TokenInfo>>> {
    Ok(Json(state.store.list_tokens(account.id).await?))
}

/// Revokes one of the caller's tokens: it fails from the next request on.
#[utoipa::path(delete, path = "/api/v1/tokens/{id}", tag = "accounts", security(("bearer" = [])),
    params(("id" = i64, Path, description = "the token's id")),
    responses((status = 204), (status = 401, body = ErrorBody),
        (status = 404, description = "no such token of the caller's", body = ErrorBody)))]
pub async fn revoke_token(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath(id): ApiPath<String>,
) -> ApiResult<StatusCode> {
    let id: i64 = id.parse().map_err(|_| ApiError::not_found())?;
    if state.store.revoke_token(account.id, id).await? {
        Ok(StatusCode::NO_CONTENT)
    } else {
        Err(ApiError::not_found())
    }
}

// ---------------------------------------------------------------------------------------------
// Friends

/// Where a friendship stands.
#[derive(Serialize, ToSchema)]
pub struct FriendState {
    /// `requested` (waiting for the other) or `friends`.
    pub state: &'static str,
}

/// The caller's friends and pending requests.
#[utoipa::path(get, path = "/api/v1/friends", tag = "friends", security(("bearer" = [])),
    responses((status = 200, body = Friends), (status = 401, body = ErrorBody)))]
pub async fn friends(
    State(state): State<AppState>,
    Signed(account): Signed,
) -> ApiResult<Json<Friends>> {
    Ok(Json(state.store.friends(account.id).await?))
}

/// Asks `user` to be friends (or accepts, when `user` asked first). Friends see each other's
/// friends-only grammars.
#[utoipa::path(post, path = "/api/v1/friends/{user}", tag = "friends", security(("bearer" = [])),
    params(("user" = String, Path)),
    responses((status = 200, body = FriendState), (status = 401, body = ErrorBody),
        (status = 404, description = "no such account", body = ErrorBody)))]
pub async fn request_friend(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath(user): ApiPath<String>,
) -> ApiResult<Json<FriendState>> {
    let user = accounts::canonical_name("account", &user, MAX_ACCOUNT_NAME)
        .map_err(|_| ApiError::not_found())?;
    match state.store.request_friend(account.id, &user).await? {
        FriendRequest::Requested => Ok(Json(FriendState { state: "requested" })),
        FriendRequest::Friends => Ok(Json(FriendState { state: "friends" })),
        FriendRequest::NoSuchAccount => Err(ApiError::not_found()),
    }
}

/// Accepts the friend request `user` sent.
#[utoipa::path(post, path = "/api/v1/friends/{user}/accept", tag = "friends",
    security(("bearer" = [])), params(("user" = String, Path)),
    responses((status = 200, body = FriendState), (status = 401, body = ErrorBody),
        (status = 404, description = "no pending request from user", body = ErrorBody)))]
pub async fn accept_friend(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath(user): ApiPath<String>,
) -> ApiResult<Json<FriendState>> {
    let user = accounts::canonical_name("account", &user, MAX_ACCOUNT_NAME)
        .map_err(|_| ApiError::not_found())?;
    if state.store.accept_friend(account.id, &user).await? {
        Ok(Json(FriendState { state: "friends" }))
    } else {
        Err(ApiError::not_found())
    }
}

/// Ends a friendship, or withdraws or declines a request.
#[utoipa::path(delete, path = "/api/v1/friends/{user}", tag = "friends",
    security(("bearer" = [])), params(("user" = String, Path)),
    responses((status = 204), (status = 401, body = ErrorBody), (status = 404, body = ErrorBody)))]
pub async fn remove_friend(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath(user): ApiPath<String>,
) -> ApiResult<StatusCode> {
    let user = accounts::canonical_name("account", &user, MAX_ACCOUNT_NAME)
        .map_err(|_| ApiError::not_found())?;
    if state.store.remove_friend(account.id, &user).await? {
        Ok(StatusCode::NO_CONTENT)
    } else {
        Err(ApiError::not_found())
    }
}

// ---------------------------------------------------------------------------------------------
// Grammars

/// Filters of the grammar list.
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct ListQuery {
    /// Only this account's grammars.
    pub owner: Option<String>,
}

/// Lists the grammars the caller may see (at most 1,000), by owner and name.
#[utoipa::path(get, path = "/api/v1/grammars", tag = "grammars", params(ListQuery),
    security((), ("bearer" = [])),
    responses((status = 200, body = Vec<GrammarSummary>), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody)))]
pub async fn list_grammars(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiQuery(query): ApiQuery<ListQuery>,
) -> ApiResult<Json<Vec<GrammarSummary>>> {
    let owner = match &query.owner {
        Some(owner) => match accounts::canonical_name("account", owner, MAX_ACCOUNT_NAME) {
            Ok(owner) => Some(owner),
            Err(_) => return Ok(Json(Vec::new())),
        },
        None => None,
    };
    let list = state
        .store
        .list_grammars(Viewer::of(caller.as_ref()), owner.as_deref())
        .await?;
    Ok(Json(list))
}

/// Results per search page unless `per_page` says otherwise.
pub const SEARCH_PAGE: u32 = 50;
/// The most results a search page has.
pub const MAX_SEARCH_PAGE: u32 = 100;
/// The last page a search reaches (the database skips the pages before it one row at a time).
pub const MAX_SEARCH_PAGES: u32 = 10_000;

/// What to search for; every filter is optional and all given must hold.
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct SearchParams {
    /// A goal the grammar provides: its current version (the newest not yanked) has a rule for it (`fulfills(NAME)`,
    /// indexed as `g:NAME`). Goal names are matched exactly: 1 to 100 characters, none a control
    /// character.
    #[param(
        min_length = 1,
        max_length = 100,
        pattern = "^[^\\u0000-\\u001F\\u007F-\\u009F]*$"
    )]
    pub goal: Option<String>,
    /// A tag the grammar's rules apply to: its current version has a rule for shapes with it
    /// (`is(NAME)`, indexed as `t:NAME`). As long as a goal name.
    #[param(
        min_length = 1,
        max_length = 100,
        pattern = "^[^\\u0000-\\u001F\\u007F-\\u009F]*$"
    )]
    pub tag: Option<String>,
    /// Text the grammar's name contains (upper and lower case, `-` and `_` alike), at most 64
    /// characters; empty: any name.
    #[param(max_length = 64)]
    pub q: Option<String>,
    /// Only this account's grammars.
    pub owner: Option<String>,
    /// The page, from 1 (the default) to 10,000.
    #[param(minimum = 1, maximum = 10_000)]
    pub page: Option<u32>,
    /// Results per page, from 1 to 100; 50 by default.
    #[param(minimum = 1, maximum = 100)]
    pub per_page: Option<u32>,
}

/// A page of search results.
#[derive(Serialize, ToSchema)]
pub struct SearchResults {
    /// The grammars found, by owner and name.
    pub grammars: Vec<GrammarSummary>,
    pub page: u32,
    pub per_page: u32,
    /// The next page's number, when there are more results.
    pub next_page: Option<u32>,
}

/// A goal or tag name to search for: what a grammar could name.
fn search_key(what: &str, name: &Option<String>) -> ApiResult<Option<String>> {
    match name {
        None => Ok(None),
        Some(name) => {
            let n = name.chars().count();
            if n == 0 || n > 100 || name.chars().any(char::is_control) {
                Err(ApiError::bad_request(format!(
                    "a {what} name has 1 to 100 characters, none a control character"
                )))
            } else {
                Ok(Some(name.clone()))
            }
        }
    }
}

/// Searches the grammars the caller may see by the goals and tags of their current version's
/// rules (the newest not yanked; a grammar with every version yanked is not found), their name
/// and owner: a page of them, by owner and name.
#[utoipa::path(get, path = "/api/v1/search", tag = "grammars", params(SearchParams),
    security((), ("bearer" = [])),
    responses((status = 200, body = SearchResults), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody)))]
pub async fn search(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiQuery(params): ApiQuery<SearchParams>,
) -> ApiResult<Json<SearchResults>> {
    let goal = search_key("goal", &params.goal)?;
    let tag = search_key("tag", &params.tag)?;
    let page = params.page.unwrap_or(1);
    if !(1..=MAX_SEARCH_PAGES).contains(&page) {
        return Err(ApiError::bad_request(format!(
            "page is a number from 1 to {MAX_SEARCH_PAGES}"
        )));
    }
    let per_page = params.per_page.unwrap_or(SEARCH_PAGE);
    if !(1..=MAX_SEARCH_PAGE).contains(&per_page) {
        return Err(ApiError::bad_request(format!(
            "per_page is a number from 1 to {MAX_SEARCH_PAGE}"
        )));
    }
    let name = match params.q.as_deref().filter(|q| !q.is_empty()) {
        Some(q) if q.chars().count() > MAX_GRAMMAR_NAME => {
            return Err(ApiError::bad_request(format!(
                "q has at most {MAX_GRAMMAR_NAME} characters (the longest name)"
            )));
        }
        Some(q) => Some(accounts::canon(q)),
        None => None,
    };
    let owner = match &params.owner {
        Some(owner) => match accounts::canonical_name("account", owner, MAX_ACCOUNT_NAME) {
            Ok(owner) => Some(owner),
            Err(_) => {
                return Ok(Json(SearchResults {
                    grammars: Vec::new(),
                    page,
                    per_page,
                    next_page: None,
                }));
            }
        },
        None => None,
    };
    // One more than the page holds tells whether another page follows.
    let mut grammars = state
        .store
        .search_grammars(
            Viewer::of(caller.as_ref()),
            SearchQuery {
                goal: goal.as_deref(),
                tag: tag.as_deref(),
                name: name.as_deref(),
                owner_canon: owner.as_deref(),
                limit: i64::from(per_page) + 1,
                offset: i64::from(page - 1) * i64::from(per_page),
            },
        )
        .await?;
    let more = grammars.len() > per_page as usize;
    grammars.truncate(per_page as usize);
    Ok(Json(SearchResults {
        grammars,
        page,
        per_page,
        next_page: (more && page < MAX_SEARCH_PAGES).then_some(page + 1),
    }))
}

/// A grammar.
#[utoipa::path(get, path = "/api/v1/grammars/{owner}/{name}", tag = "grammars",
    security((), ("bearer" = [])), params(("owner" = String, Path), ("name" = String, Path)),
    responses((status = 200, body = GrammarSummary), (status = 401, body = ErrorBody),
        (status = 404, description = "no such grammar, or not visible to the caller", body = ErrorBody)))]
pub async fn grammar(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath((owner, name)): ApiPath<(String, String)>,
) -> ApiResult<Json<GrammarSummary>> {
    let (owner, name) = grammar_path(&owner, &name)?;
    state
        .store
        .grammar(Viewer::of(caller.as_ref()), &owner, &name)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// A grammar's versions, oldest first.
#[utoipa::path(get, path = "/api/v1/grammars/{owner}/{name}/versions", tag = "grammars",
    security((), ("bearer" = [])), params(("owner" = String, Path), ("name" = String, Path)),
    responses((status = 200, body = Vec<VersionInfo>), (status = 401, body = ErrorBody),
        (status = 404, body = ErrorBody)))]
pub async fn versions(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath((owner, name)): ApiPath<(String, String)>,
) -> ApiResult<Json<Vec<VersionInfo>>> {
    let (owner, name) = grammar_path(&owner, &name)?;
    state
        .store
        .versions(Viewer::of(caller.as_ref()), &owner, &name)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// A version's text and hash. Versions never change.
#[utoipa::path(get, path = "/api/v1/grammars/{owner}/{name}/versions/{version}", tag = "grammars",
    security((), ("bearer" = [])),
    params(("owner" = String, Path), ("name" = String, Path), ("version" = i64, Path, minimum = 1)),
    responses((status = 200, body = VersionText), (status = 401, body = ErrorBody),
        (status = 404, body = ErrorBody)))]
pub async fn version(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath((owner, name, version)): ApiPath<(String, String, String)>,
) -> ApiResult<Json<VersionText>> {
    let (owner, name) = grammar_path(&owner, &name)?;
    let version = version_number(&version)?;
    state
        .store
        .version(Viewer::of(caller.as_ref()), &owner, &name, version)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// A version's rule index: per rule, the keys a shape must have and must lack.
#[utoipa::path(get, path = "/api/v1/grammars/{owner}/{name}/versions/{version}/rules",
    tag = "grammars", security((), ("bearer" = [])),
    params(("owner" = String, Path), ("name" = String, Path), ("version" = i64, Path, minimum = 1)),
    responses((status = 200, body = Vec<IndexedRule>), (status = 401, body = ErrorBody),
        (status = 404, body = ErrorBody)))]
pub async fn version_rules(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath((owner, name, version)): ApiPath<(String, String, String)>,
) -> ApiResult<Json<Vec<IndexedRule>>> {
    let (owner, name) = grammar_path(&owner, &name)?;
    let version = version_number(&version)?;
    state
        .store
        .version_rules(Viewer::of(caller.as_ref()), &owner, &name, version)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// Options of a preview.
#[derive(Deserialize, IntoParams)]
#[into_params(parameter_in = Query)]
#[serde(deny_unknown_fields)]
pub struct PreviewQuery {
    /// The seed of every random choice (default 0, as `shapegram derive`): 0 to 2^64 - 1.
    #[param(schema_with = seed_schema)]
    pub seed: Option<u64>,
}

/// Any `u64`: utoipa would describe it as an `int64`, which stops at 2^63 - 1.
fn seed_schema() -> Object {
    ObjectBuilder::new()
        .schema_type(Type::Integer)
        .description(Some(
            "The seed of every random choice (default 0, as `shapegram derive`): 0 to 2^64 - 1.",
        ))
        .minimum(Some(0))
        .maximum(Some(u64::MAX))
        .build()
}

/// A version derived on its own, as `shapegram derive` would with the same seed: a GLB, made
/// by a worker process under limits of steps, time and memory that reads no files. Kept once
/// made, since versions never change.
#[utoipa::path(get, path = "/api/v1/grammars/{owner}/{name}/versions/{version}/preview",
    tag = "grammars", security((), ("bearer" = [])),
    params(("owner" = String, Path), ("name" = String, Path), ("version" = i64, Path, minimum = 1),
        PreviewQuery),
    responses(
        (status = 200, description = "the model", content_type = "model/gltf-binary", body = Glb),
        (status = 400, body = ErrorBody), (status = 401, body = ErrorBody),
        (status = 404, body = ErrorBody),
        (status = 422, description = "the grammar does not derive (a step or depth limit, a file it asks for): the message and the place", body = ErrorBody),
        (status = 503, description = "previews are off, every worker is busy (with Retry-After), or a time, memory or size limit stopped the worker: the message says which", body = ErrorBody)))]
pub async fn version_preview(
    State(state): State<AppState>,
    Caller(caller): Caller,
    ApiPath((owner, name, version)): ApiPath<(String, String, String)>,
    ApiQuery(query): ApiQuery<PreviewQuery>,
) -> Result<Response, Response> {
    let (owner, name) = grammar_path(&owner, &name).map_err(IntoResponse::into_response)?;
    let version = version_number(&version).map_err(IntoResponse::into_response)?;
    let found = state
        .store
        .version(Viewer::of(caller.as_ref()), &owner, &name, version)
        .await
        .map_err(|e| ApiError::from(e).into_response())?
        .ok_or_else(|| ApiError::not_found().into_response())?;
    let previews = state
        .previews
        .as_ref()
        .ok_or_else(|| PreviewError::Off.into_response())?;
    let glb = previews
        .glb(
            &found.name,
            &found.text,
            &found.info.sha256,
            query.seed.unwrap_or(0),
        )
        .await
        .map_err(IntoResponse::into_response)?;
    Ok(glb.into_response())
}

/// A version to publish.
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct PublishRequest {
    /// The goal grammar's text (at most 256 KiB), in either notation.
    pub text: String,
    /// Who may see the grammar from now on; omitted: unchanged (public for a new grammar).
    pub visibility: Option<Visibility>,
}

/// A published version.
#[derive(Serialize, ToSchema)]
pub struct Published {
    pub owner: String,
    pub name: String,
    #[serde(flatten)]
    pub info: VersionInfo,
    /// Number of rules indexed.
    pub rules: usize,
    pub warnings: Vec<Problem>,
}

/// Publishes a new version of a grammar of the caller's (created by its first version). The
/// text is checked with the engine's parser and compiler; every publish makes a new immutable
/// version, one past the latest.
#[utoipa::path(post, path = "/api/v1/grammars/{owner}/{name}/versions", tag = "grammars",
    security(("bearer" = [])), request_body = PublishRequest,
    params(("owner" = String, Path),
        ("name" = String, Path, min_length = 1, max_length = 64, pattern = "^[A-Za-z][A-Za-z0-9_-]*$")),
    responses((status = 201, body = Published),
        (status = 400, body = ErrorBody), (status = 401, body = ErrorBody),
        (status = 403, description = "not the caller's namespace", body = ErrorBody),
        (status = 413, description = "the body is larger than 1 MiB or the grammar than 256 KiB", body = ErrorBody),
        (status = 422, description = "the grammar does not compile: diagnostics with lines and columns", body = ErrorBody)))]
pub async fn publish(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath((owner, name)): ApiPath<(String, String)>,
    JsonBody(request): JsonBody<PublishRequest>,
) -> ApiResult<(StatusCode, Json<Published>)> {
    let me = canon(&account);
    let owner_canon =
        accounts::canonical_name("account", &owner, MAX_ACCOUNT_NAME).map_err(|_| {
            ApiError::forbidden(format!(
                "{} may publish only under their own name",
                account.name
            ))
        })?;
    policy::check(
        &account,
        &me,
        Action::Publish {
            owner_canon: &owner_canon,
        },
    )?;
    let canon_name = accounts::canonical_name("grammar", &name, MAX_GRAMMAR_NAME)
        .map_err(ApiError::bad_request)?;
    if request.text.len() > MAX_GRAMMAR_BYTES {
        return Err(ApiError::new(
            StatusCode::PAYLOAD_TOO_LARGE,
            format!("a grammar has at most {MAX_GRAMMAR_BYTES} bytes"),
        ));
    }
    let full_name = format!("{}/{name}", account.name);
    let text = request.text;
    let (checked, text) = tokio::task::spawn_blocking(move || {
        let checked = grammars::check(&full_name, &text);
        (checked, text)
    })
    .await
    .map_err(|_| {
        ApiError::new(
            StatusCode::UNPROCESSABLE_ENTITY,
            "the grammar could not be checked (the checker failed on it)",
        )
    })?;
    let checked = checked.map_err(|diagnostics| ApiError {
        status: StatusCode::UNPROCESSABLE_ENTITY,
        message: format!("{name} does not compile"),
        diagnostics,
    })?;
    let sha256 = tokens::sha256_hex(text.as_bytes());
    let info = state
        .store
        .publish(NewVersion {
            owner: &account,
            name: &name,
            canon: &canon_name,
            visibility: request.visibility,
            text: &text,
            sha256: &sha256,
            rules: &checked.rules,
        })
        .await?;
    Ok((
        StatusCode::CREATED,
        Json(Published {
            owner: account.name.clone(),
            name,
            info,
            rules: checked.rules.len(),
            warnings: checked.warnings,
        }),
    ))
}

// ---------------------------------------------------------------------------------------------
// Yanking

/// Largest yank reason, in characters.
pub const MAX_YANK_REASON: usize = 1000;

/// Why a version is yanked (the body may be left out).
#[derive(Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct YankRequest {
    /// At most 1,000 characters; line breaks allowed, no other control characters.
    #[schema(
        max_length = 1000,
        pattern = "^[^\\u0000-\\u0009\\u000B-\\u001F\\u007F-\\u009F]*$"
    )]
    pub reason: Option<String>,
}

/// The grammar's canonical name, for an action only its owner may do (`action`, given the
/// owner's canonical name): 404 when the caller may not see the grammar (as if it did not
/// exist), 403 when they may but the policy refuses.
pub(crate) async fn owned_grammar(
    state: &AppState,
    account: &Account,
    owner: &str,
    name: &str,
    action: for<'x> fn(&'x str) -> Action<'x>,
) -> ApiResult<String> {
    let (owner_canon, name_canon) = grammar_path(owner, name)?;
    let me = canon(account);
    if owner_canon != me {
        let viewer = Viewer::of(Some(account));
        if state
            .store
            .grammar(viewer, &owner_canon, &name_canon)
            .await?
            .is_none()
        {
            return Err(ApiError::not_found());
        }
    }
    policy::check(account, &me, action(&owner_canon))?;
    Ok(name_canon)
}

/// Yanks a version: it stays fetchable by its number (lock files naming it keep working) but
/// is offered to no new resolution. Yanking a yanked version changes nothing.
#[utoipa::path(post, path = "/api/v1/grammars/{owner}/{name}/versions/{version}/yank",
    tag = "grammars", security(("bearer" = [])), request_body(content = Option<YankRequest>,
        description = "optional: why"),
    params(("owner" = String, Path), ("name" = String, Path), ("version" = i64, Path, minimum = 1)),
    responses((status = 200, body = VersionInfo), (status = 400, body = ErrorBody),
        (status = 401, body = ErrorBody),
        (status = 403, description = "not the grammar's owner", body = ErrorBody),
        (status = 404, body = ErrorBody), (status = 413, description = "the body is larger than 1 MiB", body = ErrorBody)))]
pub async fn yank(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath((owner, name, version)): ApiPath<(String, String, String)>,
    OptionalJsonBody(request): OptionalJsonBody<YankRequest>,
) -> ApiResult<Json<VersionInfo>> {
    let name = owned_grammar(&state, &account, &owner, &name, |owner_canon| {
        Action::Yank { owner_canon }
    })
    .await?;
    let version = version_number(&version)?;
    let reason = request.and_then(|r| r.reason);
    if let Some(reason) = &reason
        && (reason.chars().count() > MAX_YANK_REASON
            || reason.chars().any(|c| c.is_control() && c != '\n'))
    {
        return Err(ApiError::bad_request(format!(
            "a yank reason has at most {MAX_YANK_REASON} characters and no control characters but line breaks"
        )));
    }
    state
        .store
        .yank(&account, &name, version, reason.as_deref())
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}

/// Withdraws a yank: the version is offered again. Unyanking a version not yanked changes
/// nothing.
#[utoipa::path(post, path = "/api/v1/grammars/{owner}/{name}/versions/{version}/unyank",
    tag = "grammars", security(("bearer" = [])),
    params(("owner" = String, Path), ("name" = String, Path), ("version" = i64, Path, minimum = 1)),
    responses((status = 200, body = VersionInfo), (status = 401, body = ErrorBody),
        (status = 403, description = "not the grammar's owner", body = ErrorBody),
        (status = 404, body = ErrorBody)))]
pub async fn unyank(
    State(state): State<AppState>,
    Signed(account): Signed,
    ApiPath((owner, name, version)): ApiPath<(String, String, String)>,
) -> ApiResult<Json<VersionInfo>> {
    let name = owned_grammar(&state, &account, &owner, &name, |owner_canon| {
        Action::Yank { owner_canon }
    })
    .await?;
    let version = version_number(&version)?;
    state
        .store
        .unyank(&account, &name, version)
        .await?
        .map(Json)
        .ok_or_else(ApiError::not_found)
}
