//! Versioned schema migrations, compiled into the binary: one folder per backend
//! (`migrations/sqlite/`, `migrations/postgres/`), files named `NNNN_what.sql`, applied in
//! order at start-up, each in one transaction together with its row in `schema_migration`.
//! A migration once released is never edited: the stored SHA-256 of each applied file is
//! compared at start-up and a mismatch refuses to start.

/// A migration: its version, name and SQL.
pub struct Migration {
    pub version: i64,
    pub name: &'static str,
    pub sql: &'static str,
}

/// The SQLite migrations, oldest first.
pub const SQLITE: &[Migration] = &[
    Migration {
        version: 1,
        name: "init",
        sql: include_str!("../migrations/sqlite/0001_init.sql"),
    },
    Migration {
        version: 2,
        name: "immutable_versions",
        sql: include_str!("../migrations/sqlite/0002_immutable_versions.sql"),
    },
    Migration {
        version: 3,
        name: "rule_queries",
        sql: include_str!("../migrations/sqlite/0003_rule_queries.sql"),
    },
    Migration {
        version: 4,
        name: "yank",
        sql: include_str!("../migrations/sqlite/0004_yank.sql"),
    },
    Migration {
        version: 5,
        name: "rate_limit",
        sql: include_str!("../migrations/sqlite/0005_rate_limit.sql"),
    },
    Migration {
        version: 6,
        name: "rule_count",
        sql: include_str!("../migrations/sqlite/0006_rule_count.sql"),
    },
    Migration {
        version: 7,
        name: "texts_by_hash",
        sql: include_str!("../migrations/sqlite/0007_texts_by_hash.sql"),
    },
];

/// The PostgreSQL migrations, oldest first: the SQLite schema in PostgreSQL's types.
pub const POSTGRES: &[Migration] = &[
    Migration {
        version: 1,
        name: "init",
        sql: include_str!("../migrations/postgres/0001_init.sql"),
    },
    Migration {
        version: 2,
        name: "immutable_versions",
        sql: include_str!("../migrations/postgres/0002_immutable_versions.sql"),
    },
    Migration {
        version: 3,
        name: "rule_queries",
        sql: include_str!("../migrations/postgres/0003_rule_queries.sql"),
    },
    Migration {
        version: 4,
        name: "yank",
        sql: include_str!("../migrations/postgres/0004_yank.sql"),
    },
    Migration {
        version: 5,
        name: "rate_limit",
        sql: include_str!("../migrations/postgres/0005_rate_limit.sql"),
    },
    Migration {
        version: 6,
        name: "rule_count",
        sql: include_str!("../migrations/postgres/0006_rule_count.sql"),
    },
    Migration {
        version: 7,
        name: "texts_by_hash",
        sql: include_str!("../migrations/postgres/0007_texts_by_hash.sql"),
    },
];

/// The SHA-256 of a migration's SQL, in hex.
pub fn checksum(m: &Migration) -> String {
    crate::tokens::sha256_hex(m.sql.as_bytes())
}
