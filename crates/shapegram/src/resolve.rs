//! `shapegram derive --repo URL`: a goal grammar derived with rules from a grammar repository
//! for what the user's own grammars leave open, and the lock file that pins the versions found,
//! so that a later derivation reproduces the model byte for byte (`docs/repository.md`).
//!
//! Resolution is a fixpoint: derive with what is known; ask the repository, once per distinct
//! combination of goals, tags and attributes that no rule applied to, for grammars with rules
//! that may; derive again with them (after all of the user's own rules); until no answer brings
//! a new grammar. A locked derivation asks nothing and reads the locked versions from the cache
//! (fetching those it lacks), so it runs offline once the cache has them.

use std::collections::{BTreeMap, HashSet};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use shapegram_eval::{Derivation, GoalQuery, LibraryOptions, Program};
use shapegram_syntax::SourceFile;

use crate::Failure;
use crate::cli::{DeriveArgs, LinkMode};
use crate::grammar;
use crate::repo::Repo;
use crate::repo::client::ClientError;

/// The lock file format's version.
pub const LOCK_FORMAT: u32 = 1;
/// Most queries in one request (the server's bound).
const QUERIES_PER_REQUEST: usize = 1000;
/// Most rounds of asking: each brings at least one new grammar, so only a repository of
/// grammars that keep asking for each other's goals gets this far.
const MAX_ROUNDS: usize = 64;

/// The lock file: which repository grammar versions a derivation used.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lock {
    /// The format's version ([`LOCK_FORMAT`]).
    pub lock: u32,
    /// The repository's URL.
    pub repository: String,
    /// Whose grammars were asked for: `all`, `friends` or `mine`.
    pub link: String,
    /// The repository's publish log position when it was last asked.
    pub as_of: i64,
    /// The versions, by owner and name.
    pub grammars: Vec<LockedGrammar>,
}

/// One grammar version of a lock.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LockedGrammar {
    pub owner: String,
    pub name: String,
    pub version: i64,
    /// SHA-256 of the text, in hex: a text that differs is refused.
    pub sha256: String,
}

impl LockedGrammar {
    /// `owner/name@version`: the grammar's name in the library and in messages.
    pub fn label(&self) -> String {
        format!("{}/{}@{}", self.owner, self.name, self.version)
    }

    /// Owner and name in their canonical forms: what tells grammars apart.
    fn key(&self) -> (String, String) {
        let canon = shapegram_server::accounts::canon;
        (canon(&self.owner), canon(&self.name))
    }
}

/// The lock file of a grammar file: `office.goal` is locked in `office.goal.lock`.
pub fn lock_path(grammar: &Path) -> PathBuf {
    let mut name = grammar.file_name().unwrap_or_default().to_os_string();
    name.push(".lock");
    grammar.with_file_name(name)
}

/// What a derivation of a goal grammar does about a repository.
pub enum Plan {
    /// The user's grammars alone.
    Local,
    /// Ask the repository and write the lock.
    Resolve { repo: Repo, link: LinkMode },
    /// Use the locked versions.
    Locked { lock: Lock, repo: Option<Repo> },
}

/// Decides from the arguments and the lock file beside the grammar.
pub fn plan(args: &DeriveArgs) -> Result<Plan, Failure> {
    if args.link == Some(LinkMode::This) {
        return Ok(Plan::Local);
    }
    let path = lock_path(&args.grammar);
    let given = args.repo.as_deref().map(|url| url.trim_end_matches('/'));
    if args.update {
        // The lock's repository and link mode are the defaults; its versions are not used, and
        // a lock that cannot be read is simply replaced.
        let old = path.exists().then(|| read_lock(&path).ok()).flatten();
        let url = given
            .map(str::to_owned)
            .or_else(|| old.as_ref().map(|lock| lock.repository.clone()))
            .ok_or_else(|| Failure::new("--update needs a repository: give --repo URL"))?;
        let link = args
            .link
            .or_else(|| {
                let old = old.as_ref()?;
                clap::ValueEnum::from_str(&old.link, false).ok()
            })
            .unwrap_or(LinkMode::All);
        let repo = Repo::at(Some(&url))?;
        return Ok(Plan::Resolve { repo, link });
    }
    let lock = if path.exists() {
        Some(read_lock(&path)?)
    } else {
        None
    };
    let Some(lock) = lock else {
        if args.offline {
            return Err(Failure::new(format!(
                "--offline needs a lock file: {} does not exist",
                path.display()
            ))
            .with_hints(["derive once with --repo URL to make it".to_owned()]));
        }
        return match given {
            Some(url) => Ok(Plan::Resolve {
                repo: Repo::at(Some(url))?,
                link: args.link.unwrap_or(LinkMode::All),
            }),
            None => Ok(Plan::Local),
        };
    };
    let stale = |what: &str, locked: &str, asked: &str| {
        Failure::new(format!(
            "{} was made with {what} {locked}, not {asked}",
            path.display()
        ))
        .with_hints([format!(
            "--update asks {asked} afresh and rewrites the lock"
        )])
    };
    if let Some(url) = given
        && lock.repository != url
    {
        return Err(stale("the repository", &lock.repository, url));
    }
    if let Some(link) = args.link
        && link.as_str() != lock.link
    {
        return Err(stale("--link", &lock.link, link.as_str()));
    }
    let repo = if args.offline {
        None
    } else {
        Some(Repo::at(Some(&lock.repository))?)
    };
    Ok(Plan::Locked { lock, repo })
}

fn read_lock(path: &Path) -> Result<Lock, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", path.display())))?;
    let lock: Lock = serde_json::from_str(&text).map_err(|e| {
        Failure::new(format!("{} is not a lock file: {e}", path.display())).with_hints([
            "--update makes a new one (or delete it to derive without the repository)".to_owned(),
        ])
    })?;
    if lock.lock != LOCK_FORMAT {
        return Err(Failure::new(format!(
            "{} has lock format {}; this shapegram reads format {LOCK_FORMAT}",
            path.display(),
            lock.lock
        )));
    }
    Ok(lock)
}

/// Writes the lock atomically (a temporary file renamed over it), so that an interrupted
/// write leaves the previous lock whole.
fn write_lock(path: &Path, lock: &Lock) -> Result<(), Failure> {
    let mut text = serde_json::to_string_pretty(lock).expect("a lock serializes");
    text.push('\n');
    let mut temporary = path.as_os_str().to_os_string();
    temporary.push(".tmp");
    let temporary = PathBuf::from(temporary);
    std::fs::write(&temporary, text)
        .and_then(|()| std::fs::rename(&temporary, path))
        .map_err(|e| Failure::new(format!("cannot write {}: {e}", path.display())))
}

/// Grammar texts by SHA-256, in `$SHAPEGRAM_CACHE_DIR`, else `$XDG_CACHE_HOME/shapegram`,
/// else `~/.cache/shapegram`, under `grammars/`. Texts are immutable, so a cached text is
/// good forever; one that does not match its hash is ignored.
pub struct Cache {
    folder: Option<PathBuf>,
}

impl Cache {
    /// The user's cache.
    pub fn open() -> Cache {
        let env = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
        let folder = env("SHAPEGRAM_CACHE_DIR")
            .map(PathBuf::from)
            .or_else(|| env("XDG_CACHE_HOME").map(|d| PathBuf::from(d).join("shapegram")))
            .or_else(|| env("HOME").map(|d| PathBuf::from(d).join(".cache/shapegram")))
            .map(|d| d.join("grammars"));
        Cache { folder }
    }

    fn path(&self, sha256: &str) -> Option<PathBuf> {
        let valid = sha256.len() == 64 && sha256.bytes().all(|b| b.is_ascii_hexdigit());
        self.folder
            .as_ref()
            .filter(|_| valid)
            .map(|f| f.join(format!("{sha256}.goal")))
    }

    fn get(&self, sha256: &str) -> Option<String> {
        let text = std::fs::read_to_string(self.path(sha256)?).ok()?;
        (sha256_hex(&text) == sha256).then_some(text)
    }

    /// Keeps a text; a cache that cannot be written only costs a later download.
    fn put(&self, sha256: &str, text: &str) {
        let Some(path) = self.path(sha256) else {
            return;
        };
        if let Some(folder) = path.parent() {
            let _ = std::fs::create_dir_all(folder);
        }
        let temporary = path.with_extension(format!("tmp{}", std::process::id()));
        if std::fs::write(&temporary, text).is_ok() {
            let _ = std::fs::rename(&temporary, &path);
        }
    }
}

/// SHA-256 of a text, in hex, as the repository states it.
fn sha256_hex(text: &str) -> String {
    shapegram_server::tokens::sha256_hex(text.as_bytes())
}

/// A version's text: from the cache, else from the repository (then cached); checked against
/// its hash either way.
fn text_of(grammar: &LockedGrammar, cache: &Cache, repo: Option<&Repo>) -> Result<String, Failure> {
    if let Some(text) = cache.get(&grammar.sha256) {
        return Ok(text);
    }
    let Some(repo) = repo else {
        return Err(Failure::new(format!(
            "{} is not in the cache, and --offline asks nothing of the repository",
            grammar.label()
        )));
    };
    // By hash, not by name: a grammar renamed since still has the text.
    let text = repo
        .client()
        .text(&grammar.sha256)
        .map_err(|e| Failure::new(format!("cannot fetch {}: {e}", grammar.label())))?
        .text;
    if sha256_hex(&text) != grammar.sha256 {
        return Err(Failure::new(format!(
            "the repository's text of {} does not match its SHA-256 {}",
            grammar.label(),
            grammar.sha256
        )));
    }
    cache.put(&grammar.sha256, &text);
    Ok(text)
}

/// What a derivation with a repository did, for the summary and `--stats`.
#[derive(Debug, Default, Serialize)]
pub struct Report {
    pub repository: String,
    pub link: String,
    /// Whether the lock was used as it was (nothing asked).
    pub locked: bool,
    /// The lock file, when one was written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrote: Option<String>,
    /// Requests of rule queries sent, and the queries in them.
    pub rounds: usize,
    pub queries: usize,
    /// The repository's grammars in the library.
    pub grammars: Vec<String>,
    /// Combinations of goals that still found no rule.
    pub unmatched: usize,
}

/// A derivation with its program, the sources its errors point into and, with a
/// repository, what was asked and found.
pub struct Derived {
    pub program: Program,
    pub sources: Vec<SourceFile>,
    pub derivation: Derivation,
    pub report: Option<Report>,
}

/// Derives a compiled program; errors point into the sources given.
pub type DeriveFn<'a> = dyn Fn(&Program, &[SourceFile]) -> Result<Derivation, Failure> + 'a;

/// The user's grammars and how they are compiled and derived, for every round.
pub struct Library<'a> {
    /// The main grammar and the `--library` files.
    pub local: Vec<SourceFile>,
    pub args: &'a DeriveArgs,
    /// Compiles and derives; the error already explains itself.
    pub derive: &'a DeriveFn<'a>,
}

impl Library<'_> {
    /// Compiles the user's grammars with `remote` after them and derives. With a repository
    /// the library is open (a repository's grammar may set what the user's read); warnings of
    /// the user's files are printed when `warn` is set.
    fn derive_with(
        &self,
        remote: &[(LockedGrammar, String)],
        repository: bool,
        warn: bool,
    ) -> Result<(Program, Vec<SourceFile>, Derivation), Failure> {
        let mut sources = self.local.clone();
        sources.extend(
            remote
                .iter()
                .map(|(g, text)| SourceFile::new(g.label(), text.clone())),
        );
        let options = LibraryOptions {
            repository_from: self.local.len(),
            open: repository,
        };
        let dialect = self.args.dialect.dialect();
        let compiled = grammar::compile_library_with(sources, warn, dialect, &options);
        let program = match compiled.program {
            Some(program) if compiled.errors == 0 => program,
            _ => {
                return Err(Failure::new(grammar::error_summary(
                    compiled.errors,
                    &grammar::library_name(&compiled.sources[..self.local.len()]),
                )));
            }
        };
        let derivation = (self.derive)(&program, &compiled.sources)?;
        Ok((program, compiled.sources, derivation))
    }
}

/// Derives as `plan` says.
pub fn derive(library: &Library<'_>, plan: Plan) -> Result<Derived, Failure> {
    let cache = Cache::open();
    match plan {
        Plan::Local => {
            let warn = !library.args.quiet;
            let (program, sources, derivation) = library.derive_with(&[], false, warn)?;
            Ok(Derived {
                program,
                sources,
                derivation,
                report: None,
            })
        }
        Plan::Locked { lock, repo } => {
            let mut remote = Vec::with_capacity(lock.grammars.len());
            for g in &lock.grammars {
                remote.push((g.clone(), text_of(g, &cache, repo.as_ref())?));
            }
            let warn = !library.args.quiet;
            let (program, sources, derivation) = library.derive_with(&remote, true, warn)?;
            let report = Report {
                repository: lock.repository.clone(),
                link: lock.link.clone(),
                locked: true,
                grammars: lock.grammars.iter().map(LockedGrammar::label).collect(),
                unmatched: derivation.unmatched.len(),
                ..Report::default()
            };
            Ok(Derived {
                program,
                sources,
                derivation,
                report: Some(report),
            })
        }
        Plan::Resolve { repo, link } => resolve(library, &repo, link, &cache),
    }
}

/// The fixpoint (see the module's documentation), then the lock.
fn resolve(
    library: &Library<'_>,
    repo: &Repo,
    link: LinkMode,
    cache: &Cache,
) -> Result<Derived, Failure> {
    let client = repo.client();
    let own: HashSet<String> = library.local.iter().map(|s| sha256_hex(s.text())).collect();
    // By canonical owner and name: the order of the library, and of the lock.
    let mut remote: BTreeMap<(String, String), (LockedGrammar, String)> = BTreeMap::new();
    let mut asked: HashSet<GoalQuery> = HashSet::new();
    let mut report = Report {
        repository: repo.url.clone(),
        link: link.as_str().to_owned(),
        ..Report::default()
    };
    let mut as_of = 0;
    let mut warn = !library.args.quiet;
    loop {
        let grammars: Vec<(LockedGrammar, String)> = remote.values().cloned().collect();
        let (program, sources, derivation) = library.derive_with(&grammars, true, warn)?;
        warn = false;
        let new: Vec<GoalQuery> = derivation
            .unmatched
            .iter()
            .filter(|q| asked.insert((*q).clone()))
            .cloned()
            .collect();
        let mut added = false;
        if !new.is_empty() {
            if report.rounds == MAX_ROUNDS {
                return Err(Failure::new(format!(
                    "the repository's grammars still ask for new goals after {MAX_ROUNDS} rounds of queries"
                ))
                .with_hints(["--link mine or --link friends asks fewer grammars".to_owned()]));
            }
            report.rounds += 1;
            for batch in new.chunks(QUERIES_PER_REQUEST) {
                report.queries += batch.len();
                let answers = client
                    .query(link.as_str(), batch)
                    .map_err(|e| query_failure(repo, e))?;
                as_of = as_of.max(answers.as_of);
                for found in answers.grammars {
                    let grammar = LockedGrammar {
                        owner: found.owner,
                        name: found.name,
                        version: found.version,
                        sha256: found.sha256,
                    };
                    // The user's own copy of a published grammar is one grammar, not two;
                    // a grammar published again between rounds keeps the version found first.
                    if own.contains(&grammar.sha256) || remote.contains_key(&grammar.key()) {
                        continue;
                    }
                    let text = text_of(&grammar, cache, Some(repo))?;
                    remote.insert(grammar.key(), (grammar, text));
                    added = true;
                }
            }
        }
        if added {
            continue;
        }
        let lock = Lock {
            lock: LOCK_FORMAT,
            repository: repo.url.clone(),
            link: link.as_str().to_owned(),
            as_of,
            grammars: remote.into_values().map(|(g, _)| g).collect(),
        };
        let path = lock_path(&library.args.grammar);
        write_lock(&path, &lock)?;
        report.wrote = Some(path.display().to_string());
        report.grammars = lock.grammars.iter().map(LockedGrammar::label).collect();
        report.unmatched = derivation.unmatched.len();
        return Ok(Derived {
            program,
            sources,
            derivation,
            report: Some(report),
        });
    }
}

fn query_failure(repo: &Repo, e: ClientError) -> Failure {
    let code = if matches!(e, ClientError::Connection(_)) {
        2
    } else {
        1
    };
    Failure::new(format!("cannot ask {} for rules: {e}", repo.url)).with_code(code)
}

impl Report {
    /// The lines `derive` prints about the repository.
    pub fn summary(&self) -> String {
        let grammars = crate::counted(self.grammars.len(), "grammar", "grammars");
        let listed = if self.grammars.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.grammars.join(", "))
        };
        let mut out = match &self.wrote {
            Some(lock) => format!(
                "repository {} (link {}): {grammars}{listed} from {} in {}, locked in {lock}\n",
                self.repository,
                self.link,
                crate::counted(self.queries, "query", "queries"),
                crate::counted(self.rounds, "round", "rounds"),
            ),
            None => format!(
                "repository {} (link {}): {grammars}{listed} as locked\n",
                self.repository, self.link
            ),
        };
        if self.unmatched > 0 {
            out.push_str(&format!(
                "note: shapes of {} kept goals no rule fulfils{}\n",
                crate::counted(self.unmatched, "kind", "kinds"),
                if self.locked {
                    " (--update asks the repository again)"
                } else {
                    ""
                }
            ));
        }
        out
    }
}
