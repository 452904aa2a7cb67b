//! The page and its assets, built from `studio/` by esbuild (`npm run build`) into
//! `studio/dist/`, which is checked in so that building the binary needs no Node; `.ci/run`
//! rebuilds it and fails when the result differs from what is checked in.

use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;
use crate::extract::ApiPath;

/// The page.
const INDEX: &str = include_str!("../../../../studio/dist/index.html");
/// The bundle: CodeMirror, three.js and the studio's code.
const SCRIPT: &str = include_str!("../../../../studio/dist/studio.js");
/// The styles of the page and the editor.
const STYLE: &str = include_str!("../../../../studio/dist/studio.css");
/// The split grammar editor's page, for `.sgproj.json` projects.
const TOPO_INDEX: &str = include_str!("../../../../studio/dist/topo.html");
/// The split grammar editor's bundle: three.js and `studio/src/topo/`.
const TOPO_SCRIPT: &str = include_str!("../../../../studio/dist/topo.js");
/// The split grammar editor's styles.
const TOPO_STYLE: &str = include_str!("../../../../studio/dist/topo.css");

/// `GET /`: the page.
pub async fn index() -> Response {
    with_type(INDEX, "text/html; charset=utf-8")
}

/// `GET /topo?path=…`: the split grammar editor's page (it opens the project itself).
pub async fn topo() -> Response {
    with_type(TOPO_INDEX, "text/html; charset=utf-8")
}

/// `GET /assets/{name}`: the scripts or the styles.
pub async fn asset(ApiPath(name): ApiPath<String>) -> Result<Response, ApiError> {
    match name.as_str() {
        "studio.js" => Ok(with_type(SCRIPT, "text/javascript; charset=utf-8")),
        "studio.css" => Ok(with_type(STYLE, "text/css; charset=utf-8")),
        "topo.js" => Ok(with_type(TOPO_SCRIPT, "text/javascript; charset=utf-8")),
        "topo.css" => Ok(with_type(TOPO_STYLE, "text/css; charset=utf-8")),
        _ => Err(ApiError::not_found()),
    }
}

fn with_type(body: &'static str, content_type: &'static str) -> Response {
    let mut response = body.into_response();
    response
        .headers_mut()
        .insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type));
    // The assets change with the binary: a page from an older studio must not linger.
    response
        .headers_mut()
        .insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    response
}
