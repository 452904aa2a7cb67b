//! The stores themselves: SQLite's settings, the migrations of both (PostgreSQL's from several
//! servers starting at once), and the database refusing to change a published version whatever
//! code asks.

use shapegram_server::postgres::PgStore;
use shapegram_server::sqlite::SqliteStore;
use shapegram_server::store::{Account, IndexedRule, NewVersion, Store, Viewer, Visibility};
use shapegram_server::testing::TestDatabase;

/// Statements the database must refuse, whatever code sends them.
const FORBIDDEN: [&str; 5] = [
    "UPDATE grammar_version SET text = 'changed' WHERE version = 1",
    "DELETE FROM grammar_version WHERE version = 1",
    "UPDATE rule_key SET key = 'g:metal'",
    "DELETE FROM rule",
    "DELETE FROM publish_log",
];

fn refused(sql: &str, error: sqlx::Error) {
    let message = error.to_string();
    assert!(
        message.contains("published versions are immutable")
            || message.contains("the publish log is append-only"),
        "{sql}: {message}"
    );
}

async fn publish(store: &dyn Store, owner: &Account, text: &str) -> i64 {
    let rules = [IndexedRule {
        index: 0,
        positive: vec!["g:wooden".into()],
        ..IndexedRule::default()
    }];
    store
        .publish(NewVersion {
            owner,
            name: "paint",
            canon: "paint",
            visibility: Some(Visibility::Public),
            text,
            sha256: "not checked here",
            rules: &rules,
        })
        .await
        .unwrap()
        .version
}

#[tokio::test]
async fn settings_migrations_and_immutability() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("repo.db");
    let store = SqliteStore::open(&path).await.unwrap();
    let pool = store.pool();
    let journal: String = sqlx::query_scalar("PRAGMA journal_mode")
        .fetch_one(pool)
        .await
        .unwrap();
    assert_eq!(journal, "wal");
    let foreign_keys: i64 = sqlx::query_scalar("PRAGMA foreign_keys")
        .fetch_one(pool)
        .await
        .unwrap();
    assert_eq!(foreign_keys, 1);
    let busy: i64 = sqlx::query_scalar("PRAGMA busy_timeout")
        .fetch_one(pool)
        .await
        .unwrap();
    assert!(busy >= 5000, "{busy}");
    let versions: Vec<i64> =
        sqlx::query_scalar("SELECT version FROM schema_migration ORDER BY version")
            .fetch_all(pool)
            .await
            .unwrap();
    // Every migration applied, numbered from 1 without gaps.
    let numbered: Vec<i64> = (1..=shapegram_server::migrations::SQLITE.len() as i64).collect();
    assert_eq!(versions, numbered);

    let ana = store
        .create_account("ana", "ana", "$argon2id$stand-in")
        .await
        .unwrap();
    assert_eq!(publish(&store, &ana, "one").await, 1);
    assert_eq!(publish(&store, &ana, "two").await, 2);

    // The database refuses to change or remove a published version or its index.
    for sql in FORBIDDEN {
        let error = sqlx::raw_sql(sqlx::AssertSqlSafe(sql))
            .execute(pool)
            .await
            .unwrap_err();
        refused(sql, error);
    }
    // Foreign keys hold: no token of an account that does not exist.
    let orphan = sqlx::query("INSERT INTO api_token (account_id, name, hash, prefix, created_at) VALUES (999, 't', x'00', 'p', 0)")
        .execute(pool)
        .await;
    assert!(orphan.is_err());
    drop(store);

    // Opened again: nothing re-applied, everything there.
    let store = SqliteStore::open(&path).await.unwrap();
    let text = store
        .version(Viewer::ANONYMOUS, "ana", "paint", 1)
        .await
        .unwrap()
        .unwrap()
        .text;
    assert_eq!(text, "one");
    // A migration changed after it was applied refuses to start.
    sqlx::query("UPDATE schema_migration SET sha256 = 'edited' WHERE version = 2")
        .execute(store.pool())
        .await
        .unwrap();
    drop(store);
    let refused = SqliteStore::open(&path).await.err().expect("refused");
    assert!(refused.to_string().contains("migration 2"), "{refused}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn postgres_migrations_from_servers_starting_at_once_and_immutability() {
    let Some(database) = TestDatabase::create() else {
        return;
    };
    // Four servers start at once on an empty database: one migrates, the others wait for it.
    let starting: Vec<_> = (0..4)
        .map(|_| tokio::spawn(PgStore::connect_with(database.options())))
        .collect();
    let mut stores = Vec::new();
    for start in starting {
        stores.push(start.await.unwrap().expect("every server starts"));
    }
    let store = stores.pop().unwrap();
    drop(stores);
    let pool = store.pool();
    let versions: Vec<(i64, String)> =
        sqlx::query_as("SELECT version, name FROM schema_migration ORDER BY version")
            .fetch_all(pool)
            .await
            .unwrap();
    let expected: Vec<(i64, String)> = shapegram_server::migrations::POSTGRES
        .iter()
        .map(|m| (m.version, m.name.to_owned()))
        .collect();
    assert_eq!(
        versions[..2],
        [(1, "init".to_owned()), (2, "immutable_versions".to_owned())]
    );
    assert_eq!(versions, expected);

    // Names and keys sort byte by byte, as on SQLite, whatever the database's locale.
    let collations: Vec<(String, String, Option<String>)> = sqlx::query_as(
        "SELECT table_name::text, column_name::text, collation_name::text
         FROM information_schema.columns
         WHERE table_schema = 'public' AND column_name IN ('canon', 'key')
         ORDER BY table_name, column_name",
    )
    .fetch_all(pool)
    .await
    .unwrap();
    assert!(
        collations.iter().all(|(_, _, c)| c.as_deref() == Some("C")),
        "{collations:?}"
    );
    let tables: Vec<&str> = collations.iter().map(|(t, _, _)| t.as_str()).collect();
    for table in ["account", "grammar", "rule_key", "rule_neg"] {
        assert!(tables.contains(&table), "{table}: {collations:?}");
    }

    let ana = store
        .create_account("ana", "ana", "$argon2id$stand-in")
        .await
        .unwrap();
    assert_eq!(publish(&store, &ana, "one").await, 1);
    assert_eq!(publish(&store, &ana, "two").await, 2);
    // Publishes of eight grammars at once: the log is numbered without gaps, in the order of
    // the commits (each publish's entry is the greatest when it commits).
    let publishes: Vec<_> = (0..8)
        .map(|i| {
            let (store, ana) = (store.clone(), ana.clone());
            tokio::spawn(async move {
                let name = format!("g{i}");
                store
                    .publish(NewVersion {
                        owner: &ana,
                        name: &name,
                        canon: &name,
                        visibility: None,
                        text: "text",
                        sha256: "not checked here",
                        rules: &[],
                    })
                    .await
                    .unwrap();
            })
        })
        .collect();
    for publish in publishes {
        publish.await.unwrap();
    }
    let log: Vec<i64> = sqlx::query_scalar("SELECT seq FROM publish_log ORDER BY seq")
        .fetch_all(pool)
        .await
        .unwrap();
    assert_eq!(log, (1..=10).collect::<Vec<i64>>());

    for sql in FORBIDDEN
        .into_iter()
        .chain(["TRUNCATE rule_neg", "TRUNCATE publish_log"])
    {
        let error = sqlx::raw_sql(sqlx::AssertSqlSafe(sql))
            .execute(pool)
            .await
            .unwrap_err();
        refused(sql, error);
    }
    let orphan = sqlx::query(
        "INSERT INTO api_token (account_id, name, hash, prefix, created_at)
         VALUES (999, 't', '\\x00', 'p', 0)",
    )
    .execute(pool)
    .await
    .unwrap_err();
    assert!(orphan.to_string().contains("foreign key"), "{orphan}");
    drop(store);

    // Connected again: nothing re-applied, everything there.
    let store = PgStore::connect(database.url()).await.unwrap();
    let text = store
        .version(Viewer::ANONYMOUS, "ana", "paint", 1)
        .await
        .unwrap()
        .unwrap()
        .text;
    assert_eq!(text, "one");
    let applied: i64 = sqlx::query_scalar("SELECT count(*) FROM schema_migration")
        .fetch_one(store.pool())
        .await
        .unwrap();
    assert_eq!(applied, expected.len() as i64);
    // A migration changed after it was applied refuses to start.
    sqlx::query("UPDATE schema_migration SET sha256 = 'edited' WHERE version = 2")
        .execute(store.pool())
        .await
        .unwrap();
    drop(store);
    let refused = PgStore::connect(database.url())
        .await
        .err()
        .expect("refused");
    assert!(refused.to_string().contains("migration 2"), "{refused}");
}

/// Publishes `text` with its real hash and `n` rules.
async fn publish_hashed(store: &dyn Store, owner: &Account, grammar: &str, text: &str, n: i64) {
    let rules: Vec<IndexedRule> = (0..n)
        .map(|index| IndexedRule {
            index,
            positive: vec!["g:wooden".into()],
            ..IndexedRule::default()
        })
        .collect();
    let sha256 = shapegram_server::tokens::sha256_hex(text.as_bytes());
    store
        .publish(NewVersion {
            owner,
            name: grammar,
            canon: grammar,
            visibility: None,
            text,
            sha256: &sha256,
            rules: &rules,
        })
        .await
        .unwrap();
}

#[tokio::test]
async fn the_audit_finds_what_a_crash_could_break() {
    let dir = tempfile::tempdir().unwrap();
    let store = SqliteStore::open(&dir.path().join("repo.db"))
        .await
        .unwrap();
    let raw = async |sql: &'static str| {
        sqlx::query(sql).execute(store.pool()).await.unwrap();
    };
    audit_finds_breakage(&store, raw).await;
}

#[tokio::test]
async fn the_audit_finds_what_a_crash_could_break_on_postgres() {
    let Some(database) = TestDatabase::create() else {
        return;
    };
    let store = PgStore::connect_with(database.options()).await.unwrap();
    let raw = async |sql: &'static str| {
        sqlx::query(sql).execute(store.pool()).await.unwrap();
    };
    audit_finds_breakage(&store, raw).await;
}

/// What a half-written publish would leave, written by `raw` (a statement run on the store's
/// database); the audit must name each.
async fn audit_finds_breakage(store: &dyn Store, raw: impl AsyncFn(&'static str)) {
    let ana = store
        .create_account("ana", "ana", "$argon2id$stand-in")
        .await
        .unwrap();
    publish_hashed(store, &ana, "paint", "one", 1).await;
    publish_hashed(store, &ana, "paint", "two", 3).await;
    // A grammar without rules is complete with an empty index.
    publish_hashed(store, &ana, "wood", "", 0).await;
    assert_eq!(store.audit().await.unwrap(), Vec::<String>::new());
    // A wrong hash, a version without its index or log entry, a counter ahead of the
    // versions: what a half-written publish would leave (the triggers stop updates, not
    // inserts, and the audit reads what is there).
    publish(store, &ana, "four").await;
    raw("INSERT INTO grammar_version
            (grammar_id, version, text, sha256, publisher_id, published_at, rule_count)
         SELECT id, 9, 'half', 'x', owner_id, 0, 1 FROM grammar WHERE canon = 'wood'")
    .await;
    raw("UPDATE grammar SET latest_version = 5, current_version = 2 WHERE canon = 'paint'").await;
    let problems = store.audit().await.unwrap();
    assert_eq!(
        problems,
        [
            "wood 9 has not the rule index it was published with",
            "wood 9 is not in the publish log",
            "paint has versions numbered with a gap, or a latest version it does not have",
            "wood has versions numbered with a gap, or a latest version it does not have",
            "paint has a current version other than its newest not yanked",
            "wood has a current version other than its newest not yanked",
            "paint 3: the text does not match its SHA-256",
            "wood 9: the text does not match its SHA-256",
        ]
    );
}
