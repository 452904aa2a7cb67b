//! Previews: a published version derived into a GLB by a worker process (research §2.7).
//!
//! The grammar is untrusted, so it is never derived inside the server: a worker (`shapegram
//! preview-worker`) gets it on stdin, limits its own memory, CPU time, files and output with
//! `setrlimit` before it reads it (limits that would cap the whole server if set here), reads no
//! file on the grammar's behalf, and writes the GLB on stdout. The server kills it at a
//! wall-clock deadline, runs at most a few at once and keeps what they made (see [`cache`]).
//!
//! The worker's side of the protocol is in the `shapegram` crate (`src/preview.rs`); the
//! request, the failure and the exit codes are defined here for both.

pub mod cache;
mod worker;

use std::ffi::OsString;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Duration;

use axum::body::Bytes;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use tokio::sync::Semaphore;

use crate::error::ApiError;
use crate::grammars::Problem;

/// The worker's exit code for a grammar that does not derive: its stdout is a
/// [`WorkerFailure`].
pub const EXIT_DOES_NOT_DERIVE: u8 = 3;
/// The worker's exit code for a request it cannot read (a bug on the server's side).
pub const EXIT_BAD_REQUEST: u8 = 4;

/// What the server sends a worker on stdin, as JSON.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkerRequest {
    /// The grammar's name (what its rules are called by in the model).
    pub name: String,
    /// The goal grammar's text, in either notation.
    pub text: String,
    /// The seed of every random choice.
    pub seed: u64,
    /// Stop with an error after this many derivation steps.
    pub max_steps: usize,
}

/// What a worker writes on stdout when the grammar does not derive (exit code
/// [`EXIT_DOES_NOT_DERIVE`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WorkerFailure {
    /// One line: what went wrong.
    pub error: String,
    /// The errors with a place in the grammar.
    pub diagnostics: Vec<WorkerDiagnostic>,
}

/// An error at a place in the grammar.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WorkerDiagnostic {
    pub message: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    pub hints: Vec<String>,
}

/// The limits of a preview, and how many run at once.
#[derive(Clone, Debug)]
pub struct PreviewLimits {
    /// Wall-clock time of one worker; it is killed then. Also how long a request waits for a
    /// free worker.
    pub timeout: Duration,
    /// The worker's address space (`RLIMIT_AS`), in MiB.
    pub memory_mib: u64,
    /// Derivation steps (rule applications).
    pub steps: usize,
    /// Workers running at once.
    pub workers: usize,
}

/// Largest GLB a preview may be, in bytes.
pub const MAX_PREVIEW_BYTES: usize = 64 << 20;
/// What the cache of previews holds at most, in bytes.
pub const CACHE_BYTES: usize = 128 << 20;

/// How to run the worker: `worker args… --memory-mib M --cpu-seconds C --max-output-mib O`,
/// the request on stdin.
#[derive(Clone, Debug)]
pub struct PreviewConfig {
    /// The executable (`shapegram serve` sets its own).
    pub worker: PathBuf,
    /// Its first arguments (`preview-worker`).
    pub args: Vec<OsString>,
    pub limits: PreviewLimits,
}

/// A preview: a GLB model, answered as `model/gltf-binary`.
#[derive(Debug, utoipa::ToSchema)]
#[schema(value_type = String, format = Binary)]
pub struct Glb(pub Bytes);

impl IntoResponse for Glb {
    fn into_response(self) -> Response {
        ([(header::CONTENT_TYPE, "model/gltf-binary")], self.0).into_response()
    }
}

/// Why a grammar does not derive: the message and the errors' places. A 422 answer.
#[derive(Clone, Debug)]
pub struct Refusal {
    pub message: String,
    pub diagnostics: Vec<Problem>,
}

/// Why there is no preview.
#[derive(Debug)]
pub enum PreviewError {
    /// The server runs without previews.
    Off,
    /// Every worker stayed busy for as long as a preview may take; try again after the
    /// seconds given.
    Busy { retry_after: u64 },
    /// The grammar does not derive (deterministic: kept in the cache).
    DoesNotDerive(Refusal),
    /// The worker was stopped by a limit: the message names it.
    Killed(String),
    /// The worker could not be run, or broke the protocol (logged).
    Failed(String),
}

impl IntoResponse for PreviewError {
    fn into_response(self) -> Response {
        match self {
            PreviewError::Off => {
                ApiError::new(StatusCode::SERVICE_UNAVAILABLE, "previews are off").into_response()
            }
            PreviewError::Busy { retry_after } => {
                let mut response = ApiError::new(
                    StatusCode::SERVICE_UNAVAILABLE,
                    "every preview worker is busy: try again later",
                )
                .into_response();
                response
                    .headers_mut()
                    .insert(header::RETRY_AFTER, HeaderValue::from(retry_after));
                response
            }
            PreviewError::DoesNotDerive(refusal) => ApiError {
                status: StatusCode::UNPROCESSABLE_ENTITY,
                message: refusal.message,
                diagnostics: refusal.diagnostics,
            }
            .into_response(),
            PreviewError::Killed(message) => {
                ApiError::new(StatusCode::SERVICE_UNAVAILABLE, message).into_response()
            }
            PreviewError::Failed(why) => ApiError::internal(why).into_response(),
        }
    }
}

/// The previews of a server: its worker, the permits of the workers running, and the cache.
pub struct Previews {
    config: PreviewConfig,
    permits: Semaphore,
    cache: Mutex<cache::Cache>,
}

impl Previews {
    /// Previews made as `config` says, with an empty cache.
    pub fn new(config: PreviewConfig) -> Previews {
        Previews {
            permits: Semaphore::new(config.limits.workers.max(1)),
            cache: Mutex::new(cache::Cache::new(CACHE_BYTES)),
            config,
        }
    }

    fn cached(&self, key: &cache::Key) -> Option<cache::Outcome> {
        self.cache
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(key)
    }

    /// The GLB of the grammar `name` whose text has the hash `sha256`, derived with `seed`:
    /// from the cache, or from a worker once one is free (waiting at most the timeout).
    pub async fn glb(
        &self,
        name: &str,
        text: &str,
        sha256: &str,
        seed: u64,
    ) -> Result<Glb, PreviewError> {
        let key = (sha256.to_owned(), seed);
        if let Some(outcome) = self.cached(&key) {
            return outcome.map(Glb).map_err(PreviewError::DoesNotDerive);
        }
        let limits = &self.config.limits;
        let _permit = match tokio::time::timeout(limits.timeout, self.permits.acquire()).await {
            Ok(Ok(permit)) => permit,
            _ => {
                return Err(PreviewError::Busy {
                    retry_after: limits.timeout.as_secs().max(1),
                });
            }
        };
        // Requests for one preview that waited together: the first one made it.
        if let Some(outcome) = self.cached(&key) {
            return outcome.map(Glb).map_err(PreviewError::DoesNotDerive);
        }
        let request = WorkerRequest {
            name: name.to_owned(),
            text: text.to_owned(),
            seed,
            max_steps: limits.steps,
        };
        let outcome = worker::run(&self.config, &request).await;
        // Time and memory kills depend on the machine's load; those are not kept.
        let kept = match &outcome {
            Ok(glb) => Some(Ok(glb.clone())),
            Err(PreviewError::DoesNotDerive(refusal)) => Some(Err(refusal.clone())),
            Err(_) => None,
        };
        if let Some(kept) = kept {
            self.cache
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .insert(key, kept);
        }
        outcome.map(Glb)
    }
}
