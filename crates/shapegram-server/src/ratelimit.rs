//! Rate limits held in the database, so that several processes serving one database share them
//! (as crates.io moved its limits into its database, research §1.1, §2.5): a number of requests
//! per fixed window, per API token, per address for anonymous callers, and per address for
//! sign-up and login attempts. One check is one UPSERT … RETURNING
//! ([`Store::rate_limit_hit`](crate::store::Store::rate_limit_hit)).
//!
//! A request with a token is checked after the token: a revoked or unknown token is refused
//! with 401 whatever the counts, so that 429 never hides a revocation.

use std::fmt;
use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicI64, Ordering};

use axum::extract::{ConnectInfo, Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};

use crate::AppState;
use crate::error::ApiError;
use crate::extract::{self, Caller};

/// At most `requests` per `window` seconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limit {
    /// Requests allowed in a window.
    pub requests: u32,
    /// The window's length, in seconds.
    pub window: u32,
}

impl Limit {
    /// Parses `N/s`, `N/min`, `N/h` or `N/day` (also `N/second`, `N/minute`, `N/hour`); `0` and
    /// `off` give `None`, no limit.
    pub fn parse(text: &str) -> Result<Option<Limit>, String> {
        let text = text.trim();
        if text == "0" || text.eq_ignore_ascii_case("off") {
            return Ok(None);
        }
        let bad = || format!("{text:?} is no rate limit: write N/s, N/min, N/h or N/day, or off");
        let (n, unit) = text.split_once('/').ok_or_else(bad)?;
        let requests: u32 = n.trim().parse().map_err(|_| bad())?;
        let window = match unit.trim() {
            "s" | "sec" | "second" => 1,
            "min" | "minute" => 60,
            "h" | "hour" => 3600,
            "d" | "day" => 86_400,
            _ => return Err(bad()),
        };
        Ok((requests > 0).then_some(Limit { requests, window }))
    }
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.window {
            1 => write!(f, "{}/s", self.requests),
            60 => write!(f, "{}/min", self.requests),
            3600 => write!(f, "{}/h", self.requests),
            86_400 => write!(f, "{}/day", self.requests),
            w => write!(f, "{} per {w} s", self.requests),
        }
    }
}

/// The configured limits; `None` is unlimited.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RateLimits {
    /// Every request: per token, or per address without one.
    pub requests: Option<Limit>,
    /// Sign-up and login attempts, per address.
    pub sign_in: Option<Limit>,
}

impl RateLimits {
    /// No limits (the default of [`crate::router`], for tests and embedding).
    pub const OFF: RateLimits = RateLimits {
        requests: None,
        sign_in: None,
    };
}

/// Seconds since the Unix epoch; injectable so tests move time instead of sleeping.
pub type Clock = Arc<dyn Fn() -> i64 + Send + Sync>;

/// The system clock.
pub fn system_clock() -> Clock {
    Arc::new(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs() as i64)
    })
}

/// Checks requests against the limits, counting in the store.
pub struct RateLimiter {
    limits: RateLimits,
    clock: Clock,
    /// The last period (of the longest window) whose ended windows were pruned.
    pruned: AtomicI64,
}

impl RateLimiter {
    /// A limiter of `limits`, reading the time from `clock`.
    pub fn new(limits: RateLimits, clock: Clock) -> RateLimiter {
        RateLimiter {
            limits,
            clock,
            pruned: AtomicI64::new(i64::MIN),
        }
    }

    fn longest_window(&self) -> i64 {
        [self.limits.requests, self.limits.sign_in]
            .into_iter()
            .flatten()
            .map(|l| i64::from(l.window))
            .max()
            .unwrap_or(1)
    }
}

/// Whom a request is counted against.
enum Subject {
    Token([u8; 32]),
    Address(IpAddr),
    SignIn(IpAddr),
}

impl Subject {
    fn key(&self) -> String {
        match self {
            Subject::Token(hash) => {
                let hex: String = hash[..16].iter().map(|b| format!("{b:02x}")).collect();
                format!("token:{hex}")
            }
            Subject::Address(ip) => format!("ip:{ip}"),
            Subject::SignIn(ip) => format!("sign-in:{ip}"),
        }
    }

    fn describe(&self) -> &'static str {
        match self {
            Subject::Token(_) => "too many requests with this token",
            Subject::Address(_) => "too many requests from this address without a token",
            Subject::SignIn(_) => "too many sign-up and login attempts from this address",
        }
    }
}

fn is_sign_in(request: &Request) -> bool {
    request.method() == Method::POST
        && matches!(request.uri().path(), "/api/v1/login" | "/api/v1/accounts")
}

/// The middleware: resolves the caller's token (401 when it is bad, before any count), counts
/// the request, and answers 429 with `Retry-After` over the limit. The resolved caller is
/// passed on to the handlers' [`Caller`] extractor, so a token is looked up once.
pub async fn limit(State(state): State<AppState>, mut request: Request, next: Next) -> Response {
    let limiter = state.limiter.clone();
    if limiter.limits == RateLimits::OFF {
        return next.run(request).await;
    }
    // Behind a proxy every anonymous caller has the proxy's address (forwarding headers are
    // spoofable, so they are not read).
    let ip = request
        .extensions()
        .get::<ConnectInfo<SocketAddr>>()
        .map_or(IpAddr::from([0, 0, 0, 0]), |ConnectInfo(addr)| addr.ip());
    let (subject, limit) = if is_sign_in(&request) {
        (Subject::SignIn(ip), limiter.limits.sign_in)
    } else {
        match extract::resolve_token(request.headers(), &state).await {
            Err(e) => return e.into_response(),
            Ok(Some((account, hash))) => {
                request.extensions_mut().insert(Caller(Some(account)));
                (Subject::Token(hash), limiter.limits.requests)
            }
            Ok(None) => {
                request.extensions_mut().insert(Caller(None));
                (Subject::Address(ip), limiter.limits.requests)
            }
        }
    };
    let Some(limit) = limit else {
        return next.run(request).await;
    };
    match check(&state, &limiter, &subject, limit).await {
        Ok(None) => next.run(request).await,
        Ok(Some(retry_after)) => too_many(&subject, limit, retry_after),
        Err(e) => e.into_response(),
    }
}

/// Counts one request; `Some(seconds to wait)` when it is over the limit.
async fn check(
    state: &AppState,
    limiter: &RateLimiter,
    subject: &Subject,
    limit: Limit,
) -> Result<Option<i64>, ApiError> {
    let now = (limiter.clock)();
    let window = i64::from(limit.window);
    let start = now.div_euclid(window) * window;
    let hits = state.store.rate_limit_hit(&subject.key(), start).await?;
    // Once per longest window, one process forgets the windows that have ended.
    let longest = limiter.longest_window();
    let period = now.div_euclid(longest);
    if limiter.pruned.fetch_max(period, Ordering::Relaxed) < period {
        state.store.prune_rate_limits(now - longest).await?;
    }
    Ok((hits > i64::from(limit.requests)).then(|| start + window - now))
}

fn too_many(subject: &Subject, limit: Limit, retry_after: i64) -> Response {
    let retry_after = retry_after.max(1);
    let mut response = ApiError::new(
        StatusCode::TOO_MANY_REQUESTS,
        format!(
            "{}: at most {limit}; retry in {retry_after} s",
            subject.describe()
        ),
    )
    .into_response();
    if let Ok(value) = HeaderValue::from_str(&retry_after.to_string()) {
        response.headers_mut().insert(header::RETRY_AFTER, value);
    }
    response
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_parse() {
        assert_eq!(
            Limit::parse("600/min"),
            Ok(Some(Limit {
                requests: 600,
                window: 60
            }))
        );
        assert_eq!(
            Limit::parse("5/s"),
            Ok(Some(Limit {
                requests: 5,
                window: 1
            }))
        );
        assert_eq!(Limit::parse("off"), Ok(None));
        assert_eq!(Limit::parse("0"), Ok(None));
        assert_eq!(Limit::parse("0/min"), Ok(None));
        assert_eq!(
            Limit::parse("600").unwrap_err(),
            "\"600\" is no rate limit: write N/s, N/min, N/h or N/day, or off"
        );
        assert!(Limit::parse("-1/min").is_err());
        assert!(Limit::parse("10/week").is_err());
        assert_eq!(
            Limit::parse("1000/h").unwrap().unwrap().to_string(),
            "1000/h"
        );
    }
}
