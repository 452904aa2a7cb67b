//! `shapegram repo`: the grammar repository's command-line client (`docs/repository.md`):
//! accounts and tokens ([`account`]), publishing, searching and fetching grammars
//! ([`grammars`]), over the HTTP client of [`client`] with the logins of [`credentials`].

pub mod account;
pub mod client;
pub mod credentials;
pub mod grammars;

use std::path::PathBuf;

use clap::{Args, Subcommand};

use crate::Failure;
use client::{Client, ClientError};
use credentials::{Credentials, Login};

/// The repository used without `--repo` or `SHAPEGRAM_REPO`: a `shapegram serve` on this
/// machine.
pub const DEFAULT_REPO: &str = "http://127.0.0.1:8080";

/// Arguments of `shapegram repo`.
#[derive(Debug, Args)]
pub struct RepoArgs {
    /// The repository's URL [default: $SHAPEGRAM_REPO, else http://127.0.0.1:8080]
    #[arg(long, global = true, value_name = "URL")]
    pub repo: Option<String>,
    #[command(subcommand)]
    pub command: RepoCommand,
}

/// What to do with the repository.
#[derive(Debug, Subcommand)]
pub enum RepoCommand {
    /// Create an account, then log in with it
    #[command(after_help = "Examples:\n  \
        shapegram repo signup ana\n  \
        printf '%s' \"$PASSWORD\" | shapegram repo signup ana --password-stdin")]
    Signup(LoginArgs),
    /// Log in: get an API token and keep it in the credentials file
    #[command(
        long_about = "Log in: get an API token and keep it in the credentials file.\n\n\
            Asks for the name (unless given) and the password (not shown as it is typed).\n\
            The token is stored per repository URL in credentials.json, in\n\
            $SHAPEGRAM_CONFIG_DIR, else $XDG_CONFIG_HOME/shapegram, else ~/.config/shapegram,\n\
            readable by you alone; the token it replaces is revoked. The other commands send\n\
            it; SHAPEGRAM_TOKEN, when set, is sent instead.",
        after_help = "Examples:\n  \
            shapegram repo login\n  \
            shapegram repo login ana --repo https://grammars.example.org\n  \
            printf '%s' \"$PASSWORD\" | shapegram repo login ana --password-stdin"
    )]
    Login(LoginArgs),
    /// Log out: revoke the stored token on the server and forget it
    Logout,
    /// Print the name of the account you are logged in as
    Whoami,
    /// Publish a goal grammar file as the next version of one of your grammars
    #[command(
        long_about = "Publish a goal grammar file as the next version of one of your grammars.\n\n\
            The server checks the grammar with the engine's parser and compiler; a grammar\n\
            with errors is refused and its errors are printed as FILE:LINE:COLUMN: error: …\n\
            Each publish makes a new, immutable version, one past the latest. The grammar is\n\
            named after the file (wood.goal: wood) unless --name says otherwise; a new one is\n\
            public unless --visibility says otherwise, and --visibility changes an existing\n\
            one's.",
        after_help = "Examples:\n  \
            shapegram repo publish examples/chairs/materials/wood.goal\n  \
            shapegram repo publish chair.goal --name my-chair --visibility friends"
    )]
    Publish(PublishArgs),
    /// Find grammars by the goals and tags of their rules, or by name
    #[command(
        long_about = "Find grammars by the goals and tags of their rules, or by name.\n\n\
            --goal G finds grammars whose current version (the newest not yanked) has a rule\n\
            for the goal G (fulfills(G)); --tag T one for shapes tagged T (is(T)); TEXT is\n\
            part of the grammar's name. All that is given must hold. Only grammars you may see are found:\n\
            public ones, your own, and your friends' friends-only ones. Results come 50 to a\n\
            page, by owner and name.",
        after_help = "Examples:\n  \
            shapegram repo search --goal wooden\n  \
            shapegram repo search --tag chair --owner ana\n  \
            shapegram repo search wood --page 2"
    )]
    Search(SearchArgs),
    /// Download a grammar's text (the newest version not yanked unless @VERSION is given)
    #[command(after_help = "Examples:\n  \
        shapegram repo fetch ana/wood\n  \
        shapegram repo fetch ana/wood@2 -o wood.goal")]
    Fetch(FetchArgs),
    /// List a grammar's versions, oldest first
    Versions(GrammarArg),
    /// Yank a version of one of your grammars: it stays fetchable by its number (locks that
    /// name it keep working) but is offered to no new resolution or search
    #[command(after_help = "Examples:\n  \
        shapegram repo yank ana/wood@3 --reason \"the legs float\"\n  \
        shapegram repo yank ana/wood@3 --undo")]
    Yank(YankArgs),
    /// Rename one of your grammars: derivations find rules by goals and locks fetch texts by
    /// their hash, so nobody's derivation breaks
    #[command(after_help = "Example:\n  shapegram repo rename ana/wood timber")]
    Rename(RenameArgs),
    /// List your friends and requests, or ask, accept or remove a friend
    #[command(
        long_about = "List your friends and requests, or ask, accept or remove a friend.\n\n\
            Friends see each other's friends-only grammars. Friendship needs both: one asks\n\
            (add), the other accepts (accept, or add back). remove ends a friendship, or\n\
            withdraws or declines a request.",
        after_help = "Examples:\n  \
            shapegram repo friends\n  \
            shapegram repo friends add bob\n  \
            shapegram repo friends accept ana"
    )]
    Friends {
        #[command(subcommand)]
        action: Option<FriendAction>,
    },
    /// List your API tokens, make a new one (for CI, another machine) or revoke one
    #[command(after_help = "Examples:\n  \
        shapegram repo tokens\n  \
        shapegram repo tokens new ci\n  \
        shapegram repo tokens revoke 3")]
    Tokens {
        #[command(subcommand)]
        action: Option<TokenAction>,
    },
}

/// Arguments of `signup` and `login`.
#[derive(Debug, Args)]
pub struct LoginArgs {
    /// The account's name (asked for when not given)
    pub name: Option<String>,
    /// Read the password from standard input (for scripts) instead of asking for it
    #[arg(long)]
    pub password_stdin: bool,
}

/// Arguments of `publish`.
#[derive(Debug, Args)]
pub struct PublishArgs {
    /// The goal grammar file
    pub file: PathBuf,
    /// The grammar's name [default: the file's name without its extension]
    #[arg(long, value_name = "NAME")]
    pub name: Option<String>,
    /// Who may see the grammar: public (everyone), friends (you and your friends) or private
    /// (you) [default: unchanged; public for a new grammar]
    #[arg(long, value_name = "WHO", value_parser = ["public", "friends", "private"])]
    pub visibility: Option<String>,
}

/// Arguments of `search`.
#[derive(Debug, Args)]
pub struct SearchArgs {
    /// Part of the grammar's name
    pub text: Option<String>,
    /// A goal the grammar has a rule for
    #[arg(long, value_name = "GOAL")]
    pub goal: Option<String>,
    /// A tag the grammar has a rule for
    #[arg(long, value_name = "TAG")]
    pub tag: Option<String>,
    /// Only this account's grammars
    #[arg(long, value_name = "NAME")]
    pub owner: Option<String>,
    /// The page of results (50 to a page)
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub page: u32,
}

/// Arguments of `fetch`.
#[derive(Debug, Args)]
pub struct FetchArgs {
    /// The grammar: OWNER/NAME, or OWNER/NAME@VERSION for one version
    #[arg(value_name = "OWNER/NAME[@VERSION]")]
    pub grammar: String,
    /// Write the text to this file instead of standard output
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// A grammar named on the command line.
#[derive(Debug, Args)]
pub struct GrammarArg {
    /// The grammar: OWNER/NAME
    #[arg(value_name = "OWNER/NAME")]
    pub grammar: String,
}

/// `rename` arguments.
#[derive(Debug, Args)]
pub struct RenameArgs {
    /// The grammar: OWNER/NAME
    #[arg(value_name = "OWNER/NAME")]
    pub grammar: String,
    /// Its new name
    #[arg(value_name = "NEW-NAME")]
    pub name: String,
}

/// `yank` arguments.
#[derive(Debug, Args)]
pub struct YankArgs {
    /// The version: OWNER/NAME@VERSION
    #[arg(value_name = "OWNER/NAME@VERSION")]
    pub grammar: String,
    /// Why (shown with the version)
    #[arg(long, value_name = "TEXT", conflicts_with = "undo")]
    pub reason: Option<String>,
    /// Withdraw the yank: the version is offered again
    #[arg(long)]
    pub undo: bool,
}

/// `friends` actions.
#[derive(Debug, Subcommand)]
pub enum FriendAction {
    /// Ask USER to be friends (or accept, when USER asked you first)
    Add { user: String },
    /// Accept USER's request
    Accept { user: String },
    /// End the friendship with USER, or withdraw or decline a request
    Remove { user: String },
}

/// `tokens` actions.
#[derive(Debug, Subcommand)]
pub enum TokenAction {
    /// Make a new token named NAME and print it (shown this once)
    New { name: String },
    /// Revoke the token with this id (see `shapegram repo tokens`)
    Revoke { id: i64 },
}

/// The repository a command talks to, and the caller's login there.
pub struct Repo {
    /// The base URL, without a trailing `/`.
    pub url: String,
    /// The credentials file (`None` without any configuration folder).
    pub credentials: Option<PathBuf>,
    /// The stored login for `url`.
    pub login: Option<Login>,
    /// `SHAPEGRAM_TOKEN`, which overrides the stored login's token.
    pub env_token: Option<String>,
}

impl Repo {
    /// The repository of `--repo`, `SHAPEGRAM_REPO` or the default, with its stored login.
    fn open(args: &RepoArgs) -> Result<Repo, Failure> {
        Repo::at(args.repo.as_deref())
    }

    /// The repository at `url`, else at `SHAPEGRAM_REPO`, else at the default URL, with the
    /// stored login for it.
    pub fn at(url: Option<&str>) -> Result<Repo, Failure> {
        let url = url
            .map(str::to_owned)
            .or_else(|| {
                std::env::var("SHAPEGRAM_REPO")
                    .ok()
                    .filter(|v| !v.is_empty())
            })
            .unwrap_or_else(|| DEFAULT_REPO.to_owned());
        let url = url.trim_end_matches('/').to_owned();
        let rest = url
            .strip_prefix("http://")
            .or_else(|| url.strip_prefix("https://"));
        if rest.is_none_or(str::is_empty) {
            return Err(usage(format!(
                "{url} is not a repository URL: it is http://HOST[:PORT] or https://HOST[:PORT]"
            )));
        }
        let credentials = credentials::config_dir().map(|dir| credentials::file_in(&dir));
        let login = match &credentials {
            Some(path) => Credentials::load(path)
                .map_err(Failure::new)?
                .repositories
                .remove(&url),
            None => None,
        };
        let env_token = std::env::var("SHAPEGRAM_TOKEN")
            .ok()
            .filter(|v| !v.is_empty());
        Ok(Repo {
            url,
            credentials,
            login,
            env_token,
        })
    }

    /// The token sent: `SHAPEGRAM_TOKEN`, else the stored one.
    pub fn token(&self) -> Option<String> {
        self.env_token
            .clone()
            .or_else(|| self.login.as_ref().map(|l| l.token.clone()))
    }

    /// A client sending the token, if any.
    pub fn client(&self) -> Client {
        Client::new(&self.url, self.token())
    }

    /// A client for a command that needs a login; fails without a token.
    pub fn signed_client(&self) -> Result<Client, Failure> {
        match self.token() {
            Some(token) => Ok(Client::new(&self.url, Some(token))),
            None => Err(
                Failure::new(format!("not logged in to {}", self.url)).with_hints([format!(
                    "log in with `shapegram repo login --repo {}`",
                    self.url
                )]),
            ),
        }
    }

    /// The credentials file, or why there is none.
    pub fn credentials_path(&self) -> Result<&PathBuf, Failure> {
        self.credentials.as_ref().ok_or_else(|| {
            Failure::new("no folder for the credentials file: set SHAPEGRAM_CONFIG_DIR or HOME")
                .with_code(2)
        })
    }

    /// Stores (or, with `None`, forgets) the login for this repository.
    pub fn store_login(&self, login: Option<Login>) -> Result<(), Failure> {
        let path = self.credentials_path()?;
        let mut stored = Credentials::load(path).map_err(Failure::new)?;
        match login {
            Some(login) => stored.repositories.insert(self.url.clone(), login),
            None => stored.repositories.remove(&self.url),
        };
        stored.save(path).map_err(Failure::new)
    }
}

/// A usage error (exit code 2).
pub fn usage(message: impl Into<String>) -> Failure {
    Failure::new(message).with_code(2)
}

/// A failed request as a failure: exit code 1 when the server refused, 2 when it could not be
/// reached; a refused token gets a hint.
pub fn failure(e: ClientError) -> Failure {
    match e {
        ClientError::Refused {
            status: 401,
            message,
            ..
        } => Failure::new(message).with_hints([
            "log in again with `shapegram repo login` (or check SHAPEGRAM_TOKEN)".to_owned(),
        ]),
        ClientError::Refused { message, .. } => Failure::new(message),
        ClientError::Connection(message) => Failure::new(message).with_code(2),
    }
}

/// Runs a `shapegram repo` command.
pub fn run(args: &RepoArgs) -> Result<(), Failure> {
    let repo = Repo::open(args)?;
    match &args.command {
        RepoCommand::Signup(a) => account::signup(&repo, a),
        RepoCommand::Login(a) => account::login(&repo, a),
        RepoCommand::Logout => account::logout(&repo),
        RepoCommand::Whoami => account::whoami(&repo),
        RepoCommand::Friends { action } => account::friends(&repo, action.as_ref()),
        RepoCommand::Tokens { action } => account::tokens(&repo, action.as_ref()),
        RepoCommand::Publish(a) => grammars::publish(&repo, a),
        RepoCommand::Search(a) => grammars::search(&repo, a),
        RepoCommand::Fetch(a) => grammars::fetch(&repo, a),
        RepoCommand::Versions(a) => grammars::versions(&repo, a),
        RepoCommand::Yank(a) => grammars::yank(&repo, a),
        RepoCommand::Rename(a) => grammars::rename(&repo, a),
    }
}

/// Rows as a table: columns padded to their widest cell, two spaces apart, the header first.
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    let header: Vec<String> = header.iter().map(|h| h.to_string()).collect();
    for row in std::iter::once(&header).chain(rows) {
        let mut line = String::new();
        for (i, (cell, w)) in row.iter().zip(&widths).enumerate() {
            if i > 0 {
                line.push_str("  ");
            }
            line.push_str(cell);
            if i + 1 < row.len() {
                line.push_str(&" ".repeat(w - cell.chars().count()));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

/// Seconds since the Unix epoch as a UTC date and time, `2026-12-02 13:45`.
pub fn utc(seconds: i64) -> String {
    let days = seconds.div_euclid(86_400);
    let minutes = seconds.rem_euclid(86_400) / 60;
    // Civil from days (H. Hinnant): the proleptic Gregorian calendar, eras of 400 years.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}",
        minutes / 60,
        minutes % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_pad_every_column_but_the_last() {
        let rows = vec![
            vec!["ana/wood".to_owned(), "1".to_owned(), "public".to_owned()],
            vec!["b/c".to_owned(), "12".to_owned(), "friends".to_owned()],
        ];
        assert_eq!(
            table(&["GRAMMAR", "VERSION", "VISIBILITY"], &rows),
            "GRAMMAR   VERSION  VISIBILITY\n\
             ana/wood  1        public\n\
             b/c       12       friends\n"
        );
    }

    #[test]
    fn utc_dates() {
        assert_eq!(utc(0), "1970-01-01 00:00");
        assert_eq!(utc(951_782_400), "2000-02-29 00:00");
        assert_eq!(utc(1_796_217_599), "2026-12-02 13:19");
        assert_eq!(utc(-60), "1969-12-31 23:59");
    }
}
