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
