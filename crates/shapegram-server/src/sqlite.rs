//! The embedded store: one SQLite file in WAL mode, with foreign keys on, a busy timeout, and
//! `BEGIN IMMEDIATE` for every transaction that writes (a deferred transaction that reads first
//! can fail with SQLITE_BUSY despite the timeout). All SQL is static text with bound parameters.

use std::path::Path;
use std::str::FromStr;
use std::time::Duration;

use sqlx::sqlite::{
    SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteSynchronous,
};
use sqlx::{Row, Sqlite, Transaction};

use crate::failpoint::{FailPoint, FailPoints};
use crate::migrations;
use crate::store::*;

/// A grammar the viewer `?1` may see (`g` the grammar): public, the viewer's own, or
/// friends-only and owned by one of the viewer's friends. See [`crate::policy`].
macro_rules! visible {
    () => {
        "(g.visibility = 'public' OR g.owner_id = ?1 OR (g.visibility = 'friends' AND EXISTS (
            SELECT 1 FROM friendship f WHERE f.accepted_at IS NOT NULL AND (
                (f.requester_id = ?1 AND f.addressee_id = g.owner_id)
                OR (f.addressee_id = ?1 AND f.requester_id = g.owner_id)))))"
    };
}

/// The repository in a SQLite database file.
#[derive(Clone)]
pub struct SqliteStore {
    pool: SqlitePool,
    /// One connection for the rate-limit counters, which every request writes: without an
    /// fsync per commit (`synchronous=NORMAL`: in WAL mode the database stays consistent, and
    /// a power cut loses at most the last counts), and queued here rather than in SQLite's
    /// busy loop.
    counters: SqlitePool,
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

fn db_text(e: &dyn std::fmt::Display) -> StoreError {
    StoreError::Database(e.to_string())
}

fn is_unique_violation(e: &sqlx::Error) -> bool {
    matches!(e, sqlx::Error::Database(d) if d.is_unique_violation())
}

impl SqliteStore {
    /// Opens (creating it if need be) the database at `path` and brings its schema up to date.
    pub async fn open(path: &Path) -> Result<SqliteStore, StoreError> {
        let options = SqliteConnectOptions::from_str("sqlite:")
            .map_err(db)?
            .filename(path)
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Full)
            .busy_timeout(Duration::from_secs(10))
            .foreign_keys(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(8)
            .connect_with(options.clone())
            .await
            .map_err(db)?;
        let counters = SqlitePoolOptions::new()
            .max_connections(1)
            .connect_with(options.synchronous(SqliteSynchronous::Normal))
            .await
            .map_err(db)?;
        let store = SqliteStore {
            pool,
            counters,
            fail_points: FailPoints::NONE,
        };
        store.migrate().await?;
        Ok(store)
    }

    /// The same store, stopping at `fail_points` during a publish (the crash test).
    pub fn with_fail_points(self, fail_points: FailPoints) -> SqliteStore {
        SqliteStore {
            fail_points,
            ..self
        }
    }

    /// The connection pool, for tools and tests that look at the database itself.
    pub fn pool(&self) -> &SqlitePool {
        &self.pool
    }

    async fn begin_write(&self) -> Result<Transaction<'static, Sqlite>, StoreError> {
        self.pool.begin_with("BEGIN IMMEDIATE").await.map_err(db)
    }

    /// Applies the migrations not applied yet, each in its own write transaction.
    async fn migrate(&self) -> Result<(), StoreError> {
        sqlx::raw_sql(
            "CREATE TABLE IF NOT EXISTS schema_migration (
                version INTEGER PRIMARY KEY, name TEXT NOT NULL, sha256 TEXT NOT NULL,
                applied_at INTEGER NOT NULL)",
        )
        .execute(&self.pool)
        .await
        .map_err(db)?;
        for m in migrations::SQLITE {
            let mut tx = self.begin_write().await?;
            let applied: Option<String> =
                sqlx::query_scalar("SELECT sha256 FROM schema_migration WHERE version = ?1")
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
                 VALUES (?1, ?2, ?3, ?4)",
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
        Ok(())
    }

    async fn account_id(&self, canon: &str) -> Result<Option<Id>, StoreError> {
        sqlx::query_scalar("SELECT id FROM account WHERE canon = ?1")
            .bind(canon)
            .fetch_optional(&self.pool)
            .await
            .map_err(db)
    }
}

fn summary(row: sqlx::sqlite::SqliteRow) -> Result<GrammarSummary, StoreError> {
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
fn version_text(row: &sqlx::sqlite::SqliteRow) -> Result<VersionText, StoreError> {
    Ok(VersionText {
        owner: row.try_get("owner").map_err(db)?,
        name: row.try_get("grammar").map_err(db)?,
        info: version_info(row)?,
        text: row.try_get("text").map_err(db)?,
    })
}

fn version_info(row: &sqlx::sqlite::SqliteRow) -> Result<VersionInfo, StoreError> {
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

impl Store for SqliteStore {
    fn create_account<'a>(
        &'a self,
        name: &'a str,
        canon: &'a str,
        password_hash: &'a str,
    ) -> StoreFuture<'a, Account> {
        Box::pin(async move {
            let id: Id = sqlx::query_scalar(
                "INSERT INTO account (name, canon, password_hash, created_at)
                 VALUES (?1, ?2, ?3, ?4) RETURNING id",
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
                sqlx::query_as("SELECT id, name, password_hash FROM account WHERE canon = ?1")
                    .bind(canon)
                    .fetch_optional(&self.pool)
                    .await
                    .map_err(db)?;
            Ok(row.map(|(id, name, hash)| (Account { id, name }, hash)))
        })
    }

    fn set_password_hash<'a>(&'a self, account: Id, password_hash: &'a str) -> StoreFuture<'a, ()> {
        Box::pin(async move {
            sqlx::query("UPDATE account SET password_hash = ?2 WHERE id = ?1")
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
                 VALUES (?1, ?2, ?3, ?4, ?5) RETURNING id",
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
                 WHERE t.hash = ?1 AND t.revoked_at IS NULL",
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
                 WHERE account_id = ?1 ORDER BY id",
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
                "UPDATE api_token SET revoked_at = COALESCE(revoked_at, ?3)
                 WHERE id = ?1 AND account_id = ?2",
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
            let mut tx = self.begin_write().await?;
            let to: Option<Id> = sqlx::query_scalar("SELECT id FROM account WHERE canon = ?1")
                .bind(to_canon)
                .fetch_optional(&mut *tx)
                .await
                .map_err(db)?;
            let Some(to) = to.filter(|&to| to != from) else {
                return Ok(FriendRequest::NoSuchAccount);
            };
            // A request the other way (pending or accepted) makes us friends.
            let reverse = sqlx::query(
                "UPDATE friendship SET accepted_at = COALESCE(accepted_at, ?3)
                 WHERE requester_id = ?1 AND addressee_id = ?2",
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
                     VALUES (?1, ?2, ?3) ON CONFLICT (requester_id, addressee_id) DO NOTHING",
                )
                .bind(from)
                .bind(to)
                .bind(now())
                .execute(&mut *tx)
                .await
                .map_err(db)?;
                let accepted: Option<i64> = sqlx::query_scalar(
                    "SELECT accepted_at FROM friendship WHERE requester_id = ?1 AND addressee_id = ?2",
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
                "UPDATE friendship SET accepted_at = ?3
                 WHERE addressee_id = ?1 AND accepted_at IS NULL
                   AND requester_id = (SELECT id FROM account WHERE canon = ?2)",
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
                "DELETE FROM friendship WHERE (requester_id = ?1 AND addressee_id = ?2)
                    OR (requester_id = ?2 AND addressee_id = ?1)",
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
                "SELECT a.name, f.accepted_at IS NOT NULL, f.requester_id = ?1
                 FROM friendship f JOIN account a
                   ON a.id = CASE WHEN f.requester_id = ?1 THEN f.addressee_id ELSE f.requester_id END
                 WHERE f.requester_id = ?1 OR f.addressee_id = ?1
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
            self.fail_points.hit(FailPoint::BeforeTransaction).await;
            let mut tx = self.begin_write().await?;
            sqlx::query(
                "INSERT INTO grammar (owner_id, name, canon, visibility, created_at, updated_at)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?5) ON CONFLICT (owner_id, canon) DO NOTHING",
            )
            .bind(v.owner.id)
            .bind(v.name)
            .bind(v.canon)
            .bind(v.visibility.unwrap_or(Visibility::Public).as_str())
            .bind(at)
            .execute(&mut *tx)
            .await
            .map_err(db)?;
            let (grammar, version): (Id, i64) = sqlx::query_as(
                "UPDATE grammar SET latest_version = latest_version + 1,
                    current_version = latest_version + 1, updated_at = ?3,
                    visibility = COALESCE(?4, visibility)
                 WHERE owner_id = ?1 AND canon = ?2 RETURNING id, latest_version",
            )
            .bind(v.owner.id)
            .bind(v.canon)
            .bind(at)
            .bind(v.visibility.map(Visibility::as_str))
            .fetch_one(&mut *tx)
            .await
            .map_err(db)?;
            let version_id: Id = sqlx::query_scalar(
                "INSERT INTO grammar_version
                    (grammar_id, version, text, sha256, publisher_id, published_at, rule_count)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7) RETURNING id",
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
                     VALUES (?1, ?2, ?3, ?4, ?5) RETURNING id",
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
                    sqlx::query("INSERT INTO rule_key (key, rule_id) VALUES (?1, ?2)")
                        .bind(key)
                        .bind(rule_id)
                        .execute(&mut *tx)
                        .await
                        .map_err(db)?;
                }
                for (group, keys) in rule.negative.iter().enumerate() {
                    for key in keys {
                        sqlx::query(
                            "INSERT INTO rule_neg (rule_id, grp, key) VALUES (?1, ?2, ?3)
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
            sqlx::query("INSERT INTO publish_log (version_id, logged_at) VALUES (?1, ?2)")
                .bind(version_id)
                .bind(at)
                .execute(&mut *tx)
                .await
                .map_err(db)?;
            self.fail_points.hit(FailPoint::BeforeCommit).await;
            tx.commit().await.map_err(db)?;
            self.fail_points.hit(FailPoint::AfterCommit).await;
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
                "SELECT a.name, g.name, g.visibility, g.latest_version,
                    g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE (?2 IS NULL OR a.canon = ?2) AND ",
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
            // Portable SQL (the PostgreSQL store shares it): LIKE on the lower-case canonical
            // name; only current versions (the newest not yanked); per key, the versions that have it, read once from the index by key (a
            // correlated EXISTS per grammar was 4 to 8 times slower over 20,000 grammars).
            let rows = sqlx::query(concat!(
                "SELECT a.name, g.name, g.visibility, g.latest_version, g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                   JOIN grammar_version v ON v.grammar_id = g.id AND v.version = g.current_version
                 WHERE (?2 IS NULL OR a.canon = ?2)
                   AND (?3 IS NULL OR g.canon LIKE ?3 ESCAPE '\\')
                   AND (?4 IS NULL OR v.id IN (SELECT r.version_id FROM rule_key k
                        JOIN rule r ON r.id = k.rule_id WHERE k.key = ?4))
                   AND (?5 IS NULL OR v.id IN (SELECT r.version_id FROM rule_key k
                        JOIN rule r ON r.id = k.rule_id WHERE k.key = ?5))
                   AND ",
                visible!(),
                " ORDER BY a.canon, g.canon LIMIT ?6 OFFSET ?7"
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
                "SELECT a.name, g.name, g.visibility, g.latest_version,
                    g.current_version,
                    g.updated_at
                 FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE a.canon = ?2 AND g.canon = ?3 AND ",
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
            // One read transaction, so that the grammar and its versions agree.
            let mut tx = self.pool.begin().await.map_err(db)?;
            let grammar: Option<Id> = sqlx::query_scalar(concat!(
                "SELECT g.id FROM grammar g JOIN account a ON a.id = g.owner_id
                 WHERE a.canon = ?2 AND g.canon = ?3 AND ",
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
                "WHERE v.grammar_id = ?1 ORDER BY v.version"
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
                "WHERE a.canon = ?2 AND g.canon = ?3 AND v.version = ?4 AND ",
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
            let mut tx = self.pool.begin().await.map_err(db)?;
            let version_id: Option<Id> = sqlx::query_scalar(concat!(
                "SELECT v.id FROM grammar g JOIN account a ON a.id = g.owner_id
                   JOIN grammar_version v ON v.grammar_id = g.id
                 WHERE a.canon = ?2 AND g.canon = ?3 AND v.version = ?4 AND ",
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
                "SELECT id, idx, local, conditional FROM rule WHERE version_id = ?1 ORDER BY idx",
            )
            .bind(version_id)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            let keys: Vec<(Id, String)> = sqlx::query_as(
                "SELECT k.rule_id, k.key FROM rule_key k JOIN rule r ON r.id = k.rule_id
                 WHERE r.version_id = ?1 ORDER BY k.rule_id, k.key",
            )
            .bind(version_id)
            .fetch_all(&mut *tx)
            .await
            .map_err(db)?;
            let negs: Vec<(Id, i64, String)> = sqlx::query_as(
                "SELECT n.rule_id, n.grp, n.key FROM rule_neg n JOIN rule r ON r.id = n.rule_id
                 WHERE r.version_id = ?1 ORDER BY n.rule_id, n.grp, n.key",
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
            // One read transaction: every answer sees the same publishes, up to `as_of`.
            let mut tx = self.pool.begin().await.map_err(db)?;
            let as_of: i64 = sqlx::query_scalar("SELECT coalesce(max(seq), 0) FROM publish_log")
                .fetch_one(&mut *tx)
                .await
                .map_err(db)?;
            let mut found = FoundSet::default();
            for keys in queries {
                let keys = serde_json::to_string(keys).map_err(|e| db_text(&e))?;
                // The rules all of whose positive keys are among the query's (counted through
                // the key index), or that have none; then those of the current versions (the
                // newest not yanked) the viewer may see and the link admits; then those no negated group rules out.
                let rows: Vec<QueryRow> = sqlx::query_as(concat!(
                    "WITH k(key) AS (SELECT value FROM json_each(?2)),
                     m(id, n) AS (
                         SELECT rk.rule_id, count(*) FROM rule_key rk JOIN k ON rk.key = k.key
                         GROUP BY rk.rule_id
                         UNION ALL SELECT r0.id, 0 FROM rule r0 WHERE r0.n_pos = 0)
                     SELECT g.id, a.name, g.name, v.version, v.sha256, r.idx
                     FROM m JOIN rule r ON r.id = m.id AND r.n_pos = m.n AND r.local = 0
                       JOIN grammar_version v ON v.id = r.version_id
                       JOIN grammar g ON g.id = v.grammar_id AND g.current_version = v.version
                       JOIN account a ON a.id = g.owner_id
                     WHERE ",
                    visible!(),
                    " AND (?3 = 'all' OR g.owner_id = ?1 OR (?3 = 'friends' AND EXISTS (
                         SELECT 1 FROM friendship f WHERE f.accepted_at IS NOT NULL AND (
                             (f.requester_id = ?1 AND f.addressee_id = g.owner_id)
                             OR (f.addressee_id = ?1 AND f.requester_id = g.owner_id)))))
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
            let mut tx = self.begin_write().await?;
            let Some(version_id) = owned_version(&mut tx, owner.id, canon, version).await? else {
                return Ok(None);
            };
            sqlx::query(
                "INSERT INTO version_yank (version_id, yanked_by, yanked_at, reason)
                 VALUES (?1, ?2, ?3, ?4) ON CONFLICT (version_id) DO NOTHING",
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
            let mut tx = self.begin_write().await?;
            let Some(version_id) = owned_version(&mut tx, owner.id, canon, version).await? else {
                return Ok(None);
            };
            sqlx::query("DELETE FROM version_yank WHERE version_id = ?1")
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
            let mut tx = self.begin_write().await?;
            let renamed = sqlx::query(
                "UPDATE grammar SET name = ?3, canon = ?4, updated_at = ?5
                 WHERE owner_id = ?1 AND canon = ?2",
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
                 WHERE g.owner_id = ?1 AND g.canon = ?2",
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
                "WHERE v.sha256 = ?2 AND ",
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
                "INSERT INTO rate_limit (key, window_start, hits) VALUES (?1, ?2, 1)
                 ON CONFLICT (key, window_start) DO UPDATE SET hits = hits + 1
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
            sqlx::query("DELETE FROM rate_limit WHERE window_start < ?1")
                .bind(before)
                .execute(&self.counters)
                .await
                .map_err(db)?;
            Ok(())
        })
    }

    fn audit(&self) -> StoreFuture<'_, Vec<String>> {
        Box::pin(async move {
            // One read transaction: one snapshot of the database.
            let mut tx = self.pool.begin().await.map_err(db)?;
            let mut problems: Vec<String> = sqlx::query_scalar("PRAGMA integrity_check")
                .fetch_all(&mut *tx)
                .await
                .map_err(db)?;
            problems.retain(|p: &String| p != "ok");
            let foreign: Vec<(String, i64)> =
                sqlx::query_as("SELECT \"table\", rowid FROM pragma_foreign_key_check")
                    .fetch_all(&mut *tx)
                    .await
                    .map_err(db)?;
            problems.extend(
                foreign
                    .into_iter()
                    .map(|(table, row)| format!("{table} row {row}: a foreign key is broken")),
            );
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
                    "SELECT g.canon FROM grammar g WHERE g.current_version IS NOT (
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

/// The id of version `version` of the grammar `canon` that `owner` owns.
async fn owned_version(
    tx: &mut Transaction<'static, Sqlite>,
    owner: Id,
    canon: &str,
    version: i64,
) -> Result<Option<Id>, StoreError> {
    sqlx::query_scalar(
        "SELECT v.id FROM grammar g JOIN grammar_version v ON v.grammar_id = g.id
         WHERE g.owner_id = ?1 AND g.canon = ?2 AND v.version = ?3",
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
    tx: &mut Transaction<'static, Sqlite>,
    version_id: Id,
) -> Result<(), StoreError> {
    sqlx::query(
        "UPDATE grammar SET current_version = (
            SELECT MAX(v.version) FROM grammar_version v
            WHERE v.grammar_id = grammar.id
              AND NOT EXISTS (SELECT 1 FROM version_yank y WHERE y.version_id = v.id))
         WHERE id = (SELECT grammar_id FROM grammar_version WHERE id = ?1)",
    )
    .bind(version_id)
    .execute(&mut **tx)
    .await
    .map_err(db)?;
    Ok(())
}

/// A version's information, with its yank, by row id.
async fn version_by_id(
    tx: &mut Transaction<'static, Sqlite>,
    version_id: Id,
) -> Result<VersionInfo, StoreError> {
    let row = sqlx::query(concat!(
        "SELECT v.version, v.sha256, v.published_at, p.name AS publisher, ",
        yank_columns!(),
        " FROM grammar_version v JOIN account p ON p.id = v.publisher_id",
        yank_join!(),
        "WHERE v.id = ?1"
    ))
    .bind(version_id)
    .fetch_one(&mut **tx)
    .await
    .map_err(db)?;
    version_info(&row)
}
