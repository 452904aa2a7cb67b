//! Throwaway PostgreSQL databases for the test suites (this crate's and the `shapegram`
//! command's). The server is named by one environment variable, [`VARIABLE`]: an
//! administrator's URL such as `postgres://postgres:secret@127.0.0.1:5432/postgres`. Each test
//! creates a database of its own, with a random name, and drops it when done.

use std::io::Write;
use std::str::FromStr;
use std::sync::Once;

use sqlx::postgres::{PgConnectOptions, PgConnection};
use sqlx::{AssertSqlSafe, Connection};

/// The environment variable naming the PostgreSQL server the tests may use.
pub const VARIABLE: &str = "SHAPEGRAM_TEST_POSTGRES";

/// The line printed (once per test program) when the PostgreSQL tests are skipped.
pub const SKIPPED: &str = "PostgreSQL tests skipped: set SHAPEGRAM_TEST_POSTGRES to an administrator's URL (postgres://user:password@127.0.0.1:5432/postgres) to run them";

/// A database made for one test, dropped with this value (also when the test panics).
pub struct TestDatabase {
    admin: PgConnectOptions,
    name: String,
    url: String,
}

impl TestDatabase {
    /// A new, empty database on the server [`VARIABLE`] names; `None` when the variable is not
    /// set, after printing [`SKIPPED`] on stderr once. Panics when the variable is not set but
    /// `CI` is (CI must run these tests), or when the server refuses.
    pub fn create() -> Option<TestDatabase> {
        let Some(admin_url) = std::env::var(VARIABLE).ok().filter(|v| !v.is_empty()) else {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("CI=true but {VARIABLE} is not set: the PostgreSQL tests must run in CI");
            }
            static SAID: Once = Once::new();
            // Straight to stderr: the test harness captures `eprintln!` of passing tests.
            SAID.call_once(|| {
                let _ = writeln!(std::io::stderr(), "{SKIPPED}");
            });
            return None;
        };
        let admin = PgConnectOptions::from_str(&admin_url)
            .unwrap_or_else(|e| panic!("{VARIABLE} is not a PostgreSQL URL: {e}"));
        let mut bytes = [0u8; 8];
        getrandom::fill(&mut bytes).expect("random bytes");
        let name: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        let name = format!("shapegram_test_{name}");
        let mut url =
            url::Url::parse(&admin_url).unwrap_or_else(|e| panic!("{VARIABLE} is not a URL: {e}"));
        url.set_path(&name);
        // The name is ours (letters, digits, `_`): a database name cannot be a bound parameter.
        let sql = format!("CREATE DATABASE {name}");
        on_the_side(admin.clone(), sql)
            .unwrap_or_else(|e| panic!("cannot create a database on {VARIABLE}'s server: {e}"));
        Some(TestDatabase {
            admin,
            name,
            url: url.to_string(),
        })
    }

    /// The database's URL, with the administrator's credentials.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The database's connection options.
    pub fn options(&self) -> PgConnectOptions {
        self.admin.clone().database(&self.name)
    }
}

impl Drop for TestDatabase {
    fn drop(&mut self) {
        // FORCE ends the connections the test's pools still hold.
        let sql = format!("DROP DATABASE IF EXISTS {} WITH (FORCE)", self.name);
        if let Err(e) = on_the_side(self.admin.clone(), sql) {
            let _ = writeln!(std::io::stderr(), "cannot drop {}: {e}", self.name);
        }
    }
}

/// Runs one statement on the administrator's connection, on a thread and runtime of its own:
/// callers may be inside a runtime (async tests, `Drop` while one unwinds) or not.
fn on_the_side(admin: PgConnectOptions, sql: String) -> Result<(), String> {
    std::thread::spawn(move || {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .map_err(|e| e.to_string())?;
        runtime.block_on(async {
            let mut conn = PgConnection::connect_with(&admin)
                .await
                .map_err(|e| e.to_string())?;
            sqlx::raw_sql(AssertSqlSafe(sql))
                .execute(&mut conn)
                .await
                .map_err(|e| e.to_string())?;
            conn.close().await.map_err(|e| e.to_string())
        })
    })
    .join()
    .map_err(|_| "the database thread panicked".to_owned())?
}
