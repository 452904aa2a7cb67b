//! Running one worker: spawned with an empty environment, fed the request, read with its output
//! bounded, killed at the deadline and reaped, and its end told apart: a GLB, a grammar that
//! does not derive, or which limit stopped it.

use std::process::{ExitStatus, Stdio};

use axum::body::Bytes;
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWriteExt};
use tokio::process::Command;

use super::{
    EXIT_DOES_NOT_DERIVE, MAX_PREVIEW_BYTES, PreviewConfig, PreviewError, PreviewLimits, Refusal,
    WorkerFailure, WorkerRequest,
};
use crate::grammars::Problem;

/// What of the worker's stderr is kept for the log and to tell why it died.
const MAX_STDERR_BYTES: usize = 16 << 10;

/// How a worker's run ended, before it is interpreted.
enum End {
    /// It exited or was killed by a signal, with what it wrote.
    Exited {
        status: ExitStatus,
        stdout: Vec<u8>,
        stderr: Vec<u8>,
    },
    /// The deadline passed.
    TimedOut,
}

/// Derives `request` in a worker under `config`'s limits.
pub async fn run(config: &PreviewConfig, request: &WorkerRequest) -> Result<Bytes, PreviewError> {
    let limits = &config.limits;
    let mut command = Command::new(&config.worker);
    command
        .args(&config.args)
        .arg("--memory-mib")
        .arg(limits.memory_mib.to_string())
        .arg("--cpu-seconds")
        .arg(cpu_seconds(limits).to_string())
        .arg("--max-output-mib")
        .arg((MAX_PREVIEW_BYTES >> 20).to_string())
        // Nothing of the server's: no environment, not its working folder.
        .env_clear()
        .current_dir(std::path::Path::new("/"))
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Also when the request is dropped (its client went away): no orphan keeps working.
        .kill_on_drop(true);
    let mut child = command.spawn().map_err(|e| {
        PreviewError::Failed(format!(
            "cannot start the preview worker {}: {e}",
            config.worker.display()
        ))
    })?;
    let body = serde_json::to_vec(request)
        .map_err(|e| PreviewError::Failed(format!("cannot write a preview request: {e}")))?;
    let (Some(mut stdin), Some(stdout), Some(stderr)) =
        (child.stdin.take(), child.stdout.take(), child.stderr.take())
    else {
        return Err(PreviewError::Failed(
            "the preview worker has no pipes".into(),
        ));
    };
    let talk = async {
        let feed = async {
            // A worker that died at once (a limit it could not set) closes its stdin: its exit
            // status says more than this write.
            let _ = stdin.write_all(&body).await;
            drop(stdin);
            Ok(())
        };
        let wait = async {
            child.wait().await.map_err(|e| {
                PreviewError::Failed(format!("cannot wait for the preview worker: {e}"))
            })
        };
        // An output too large ends the others at once, and the worker is killed below.
        let stdout = async {
            read_bounded(stdout, MAX_PREVIEW_BYTES)
                .await
                .ok_or(PreviewError::Killed(too_large()))
        };
        let stderr = async { Ok(read_head(stderr, MAX_STDERR_BYTES).await) };
        let ((), stdout, stderr, status) = tokio::try_join!(feed, stdout, stderr, wait)?;
        Ok::<_, PreviewError>(End::Exited {
            status,
            stdout,
            stderr,
        })
    };
    let end = tokio::time::timeout(limits.timeout, talk)
        .await
        .unwrap_or(Ok(End::TimedOut));
    if !matches!(end, Ok(End::Exited { .. })) {
        // Killed and reaped here, not left to the runtime.
        let _ = child.kill().await;
    }
    interpret(config, request, end?)
}

/// Reads `from` to its end; `None` as soon as it holds more than `max` bytes.
async fn read_bounded(from: impl AsyncRead + Unpin, max: usize) -> Option<Vec<u8>> {
    let mut kept = Vec::new();
    // A failed read ends the output early: the exit status tells what happened.
    let _ = from.take(max as u64 + 1).read_to_end(&mut kept).await;
    (kept.len() <= max).then_some(kept)
}

/// Reads `from` to its end, keeping its first `max` bytes and dropping the rest, so that the
/// worker never blocks on a full pipe.
async fn read_head(mut from: impl AsyncRead + Unpin, max: usize) -> Vec<u8> {
    let mut kept = Vec::new();
    let _ = (&mut from).take(max as u64).read_to_end(&mut kept).await;
    let _ = tokio::io::copy(&mut from, &mut tokio::io::sink()).await;
    kept
}

/// What the end of a worker's run means for the request.
fn interpret(
    config: &PreviewConfig,
    request: &WorkerRequest,
    end: End,
) -> Result<Bytes, PreviewError> {
    let limits = &config.limits;
    let (status, stdout, stderr) = match end {
        End::TimedOut => {
            return Err(PreviewError::Killed(format!(
                "the preview took longer than {} (the time limit): stopped",
                seconds(limits.timeout.as_secs_f64())
            )));
        }
        End::Exited {
            status,
            stdout,
            stderr,
        } => (
            status,
            stdout,
            String::from_utf8_lossy(&stderr).into_owned(),
        ),
    };
    let memory = || {
        PreviewError::Killed(format!(
            "the preview needed more than {} MiB of memory (the memory limit): stopped",
            limits.memory_mib
        ))
    };
    // Allocation failures abort (`memory allocation of N bytes failed`); a thread or mapping
    // refused for want of address space panics with ENOMEM.
    let out_of_memory =
        stderr.contains("memory allocation of") || stderr.contains("Cannot allocate memory");
    match status.code() {
        Some(0) if stdout.starts_with(b"glTF") => Ok(Bytes::from(stdout)),
        Some(code) if code == i32::from(EXIT_DOES_NOT_DERIVE) => {
            let failure: WorkerFailure = serde_json::from_slice(&stdout).map_err(|e| {
                PreviewError::Failed(format!(
                    "the preview worker's failure is not JSON ({e}): {stderr}"
                ))
            })?;
            Err(PreviewError::DoesNotDerive(Refusal {
                message: failure.error,
                diagnostics: failure
                    .diagnostics
                    .into_iter()
                    .map(|d| Problem {
                        severity: "error",
                        message: d.message,
                        line: d.line,
                        column: d.column,
                        hints: d.hints,
                    })
                    .collect(),
            }))
        }
        _ if out_of_memory => Err(memory()),
        _ if cpu_limit(status) => Err(PreviewError::Killed(format!(
            "the preview used more than {} of CPU time (the CPU limit): stopped",
            seconds(cpu_seconds(limits) as f64)
        ))),
        // A panic (101) or a crash of the engine on this grammar is a bug, but one this grammar
        // sets off every time.
        Some(101) | None => {
            eprintln!(
                "shapegram serve: the preview worker failed on {} ({status}): {stderr}",
                request.name
            );
            Err(PreviewError::DoesNotDerive(Refusal {
                message: format!(
                    "{} does not derive: the engine failed on it (a bug, logged on the server)",
                    request.name
                ),
                diagnostics: Vec::new(),
            }))
        }
        _ => Err(PreviewError::Failed(format!(
            "the preview worker {} ended with {status}: {stderr}",
            config.worker.display()
        ))),
    }
}

/// Why a worker writing more than a preview may be was stopped.
fn too_large() -> String {
    format!(
        "the preview is larger than {} MiB (the size limit): stopped",
        MAX_PREVIEW_BYTES >> 20
    )
}

/// The worker's CPU time limit: a backstop should the server die and leave it running, since
/// the deadline kills it first (it derives on one thread).
fn cpu_seconds(limits: &PreviewLimits) -> u64 {
    limits.timeout.as_secs() + 2
}

/// Whether the kernel stopped the process for its CPU time: `SIGXCPU` at the soft limit,
/// `SIGKILL` at the hard one (the server kills only at the deadline, which is told apart).
#[cfg(unix)]
fn cpu_limit(status: ExitStatus) -> bool {
    use std::os::unix::process::ExitStatusExt;
    matches!(status.signal(), Some(libc::SIGXCPU | libc::SIGKILL))
}

#[cfg(not(unix))]
fn cpu_limit(_: ExitStatus) -> bool {
    false
}

/// `10 s`, `2.5 s`.
fn seconds(s: f64) -> String {
    format!("{s} s")
}
