//! `fileSearch` queries as CityEngine reads them: terms separated by spaces, all of which a
//! file's path must match, letter case aside. A term is a pattern with `*` (any characters, `/`
//! included) and `?` (one) as wildcards, or, starting with `$`, a regular expression. A pattern
//! starting with `/`, `*` or `?` is matched against the whole workspace path
//! (`/Project/assets/a.obj`); any other against the path in the project (`assets/a.obj`) or in
//! its `assets` folder (`a.obj`). A regular expression matches any of the three whole.
//! Results are workspace paths, sorted.

use std::path::Path;

use regex::{Regex, RegexBuilder};

use crate::files::Files;

/// One term of a query.
enum Term {
    /// A wildcard pattern, lower-cased; `absolute` for one matched against workspace paths.
    Pattern { chars: Vec<char>, absolute: bool },
    /// A `$` term: a regular expression anchored at both ends.
    Regex(Regex),
}

impl Term {
    fn parse(term: &str) -> Result<Self, String> {
        if let Some(expression) = term.strip_prefix('$') {
            return RegexBuilder::new(&format!("^(?:{expression})$"))
                .case_insensitive(true)
                .build()
                .map(Term::Regex)
                .map_err(|e| {
                    // The library's message draws the pattern over several lines; its last
                    // line says what is wrong.
                    let e = e.to_string();
                    let why = e
                        .lines()
                        .last()
                        .unwrap_or_default()
                        .trim_start_matches("error: ");
                    format!("`{term}` is not a regular expression: {why}")
                });
        }
        if term.starts_with('\'') || term.contains(':') {
            return Err(format!(
                "`{term}`: quoted terms and properties (`Name:`, `Ext:`) in file searches are not supported yet"
            ));
        }
        Ok(Term::Pattern {
            chars: term.to_lowercase().chars().collect(),
            absolute: term.starts_with(['/', '*', '?']),
        })
    }

    /// Whether a file matches, given its workspace path, its path in the project and, for
    /// a file in the `assets` folder, its path there.
    fn matches(&self, workspace: &str, in_project: &str, in_assets: Option<&str>) -> bool {
        match self {
            Term::Regex(regex) => [Some(workspace), Some(in_project), in_assets]
                .into_iter()
                .flatten()
                .any(|path| regex.is_match(path)),
            Term::Pattern { chars, absolute } => {
                let matches =
                    |path: &str| wildcard(chars, &path.to_lowercase().chars().collect::<Vec<_>>());
                if *absolute {
                    matches(workspace)
                } else {
                    matches(in_project) || in_assets.is_some_and(matches)
                }
            }
        }
    }
}

/// The files under `project` (hidden folders aside) that `query` finds, as workspace paths
/// (`/{project's name}/…`), sorted.
pub fn search(project: &Path, query: &str) -> Result<Vec<String>, String> {
    let name = project
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    search_in(&Files::Disk, project, &name, query)
}

/// [`search`] over the files under `project` in `files`, the project called `name`.
pub(crate) fn search_in(
    files: &Files,
    project: &Path,
    name: &str,
    query: &str,
) -> Result<Vec<String>, String> {
    let terms = query
        .split_whitespace()
        .map(Term::parse)
        .collect::<Result<Vec<_>, _>>()?;
    if terms.is_empty() {
        return Err("an empty file search: give a name or pattern, such as `assets/*.obj`".into());
    }
    let mut found: Vec<String> = files
        .listing(project)
        .into_iter()
        .map(|parts| parts.join("/"))
        .filter_map(|in_project| {
            let workspace = format!("/{name}/{in_project}");
            let in_assets = in_project.strip_prefix("assets/");
            terms
                .iter()
                .all(|t| t.matches(&workspace, &in_project, in_assets))
                .then_some(workspace)
        })
        .collect();
    found.sort();
    Ok(found)
}

/// Whether `text` matches `pattern` whole, `*` standing for any run of characters and `?` for
/// one.
fn wildcard(pattern: &[char], text: &[char]) -> bool {
    // The last `*` seen and where in the text its run ends so far: on a mismatch the run
    // grows by one and matching goes on from there.
    let (mut p, mut t) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while t < text.len() {
        match pattern.get(p) {
            Some('*') => {
                star = Some((p, t));
                p += 1;
            }
            Some(&c) if c == '?' || c == text[t] => {
                p += 1;
                t += 1;
            }
            _ => match star {
                Some((sp, st)) => {
                    star = Some((sp, st + 1));
                    p = sp + 1;
                    t = st + 1;
                }
                None => return false,
            },
        }
    }
    pattern[p..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matches(pattern: &str, text: &str) -> bool {
        wildcard(
            &pattern.chars().collect::<Vec<_>>(),
            &text.chars().collect::<Vec<_>>(),
        )
    }

    #[test]
    fn wildcards_match_runs_and_single_characters() {
        assert!(matches(
            "*facade_textures/f*.tif",
            "/p/assets/facade_textures/f12.tif"
        ));
        assert!(!matches(
            "*facade_textures/f*.tif",
            "/p/assets/facade_textures/g12.tif"
        ));
        assert!(matches("/p/a?c", "/p/abc"));
        assert!(!matches("/p/a?c", "/p/abbc"));
        assert!(matches("*", ""));
        assert!(matches("a**b", "ab"));
        assert!(!matches("", "a"));
    }

    #[test]
    fn a_project_is_searched_by_relative_and_workspace_patterns() {
        let root = std::env::temp_dir().join(format!("shapegram-search-{}", std::process::id()));
        let project = root.join("Town");
        for file in [
            "assets/trees/Oak.obj",
            "assets/trees/birch.obj",
            "assets/roof.obj",
            ".hidden/x.obj",
        ] {
            let path = project.join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, "").unwrap();
        }
        assert_eq!(
            search(&project, "assets/trees/*.obj").unwrap(),
            ["/Town/assets/trees/Oak.obj", "/Town/assets/trees/birch.obj"]
        );
        assert_eq!(search(&project, "*.OBJ oak").unwrap_or_default().len(), 0);
        assert_eq!(
            search(&project, "*.OBJ *oak*").unwrap(),
            ["/Town/assets/trees/Oak.obj"]
        );
        assert_eq!(search(&project, "*x.obj").unwrap(), Vec::<String>::new());
        // A relative pattern is also read in the assets folder, as CityEngine's `textures/*`.
        assert_eq!(
            search(&project, "trees/b*").unwrap(),
            ["/Town/assets/trees/birch.obj"]
        );
        assert!(
            search(&project, "'a b'")
                .unwrap_err()
                .contains("not supported yet")
        );
        std::fs::remove_dir_all(root).unwrap();
    }

    #[test]
    fn dollar_terms_are_regular_expressions_matched_whole() {
        let root = std::env::temp_dir().join(format!("shapegram-regex-{}", std::process::id()));
        let project = root.join("MyProject");
        for file in [
            "assets/textures/1.png",
            "assets/textures/2.png",
            "assets/textures/4.png",
            "assets/tower.obj",
            "rules/a.cga",
        ] {
            let path = project.join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, "").unwrap();
        }
        let found = |query: &str| search(&project, query).unwrap();
        // The reference's examples: relative to the assets folder, the project or the
        // workspace, and matched whole.
        assert_eq!(found("$[12].png"), Vec::<String>::new());
        assert_eq!(
            found("$textures/[12].png"),
            [
                "/MyProject/assets/textures/1.png",
                "/MyProject/assets/textures/2.png"
            ]
        );
        assert_eq!(
            found("$textures/[2-5].PNG"),
            [
                "/MyProject/assets/textures/2.png",
                "/MyProject/assets/textures/4.png"
            ]
        );
        assert_eq!(
            found("$textures/[12].png|.*.obj"),
            [
                "/MyProject/assets/textures/1.png",
                "/MyProject/assets/textures/2.png",
                "/MyProject/assets/tower.obj"
            ]
        );
        assert_eq!(found("$/MyProject/rules/.*"), ["/MyProject/rules/a.cga"]);
        assert_eq!(found("$rules/a"), Vec::<String>::new());
        // Terms still combine: a regular expression and a pattern.
        assert_eq!(
            found("$.*/[0-9].png *4*"),
            ["/MyProject/assets/textures/4.png"]
        );
        assert_eq!(
            search(&project, "$textures/[12.png").unwrap_err(),
            "`$textures/[12.png` is not a regular expression: unclosed character class"
        );
        std::fs::remove_dir_all(root).unwrap();
    }
}
