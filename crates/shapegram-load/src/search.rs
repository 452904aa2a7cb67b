//! `fileSearch` queries as CityEngine reads them: terms separated by spaces, all of which a
//! file must match, letter case aside. A term is a pattern with `*` (any characters, `/`
//! included) and `?` (one) as wildcards; in single quotes it may hold spaces. A pattern
//! starting with `/`, `*` or `?` is matched against the whole workspace path
//! (`/Project/assets/a.obj`); any other against the path in the project (`assets/a.obj`) or in
//! its `assets` folder (`a.obj`). A term starting with `$` is a regular expression that must
//! match one of the three whole. `Name=`, `Ext=`, `Project=` and `Path=` (or `Name:` …) match
//! a pattern against the file's name, extension, project or workspace path.
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
    /// A property term: a wildcard pattern, lower-cased, matched against one property.
    Property {
        property: Property,
        chars: Vec<char>,
    },
}

/// What a property term compares.
#[derive(Clone, Copy)]
enum Property {
    /// The file name, `tower.obj`.
    Name,
    /// The extension without its dot, `obj`.
    Ext,
    /// The project's name.
    Project,
    /// The workspace path.
    Path,
}

/// The paths a file is matched by.
struct Candidate<'a> {
    /// `/Project/assets/a.obj`.
    workspace: &'a str,
    /// `assets/a.obj`.
    in_project: &'a str,
    /// `a.obj`, for a file in the `assets` folder.
    in_assets: Option<&'a str>,
    /// The project's name.
    project: &'a str,
}

impl Term {
    /// The term `text`, written in single quotes when `quoted`.
    fn parse(text: &str, quoted: bool) -> Result<Self, String> {
        let pattern = |text: &str| text.to_lowercase().chars().collect::<Vec<_>>();
        if quoted {
            return Ok(Term::Pattern {
                chars: pattern(text),
                absolute: text.starts_with(['/', '*', '?']),
            });
        }
        if let Some(expression) = text.strip_prefix('$') {
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
                    format!("`{text}` is not a regular expression: {why}")
                });
        }
        if let Some(at) = text.find(['=', ':'])
            && text[..at].chars().all(|c| c.is_ascii_alphabetic())
        {
            let property = match text[..at].to_ascii_lowercase().as_str() {
                "name" => Property::Name,
                "ext" => Property::Ext,
                "project" => Property::Project,
                "path" => Property::Path,
                _ => {
                    return Err(format!(
                        "`{text}`: `{}` is no file property (Name, Ext, Project or Path); a file name with `{}` goes in single quotes",
                        &text[..at],
                        &text[at..=at]
                    ));
                }
            };
            return Ok(Term::Property {
                property,
                chars: pattern(&text[at + 1..]),
            });
        }
        Ok(Term::Pattern {
            chars: pattern(text),
            absolute: text.starts_with(['/', '*', '?']),
        })
    }

    /// Whether the file `file` matches.
    fn matches(&self, file: &Candidate<'_>) -> bool {
        let like = |chars: &[char], text: &str| {
            wildcard(chars, &text.to_lowercase().chars().collect::<Vec<_>>())
        };
        match self {
            Term::Regex(regex) => [Some(file.workspace), Some(file.in_project), file.in_assets]
                .into_iter()
                .flatten()
                .any(|path| regex.is_match(path)),
            Term::Pattern {
                chars,
                absolute: true,
            } => like(chars, file.workspace),
            Term::Pattern { chars, .. } => {
                like(chars, file.in_project) || file.in_assets.is_some_and(|p| like(chars, p))
            }
            Term::Property { property, chars } => {
                let name = file.workspace.rsplit('/').next().unwrap_or_default();
                let value = match property {
                    Property::Name => name,
                    Property::Ext => name.rsplit_once('.').map_or("", |(_, ext)| ext),
                    Property::Project => file.project,
                    Property::Path => file.workspace,
                };
                like(chars, value)
            }
        }
    }
}

/// The terms of `query` and whether each was quoted: separated by spaces, a term starting
/// with `'` running to the next `'`.
fn split_terms(query: &str) -> Result<Vec<(&str, bool)>, String> {
    let mut terms = Vec::new();
    let mut rest = query.trim_start();
    while !rest.is_empty() {
        if let Some(quoted) = rest.strip_prefix('\'') {
            let end = quoted
                .find('\'')
                .ok_or_else(|| format!("`{rest}`: the quote is not closed"))?;
            terms.push((&quoted[..end], true));
            rest = quoted[end + 1..].trim_start();
        } else {
            let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
            terms.push((&rest[..end], false));
            rest = rest[end..].trim_start();
        }
    }
    Ok(terms)
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
    let terms = split_terms(query)?
        .into_iter()
        .map(|(text, quoted)| Term::parse(text, quoted))
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
            let file = Candidate {
                workspace: &workspace,
                in_project: &in_project,
                in_assets: in_project.strip_prefix("assets/"),
                project: name,
            };
            let kept = terms.iter().all(|t| t.matches(&file));
            kept.then_some(workspace)
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
        assert_eq!(
            search(&project, "'a b").unwrap_err(),
            "`'a b`: the quote is not closed"
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

    #[test]
    fn quoted_terms_keep_their_spaces_and_properties_match_one_part_of_the_file() {
        let root = std::env::temp_dir().join(format!("shapegram-props-{}", std::process::id()));
        let project = root.join("MyProject");
        for file in [
            "assets/facade pictures/greek style 1.png",
            "assets/textures/1.png",
            "assets/tower.obj",
            "assets/tower.OBJ.txt",
        ] {
            let path = project.join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, "").unwrap();
        }
        let found = |query: &str| search(&project, query).unwrap();
        assert_eq!(
            found("'facade pictures/greek style *.png'"),
            ["/MyProject/assets/facade pictures/greek style 1.png"]
        );
        assert_eq!(found("Name=1.png"), ["/MyProject/assets/textures/1.png"]);
        assert_eq!(
            found("Project=MyProject Ext:obj"),
            ["/MyProject/assets/tower.obj"]
        );
        assert_eq!(
            found("ext=txt path=*/tower*"),
            ["/MyProject/assets/tower.OBJ.txt"]
        );
        assert_eq!(found("Project=Other"), Vec::<String>::new());
        assert_eq!(
            search(&project, "Nmae=1.png").unwrap_err(),
            "`Nmae=1.png`: `Nmae` is no file property (Name, Ext, Project or Path); a file name with `=` goes in single quotes"
        );
        std::fs::remove_dir_all(root).unwrap();
    }
}
