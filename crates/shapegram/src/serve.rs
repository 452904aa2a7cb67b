//! `shapegram serve`: the grammar repository server (crate `shapegram-server`).

use std::path::PathBuf;

use clap::Args;

use shapegram_server::ServeOptions;
use shapegram_server::ratelimit::{Limit, RateLimits};

use crate::Failure;

/// Arguments of `shapegram serve`.
#[derive(Debug, Args)]
pub struct ServeArgs {
    /// The SQLite database file (created on first start)
    #[arg(long, value_name = "FILE", default_value = "repo.db")]
    pub data: PathBuf,
    /// Address and port to listen on (port 0: any free port)
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:8080")]
    pub listen: String,
    /// Requests per token, or per address without one: N/s, N/min, N/h, N/day, or off
    #[arg(long, value_name = "LIMIT", default_value = "600/min")]
    pub rate_limit: String,
    /// Sign-up and login attempts per address: N/s, N/min, N/h, N/day, or off
    #[arg(long, value_name = "LIMIT", default_value = "20/min")]
    pub sign_in_rate_limit: String,
}

pub fn run(args: &ServeArgs) -> Result<(), Failure> {
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
    };
    let data = args.data.display().to_string();
    runtime
        .block_on(shapegram_server::serve(
            &args.data,
            &args.listen,
            options,
            |addr| {
                println!("shapegram serve: listening on http://{addr} (database {data})");
                // Scripts and tests read the address from the first line.
                let _ = std::io::Write::flush(&mut std::io::stdout());
            },
        ))
        .map_err(Failure::new)
}
