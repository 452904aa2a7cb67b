//! `shapegram repo publish|search|fetch|versions`: grammars.

use std::path::Path;

use super::client::{ClientError, Diagnostic, Search};
use super::{
    FetchArgs, GrammarArg, PublishArgs, RenameArgs, Repo, SearchArgs, YankArgs, failure, table,
    usage, utc,
};
use crate::{Failure, counted, print_stdout};

/// `FILE:LINE:COLUMN: SEVERITY: MESSAGE` and its hints, one diagnostic a line as compilers and
/// editors read them.
fn print_diagnostics(file: &Path, diagnostics: &[Diagnostic]) {
    for d in diagnostics {
        eprintln!(
            "{}:{}:{}: {}: {}",
            file.display(),
            d.line,
            d.column,
            d.severity,
            d.message
        );
        for hint in &d.hints {
            eprintln!("  = hint: {hint}");
        }
    }
}

/// `publish FILE`.
pub fn publish(repo: &Repo, args: &PublishArgs) -> Result<(), Failure> {
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| Failure::new(format!("cannot read {}: {e}", args.file.display())))?;
    let name = match &args.name {
        Some(name) => name.clone(),
        None => args
            .file
            .file_stem()
            .and_then(|s| s.to_str())
            .map(str::to_owned)
            .ok_or_else(|| {
                usage(format!(
                    "no grammar name in {}: give --name",
                    args.file.display()
                ))
            })?,
    };
    let client = repo.signed_client()?;
    let owner = match (&repo.env_token, &repo.login) {
        (None, Some(login)) => login.name.clone(),
        _ => client.me().map_err(failure)?.name,
    };
    match client.publish(&owner, &name, &text, args.visibility.as_deref()) {
        Ok(published) => {
            print_diagnostics(&args.file, &published.warnings);
            print_stdout(&format!(
                "published {}/{}@{} ({}, {})\n",
                published.owner,
                published.name,
                published.info.version,
                counted(published.rules, "rule", "rules"),
                counted(published.warnings.len(), "warning", "warnings"),
            ))
        }
        Err(ClientError::Refused {
            status: 422,
            message,
            diagnostics,
        }) => {
            print_diagnostics(&args.file, &diagnostics);
            Err(Failure::new(format!("{message}: nothing published")))
        }
        Err(e) => Err(failure(e)),
    }
}

/// `search`.
pub fn search(repo: &Repo, args: &SearchArgs) -> Result<(), Failure> {
    let results = repo
        .client()
        .search(&Search {
            goal: args.goal.as_deref(),
            tag: args.tag.as_deref(),
            text: args.text.as_deref(),
            owner: args.owner.as_deref(),
            page: Some(args.page),
        })
        .map_err(failure)?;
    if results.grammars.is_empty() {
        eprintln!("no grammars found");
        return Ok(());
    }
    let rows: Vec<Vec<String>> = results
        .grammars
        .iter()
        .map(|g| {
            vec![
                format!("{}/{}", g.owner, g.name),
                g.current_version.unwrap_or(g.latest_version).to_string(),
                g.visibility.clone(),
            ]
        })
        .collect();
    print_stdout(&table(&["GRAMMAR", "VERSION", "VISIBILITY"], &rows))?;
    if let Some(next) = results.next_page {
        eprintln!("more results: --page {next}");
    }
    Ok(())
}

/// `OWNER/NAME` and the version of `OWNER/NAME@VERSION`.
fn grammar_name(spec: &str, versioned: bool) -> Result<(&str, &str, Option<i64>), Failure> {
    let form = if versioned {
        "OWNER/NAME or OWNER/NAME@VERSION"
    } else {
        "OWNER/NAME"
    };
    let bad = || usage(format!("{spec} does not name a grammar: write {form}"));
    let (grammar, version) = match spec.split_once('@') {
        Some((grammar, version)) if versioned => {
            let version = version
                .parse::<i64>()
                .ok()
                .filter(|v| *v >= 1)
                .ok_or_else(|| {
                    usage(format!(
                        "{version} is not a version: versions are numbered from 1"
                    ))
                })?;
            (grammar, Some(version))
        }
        Some(_) => return Err(bad()),
        None => (spec, None),
    };
    match grammar.split_once('/') {
        Some((owner, name)) if !owner.is_empty() && !name.is_empty() && !name.contains('/') => {
            Ok((owner, name, version))
        }
        _ => Err(bad()),
    }
}

/// `fetch OWNER/NAME[@VERSION]`: the text, checked against its SHA-256; without a version, the
/// current one (the newest not yanked).
pub fn fetch(repo: &Repo, args: &FetchArgs) -> Result<(), Failure> {
    let (owner, name, version) = grammar_name(&args.grammar, true)?;
    let client = repo.client();
    let version = match version {
        Some(version) => version,
        None => client
            .grammar(owner, name)
            .map_err(failure)?
            .current_version
            .ok_or_else(|| {
                Failure::new(format!(
                    "every version of {owner}/{name} is yanked: name one ({owner}/{name}@VERSION)"
                ))
            })?,
    };
    let fetched = client.version(owner, name, version).map_err(failure)?;
    let label = format!(
        "{}/{}@{}",
        fetched.owner, fetched.name, fetched.info.version
    );
    if shapegram_server::tokens::sha256_hex(fetched.text.as_bytes()) != fetched.info.sha256 {
        return Err(Failure::new(format!(
            "the text of {label} does not match its SHA-256: it was damaged on the way"
        )));
    }
    match &args.output {
        Some(path) => {
            std::fs::write(path, &fetched.text)
                .map_err(|e| Failure::new(format!("cannot write {}: {e}", path.display())))?;
            eprintln!("wrote {} ({label})", path.display());
            Ok(())
        }
        None => print_stdout(&fetched.text),
    }
}

/// `versions OWNER/NAME`.
pub fn versions(repo: &Repo, args: &GrammarArg) -> Result<(), Failure> {
    let (owner, name, _) = grammar_name(&args.grammar, false)?;
    let versions = repo.client().versions(owner, name).map_err(failure)?;
    let rows: Vec<Vec<String>> = versions
        .iter()
        .map(|v| {
            vec![
                v.version.to_string(),
                utc(v.published_at),
                v.publisher.clone(),
                if v.yanked { "yanked" } else { "" }.to_owned(),
                v.sha256.clone(),
            ]
        })
        .collect();
    print_stdout(&table(
        &[
            "VERSION",
            "PUBLISHED (UTC)",
            "PUBLISHER",
            "YANKED",
            "SHA-256",
        ],
        &rows,
    ))
}

/// `rename OWNER/NAME NEW-NAME`.
pub fn rename(repo: &Repo, args: &RenameArgs) -> Result<(), Failure> {
    let (owner, name, _) = grammar_name(&args.grammar, false)?;
    let renamed = repo
        .signed_client()?
        .rename(owner, name, &args.name)
        .map_err(failure)?;
    eprintln!(
        "renamed {owner}/{name} to {}/{}",
        renamed.owner, renamed.name
    );
    Ok(())
}

/// `yank OWNER/NAME@VERSION [--reason TEXT] [--undo]`.
pub fn yank(repo: &Repo, args: &YankArgs) -> Result<(), Failure> {
    let (owner, name, version) = grammar_name(&args.grammar, true)?;
    let Some(version) = version else {
        return Err(usage(format!(
            "{} names no version: yank OWNER/NAME@VERSION",
            args.grammar
        )));
    };
    let client = repo.signed_client()?;
    let info = client
        .yank(owner, name, version, !args.undo, args.reason.as_deref())
        .map_err(failure)?;
    let label = format!("{owner}/{name}@{}", info.version);
    if info.yanked {
        eprintln!(
            "yanked {label}: new resolutions and searches skip it; locks that name it keep it"
        );
    } else {
        eprintln!("{label} is offered again");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grammar_names_and_versions() {
        assert_eq!(
            grammar_name("ana/wood", true).unwrap(),
            ("ana", "wood", None)
        );
        assert_eq!(
            grammar_name("ana/wood@12", true).unwrap(),
            ("ana", "wood", Some(12))
        );
        for (spec, versioned, message) in [
            (
                "wood",
                true,
                "wood does not name a grammar: write OWNER/NAME or OWNER/NAME@VERSION",
            ),
            (
                "a/b/c",
                true,
                "a/b/c does not name a grammar: write OWNER/NAME or OWNER/NAME@VERSION",
            ),
            (
                "/wood",
                false,
                "/wood does not name a grammar: write OWNER/NAME",
            ),
            (
                "ana/wood@1",
                false,
                "ana/wood@1 does not name a grammar: write OWNER/NAME",
            ),
            (
                "ana/wood@0",
                true,
                "0 is not a version: versions are numbered from 1",
            ),
            (
                "ana/wood@x",
                true,
                "x is not a version: versions are numbered from 1",
            ),
        ] {
            let failure = grammar_name(spec, versioned).unwrap_err();
            assert_eq!(failure.message.as_deref(), Some(message), "{spec}");
            assert_eq!(failure.code, 2, "{spec}");
        }
    }
}
