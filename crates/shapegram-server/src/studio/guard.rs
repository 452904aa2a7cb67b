//! The studio's guard: every request must name this server in its Host (a page of another site
//! that rebinds its DNS name to 127.0.0.1 sends its own name there), and every request that is
//! not a GET or HEAD must carry the Origin of the studio's page (browsers send it with every
//! such request, so another site's form or script cannot write files). Refusals are 403 with a
//! JSON message. Answers also forbid framing and content sniffing.

use axum::extract::{Request, State};
use axum::http::header::{HOST, ORIGIN};
use axum::http::{HeaderValue, Method, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use super::StudioState;
use crate::error::ApiError;

/// Refuses requests whose Host or Origin is not the studio's, and adds the security headers.
pub async fn check(State(state): State<StudioState>, request: Request, next: Next) -> Response {
    if let Err(refusal) = admit(&state, &request) {
        return refusal.into_response();
    }
    let mut response = next.run(request).await;
    let headers = response.headers_mut();
    headers.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    headers.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:; connect-src 'self' data: blob:; frame-ancestors 'none'",
        ),
    );
    response
}

/// Whether `request` may pass.
fn admit(state: &StudioState, request: &Request) -> Result<(), ApiError> {
    let host = request
        .headers()
        .get(HOST)
        .and_then(|h| h.to_str().ok())
        .ok_or_else(|| ApiError::forbidden("the request has no Host header"))?;
    if !is_studio_host(host, state.port) {
        return Err(ApiError::forbidden(format!(
            "the Host `{host}` is not this studio's (127.0.0.1:{port} or localhost:{port})",
            port = state.port
        )));
    }
    if request.method() == Method::GET || request.method() == Method::HEAD {
        return Ok(());
    }
    match request.headers().get(ORIGIN).and_then(|o| o.to_str().ok()) {
        Some(origin)
            if origin
                .strip_prefix("http://")
                .is_some_and(|host| is_studio_host(host, state.port)) =>
        {
            Ok(())
        }
        Some(origin) => Err(ApiError::forbidden(format!(
            "the Origin `{origin}` is not this studio's page: only the studio may change files"
        ))),
        None => Err(ApiError::forbidden(
            "a request that changes something must carry the Origin of the studio's page",
        )),
    }
}

/// `127.0.0.1:PORT` or `localhost:PORT`, nothing else (no other name, no default port).
fn is_studio_host(host: &str, port: u16) -> bool {
    let Some((name, given)) = host.rsplit_once(':') else {
        return false;
    };
    (name == "127.0.0.1" || name.eq_ignore_ascii_case("localhost"))
        && given.parse::<u16>().ok() == Some(port)
}

#[cfg(test)]
mod tests {
    use super::is_studio_host;

    #[test]
    fn only_loopback_names_with_the_port_are_the_studio() {
        assert!(is_studio_host("127.0.0.1:7370", 7370));
        assert!(is_studio_host("localhost:7370", 7370));
        assert!(is_studio_host("LOCALHOST:7370", 7370));
        assert!(!is_studio_host("127.0.0.1:7371", 7370));
        assert!(!is_studio_host("127.0.0.1", 7370));
        assert!(!is_studio_host("evil.example:7370", 7370));
        assert!(!is_studio_host("127.0.0.1.evil.example:7370", 7370));
        assert!(!is_studio_host("[::1]:7370", 7370));
    }
}
