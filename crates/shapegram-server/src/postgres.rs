//! The PostgreSQL store, for several server processes on one database: a connection pool, the
//! schema migrated under an advisory lock, and PostgreSQL's default isolation (read committed).
//! Writes that must not interleave take locks: a publish updates its grammar's row (so
//! concurrent publishes of one grammar queue up and become consecutive versions) and numbers its
//! publish-log entry under a lock on the log held to its commit; a friend request locks both
//! accounts' rows. All SQL is static text with bound parameters, the same statements as the
//! SQLite store's wherever the two dialects agree.

use std::str::FromStr;
use std::time::Duration;

use sqlx::postgres::{PgConnectOptions, PgConnection, PgPool, PgPoolOptions, PgRow};
use sqlx::{Connection, Postgres, Row, Transaction};

use crate::failpoint::{FailPoint, FailPoints};
use crate::migrations;
use crate::store::*;

/// A grammar the viewer `$1` may see (`g` the grammar): public, the viewer's own, or
/// friends-only and owned by one of the viewer's friends. See [`crate::policy`].
macro_rules! visible {
    () => {
        "(g.visibility = 'public' OR g.owner_id = $1 OR (g.visibility = 'friends' AND EXISTS (
            SELECT 1 FROM friendship f WHERE f.accepted_at IS NOT NULL AND (
                (f.requester_id = $1 AND f.addressee_id = g.owner_id)
                OR (f.addressee_id = $1 AND f.requester_id = g.owner_id)))))"
    };
}

/// The key of the session-level advisory lock held while migrating, so that servers starting
/// at once on one database migrate one after the other ("shapegrm" in ASCII).
const MIGRATION_LOCK: i64 = 0x7368_6170_6567_726d;

/// The repository in a PostgreSQL database.
#[derive(Clone)]
pub struct PgStore {
    pool: PgPool,
    /// Connections for the rate-limit counters, which every request writes: without waiting
    /// for the commit's WAL flush (`synchronous_commit=off`: the database stays consistent, and
    /// a crash of the server's machine loses at most the last counts).
    counters: PgPool,
    fail_points: FailPoints,
}

fn db(e: sqlx::Error) -> StoreError {
    StoreError::Database(e.to_string())
}

fn now() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64)
}

fn is_unique_violation(e: &sqlx::Error) -> bool {
    matches!(e, sqlx::Error::Database(d) if d.is_unique_violation())
}

impl PgStore {
    /// Connects to the database at `url` (`postgres://user:password@host:port/database`) and
    /// brings its schema up to date. The database must exist.
    pub async fn connect(url: &str) -> Result<PgStore, StoreError> {
        let options = PgConnectOptions::from_str(url).map_err(db)?;
        Self::connect_with(options).await
    }

    /// [`PgStore::connect`] with options already parsed.
    pub async fn connect_with(options: PgConnectOptions) -> Result<PgStore, StoreError> {
        migrate(&options).await?;
        let pool = PgPoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(10))
            .connect_with(options.clone())
            .await
            .map_err(db)?;
        let counters = PgPoolOptions::new()
            .max_connections(2)
            .acquire_timeout(Duration::from_secs(10))
            .connect_with(options.options([("synchronous_commit", "off")]))
            .await
            .map_err(db)?;
        let store = PgStore {
            pool,
            counters,
            fail_points: FailPoints::NONE,
        };
        store.refresh_statistics().await?;
        Ok(store)
    }

    /// Brings the planner's statistics of the tables rule queries and search read up to date.
    /// Autovacuum does so only after a minute or so, and without statistics a repository that
    /// grew from nothing is planned as empty: a rule query took 184 ms instead of 2.4 ms on
    /// the load bench's 10,000 rules. Run at start-up and after the publishes numbered by a
    /// power of two or a multiple of 1,024, so the tables are analysed whenever they double.
    async fn refresh_statistics(&self) -> Result<(), StoreError> {
        sqlx::query(
            "ANALYZE account, friendship, grammar, grammar_version, rule, rule_key, rule_neg",
        )
        .execute(&self.pool)
        .await
        .map_err(db)?;
        Ok(())
    }

    /// The same store, stopping at `fail_points` during a publish (the crash test).
    pub fn with_fail_points(self, fail_points: FailPoints) -> PgStore {
        PgStore {
            fail_points,
            ..self
        }
    }

    /// The connection pool, for tools and tests that look at the database itself.
    pub fn pool(&self) -> &PgPool {
        &self.pool
    }

    /// A read-only transaction whose statements all see one snapshot (read committed, the
    /// default, takes a new one per statement).
    async fn begin_read(&self) -> Result<Transaction<'static, Postgres>, StoreError> {
        self.pool
            .begin_with("BEGIN ISOLATION LEVEL REPEATABLE READ, READ ONLY")
            .await
            .map_err(db)
    }

    async fn account_id(&self, canon: &str) -> Result<Option<Id>, StoreError> {
        sqlx::query_scalar("SELECT id FROM account WHERE canon = $1")
            .bind(canon)
            .fetch_optional(&self.pool)
            .await
            .map_err(db)
    }
}

/// Applies the migrations not applied yet, each in its own transaction, on a connection of its
/// own that holds [`MIGRATION_LOCK`] throughout: the lock goes with the connection, also when a
/// migration fails.
async fn migrate(options: &PgConnectOptions) -> Result<(), StoreError> {
    let mut conn = PgConnection::connect_with(options).await.map_err(db)?;
    sqlx::query("SELECT pg_advisory_lock($1)")
        .bind(MIGRATION_LOCK)
        .execute(&mut conn)
        .await
        .map_err(db)?;
    // Creating the table under the lock too: two `CREATE TABLE IF NOT EXISTS` at once can both
    // try to create it.
    sqlx::raw_sql(
        "CREATE TABLE IF NOT EXISTS schema_migration (
            version BIGINT PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL,
            applied_at BIGINT NOT NULL)",
    )
    .execute(&mut conn)
    .await
    .map_err(db)?;
    for m in migrations::POSTGRES {
        let mut tx = conn.begin().await.map_err(db)?;
        let applied: Option<String> =
            sqlx::query_scalar("SELECT sha256 FROM schema_migration WHERE version = $1")
                .bind(m.version)
                .fetch_optional(&mut *tx)
                .await
                .map_err(db)?;
        let sum = migrations::checksum(m);
        match applied {
            Some(stored) if stored == sum => continue,
            Some(_) => {
                return Err(StoreError::Database(format!(
                    "migration {} ({}) differs from the one applied to this database",
                    m.version, m.name
                )));
            }
            None => {}
        }
        sqlx::raw_sql(m.sql).execute(&mut *tx).await.map_err(db)?;
        sqlx::query(
            "INSERT INTO schema_migration (version, name, sha256, applied_at)
             VALUES ($1, $2, $3, $4)",
        )
        .bind(m.version)
        .bind(m.name)
        .bind(sum)
        .bind(now())
        .execute(&mut *tx)
        .await
        .map_err(db)?;
        tx.commit().await.map_err(db)?;
    }
    conn.close().await.map_err(db)
}

fn summary(row: PgRow) -> Result<GrammarSummary, StoreError> {
    let visibility: String = row.try_get(2).map_err(db)?;
    Ok(GrammarSummary {
        owner: row.try_get(0).map_err(db)?,
        name: row.try_get(1).map_err(db)?,
        visibility: Visibility::parse(&visibility)
            .ok_or_else(|| StoreError::Database(format!("bad visibility {visibility}")))?,
        latest_version: row.try_get(3).map_err(db)?,
        current_version: row.try_get(4).map_err(db)?,
        updated_at: row.try_get(5).map_err(db)?,
    })
}

/// The columns a version's yank is read from: `y` the yank, `ya` its author.
macro_rules! yank_columns {
    () => {
        "y.yanked_at, ya.name AS yanked_by, y.reason AS yank_reason"
    };
}

/// Joins a version `v`'s yank, if any.
macro_rules! yank_join {
    () => {
        " LEFT JOIN version_yank y ON y.version_id = v.id
          LEFT JOIN account ya ON ya.id = y.yanked_by "
    };
}

/// The columns [`version_text`] reads, besides the yank's: `a` the owner, `g` the grammar,
/// `v` the version, `p` its publisher.
macro_rules! version_text_columns {
    () => {
        "a.name AS owner, g.name AS grammar, v.version, v.sha256, v.published_at,
         p.name AS publisher, v.text"
    };
}

/// A version with its text, from a row of [`version_text_columns`] and the yank's columns.
fn version_text(row: &PgRow) -> Result<VersionText, StoreError> {
    Ok(VersionText {
        owner: row.try_get("owner").map_err(db)?,
        name: row.try_get("grammar").map_err(db)?,
        info: version_info(row)?,
        text: row.try_get("text").map_err(db)?,
    })
}

fn version_info(row: &PgRow) -> Result<VersionInfo, StoreError> {
    let yanked_at: Option<i64> = row.try_get("yanked_at").map_err(db)?;
    let yank = match yanked_at {
        Some(at) => Some(Yank {
            by: row.try_get("yanked_by").map_err(db)?,
            at,
            reason: row.try_get("yank_reason").map_err(db)?,
        }),
        None => None,
    };
    Ok(VersionInfo {
        version: row.try_get("version").map_err(db)?,
        sha256: row.try_get("sha256").map_err(db)?,
        published_at: row.try_get("published_at").map_err(db)?,
        publisher: row.try_get("publisher").map_err(db)?,
        yanked: yank.is_some(),
        yank,
    })
}

impl Store for PgStore {
    fn create_account<'a>(
        &'a self,
        name: &'a str,
        canon: &'a str,
        password_hash: &'a str,
    ) -> StoreFuture<'a, Account> {
        Box::pin(async move {
            let id: Id = sqlx::query_scalar(
                "INSERT INTO account (name, canon, password_hash, created_at)
                 VALUES ($1, $2, $3, $4) RETURNING id",
            )
            .bind(name)
            .bind(canon)
            .bind(password_hash)
            .bind(now())
            .fetch_one(&self.pool)
            .await
            .map_err(|e| {
                if is_unique_violation(&e) {
                    StoreError::Conflict(format!("the name {name} is taken"))
                } else {
                    db(e)
                }
            })?;
            Ok(Account {
                id,
                name: name.to_owned(),
            })
        })
    }

    fn account_for_login<'a>(
        &'a self,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<(Account, String)>> {
        Box::pin(async move {
            let row: Option<(Id, String, String)> =
                sqlx::query_as("SELECT id, name, password_hash FROM account WHERE canon = $1")
                    .bind(canon)
                    .fetch_optional(&self.pool)
                    .await
                    .map_err(db)?;
            Ok(row.map(|(id, name, hash)| (Account { id, name }, hash)))
        })
    }

    fn set_password_hash<'a>(&'a self, account: Id, password_hash: &'a str) -> StoreFuture<'a, ()> {
        Box::pin(async move {
            sqlx::query("UPDATE account SET password_hash = $2 WHERE id = $1")
                .bind(account)
                .bind(password_hash)
                .execute(&self.pool)
                .await
                .map_err(db)?;
            Ok(())
        })
    }

    fn create_token<'a>(&'a self, token: NewToken<'a>) -> StoreFuture<'a, TokenInfo> {
        Box::pin(async move {
            let created_at = now();
            let id: Id = sqlx::query_scalar(
                "INSERT INTO api_token (account_id, name, hash, prefix, created_at)
                 VALUES ($1, $2, $3, $4, $5) RETURNING id",
            )
            .bind(token.account)
            .bind(token.name)
            .bind(&token.hash[..])
            .bind(token.prefix)
            .bind(created_at)
            .fetch_one(&self.pool)
            .await
            .map_err(db)?;
            Ok(TokenInfo {
                id,
                name: token.name.to_owned(),
                prefix: token.prefix.to_owned(),
                created_at,
                revoked: false,
            })
        })
    }

    fn account_by_token<'a>(&'a self, hash: &'a [u8; 32]) -> StoreFuture<'a, Option<Account>> {
        Box::pin(async move {
            let row: Option<(Id, String)> = sqlx::query_as(
                "SELECT a.id, a.name FROM api_token t JOIN account a ON a.id = t.account_id
                 WHERE t.hash = $1 AND t.revoked_at IS NULL",
            )
            .bind(&hash[..])
            .fetch_optional(&self.pool)
            .await
            .map_err(db)?;
            Ok(row.map(|(id, name)| Account { id, name }))
        })
    }

    fn list_tokens(&self, account: Id) -> StoreFuture<'_, Vec<TokenInfo>> {
        Box::pin(async move {
            let rows: Vec<(Id, String, String, i64, Option<i64>)> = sqlx::query_as(
                "SELECT id, name, prefix, created_at, revoked_at FROM api_token
                 WHERE account_id = $1 ORDER BY id",
            )
            .bind(account)
            .fetch_all(&self.pool)
            .await
            .map_err(db)?;
            Ok(rows
                .into_iter()
                .map(|(id, name, prefix, created_at, revoked)| TokenInfo {
                    id,
                    name,
                    prefix,
                    created_at,
                    revoked: revoked.is_some(),
                })
                .collect())
        })
    }

    fn revoke_token(&self, account: Id, token: Id) -> StoreFuture<'_, bool> {
        Box::pin(async move {
            let done = sqlx::query(
                "UPDATE api_token SET revoked_at = COALESCE(revoked_at, $3)
                 WHERE id = $1 AND account_id = $2",
            )
            .bind(token)
            .bind(account)
            .bind(now())
            .execute(&self.pool)
            .await
            .map_err(db)?;
            Ok(done.rows_affected() == 1)
        })
    }

    fn request_friend<'a>(&'a self, from: Id, to_canon: &'a str) -> StoreFuture<'a, FriendRequest> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await.map_err(db)?;
            let to: Option<Id> = sqlx::query_scalar("SELECT id FROM account WHERE canon = $1")
                .bind(to_canon)
                .fetch_optional(&mut *tx)
                .await
                .map_err(db)?;
            let Some(to) = to.filter(|&to| to != from) else {
                return Ok(FriendRequest::NoSuchAccount);
            };
            // Two requests between the same two accounts wait for each other (in the order of
            // the ids, so that they cannot deadlock): two crossing requests make friends, as
            // they do one after the other. NO KEY UPDATE leaves foreign-key checks unblocked.
            sqlx::query(
                "SELECT id FROM account WHERE id IN ($1, $2) ORDER BY id FOR NO KEY UPDATE",
            )
            .bind(from)
            .bind(to)
            .execute(&mut *tx)
            .await
            .map_err(db)?;
            // A request the other way (pending or accepted) makes us friends.
            let reverse = sqlx::query(
                "UPDATE friendship SET accepted_at = COALESCE(accepted_at, $3)
                 WHERE requester_id = $1 AND addressee_id = $2",
            )
            .bind(to)
            .bind(from)
            .bind(now())
            .execute(&mut *tx)
            .await
            .map_err(db)?;
            let outcome = if reverse.rows_affected() == 1 {
                FriendRequest::Friends
            } else {
                sqlx::query(
                    "INSERT INTO friendship (requester_id, addressee_id, created_at)
                     VALUES ($1, $2, $3) ON CONFLICT (requester_id, addressee_id) DO NOTHING",
                )
                .bind(from)
                .bind(to)
                .bind(now())
                .execute(&mut *tx)
                .await
                .map_err(db)?;
                let accepted: Option<i64> = sqlx::query_scalar(
                    "SELECT accepted_at FROM friendship WHERE requester_id = $1 AND addressee_id = $2",
                )
                .bind(from)
                .bind(to)
                .fetch_one(&mut *tx)
                .await
                .map_err(db)?;
                if accepted.is_some() {
                    FriendRequest::Friends
                } else {
                    FriendRequest::Requested
                }
            };
            tx.commit().await.map_err(db)?;
            Ok(outcome)
        })
    }

    fn accept_friend<'a>(&'a self, me: Id, from_canon: &'a str) -> StoreFuture<'a, bool> {
        Box::pin(async move {
            let done = sqlx::query(
                "UPDATE friendship SET accepted_at = $3
                 WHERE addressee_id = $1 AND accepted_at IS NULL
                   AND requester_id = (SELECT id FROM account WHERE canon = $2)",
            )
            .bind(me)
            .bind(from_canon)
            .bind(now())
            .execute(&self.pool)
            .await
            .map_err(db)?;
            Ok(done.rows_affected() == 1)
        })
    }

    fn remove_friend<'a>(&'a self, me: Id, other_canon: &'a str) -> StoreFuture<'a, bool> {
        Box::pin(async move {
            let Some(other) = self.account_id(other_canon).await? else {
                return Ok(false);
            };
            let done = sqlx::query(
                "DELETE FROM friendship WHERE (requester_id = $1 AND addressee_id = $2)
                    OR (requester_id = $2 AND addressee_id = $1)",
            )
            .bind(me)
            .bind(other)
            .execute(&self.pool)
            .await
            .map_err(db)?;
            Ok(done.rows_affected() > 0)
        })
    }

    fn friends(&self, me: Id) -> StoreFuture<'_, Friends> {
        Box::pin(async move {
            let rows: Vec<(String, bool, bool)> = sqlx::query_as(
                "SELECT a.name, f.accepted_at IS NOT NULL, f.requester_id = $1
                 FROM friendship f JOIN account a
                   ON a.id = CASE WHEN f.requester_id = $1 THEN f.addressee_id ELSE f.requester_id END
                 WHERE f.requester_id = $1 OR f.addressee_id = $1
                 ORDER BY a.canon",
            )
            .bind(me)
            .fetch_all(&self.pool)
            .await
            .map_err(db)?;
            let mut friends = Friends::default();
            for (name, accepted, mine) in rows {
                match (accepted, mine) {
                    (true, _) => friends.friends.push(name),
                    (false, true) => friends.outgoing.push(name),
                    (false, false) => friends.incoming.push(name),
                }
            }
            Ok(friends)
        })
    }

    fn publish<'a>(&'a self, v: NewVersion<'a>) -> StoreFuture<'a, VersionInfo> {
        Box::pin(async move {
            let at = now();
            // The UPDATE of the grammar's row below locks it until the commit: a concurrent
            // publish of the same grammar waits there, then reads the committed latest_version.
            // A concurrent first publish waits at the INSERT's conflict check instead.
            self.fail_points.hit(FailPoint::BeforeTransaction).await;
            let mut tx = self.pool.begin().await.map_err(db)?;
            // A rename that commits between the two statements leaves no grammar of this name
            // to update: then each statement, seeing the rename (read committed), makes and
            // numbers a new grammar of the name, as on SQLite, where the rename comes first.
            let mut numbered = None;
            for _ in 0..3 {
                sqlx::query(
                    "INSERT INTO grammar (owner_id, name, canon, visibility, created_at, updated_at)
                     VALUES ($1, $2, $3, $4, $5, $5) ON CONFLICT (owner_id, canon) DO NOTHING",
                )
                .bind(v.owner.id)
                .bind(v.name)
                .bind(v.canon)
                .bind(v.visibility.unwrap_or(Visibility::Public).as_str())
                .bind(at)
                .execute(&mut *tx)
                .await
                .map_err(db)?;
                numbered = sqlx::query_as(
                    "UPDATE grammar SET latest_version = latest_version + 1,
                        current_version = latest_version + 1, updated_at = $3,
                        visibility = COALESCE($4, visibility)
                     WHERE owner_id = $1 AND canon = $2 RETURNING id, latest_version",
                )
                .bind(v.owner.id)
                .bind(v.canon)
                .bind(at)
                .bind(v.visibility.map(Visibility::as_str))
                .fetch_optional(&mut *tx)
                .await
                .map_err(db)?;
                if numbered.is_some() {
                    break;
                }
            }
            let (grammar, version): (Id, i64) = numbered.ok_or_else(|| {
                StoreError::Database(format!("{} was renamed away three times", v.canon))
            })?;
            let version_id: Id = sqlx::query_scalar(
                "INSERT INTO grammar_version
                    (grammar_id, version, text, sha256, publisher_id, published_at, rule_count)
                 VALUES ($1, $2, $3, $4, $5, $6, $7) RETURNING id",
            )
            .bind(grammar)
            .bind(version)
            .bind(v.text)
            .bind(v.sha256)
            .bind(v.owner.id)
            .bind(at)
            .bind(v.rules.len() as i64)
            .fetch_one(&mut *tx)
            .await
            .map_err(db)?;
            self.fail_points.hit(FailPoint::AfterInsertVersion).await;
            for rule in v.rules {
                let rule_id: Id = sqlx::query_scalar(
                    "INSERT INTO rule (version_id, idx, n_pos, local, conditional)
                     VALUES ($1, $2, $3, $4, $5) RETURNING id",
                )
                .bind(version_id)
                .bind(rule.index)
                .bind(rule.positive.len() as i64)
                .bind(rule.local)
                .bind(rule.conditional)
                .fetch_one(&mut *tx)
                .await
                .map_err(db)?;
                for key in &rule.positive {
                    sqlx::query("INSERT INTO rule_key (key, rule_id) VALUES ($1, $2)")
                        .bind(key)
                        .bind(rule_id)
                        .execute(&mut *tx)
                        .await
                        .map_err(db)?;
                }
                for (group, keys) in rule.negative.iter().enumerate() {
                    for key in keys {
                        sqlx::query(
                            "INSERT INTO rule_neg (rule_id, grp, key) VALUES ($1, $2, $3)
                             ON CONFLICT DO NOTHING",
                        )
                        .bind(rule_id)
                        .bind(group as i64)
                        .bind(key)
                        .execute(&mut *tx)
                        .await
                        .map_err(db)?;
                    }
                }
            }
            self.fail_points.hit(FailPoint::AfterRuleIndex).await;
            // Publishes take their place in the log one at a time, until their commits, so that
            // the log is numbered in the commits' order without gaps (readers are not blocked).
            sqlx::query("LOCK TABLE publish_log IN SHARE ROW EXCLUSIVE MODE")
                .execute(&mut *tx)
                .await
                .map_err(db)?;
            let seq: i64 = sqlx::query_scalar(
                "INSERT INTO publish_log (seq, version_id, logged_at)
                 SELECT coalesce(max(seq), 0) + 1, $1, $2 FROM publish_log RETURNING seq",
            )
            .bind(version_id)
            .bind(at)
            .fetch_one(&mut *tx)
            .await
            .map_err(db)?;
            self.fail_points.hit(FailPoint::BeforeCommit).await;
            tx.commit().await.map_err(db)?;
            self.fail_points.hit(FailPoint::AfterCommit).await;
            // The version is committed: statistics that cannot be refreshed now are no reason
            // to say it is not.
            if (seq & (seq - 1) == 0 || seq % 1024 == 0)
                && let Err(e) = self.refresh_statistics().await
            {
                eprintln!("shapegram serve: cannot refresh the planner's statistics: {e}");
            }
            Ok(VersionInfo {
                version,
                sha256: v.sha256.to_owned(),
                published_at: at,
                publisher: v.owner.name.clone(),
                yanked: false,
                yank: None,
            })
        })
    }

    fn list_grammars<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: Option<&'a str>,
    ) -> StoreFuture<'a, Vec<GrammarSummary>> {
        Box::pin(async move {
            let rows = sqlx::query(concat!(
                "SELECT a.name, g.name, g.visibility, g.latest_version, g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE ($2 IS NULL OR a.canon = $2) AND ",
                visible!(),
                " ORDER BY a.canon, g.canon LIMIT 1000"
            ))
            .bind(viewer.account)
            .bind(owner_canon)
            .fetch_all(&self.pool)
            .await
            .map_err(db)?;
            rows.into_iter().map(summary).collect()
        })
    }

    fn search_grammars<'a>(
        &'a self,
        viewer: Viewer,
        query: SearchQuery<'a>,
    ) -> StoreFuture<'a, Vec<GrammarSummary>> {
        Box::pin(async move {
            let goal = query.goal.map(|goal| format!("g:{goal}"));
            let tag = query.tag.map(|tag| format!("t:{tag}"));
            let pattern = query.name.map(like_pattern);
            // The SQLite store's statement (see there).
            let rows = sqlx::query(concat!(
                "SELECT a.name, g.name, g.visibility, g.latest_version, g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                   JOIN grammar_version v ON v.grammar_id = g.id AND v.version = g.current_version
                 WHERE ($2 IS NULL OR a.canon = $2)
                   AND ($3 IS NULL OR g.canon LIKE $3 ESCAPE '\\')
                   AND ($4 IS NULL OR v.id IN (SELECT r.version_id FROM rule_key k
                        JOIN rule r ON r.id = k.rule_id WHERE k.key = $4))
                   AND ($5 IS NULL OR v.id IN (SELECT r.version_id FROM rule_key k
                        JOIN rule r ON r.id = k.rule_id WHERE k.key = $5))
                   AND ",
                visible!(),
                " ORDER BY a.canon, g.canon LIMIT $6 OFFSET $7"
            ))
            .bind(viewer.account)
            .bind(query.owner_canon)
            .bind(pattern)
            .bind(goal)
            .bind(tag)
            .bind(query.limit)
            .bind(query.offset)
            .fetch_all(&self.pool)
            .await
            .map_err(db)?;
            rows.into_iter().map(summary).collect()
        })
    }

    fn grammar<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<GrammarSummary>> {
        Box::pin(async move {
            let row = sqlx::query(concat!(
                "SELECT a.name, g.name, g.visibility, g.latest_version, g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE a.canon = $2 AND g.canon = $3 AND ",
                visible!()
            ))
            .bind(viewer.account)
            .bind(owner_canon)
            .bind(canon)
            .fetch_optional(&self.pool)
            .await
            .map_err(db)?;
            row.map(summary).transpose()
        })
    }

    fn versions<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<Vec<VersionInfo>>> {
        Box::pin(async move {
            // One snapshot, so that the grammar and its versions agree.
            let mut tx = self.begin_read().await?;
            let grammar: Option<Id> = sqlx::query_scalar(concat!(
                "SELECT g.id FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE a.canon = $2 AND g.canon = $3 AND ",
                visible!()
            ))
            .bind(viewer.account)
            .bind(owner_canon)
            .bind(canon)
            .fetch_optional(&mut *tx)
            .await
            .map_err(db)?;
            let Some(grammar) = grammar else {
                return Ok(None);
            };
            let rows = sqlx::query(concat!(
                "SELECT v.version, v.sha256, v.published_at, p.name AS publisher, ",
                yank_columns!(),
                " FROM grammar_version v JOIN account p ON p.id = v.publisher_id",
                yank_join!(),
                "WHERE v.grammar_id = $1 ORDER BY v.version"
            ))
            .bind(grammar)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            tx.commit().await.map_err(db)?;
            rows.iter()
                .map(version_info)
                .collect::<Result<_, _>>()
                .map(Some)
        })
    }

    fn version<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<VersionText>> {
        Box::pin(async move {
            let row = sqlx::query(concat!(
                "SELECT ",
                version_text_columns!(),
                ", ",
                yank_columns!(),
                " FROM grammar g JOIN account a ON a.id = g.owner_id
                   JOIN grammar_version v ON v.grammar_id = g.id
                   JOIN account p ON p.id = v.publisher_id",
                yank_join!(),
                "WHERE a.canon = $2 AND g.canon = $3 AND v.version = $4 AND ",
                visible!()
            ))
            .bind(viewer.account)
            .bind(owner_canon)
            .bind(canon)
            .bind(version)
            .fetch_optional(&self.pool)
            .await
            .map_err(db)?;
            let Some(row) = row else { return Ok(None) };
            version_text(&row).map(Some)
        })
    }

    fn version_rules<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<Vec<IndexedRule>>> {
        Box::pin(async move {
            let mut tx = self.begin_read().await?;
            let version_id: Option<Id> = sqlx::query_scalar(concat!(
                "SELECT v.id FROM grammar g JOIN account a ON a.id = g.owner_id
                   JOIN grammar_version v ON v.grammar_id = g.id
                 WHERE a.canon = $2 AND g.canon = $3 AND v.version = $4 AND ",
                visible!()
            ))
            .bind(viewer.account)
            .bind(owner_canon)
            .bind(canon)
            .bind(version)
            .fetch_optional(&mut *tx)
            .await
            .map_err(db)?;
            let Some(version_id) = version_id else {
                return Ok(None);
            };
            let rules: Vec<(Id, i64, bool, bool)> = sqlx::query_as(
                "SELECT id, idx, local, conditional FROM rule WHERE version_id = $1 ORDER BY idx",
            )
            .bind(version_id)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            let keys: Vec<(Id, String)> = sqlx::query_as(
                "SELECT k.rule_id, k.key FROM rule_key k JOIN rule r ON r.id = k.rule_id
                 WHERE r.version_id = $1 ORDER BY k.rule_id, k.key",
            )
            .bind(version_id)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            let negs: Vec<(Id, i64, String)> = sqlx::query_as(
                "SELECT n.rule_id, n.grp, n.key FROM rule_neg n JOIN rule r ON r.id = n.rule_id
                 WHERE r.version_id = $1 ORDER BY n.rule_id, n.grp, n.key",
            )
            .bind(version_id)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            tx.commit().await.map_err(db)?;
            let mut out: Vec<IndexedRule> = Vec::with_capacity(rules.len());
            let mut by_id = std::collections::HashMap::with_capacity(rules.len());
            for (id, index, local, conditional) in rules {
                by_id.insert(id, out.len());
                out.push(IndexedRule {
                    index,
                    local,
                    conditional,
                    ..IndexedRule::default()
                });
            }
            for (id, key) in keys {
                if let Some(&i) = by_id.get(&id) {
                    out[i].positive.push(key);
                }
            }
            for (id, group, key) in negs {
                if let Some(&i) = by_id.get(&id) {
                    let negative = &mut out[i].negative;
                    let group = usize::try_from(group).unwrap_or(0);
                    if negative.len() <= group {
                        negative.resize(group + 1, Vec::new());
                    }
                    negative[group].push(key);
                }
            }
            Ok(Some(out))
        })
    }

    fn query_rules<'a>(
        &'a self,
        viewer: Viewer,
        link: Link,
        queries: &'a [Vec<String>],
    ) -> StoreFuture<'a, QueryAnswers> {
        Box::pin(async move {
            // One snapshot: every answer sees the same publishes, up to `as_of` (the log's
            // order is the commits', so every entry up to it is visible).
            let mut tx = self.begin_read().await?;
            let as_of: i64 = sqlx::query_scalar("SELECT coalesce(max(seq), 0) FROM publish_log")
                .fetch_one(&mut *tx)
                .await
                .map_err(db)?;
            let mut found = FoundSet::default();
            for keys in queries {
                // The SQLite store's statement (see there), the keys bound as an array.
                let rows: Vec<QueryRow> = sqlx::query_as(concat!(
                    "WITH k(key) AS (SELECT unnest($2::text[]) COLLATE \"C\"),
                     m(id, n) AS (
                         SELECT rk.rule_id, count(*) FROM rule_key rk JOIN k ON rk.key = k.key
                         GROUP BY rk.rule_id
                         UNION ALL SELECT r0.id, 0 FROM rule r0 WHERE r0.n_pos = 0)
                     SELECT g.id, a.name, g.name, v.version, v.sha256, r.idx
                     FROM m JOIN rule r ON r.id = m.id AND r.n_pos = m.n AND NOT r.local
                       JOIN grammar_version v ON v.id = r.version_id
                       JOIN grammar g ON g.id = v.grammar_id AND g.current_version = v.version
                       JOIN account a ON a.id = g.owner_id
                     WHERE ",
                    visible!(),
                    " AND ($3 = 'all' OR g.owner_id = $1 OR ($3 = 'friends' AND EXISTS (
                         SELECT 1 FROM friendship f WHERE f.accepted_at IS NOT NULL AND (
                             (f.requester_id = $1 AND f.addressee_id = g.owner_id)
                             OR (f.addressee_id = $1 AND f.requester_id = g.owner_id)))))
                       AND NOT EXISTS (
                         SELECT 1 FROM rule_neg n WHERE n.rule_id = r.id GROUP BY n.grp
                         HAVING count(*) = sum(CASE WHEN n.key IN (SELECT key FROM k)
                                                    THEN 1 ELSE 0 END))
                     ORDER BY a.canon, g.canon, r.idx"
                ))
                .bind(viewer.account)
                .bind(keys)
                .bind(link.as_str())
                .fetch_all(&mut *tx)
                .await
                .map_err(db)?;
                found.answer(rows);
            }
            tx.commit().await.map_err(db)?;
            Ok(found.into_answers(as_of))
        })
    }
    fn yank<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        version: i64,
        reason: Option<&'a str>,
    ) -> StoreFuture<'a, Option<VersionInfo>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await.map_err(db)?;
            let Some(version_id) = owned_version(&mut tx, owner.id, canon, version).await? else {
                return Ok(None);
            };
            sqlx::query(
                "INSERT INTO version_yank (version_id, yanked_by, yanked_at, reason)
                 VALUES ($1, $2, $3, $4) ON CONFLICT (version_id) DO NOTHING",
            )
            .bind(version_id)
            .bind(owner.id)
            .bind(now())
            .bind(reason)
            .execute(&mut *tx)
            .await
            .map_err(db)?;
            update_current_version(&mut tx, version_id).await?;
            let info = version_by_id(&mut tx, version_id).await?;
            tx.commit().await.map_err(db)?;
            Ok(Some(info))
        })
    }

    fn unyank<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<VersionInfo>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await.map_err(db)?;
            let Some(version_id) = owned_version(&mut tx, owner.id, canon, version).await? else {
                return Ok(None);
            };
            sqlx::query("DELETE FROM version_yank WHERE version_id = $1")
                .bind(version_id)
                .execute(&mut *tx)
                .await
                .map_err(db)?;
            update_current_version(&mut tx, version_id).await?;
            let info = version_by_id(&mut tx, version_id).await?;
            tx.commit().await.map_err(db)?;
            Ok(Some(info))
        })
    }

    fn rename_grammar<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        name: &'a str,
        new_canon: &'a str,
    ) -> StoreFuture<'a, Option<GrammarSummary>> {
        Box::pin(async move {
            let mut tx = self.pool.begin().await.map_err(db)?;
            let renamed = sqlx::query(
                "UPDATE grammar SET name = $3, canon = $4, updated_at = $5
                 WHERE owner_id = $1 AND canon = $2",
            )
            .bind(owner.id)
            .bind(canon)
            .bind(name)
            .bind(new_canon)
            .bind(now())
            .execute(&mut *tx)
            .await
            .map_err(|e| {
                if is_unique_violation(&e) {
                    StoreError::Conflict(format!("{}/{name} exists already", owner.name))
                } else {
                    db(e)
                }
            })?;
            if renamed.rows_affected() == 0 {
                return Ok(None);
            }
            let row = sqlx::query(
                "SELECT a.name, g.name, g.visibility, g.latest_version, g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE g.owner_id = $1 AND g.canon = $2",
            )
            .bind(owner.id)
            .bind(new_canon)
            .fetch_one(&mut *tx)
            .await
            .map_err(db)?;
            tx.commit().await.map_err(db)?;
            summary(row).map(Some)
        })
    }

    fn version_by_sha256<'a>(
        &'a self,
        viewer: Viewer,
        sha256: &'a str,
    ) -> StoreFuture<'a, Option<VersionText>> {
        Box::pin(async move {
            let row = sqlx::query(concat!(
                "SELECT ",
                version_text_columns!(),
                ", ",
                yank_columns!(),
                " FROM grammar_version v JOIN grammar g ON g.id = v.grammar_id
                   JOIN account a ON a.id = g.owner_id
                   JOIN account p ON p.id = v.publisher_id",
                yank_join!(),
                "WHERE v.sha256 = $2 AND ",
                visible!(),
                " ORDER BY v.id DESC LIMIT 1"
            ))
            .bind(viewer.account)
            .bind(sha256)
            .fetch_optional(&self.pool)
            .await
            .map_err(db)?;
            let Some(row) = row else { return Ok(None) };
            version_text(&row).map(Some)
        })
    }

    fn rate_limit_hit<'a>(&'a self, key: &'a str, window_start: i64) -> StoreFuture<'a, i64> {
        Box::pin(async move {
            sqlx::query_scalar(
                "INSERT INTO rate_limit (key, window_start, hits) VALUES ($1, $2, 1)
                 ON CONFLICT (key, window_start) DO UPDATE SET hits = rate_limit.hits + 1
                 RETURNING hits",
            )
            .bind(key)
            .bind(window_start)
            .fetch_one(&self.counters)
            .await
            .map_err(db)
        })
    }

    fn prune_rate_limits(&self, before: i64) -> StoreFuture<'_, ()> {
        Box::pin(async move {
            sqlx::query("DELETE FROM rate_limit WHERE window_start < $1")
                .bind(before)
                .execute(&self.counters)
                .await
                .map_err(db)?;
            Ok(())
        })
    }

    fn audit(&self) -> StoreFuture<'_, Vec<String>> {
        Box::pin(async move {
            // One snapshot of the database. PostgreSQL checks its pages and foreign keys itself
            // (there is no PRAGMA to ask): what is left are the checks of our own invariants.
            let mut tx = self.begin_read().await?;
            let mut problems = Vec::new();
            let checks: [(&str, &str); 5] = [
                (
                    "SELECT g.canon || ' ' || v.version FROM grammar_version v
                     JOIN grammar g ON g.id = v.grammar_id
                     WHERE v.rule_count IS NOT NULL
                       AND v.rule_count <> (SELECT COUNT(*) FROM rule r WHERE r.version_id = v.id)
                     ORDER BY v.id",
                    "has not the rule index it was published with",
                ),
                (
                    "SELECT g.canon || ' ' || v.version FROM grammar_version v
                     JOIN grammar g ON g.id = v.grammar_id
                     WHERE NOT EXISTS (SELECT 1 FROM publish_log l WHERE l.version_id = v.id)
                     ORDER BY v.id",
                    "is not in the publish log",
                ),
                (
                    "SELECT g.canon FROM grammar g WHERE g.latest_version <> (
                        SELECT COUNT(*) FROM grammar_version v WHERE v.grammar_id = g.id)
                     OR g.latest_version <> (SELECT COALESCE(MAX(v.version), 0)
                        FROM grammar_version v WHERE v.grammar_id = g.id)
                     ORDER BY g.id",
                    "has versions numbered with a gap, or a latest version it does not have",
                ),
                (
                    "SELECT g.canon FROM grammar g WHERE g.current_version IS DISTINCT FROM (
                        SELECT MAX(v.version) FROM grammar_version v WHERE v.grammar_id = g.id
                          AND NOT EXISTS (SELECT 1 FROM version_yank y WHERE y.version_id = v.id))
                     ORDER BY g.id",
                    "has a current version other than its newest not yanked",
                ),
                (
                    "SELECT 'entry ' || MAX(seq) FROM publish_log
                     HAVING COUNT(*) <> MAX(seq) - MIN(seq) + 1 OR MIN(seq) <> 1",
                    "is the last of a publish log numbered with a gap",
                ),
            ];
            for (sql, what) in checks {
                let found: Vec<String> = sqlx::query_scalar(sql)
                    .fetch_all(&mut *tx)
                    .await
                    .map_err(db)?;
                problems.extend(found.into_iter().map(|f| format!("{f} {what}")));
            }
            let texts: Vec<(String, i64, String, String)> = sqlx::query_as(
                "SELECT g.canon, v.version, v.text, v.sha256 FROM grammar_version v
                 JOIN grammar g ON g.id = v.grammar_id ORDER BY v.id",
            )
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            for (grammar, version, text, sha256) in texts {
                if crate::tokens::sha256_hex(text.as_bytes()) != sha256 {
                    problems.push(format!(
                        "{grammar} {version}: the text does not match its SHA-256"
                    ));
                }
            }
            tx.commit().await.map_err(db)?;
            Ok(problems)
        })
    }
}
/// The id of version `version` of the grammar `canon` that `owner` owns, its grammar's row
/// locked until the commit: a concurrent publish, yank or unyank of the grammar waits, so that
/// the current version computed afterwards sees every version and yank committed before.
async fn owned_version(
    tx: &mut Transaction<'static, Postgres>,
    owner: Id,
    canon: &str,
    version: i64,
) -> Result<Option<Id>, StoreError> {
    sqlx::query_scalar(
        "SELECT v.id FROM grammar g JOIN grammar_version v ON v.grammar_id = g.id
         WHERE g.owner_id = $1 AND g.canon = $2 AND v.version = $3
         FOR UPDATE OF g",
    )
    .bind(owner)
    .bind(canon)
    .bind(version)
    .fetch_optional(&mut **tx)
    .await
    .map_err(db)
}

/// Sets the current version of the grammar of version `version_id` to its newest version not
/// yanked (NULL when every one is), after a yank or unyank.
async fn update_current_version(
    tx: &mut Transaction<'static, Postgres>,
    version_id: Id,
) -> Result<(), StoreError> {
    sqlx::query(
        "UPDATE grammar SET current_version = (
            SELECT MAX(v.version) FROM grammar_version v
            WHERE v.grammar_id = grammar.id
              AND NOT EXISTS (SELECT 1 FROM version_yank y WHERE y.version_id = v.id))
         WHERE id = (SELECT grammar_id FROM grammar_version WHERE id = $1)",
    )
    .bind(version_id)
    .execute(&mut **tx)
    .await
    .map_err(db)?;
    Ok(())
}

/// A version's information, with its yank, by row id.
async fn version_by_id(
    tx: &mut Transaction<'static, Postgres>,
    version_id: Id,
) -> Result<VersionInfo, StoreError> {
    let row = sqlx::query(concat!(
        "SELECT v.version, v.sha256, v.published_at, p.name AS publisher, ",
        yank_columns!(),
        " FROM grammar_version v JOIN account p ON p.id = v.publisher_id",
        yank_join!(),
        "WHERE v.id = $1"
    ))
    .bind(version_id)
    .fetch_one(&mut **tx)
    .await
    .map_err(db)?;
    version_info(&row)
}
