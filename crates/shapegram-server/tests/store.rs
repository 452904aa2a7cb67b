//! The SQLite store itself: its settings, its migrations, and the database refusing to change a
//! published version whatever code asks.

use shapegram_server::sqlite::SqliteStore;
use shapegram_server::store::{Account, IndexedRule, NewVersion, Store, Viewer, Visibility};

async fn publish(store: &SqliteStore, owner: &Account, text: &str) -> i64 {
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
    for sql in [
        "UPDATE grammar_version SET text = 'changed' WHERE version = 1",
        "DELETE FROM grammar_version WHERE version = 1",
        "UPDATE rule_key SET key = 'g:metal'",
        "DELETE FROM rule",
        "DELETE FROM publish_log",
    ] {
        let error = sqlx::raw_sql(sqlx::AssertSqlSafe(sql))
            .execute(pool)
            .await
            .unwrap_err();
        assert!(
            error.to_string().contains("immutable") || error.to_string().contains("append-only"),
            "{sql}: {error}"
        );
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

/// Publishes `text` with its real hash and `n` rules.
async fn publish_hashed(store: &SqliteStore, owner: &Account, grammar: &str, text: &str, n: i64) {
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
    let ana = store
        .create_account("ana", "ana", "$argon2id$stand-in")
        .await
        .unwrap();
    publish_hashed(&store, &ana, "paint", "one", 1).await;
    publish_hashed(&store, &ana, "paint", "two", 3).await;
    // A grammar without rules is complete with an empty index.
    publish_hashed(&store, &ana, "wood", "", 0).await;
    assert_eq!(store.audit().await.unwrap(), Vec::<String>::new());
    // A wrong hash, a version without its index or log entry, a counter ahead of the
    // versions: what a half-written publish would leave (the triggers stop updates, not
    // inserts, and the audit reads what is there).
    publish(&store, &ana, "four").await;
    let pool = store.pool();
    sqlx::query(
        "INSERT INTO grammar_version
            (grammar_id, version, text, sha256, publisher_id, published_at, rule_count)
         SELECT id, 9, 'half', 'x', owner_id, 0, 1 FROM grammar WHERE canon = 'wood'",
    )
    .execute(pool)
    .await
    .unwrap();
    sqlx::query("UPDATE grammar SET latest_version = 5, current_version = 2 WHERE canon = 'paint'")
        .execute(pool)
        .await
        .unwrap();
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
