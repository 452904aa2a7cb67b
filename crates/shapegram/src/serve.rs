//! `shapegram serve`: the grammar repository server (crate `shapegram-server`), with previews
//! made by this executable's hidden `preview-worker` subcommand.

use std::path::PathBuf;
use std::time::Duration;

use clap::Args;
use shapegram_server::failpoint::FailPoints;
use shapegram_server::preview::{PreviewConfig, PreviewLimits};
use shapegram_server::ratelimit::{Limit, RateLimits};
use shapegram_server::{Database, ServeOptions};

use crate::Failure;

/// Arguments of `shapegram serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The SQLite database file (created on first start)
    #[arg(long, value_name = "FILE", default_value = "repo.db")]
    pub data: PathBuf,
    /// A PostgreSQL database instead, which must exist: postgres://USER:PASSWORD@HOST:PORT/NAME
    /// (several servers may share one)
    #[arg(long, value_name = "URL", conflicts_with = "data")]
    pub database: Option<String>,
    /// Address and port to listen on (port 0: any free port)
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8080")]
    pub listen: String,
    /// Previews: wall-clock seconds a worker may take before it is killed (also how long a
    /// request waits for a free worker)
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0, value_parser = parse_seconds)]
    pub preview_timeout: f64,
    /// Previews: a worker's address space in MiB; beyond it allocations fail and it stops
    #[arg(long, value_name = "MIB", default_value_t = 1024,
        value_parser = clap::value_parser!(u64).range(16..=1 << 20))]
    pub preview_memory: u64,
    /// Previews: derivation steps (rule applications) before a grammar is refused
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    pub preview_steps: usize,
    /// Previews: workers running at once (0: previews off)
    #[arg(long, value_name = "N", default_value_t = 2)]
    pub preview_workers: usize,
    /// Requests per token, or per address without one: N/s, N/min, N/h, N/day, or off
    #[arg(long, value_name = "LIMIT", default_value = "600/min")]
    pub rate_limit: String,
    /// Sign-up and login attempts per address: N/s, N/min, N/h, N/day, or off
    #[arg(long, value_name = "LIMIT", default_value = "20/min")]
    pub sign_in_rate_limit: String,
}

/// A positive number of seconds, at most a day.
fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && s <= 86_400.0 => Ok(s),
        _ => Err("expected a number of seconds above 0, like 10 or 2.5".to_owned()),
    }
}

/// How previews are made: this executable's `preview-worker` under the limits given; `None`
/// when they are off or the executable cannot be found.
fn previews(args: &ServeArgs) -> Option<PreviewConfig> {
    if args.preview_workers == 0 {
        return None;
    }
    let worker = match std::env::current_exe() {
        Ok(worker) => worker,
        Err(e) => {
            eprintln!("warning: previews are off: cannot find this executable: {e}");
            return None;
        }
    };
    Some(PreviewConfig {
        worker,
        args: vec!["preview-worker".into()],
        limits: PreviewLimits {
            timeout: Duration::from_secs_f64(args.preview_timeout),
            memory_mib: args.preview_memory,
            steps: args.preview_steps,
            workers: args.preview_workers,
        },
    })
}

pub fn run(args: &ServeArgs) -> Result<(), Failure> {
    let database = match &args.database {
        Some(url) => Database::postgres(url)
            .map_err(|e| Failure::usage(format!("--database {}: {e}", redacted(url))))?,
        None => Database::Sqlite(args.data.clone()),
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::new(format!("cannot start the server's runtime: {e}")))?;
    let limit = |flag: &str, text: &str| {
        Limit::parse(text).map_err(|e| Failure::new(format!("--{flag}: {e}")))
    };
    let options = ServeOptions {
        rate_limits: RateLimits {
            requests: limit("rate-limit", &args.rate_limit)?,
            sign_in: limit("sign-in-rate-limit", &args.sign_in_rate_limit)?,
        },
        previews: previews(args),
    };
    let fail_points = FailPoints::from_env().map_err(Failure::new)?;
    runtime.block_on(async {
        let store = database.open(fail_points).await.map_err(|e| {
            let message = format!("cannot open {database}: {e}");
            // A PostgreSQL server that refuses us is a setting to correct, like a bad URL.
            match database {
                Database::Postgres(_) => Failure::usage(message),
                Database::Sqlite(_) => Failure::new(message),
            }
        })?;
        shapegram_server::serve(store, &args.listen, options, |addr| {
            println!("shapegram serve: listening on http://{addr} (database {database})");
            // Scripts and tests read the address from the first line.
            let _ = std::io::Write::flush(&mut std::io::stdout());
        })
        .await
        .map_err(Failure::new)
    })
}

/// A URL as the user typed it, its password (between `user:` and `@`) replaced with `***`,
/// for messages about a URL that did not parse.
fn redacted(url: &str) -> String {
    let Some((scheme, rest)) = url.split_once("://") else {
        return url.to_owned();
    };
    match rest.rsplit_once('@') {
        Some((credentials, host)) => match credentials.split_once(':') {
            Some((user, _)) => format!("{scheme}://{user}:***@{host}"),
            None => url.to_owned(),
        },
        None => url.to_owned(),
    }
}
