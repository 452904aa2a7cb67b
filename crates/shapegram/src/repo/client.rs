//! A small blocking client of the grammar repository's JSON API (`docs/repository.md`): a
//! `get`/`post`/`delete` core over a base URL and an optional bearer token, typed methods for
//! the endpoints, and errors that say what went wrong in words.

use std::time::Duration;

use serde::Deserialize;
use serde::de::DeserializeOwned;
use serde_json::{Value, json};

/// What a request to the repository can fail with.
#[derive(Debug)]
pub enum ClientError {
    /// The server answered with an error status: its `{"error"}` message (or, from something
    /// else than a repository, the status and the start of the answer) and, for a grammar that
    /// does not compile, its diagnostics.
    Refused {
        status: u16,
        message: String,
        diagnostics: Vec<Diagnostic>,
    },
    /// The server could not be reached, or did not answer in the API's terms.
    Connection(String),
}

impl std::fmt::Display for ClientError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ClientError::Refused { message, .. } => write!(f, "{message}"),
            ClientError::Connection(message) => write!(f, "{message}"),
        }
    }
}

/// A diagnostic of a grammar the server refused (lines and columns from 1).
#[derive(Clone, Debug, Deserialize)]
pub struct Diagnostic {
    /// `error` or `warning`.
    pub severity: String,
    pub message: String,
    pub line: usize,
    pub column: usize,
    #[serde(default)]
    pub hints: Vec<String>,
}

/// An account.
#[derive(Debug, Deserialize)]
pub struct AccountInfo {
    pub name: String,
}

/// A token without its secret.
#[derive(Debug, Deserialize)]
pub struct TokenInfo {
    pub id: i64,
    pub name: String,
    pub prefix: String,
    pub created_at: i64,
    pub revoked: bool,
}

/// A token made just now, with its secret.
#[derive(Debug, Deserialize)]
pub struct NewToken {
    pub token: String,
    #[serde(flatten)]
    pub info: TokenInfo,
}

/// One's friends and pending requests.
#[derive(Debug, Deserialize)]
pub struct Friends {
    pub friends: Vec<String>,
    pub incoming: Vec<String>,
    pub outgoing: Vec<String>,
}

/// A grammar as lists show it.
#[derive(Debug, Deserialize)]
pub struct GrammarSummary {
    pub owner: String,
    pub name: String,
    pub visibility: String,
    pub latest_version: i64,
    /// The newest version not yanked: what a new resolution gets (none when all are yanked).
    pub current_version: Option<i64>,
}

/// A page of search results.
#[derive(Debug, Deserialize)]
pub struct SearchResults {
    pub grammars: Vec<GrammarSummary>,
    pub next_page: Option<u32>,
}

/// What to search for (see `GET /api/v1/search`).
#[derive(Debug, Default)]
pub struct Search<'a> {
    pub goal: Option<&'a str>,
    pub tag: Option<&'a str>,
    pub text: Option<&'a str>,
    pub owner: Option<&'a str>,
    pub page: Option<u32>,
}

/// A version without its text.
#[derive(Debug, Deserialize)]
pub struct VersionInfo {
    pub version: i64,
    pub sha256: String,
    pub published_at: i64,
    pub publisher: String,
    /// Withdrawn from new resolutions (still fetchable by number).
    #[serde(default)]
    pub yanked: bool,
}

/// A version with its text.
#[derive(Debug, Deserialize)]
pub struct VersionText {
    pub owner: String,
    pub name: String,
    #[serde(flatten)]
    pub info: VersionInfo,
    pub text: String,
}

/// A version just published.
#[derive(Debug, Deserialize)]
pub struct Published {
    pub owner: String,
    pub name: String,
    #[serde(flatten)]
    pub info: VersionInfo,
    pub rules: usize,
    pub warnings: Vec<Diagnostic>,
}

/// The certificates of the PEM file `SSL_CERT_FILE` names, trusted instead of the built-in
/// Mozilla roots as OpenSSL does (for a company's or a proxy's own certificate authority);
/// `None` without one, or when it holds no certificate.
fn roots_from_env() -> Option<ureq::tls::RootCerts> {
    let pem = std::fs::read(std::env::var_os("SSL_CERT_FILE")?).ok()?;
    let certs: Vec<_> = ureq::tls::parse_pem(&pem)
        .filter_map(|item| match item {
            Ok(ureq::tls::PemItem::Certificate(cert)) => Some(cert),
            _ => None,
        })
        .collect();
    (!certs.is_empty()).then(|| ureq::tls::RootCerts::new_with_certs(&certs))
}

/// The repository at one base URL, as one caller (anonymous without a token).
pub struct Client {
    agent: ureq::Agent,
    base: String,
    token: Option<String>,
}

/// A path segment, percent-encoded (names are plain ASCII, but what a user types may not be).
fn segment(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for b in text.bytes() {
        if b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.' | b'~') {
            out.push(char::from(b));
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    out
}

impl Client {
    /// A client of the repository at `base` (`http://host:port`, no trailing `/` needed).
    pub fn new(base: &str, token: Option<String>) -> Client {
        let mut tls = ureq::tls::TlsConfig::builder();
        if let Some(roots) = roots_from_env() {
            tls = tls.root_certs(roots);
        }
        let config = ureq::Agent::config_builder()
            .tls_config(tls.build())
            // Error statuses carry the server's message: they are read, not turned into errors.
            .http_status_as_error(false)
            .timeout_connect(Some(Duration::from_secs(10)))
            .timeout_global(Some(Duration::from_secs(120)))
            .user_agent(concat!("shapegram/", env!("CARGO_PKG_VERSION")))
            .build();
        Client {
            agent: config.new_agent(),
            base: base.trim_end_matches('/').to_owned(),
            token,
        }
    }

    fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }

    fn authorization(&self) -> Option<String> {
        self.token.as_ref().map(|t| format!("Bearer {t}"))
    }

    /// `GET path?query`, answered with JSON.
    pub fn get<T: DeserializeOwned>(
        &self,
        path: &str,
        query: &[(&str, String)],
    ) -> Result<T, ClientError> {
        let mut request = self.agent.get(self.url(path));
        for (key, value) in query {
            request = request.query(*key, value);
        }
        if let Some(auth) = self.authorization() {
            request = request.header("authorization", auth);
        }
        self.answer(request.call())
    }

    /// `POST path` with a JSON body, answered with JSON.
    pub fn post<T: DeserializeOwned>(&self, path: &str, body: &Value) -> Result<T, ClientError> {
        let mut request = self.agent.post(self.url(path));
        if let Some(auth) = self.authorization() {
            request = request.header("authorization", auth);
        }
        self.answer(request.send_json(body))
    }

    /// `DELETE path`, answered with no content.
    pub fn delete(&self, path: &str) -> Result<(), ClientError> {
        let mut request = self.agent.delete(self.url(path));
        if let Some(auth) = self.authorization() {
            request = request.header("authorization", auth);
        }
        self.answer::<Value>(request.call()).map(drop)
    }

    /// The JSON of a successful answer (`null` when it has no body), or why there is none.
    fn answer<T: DeserializeOwned>(
        &self,
        result: Result<ureq::http::Response<ureq::Body>, ureq::Error>,
    ) -> Result<T, ClientError> {
        let mut response = result.map_err(|e| self.connection_error(e))?;
        let status = response.status().as_u16();
        let text = response
            .body_mut()
            .read_to_string()
            .map_err(|e| self.connection_error(e))?;
        if !(200..300).contains(&status) {
            return Err(refusal(status, &text));
        }
        let text = if text.is_empty() { "null" } else { &text };
        serde_json::from_str(text).map_err(|e| {
            ClientError::Connection(format!(
                "{} answered something other than the repository's API ({e}): is it a \
                 `shapegram serve`?",
                self.base
            ))
        })
    }

    fn connection_error(&self, e: ureq::Error) -> ClientError {
        let base = &self.base;
        ClientError::Connection(match e {
            ureq::Error::Io(e) if e.kind() == std::io::ErrorKind::ConnectionRefused => {
                format!(
                    "cannot connect to {base}: connection refused (is `shapegram serve` running there?)"
                )
            }
            ureq::Error::HostNotFound => format!("cannot connect to {base}: host not found"),
            ureq::Error::BadUri(_) => {
                format!("{base} is not a repository URL (http://HOST:PORT or https://HOST)")
            }
            ureq::Error::Timeout(_) => format!("{base} did not answer in time"),
            e if e.to_string().contains("certificate") => format!(
                "cannot talk to {base}: {e} (to trust another certificate authority, name a PEM \
                 file of its certificates in SSL_CERT_FILE)"
            ),
            e => format!("cannot talk to {base}: {e}"),
        })
    }

    /// Signs up.
    pub fn sign_up(&self, name: &str, password: &str) -> Result<AccountInfo, ClientError> {
        self.post(
            "/api/v1/accounts",
            &json!({"name": name, "password": password}),
        )
    }

    /// Logs in: a new token named `login`.
    pub fn login(&self, name: &str, password: &str) -> Result<NewToken, ClientError> {
        self.post(
            "/api/v1/login",
            &json!({"name": name, "password": password}),
        )
    }

    /// The token's account.
    pub fn me(&self) -> Result<AccountInfo, ClientError> {
        self.get("/api/v1/me", &[])
    }

    /// The caller's tokens.
    pub fn tokens(&self) -> Result<Vec<TokenInfo>, ClientError> {
        self.get("/api/v1/tokens", &[])
    }

    /// A new token of the caller's.
    pub fn create_token(&self, name: &str) -> Result<NewToken, ClientError> {
        self.post("/api/v1/tokens", &json!({"name": name}))
    }

    /// Revokes one of the caller's tokens.
    pub fn revoke_token(&self, id: i64) -> Result<(), ClientError> {
        self.delete(&format!("/api/v1/tokens/{id}"))
    }

    /// The caller's friends and requests.
    pub fn friends(&self) -> Result<Friends, ClientError> {
        self.get("/api/v1/friends", &[])
    }

    /// Asks `user` to be friends (accepts when `user` asked first): `requested` or `friends`.
    pub fn request_friend(&self, user: &str) -> Result<String, ClientError> {
        let answer: Value = self.post(&format!("/api/v1/friends/{}", segment(user)), &json!({}))?;
        Ok(answer["state"].as_str().unwrap_or_default().to_owned())
    }

    /// Accepts `user`'s request.
    pub fn accept_friend(&self, user: &str) -> Result<(), ClientError> {
        self.post::<Value>(
            &format!("/api/v1/friends/{}/accept", segment(user)),
            &json!({}),
        )
        .map(drop)
    }

    /// Ends a friendship with `user`, or withdraws or declines a request.
    pub fn remove_friend(&self, user: &str) -> Result<(), ClientError> {
        self.delete(&format!("/api/v1/friends/{}", segment(user)))
    }

    fn grammar_path(owner: &str, name: &str) -> String {
        format!("/api/v1/grammars/{}/{}", segment(owner), segment(name))
    }

    /// Publishes `text` as a new version of `owner/name`.
    pub fn publish(
        &self,
        owner: &str,
        name: &str,
        text: &str,
        visibility: Option<&str>,
    ) -> Result<Published, ClientError> {
        let mut body = json!({"text": text});
        if let Some(visibility) = visibility {
            body["visibility"] = json!(visibility);
        }
        self.post(
            &format!("{}/versions", Self::grammar_path(owner, name)),
            &body,
        )
    }

    /// A page of the grammars that match.
    pub fn search(&self, search: &Search<'_>) -> Result<SearchResults, ClientError> {
        let mut query = Vec::new();
        let filters = [
            ("goal", search.goal),
            ("tag", search.tag),
            ("q", search.text),
            ("owner", search.owner),
        ];
        for (key, value) in filters {
            if let Some(value) = value {
                query.push((key, value.to_owned()));
            }
        }
        if let Some(page) = search.page {
            query.push(("page", page.to_string()));
        }
        self.get("/api/v1/search", &query)
    }

    /// One grammar.
    pub fn grammar(&self, owner: &str, name: &str) -> Result<GrammarSummary, ClientError> {
        self.get(&Self::grammar_path(owner, name), &[])
    }

    /// A grammar's versions, oldest first.
    pub fn versions(&self, owner: &str, name: &str) -> Result<Vec<VersionInfo>, ClientError> {
        self.get(
            &format!("{}/versions", Self::grammar_path(owner, name)),
            &[],
        )
    }

    /// A version with its text.
    pub fn version(
        &self,
        owner: &str,
        name: &str,
        version: i64,
    ) -> Result<VersionText, ClientError> {
        self.get(
            &format!("{}/versions/{version}", Self::grammar_path(owner, name)),
            &[],
        )
    }
}

impl Client {
    /// Yanks a version (with an optional reason), or withdraws its yank.
    pub fn yank(
        &self,
        owner: &str,
        name: &str,
        version: i64,
        yank: bool,
        reason: Option<&str>,
    ) -> Result<VersionInfo, ClientError> {
        let path = Self::grammar_path(owner, name);
        let action = if yank { "yank" } else { "unyank" };
        let body = match reason {
            Some(reason) => json!({"reason": reason}),
            None => json!({}),
        };
        self.post(&format!("{path}/versions/{version}/{action}"), &body)
    }
}

impl Client {
    /// The newest version the caller may see whose text has this SHA-256, whatever its
    /// grammar is called now.
    pub fn text(&self, sha256: &str) -> Result<VersionText, ClientError> {
        self.get(&format!("/api/v1/texts/{}", segment(sha256)), &[])
    }

    /// Renames one of the caller's grammars.
    pub fn rename(&self, owner: &str, name: &str, to: &str) -> Result<GrammarSummary, ClientError> {
        let path = Self::grammar_path(owner, name);
        self.post(&format!("{path}/rename"), &json!({ "name": to }))
    }
}

/// A grammar version that answers rule queries.
#[derive(Clone, Debug, Deserialize)]
pub struct FoundGrammar {
    pub owner: String,
    pub name: String,
    pub version: i64,
    pub sha256: String,
}

/// The answers to a batch of rule queries (the per-query matches are not needed here).
#[derive(Debug, Deserialize)]
pub struct QueryAnswers {
    /// The publish log's position the answers were read at.
    pub as_of: i64,
    /// Every grammar version some answer names.
    pub grammars: Vec<FoundGrammar>,
}

impl Client {
    /// Procedural rule queries (`POST /api/v1/queries`): the grammars with rules for shapes
    /// with these goals, tags and attributes, among those `link` (`all`, `friends`, `mine`)
    /// admits.
    pub fn query(
        &self,
        link: &str,
        queries: &[shapegram_eval::GoalQuery],
    ) -> Result<QueryAnswers, ClientError> {
        let queries: Vec<Value> = queries
            .iter()
            .map(|q| {
                let names = |list: &[std::sync::Arc<str>]| -> Vec<String> {
                    list.iter().map(|n| n.to_string()).collect()
                };
                json!({
                    "goals": names(&q.goals),
                    "tags": names(&q.tags),
                    "attributes": names(&q.attributes),
                })
            })
            .collect();
        self.post(
            "/api/v1/queries",
            &json!({"link": link, "queries": queries}),
        )
    }
}

/// An error answer: the server's `{"error", "diagnostics"}`, or the status and the start of
/// whatever else it sent.
fn refusal(status: u16, text: &str) -> ClientError {
    #[derive(Deserialize)]
    struct ErrorBody {
        error: String,
        #[serde(default)]
        diagnostics: Vec<Diagnostic>,
    }
    match serde_json::from_str::<ErrorBody>(text) {
        Ok(body) => ClientError::Refused {
            status,
            message: body.error,
            diagnostics: body.diagnostics,
        },
        Err(_) => {
            let start: String = text.chars().take(200).collect();
            ClientError::Refused {
                status,
                message: if start.trim().is_empty() {
                    format!("the server answered HTTP {status}")
                } else {
                    format!("the server answered HTTP {status}: {}", start.trim())
                },
                diagnostics: Vec::new(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_segments_are_percent_encoded() {
        assert_eq!(segment("Ana_M-2"), "Ana_M-2");
        assert_eq!(segment("a/b?c d"), "a%2Fb%3Fc%20d");
        assert_eq!(segment("é"), "%C3%A9");
    }

    #[test]
    fn refusals_carry_the_servers_message_or_its_text() {
        let e = refusal(404, r#"{"error": "not found"}"#);
        assert_eq!(e.to_string(), "not found");
        let e = refusal(502, "<html>Bad Gateway</html>");
        assert_eq!(
            e.to_string(),
            "the server answered HTTP 502: <html>Bad Gateway</html>"
        );
        let e = refusal(
            422,
            r#"{"error": "x does not compile", "diagnostics": [{"severity": "error", "message": "m", "line": 2, "column": 5, "hints": []}]}"#,
        );
        let ClientError::Refused { diagnostics, .. } = e else {
            panic!("a refusal");
        };
        assert_eq!((diagnostics[0].line, diagnostics[0].column), (2, 5));
    }

    #[test]
    fn a_closed_port_is_named_in_the_error() {
        // A port that was free a moment ago: nothing listens there.
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .map(|a| a.port())
            .unwrap();
        let client = Client::new(&format!("http://127.0.0.1:{port}/"), None);
        let e = client.me().unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "cannot connect to http://127.0.0.1:{port}: connection refused (is `shapegram \
                 serve` running there?)"
            )
        );
    }
}
