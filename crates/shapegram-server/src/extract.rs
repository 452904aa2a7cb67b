//! Request extractors whose rejections are JSON errors: bodies (bounded, strict JSON, unknown
//! fields refused by the types), paths, queries, and the caller's bearer token.

use axum::body::Bytes;
use axum::extract::{FromRequest, FromRequestParts, Path, Query, Request};
use axum::http::header::AUTHORIZATION;
use axum::http::request::Parts;
use axum::http::{HeaderMap, StatusCode};
use percent_encoding::percent_decode_str;
use serde::de::DeserializeOwned;

use crate::error::ApiError;
use crate::store::Account;
use crate::tokens;
use crate::{AppState, MAX_BODY_BYTES};

/// A JSON object as the body. Too large: 413; not JSON, not UTF-8, not an object, wrong types or
/// unknown fields: 400.
pub struct JsonBody<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for JsonBody<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, ApiError> {
        let bytes = body_bytes(req, state).await?;
        parse_object(&bytes).map(JsonBody)
    }
}

/// A JSON body that may be left out (no bytes at all, or `null`, as the OpenAPI document's
/// optional body allows): `None` then; otherwise as [`JsonBody`].
pub struct OptionalJsonBody<T>(pub Option<T>);

impl<S: Send + Sync, T: DeserializeOwned> FromRequest<S> for OptionalJsonBody<T> {
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, ApiError> {
        let bytes = body_bytes(req, state).await?;
        if matches!(bytes.trim_ascii(), b"" | b"null") {
            return Ok(OptionalJsonBody(None));
        }
        parse_object(&bytes).map(|t| OptionalJsonBody(Some(t)))
    }
}

/// The body's bytes, at most [`MAX_BODY_BYTES`].
async fn body_bytes<S: Send + Sync>(req: Request, state: &S) -> Result<Bytes, ApiError> {
    Bytes::from_request(req, state).await.map_err(|e| {
        if e.status() == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::new(
                e.status(),
                format!("a request body has at most {MAX_BODY_BYTES} bytes"),
            )
        } else {
            ApiError::new(e.status(), e.body_text())
        }
    })
}

/// `bytes` as a JSON object of type `T`. serde would also read a struct from an array of its
/// fields in order (`["text", null]`), which the OpenAPI document does not allow.
fn parse_object<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, ApiError> {
    if bytes.trim_ascii_start().first() != Some(&b'{') {
        return Err(ApiError::bad_request(
            "invalid JSON body: expected an object `{…}`",
        ));
    }
    serde_json::from_slice(bytes)
        .map_err(|e| ApiError::bad_request(format!("invalid JSON body: {e}")))
}

/// Path parameters.
pub struct ApiPath<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned + Send> FromRequestParts<S> for ApiPath<T> {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Self, ApiError> {
        Path::<T>::from_request_parts(parts, state)
            .await
            .map(|Path(t)| ApiPath(t))
            .map_err(|e| ApiError::new(e.status(), e.body_text()))
    }
}

/// Query parameters; a query string that is not UTF-8 once percent-decoded is refused (400)
/// rather than read with replacement characters.
pub struct ApiQuery<T>(pub T);

impl<S: Send + Sync, T: DeserializeOwned> FromRequestParts<S> for ApiQuery<T> {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &S) -> Result<Self, ApiError> {
        if let Some(query) = parts.uri.query()
            && percent_decode_str(query).decode_utf8().is_err()
        {
            return Err(ApiError::bad_request(
                "the query string is not UTF-8 once percent-decoded",
            ));
        }
        Query::<T>::from_request_parts(parts, state)
            .await
            .map(|Query(t)| ApiQuery(t))
            .map_err(|e| ApiError::new(e.status(), e.body_text()))
    }
}

/// The account of the bearer token in `headers` and the token's SHA-256; `None` without an
/// `Authorization` header; 401 for a header that is not a valid, unrevoked token.
pub async fn resolve_token(
    headers: &HeaderMap,
    state: &AppState,
) -> Result<Option<(Account, [u8; 32])>, ApiError> {
    let Some(header) = headers.get(AUTHORIZATION) else {
        return Ok(None);
    };
    let token = header
        .to_str()
        .ok()
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::trim)
        .ok_or_else(|| {
            ApiError::unauthorized("the Authorization header must be `Bearer <token>`")
        })?;
    if !tokens::well_formed(token) {
        return Err(ApiError::unauthorized("malformed API token"));
    }
    let hash = tokens::hash(token);
    match state.store.account_by_token(&hash).await? {
        Some(account) => Ok(Some((account, hash))),
        None => Err(ApiError::unauthorized("unknown or revoked API token")),
    }
}

/// The caller: anonymous without an `Authorization` header. A header that is not a valid,
/// unrevoked token is refused (401) on every route, even those anonymous callers may use, so
/// that a revoked token fails at once and visibly. The rate limiter resolves it first and
/// leaves it in the request's extensions.
#[derive(Clone)]
pub struct Caller(pub Option<Account>);

impl FromRequestParts<AppState> for Caller {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, ApiError> {
        if let Some(caller) = parts.extensions.get::<Caller>() {
            return Ok(caller.clone());
        }
        let resolved = resolve_token(&parts.headers, state).await?;
        Ok(Caller(resolved.map(|(account, _)| account)))
    }
}

/// A signed-in caller (401 otherwise).
pub struct Signed(pub Account);

impl FromRequestParts<AppState> for Signed {
    type Rejection = ApiError;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, ApiError> {
        match Caller::from_request_parts(parts, state).await? {
            Caller(Some(account)) => Ok(Signed(account)),
            Caller(None) => Err(ApiError::unauthorized(
                "sign in: send `Authorization: Bearer <token>` (POST /api/v1/login gives one)",
            )),
        }
    }
}
