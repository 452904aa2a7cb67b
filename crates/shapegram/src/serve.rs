//! `shapegram serve`: the grammar repository server (crate `shapegram-server`).

use std::path::PathBuf;

use clap::Args;

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
}

pub fn run(args: &ServeArgs) -> Result<(), Failure> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| Failure::new(format!("cannot start the server's runtime: {e}")))?;
    let data = args.data.display().to_string();
    runtime
        .block_on(shapegram_server::serve(&args.data, &args.listen, |addr| {
            println!("shapegram serve: listening on http://{addr} (database {data})");
            // Scripts and tests read the address from the first line.
            let _ = std::io::Write::flush(&mut std::io::stdout());
        }))
        .map_err(Failure::new)
}
