//! The storage interface: everything the server keeps goes through a [`Store`], so that the
//! embedded SQLite store ([`crate::sqlite::SqliteStore`]) and a PostgreSQL store share the
//! handlers, the policy and the tests.
//!
//! Every read of grammars takes a [`Viewer`] and the store applies the visibility rule in its
//! query (see [`crate::policy`]), so that lists and fetches never return what the viewer may not
//! see: such objects are simply not found.

use std::future::Future;
use std::pin::Pin;

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// A store operation's future (boxed, so that `dyn Store` works for either backend).
pub type StoreFuture<'a, T> = Pin<Box<dyn Future<Output = Result<T, StoreError>> + Send + 'a>>;

/// Database row id.
pub type Id = i64;

/// What can go wrong in a store.
#[derive(Debug)]
pub enum StoreError {
    /// A unique name is taken.
    Conflict(String),
    /// The database failed (I/O, corruption, a bug in our SQL).
    Database(String),
}

impl std::fmt::Display for StoreError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StoreError::Conflict(m) => write!(f, "{m}"),
            StoreError::Database(m) => write!(f, "database error: {m}"),
        }
    }
}

impl std::error::Error for StoreError {}

/// An account, as the server knows the caller.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Account {
    pub id: Id,
    /// The name as signed up (its canonical form is unique).
    pub name: String,
}

/// Who reads: an account or nobody (anonymous). Passed to every read of grammars.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Viewer {
    pub account: Option<Id>,
}

impl Viewer {
    pub const ANONYMOUS: Viewer = Viewer { account: None };

    pub fn of(account: Option<&Account>) -> Viewer {
        Viewer {
            account: account.map(|a| a.id),
        }
    }
}

/// Who may read a grammar (all of its versions).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Visibility {
    /// Everyone, signed in or not.
    Public,
    /// The owner and the owner's friends.
    Friends,
    /// The owner alone.
    Private,
}

impl Visibility {
    pub fn as_str(self) -> &'static str {
        match self {
            Visibility::Public => "public",
            Visibility::Friends => "friends",
            Visibility::Private => "private",
        }
    }

    pub fn parse(s: &str) -> Option<Visibility> {
        match s {
            "public" => Some(Visibility::Public),
            "friends" => Some(Visibility::Friends),
            "private" => Some(Visibility::Private),
            _ => None,
        }
    }
}

/// An API token, without its secret.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct TokenInfo {
    pub id: Id,
    pub name: String,
    /// The first characters of the token, to recognise it.
    pub prefix: String,
    /// Seconds since the Unix epoch.
    pub created_at: i64,
    pub revoked: bool,
}

/// A new token's row.
pub struct NewToken<'a> {
    pub account: Id,
    pub name: &'a str,
    /// SHA-256 of the whole token.
    pub hash: [u8; 32],
    pub prefix: &'a str,
}

/// The outcome of a friend request.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FriendRequest {
    /// Waiting for the other's acceptance.
    Requested,
    /// The other had asked already (or accepted before): friends now.
    Friends,
    /// No such account (or oneself).
    NoSuchAccount,
}

/// One's friends and pending requests, by account name.
#[derive(Clone, Debug, Default, Serialize, ToSchema)]
pub struct Friends {
    pub friends: Vec<String>,
    /// Requests others sent, waiting for acceptance.
    pub incoming: Vec<String>,
    /// Requests sent, waiting for the others.
    pub outgoing: Vec<String>,
}

/// A grammar as lists show it.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct GrammarSummary {
    pub owner: String,
    pub name: String,
    pub visibility: Visibility,
    /// The newest version's number (versions count from 1).
    pub latest_version: i64,
    /// The newest version not yanked, the one rule queries and search offer; `null` when every
    /// version is yanked.
    pub current_version: Option<i64>,
    pub updated_at: i64,
}

/// Who withdrew a version, when and why.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, ToSchema)]
pub struct Yank {
    /// The account that yanked it.
    pub by: String,
    /// Seconds since the Unix epoch.
    pub at: i64,
    /// Why, as the owner said (optional).
    pub reason: Option<String>,
}

/// A version without its text.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct VersionInfo {
    pub version: i64,
    /// SHA-256 of the text, in hex.
    pub sha256: String,
    pub published_at: i64,
    pub publisher: String,
    /// Withdrawn from new resolutions (still fetchable by its number).
    pub yanked: bool,
    /// The yank, when `yanked`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub yank: Option<Yank>,
}

/// A version with its text.
#[derive(Clone, Debug, Serialize, ToSchema)]
pub struct VersionText {
    pub owner: String,
    pub name: String,
    #[serde(flatten)]
    pub info: VersionInfo,
    pub text: String,
}

/// A rule of a version, as indexed for queries.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, ToSchema)]
pub struct IndexedRule {
    /// The rule's index in its grammar.
    pub index: i64,
    /// Keys a shape must all have (`g:goal`, `t:tag`, `a:attribute`; `lg:`/`lt:` for local goals).
    pub positive: Vec<String>,
    /// Per negated predicate, keys of which a shape must lack at least one.
    pub negative: Vec<Vec<String>>,
    pub local: bool,
    pub conditional: bool,
}

/// What a search asks for: grammars whose current version (the newest not yanked) has a rule indexed with the goal key
/// `g:GOAL` and one with the tag key `t:TAG`, whose canonical name contains `name`, of one
/// owner; every filter is optional. Results are ordered by owner and name (canonical forms).
#[derive(Clone, Copy, Debug, Default)]
pub struct SearchQuery<'a> {
    pub goal: Option<&'a str>,
    pub tag: Option<&'a str>,
    /// A substring of the canonical name (lower case, `-` for `_`).
    pub name: Option<&'a str>,
    pub owner_canon: Option<&'a str>,
    /// The most results to return.
    pub limit: i64,
    /// How many results to skip first (those of the pages before).
    pub offset: i64,
}

/// What a publish writes, checked beforehand.
pub struct NewVersion<'a> {
    pub owner: &'a Account,
    pub name: &'a str,
    pub canon: &'a str,
    /// `None` keeps the grammar's visibility (public for a new grammar).
    pub visibility: Option<Visibility>,
    pub text: &'a str,
    pub sha256: &'a str,
    pub rules: &'a [IndexedRule],
}

/// Whose grammars a procedural rule query draws on (the paper's link modes; its fourth,
/// `this`, asks no repository at all).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Link {
    /// Every grammar the caller may see.
    #[default]
    All,
    /// The caller's own grammars and their friends'.
    Friends,
    /// The caller's own grammars.
    Mine,
}

impl Link {
    pub fn as_str(self) -> &'static str {
        match self {
            Link::All => "all",
            Link::Friends => "friends",
            Link::Mine => "mine",
        }
    }
}

/// A grammar version that answers a rule query.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, ToSchema)]
pub struct FoundGrammar {
    pub owner: String,
    pub name: String,
    pub version: i64,
    /// SHA-256 of the version's text, in hex.
    pub sha256: String,
}

/// The rules of one grammar that match a query.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, ToSchema)]
pub struct QueryMatch {
    /// Index into [`QueryAnswers::grammars`].
    pub grammar: usize,
    /// The matching rules' indices in their grammar.
    pub rules: Vec<i64>,
}

/// Answers to a batch of rule queries, read in one transaction.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, ToSchema)]
pub struct QueryAnswers {
    /// The publish log's last entry when the answers were read (0 for an empty repository).
    pub as_of: i64,
    /// Every grammar version some answer names, by owner and name.
    pub grammars: Vec<FoundGrammar>,
    /// Per query, in order: the grammars with matching rules.
    pub answers: Vec<Vec<QueryMatch>>,
}

/// The persistent state of a repository.
pub trait Store: Send + Sync + 'static {
    /// Creates an account; [`StoreError::Conflict`] when the canonical name is taken.
    fn create_account<'a>(
        &'a self,
        name: &'a str,
        canon: &'a str,
        password_hash: &'a str,
    ) -> StoreFuture<'a, Account>;
    /// An account and its password hash, by canonical name.
    fn account_for_login<'a>(
        &'a self,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<(Account, String)>>;
    /// Replaces an account's password hash (rehashing with stronger parameters at login).
    fn set_password_hash<'a>(&'a self, account: Id, password_hash: &'a str) -> StoreFuture<'a, ()>;
    fn create_token<'a>(&'a self, token: NewToken<'a>) -> StoreFuture<'a, TokenInfo>;
    /// The account of an unrevoked token, by the token's SHA-256.
    fn account_by_token<'a>(&'a self, hash: &'a [u8; 32]) -> StoreFuture<'a, Option<Account>>;
    fn list_tokens(&self, account: Id) -> StoreFuture<'_, Vec<TokenInfo>>;
    /// Revokes one of `account`'s tokens; false when it has no such token.
    fn revoke_token(&self, account: Id, token: Id) -> StoreFuture<'_, bool>;

    fn request_friend<'a>(&'a self, from: Id, to_canon: &'a str) -> StoreFuture<'a, FriendRequest>;
    /// Accepts the pending request from `from_canon` to `me`; false when there is none.
    fn accept_friend<'a>(&'a self, me: Id, from_canon: &'a str) -> StoreFuture<'a, bool>;
    /// Ends a friendship, or withdraws or declines a request; false when there was none.
    fn remove_friend<'a>(&'a self, me: Id, other_canon: &'a str) -> StoreFuture<'a, bool>;
    fn friends(&self, me: Id) -> StoreFuture<'_, Friends>;

    /// Publishes a version in one transaction: the grammar (created on first publish), the
    /// version numbered one past the latest, its rule index and a publish-log entry.
    fn publish<'a>(&'a self, version: NewVersion<'a>) -> StoreFuture<'a, VersionInfo>;
    /// Grammars the viewer may see, optionally of one owner (canonical name), by owner and name.
    fn list_grammars<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: Option<&'a str>,
    ) -> StoreFuture<'a, Vec<GrammarSummary>>;
    /// Grammars the viewer may see that match the query, by owner and name (see
    /// [`SearchQuery`]).
    fn search_grammars<'a>(
        &'a self,
        viewer: Viewer,
        query: SearchQuery<'a>,
    ) -> StoreFuture<'a, Vec<GrammarSummary>>;
    fn grammar<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<GrammarSummary>>;
    /// A grammar's versions, oldest first; `None` when the viewer may not see the grammar.
    fn versions<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
    ) -> StoreFuture<'a, Option<Vec<VersionInfo>>>;
    fn version<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<VersionText>>;
    /// Procedural rule queries: for each set of keys a shape has (`g:` open goals, `t:` tags,
    /// `a:` attributes), the rules whose positive keys it all has and none of whose negated
    /// groups it has entirely, from the current version (the newest not yanked) of each
    /// grammar the viewer may see
    /// and `link` admits; rules that need a goal local to their grammar are left out.
    fn query_rules<'a>(
        &'a self,
        viewer: Viewer,
        link: Link,
        queries: &'a [Vec<String>],
    ) -> StoreFuture<'a, QueryAnswers>;
    /// Renames one of `owner`'s grammars (canonical name `canon`) to `name`; `None` when the
    /// owner has no such grammar, [`StoreError::Conflict`] when the new name is taken. Its
    /// versions, their numbers and hashes stay as they are.
    fn rename_grammar<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        name: &'a str,
        new_canon: &'a str,
    ) -> StoreFuture<'a, Option<GrammarSummary>>;
    /// The newest version the viewer may see whose text has this SHA-256 (hex), under its
    /// grammar's name now: what a lock file fetches, so that renames break no lock.
    fn version_by_sha256<'a>(
        &'a self,
        viewer: Viewer,
        sha256: &'a str,
    ) -> StoreFuture<'a, Option<VersionText>>;
    /// A version's rule index, by rule index.
    fn version_rules<'a>(
        &'a self,
        viewer: Viewer,
        owner_canon: &'a str,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<Vec<IndexedRule>>>;

    /// Yanks a version of one of `owner`'s grammars, recording who, when and why; yanking a
    /// yanked version keeps the first yank. `None` when there is no such version.
    fn yank<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        version: i64,
        reason: Option<&'a str>,
    ) -> StoreFuture<'a, Option<VersionInfo>>;
    /// Withdraws a version's yank (a no-op when it is not yanked). `None` when there is no such
    /// version.
    fn unyank<'a>(
        &'a self,
        owner: &'a Account,
        canon: &'a str,
        version: i64,
    ) -> StoreFuture<'a, Option<VersionInfo>>;

    /// Counts one request of `key` in the window starting at `window_start` (seconds) and
    /// returns the window's count, this request included, in one statement (UPSERT …
    /// RETURNING), so that every process on the database shares the count.
    fn rate_limit_hit<'a>(&'a self, key: &'a str, window_start: i64) -> StoreFuture<'a, i64>;
    /// Forgets the counts of windows that started before `before`.
    fn prune_rate_limits(&self, before: i64) -> StoreFuture<'_, ()>;

    /// Checks what no crash may break, reading the whole database: every version has its whole
    /// rule index (as many rules as it was published with) and its publish-log entry, the text hashes to its SHA-256, each grammar's versions
    /// are numbered 1 to its latest without a gap, the log is numbered without a gap, and the
    /// database's own integrity and foreign-key checks pass. The problems found, none when
    /// all holds.
    fn audit(&self) -> StoreFuture<'_, Vec<String>>;
}

/// A LIKE pattern (escape character `\\`) matching names that contain `text` (for every
/// store).
pub fn like_pattern(text: &str) -> String {
    let mut pattern = String::with_capacity(text.len() + 2);
    pattern.push('%');
    for c in text.chars() {
        if matches!(c, '%' | '_' | '\\') {
            pattern.push('\\');
        }
        pattern.push(c);
    }
    pattern.push('%');
    pattern
}

/// A row of a rule query: grammar id, owner, name, version, SHA-256, rule index.
pub type QueryRow = (Id, String, String, i64, String, i64);

/// Gathers the rows of a batch of rule queries into [`QueryAnswers`] (for every store).
#[derive(Default)]
pub struct FoundSet {
    by_id: std::collections::HashMap<Id, usize>,
    grammars: Vec<FoundGrammar>,
    answers: Vec<Vec<QueryMatch>>,
}

impl FoundSet {
    /// The next query's rows, grouped by grammar in the order they come.
    pub fn answer(&mut self, rows: Vec<QueryRow>) {
        let mut matches: Vec<QueryMatch> = Vec::new();
        for (id, owner, name, version, sha256, rule) in rows {
            let next = self.grammars.len();
            let grammar = *self.by_id.entry(id).or_insert(next);
            if grammar == next {
                self.grammars.push(FoundGrammar {
                    owner,
                    name,
                    version,
                    sha256,
                });
            }
            match matches.last_mut() {
                Some(m) if m.grammar == grammar => m.rules.push(rule),
                _ => matches.push(QueryMatch {
                    grammar,
                    rules: vec![rule],
                }),
            }
        }
        self.answers.push(matches);
    }

    /// The answers, with the grammars sorted by owner and name (canonical forms).
    pub fn into_answers(self, as_of: i64) -> QueryAnswers {
        let canon = crate::accounts::canon;
        let mut indexed: Vec<(usize, FoundGrammar)> =
            self.grammars.into_iter().enumerate().collect();
        indexed.sort_by_cached_key(|(_, g)| (canon(&g.owner), canon(&g.name)));
        let mut position = vec![0; indexed.len()];
        for (new, (old, _)) in indexed.iter().enumerate() {
            position[*old] = new;
        }
        let mut answers = self.answers;
        for matches in &mut answers {
            for m in matches.iter_mut() {
                m.grammar = position[m.grammar];
            }
            matches.sort_by_key(|m| m.grammar);
        }
        QueryAnswers {
            as_of,
            grammars: indexed.into_iter().map(|(_, g)| g).collect(),
            answers,
        }
    }
}
