//! The OpenAPI document, derived from the handlers' annotations and served at `/openapi.json`.

use utoipa::openapi::security::{Http, HttpAuthScheme, SecurityScheme};
use utoipa::{Modify, OpenApi};

use crate::routes;

/// The repository's API.
#[derive(OpenApi)]
#[openapi(
    info(title = "Shapegram grammar repository", description = "Accounts, API tokens, friends, versioned goal grammars and procedural rule queries. Every route may answer 429 (with Retry-After) over the rate limit. See docs/repository.md."),
    paths(
        routes::sign_up, routes::login, routes::me,
        routes::create_token, routes::list_tokens, routes::revoke_token,
        routes::friends, routes::request_friend, routes::accept_friend, routes::remove_friend,
        routes::list_grammars, routes::search, routes::grammar, routes::versions, routes::version,
        routes::version_rules, routes::version_preview, routes::publish, crate::queries::query_rules,
        routes::yank, routes::unyank, crate::names::rename, crate::names::text_by_sha256,
    ),
    modifiers(&BearerAuth)
)]
pub struct ApiDoc;

struct BearerAuth;

impl Modify for BearerAuth {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        let components = openapi.components.get_or_insert_with(Default::default);
        components.add_security_scheme(
            "bearer",
            SecurityScheme::Http(Http::new(HttpAuthScheme::Bearer)),
        );
    }
}

/// The document.
pub fn document() -> utoipa::openapi::OpenApi {
    ApiDoc::openapi()
}
