//! `fileSearch` queries as CityEngine reads them: terms separated by spaces, all of which a
//! file's path must match, each with `*` (any characters, `/` included) and `?` (one) as
//! wildcards, letter case aside. A term starting with `/`, `*` or `?` is matched against the
//! whole workspace path (`/Project/assets/a.obj`); any other is relative to the project.
//! Results are workspace paths, sorted.

use std::path::Path;

use crate::files::Files;

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
    let terms: Vec<&str> = query.split_whitespace().collect();
    if terms.is_empty() {
        return Err("an empty file search: give a name or pattern, such as `assets/*.obj`".into());
    }
    if let Some(term) = terms
        .iter()
        .find(|t| t.starts_with('$') || t.starts_with('\'') || t.contains(':'))
    {
        return Err(format!(
            "`{term}`: regular expressions, quoted terms and properties (`Name:`, `Ext:`) in file searches are not supported yet"
        ));
    }
    let patterns: Vec<Vec<char>> = terms
        .iter()
        .map(|t| {
            let full = if t.starts_with(['/', '*', '?']) {
                (*t).to_owned()
            } else {
                format!("/{name}/{t}")
            };
            full.to_lowercase().chars().collect()
        })
        .collect();
    let mut found: Vec<String> = files
        .listing(project)
        .into_iter()
        .map(|parts| format!("/{name}/{}", parts.join("/")))
        .filter(|workspace| {
            let text: Vec<char> = workspace.to_lowercase().chars().collect();
            patterns.iter().all(|p| wildcard(p, &text))
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
        assert!(
            search(&project, "$.*obj")
                .unwrap_err()
                .contains("not supported yet")
        );
        std::fs::remove_dir_all(root).unwrap();
    }
}
