//! `shapegram repo signup|login|logout|whoami|friends|tokens`: the account's side.

use std::io::{BufRead, IsTerminal, Read};

use super::client::{Client, ClientError};
use super::credentials::Login;
use super::{FriendAction, LoginArgs, Repo, TokenAction, failure, table, usage, utc};
use crate::{Failure, print_stdout};

/// The account's name: given, or asked for on the terminal (`command`: `signup` or `login`).
fn name(args: &LoginArgs, command: &str) -> Result<String, Failure> {
    if let Some(name) = &args.name {
        return Ok(name.clone());
    }
    if args.password_stdin || !std::io::stdin().is_terminal() {
        return Err(usage(format!(
            "give the account's name: `shapegram repo {command} NAME --password-stdin`"
        )));
    }
    eprint!("name: ");
    let mut line = String::new();
    std::io::stdin()
        .lock()
        .read_line(&mut line)
        .map_err(|e| usage(format!("cannot read the name: {e}")))?;
    match line.trim() {
        "" => Err(usage("no name given")),
        name => Ok(name.to_owned()),
    }
}

/// The password: standard input's first line with `--password-stdin`, else asked for on the
/// terminal without echo (twice when `confirm`).
fn password(args: &LoginArgs, confirm: bool) -> Result<String, Failure> {
    if args.password_stdin {
        let mut text = String::new();
        std::io::stdin()
            .read_to_string(&mut text)
            .map_err(|e| usage(format!("cannot read the password from standard input: {e}")))?;
        let line = text.lines().next().unwrap_or_default();
        return Ok(line.to_owned());
    }
    let ask = |prompt: &str| {
        rpassword::prompt_password(prompt).map_err(|e| {
            usage(format!(
                "cannot ask for the password ({e}): pipe it in with --password-stdin"
            ))
        })
    };
    let password = ask("password: ")?;
    if confirm && ask("password again: ")? != password {
        return Err(Failure::new("the two passwords differ"));
    }
    Ok(password)
}

/// Logs in as `name` and stores the token.
fn log_in(repo: &Repo, name: &str, password: &str) -> Result<(), Failure> {
    let anonymous = Client::new(&repo.url, None);
    let token = anonymous.login(name, password).map_err(|e| match e {
        // A wrong password: the hint to log in again would be no help.
        ClientError::Refused { message, .. } => Failure::new(message),
        e => failure(e),
    })?;
    // The name as the account spells it (`ana` logs in as `Ana` too).
    let me = Client::new(&repo.url, Some(token.token.clone()))
        .me()
        .map_err(failure)?;
    repo.store_login(Some(Login {
        name: me.name.clone(),
        id: token.info.id,
        token: token.token,
    }))?;
    if let Some(old) = &repo.login {
        // The token this login replaces would stay valid, unused and unseen: revoke it (with
        // itself, so only ever the caller's own). Already revoked or unreachable: nothing lost.
        let _ = Client::new(&repo.url, Some(old.token.clone())).revoke_token(old.id);
    }
    eprintln!(
        "logged in to {} as {} (token stored in {})",
        repo.url,
        me.name,
        repo.credentials_path()?.display()
    );
    if repo.env_token.is_some() {
        eprintln!("note: SHAPEGRAM_TOKEN is set, and is sent instead of the stored token");
    }
    Ok(())
}

/// `signup`: creates the account, then logs in.
pub fn signup(repo: &Repo, args: &LoginArgs) -> Result<(), Failure> {
    let name = name(args, "signup")?;
    let password = password(args, !args.password_stdin)?;
    let account = Client::new(&repo.url, None)
        .sign_up(&name, &password)
        .map_err(failure)?;
    eprintln!("signed up at {} as {}", repo.url, account.name);
    log_in(repo, &account.name, &password)
}

/// `login`.
pub fn login(repo: &Repo, args: &LoginArgs) -> Result<(), Failure> {
    let name = name(args, "login")?;
    let password = password(args, false)?;
    log_in(repo, &name, &password)
}

/// `logout`: revokes the stored token and forgets it.
pub fn logout(repo: &Repo) -> Result<(), Failure> {
    let Some(login) = &repo.login else {
        return Err(Failure::new(format!("not logged in to {}", repo.url)));
    };
    let client = Client::new(&repo.url, Some(login.token.clone()));
    match client.revoke_token(login.id) {
        Ok(()) => {}
        // Revoked already (or the account's data is gone): forgetting it is all there is to do.
        Err(ClientError::Refused {
            status: 401 | 404, ..
        }) => eprintln!("note: the server no longer knew the token"),
        Err(e) => return Err(failure(e)),
    }
    repo.store_login(None)?;
    eprintln!("logged out of {} ({})", repo.url, login.name);
    Ok(())
}

/// `whoami`.
pub fn whoami(repo: &Repo) -> Result<(), Failure> {
    let me = repo.signed_client()?.me().map_err(failure)?;
    print_stdout(&format!("{}\n", me.name))
}

/// `friends [add|accept|remove USER]`.
pub fn friends(repo: &Repo, action: Option<&FriendAction>) -> Result<(), Failure> {
    let client = repo.signed_client()?;
    match action {
        None => {
            let friends = client.friends().map_err(failure)?;
            let mut rows = Vec::new();
            for (names, state) in [
                (&friends.friends, "friends"),
                (
                    &friends.incoming,
                    "asks you (accept with `friends accept NAME`)",
                ),
                (&friends.outgoing, "asked, waiting"),
            ] {
                rows.extend(names.iter().map(|n| vec![n.clone(), state.to_owned()]));
            }
            if rows.is_empty() {
                eprintln!(
                    "no friends or requests yet (ask with `shapegram repo friends add NAME`)"
                );
                return Ok(());
            }
            print_stdout(&table(&["NAME", "STATE"], &rows))
        }
        Some(FriendAction::Add { user }) => {
            match client.request_friend(user).map_err(failure)?.as_str() {
                "friends" => eprintln!("you and {user} are friends now"),
                _ => eprintln!("asked {user} to be friends: waiting for them to accept"),
            }
            Ok(())
        }
        Some(FriendAction::Accept { user }) => {
            client.accept_friend(user).map_err(|e| {
                failure(e).with_hints([format!(
                    "has {user} asked you? see `shapegram repo friends`"
                )])
            })?;
            eprintln!("you and {user} are friends now");
            Ok(())
        }
        Some(FriendAction::Remove { user }) => {
            client.remove_friend(user).map_err(failure)?;
            eprintln!("no longer friends with {user} (or no longer asking)");
            Ok(())
        }
    }
}

/// `tokens [new NAME|revoke ID]`.
pub fn tokens(repo: &Repo, action: Option<&TokenAction>) -> Result<(), Failure> {
    let client = repo.signed_client()?;
    match action {
        None => {
            let tokens = client.tokens().map_err(failure)?;
            let rows: Vec<Vec<String>> = tokens
                .iter()
                .map(|t| {
                    vec![
                        t.id.to_string(),
                        t.name.clone(),
                        format!("{}…", t.prefix),
                        utc(t.created_at),
                        if t.revoked { "revoked" } else { "active" }.to_owned(),
                    ]
                })
                .collect();
            print_stdout(&table(
                &["ID", "NAME", "TOKEN", "CREATED (UTC)", "STATE"],
                &rows,
            ))
        }
        Some(TokenAction::New { name }) => {
            let token = client.create_token(name).map_err(failure)?;
            eprintln!(
                "token {} (id {}): shown this once; use it as SHAPEGRAM_TOKEN",
                token.info.name, token.info.id
            );
            print_stdout(&format!("{}\n", token.token))
        }
        Some(TokenAction::Revoke { id }) => {
            client.revoke_token(*id).map_err(failure)?;
            eprintln!("revoked token {id}");
            if repo.login.as_ref().is_some_and(|l| l.id == *id) {
                repo.store_login(None)?;
                eprintln!(
                    "it was the stored login's token: logged out of {}",
                    repo.url
                );
            }
            Ok(())
        }
    }
}
