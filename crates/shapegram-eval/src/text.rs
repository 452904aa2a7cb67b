//! CGA's string functions and string lists (`"a;b;c;"`: every item ends in `;`), as CityEngine
//! and its utility library define them. Indices count from 0 and in characters.

/// A string or string-list function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Text {
    Find,
    FindFirst,
    FindLast,
    Count,
    Substring,
    Len,
    GetPrefix,
    GetSuffix,
    GetRange,
    Replace,
    FileExtension,
    FileName,
    FileBasename,
    FileDirectory,
    SplitString,
    ListSize,
    ListItem,
    ListFirst,
    ListLast,
    ListRandom,
    ListRange,
    ListIndex,
    ListCount,
    ListAdd,
    ListRemove,
    ListRemoveAll,
    ListRetainAll,
    ListClean,
    ListTerminate,
    ListToArray,
    ListFromArray,
}

/// Each function's name, fewest and most arguments, and signature.
const TABLE: &[(Text, &str, usize, usize, &str)] = &[
    (Text::Find, "find", 3, 3, "find(string, match, n)"),
    (
        Text::FindFirst,
        "findFirst",
        2,
        2,
        "findFirst(string, match)",
    ),
    (Text::FindLast, "findLast", 2, 2, "findLast(string, match)"),
    (Text::Count, "count", 2, 2, "count(string, match)"),
    (
        Text::Substring,
        "substring",
        3,
        3,
        "substring(string, start, end)",
    ),
    (Text::Len, "len", 1, 1, "len(string)"),
    (
        Text::GetPrefix,
        "getPrefix",
        2,
        2,
        "getPrefix(string, match)",
    ),
    (
        Text::GetSuffix,
        "getSuffix",
        2,
        2,
        "getSuffix(string, match)",
    ),
    (
        Text::GetRange,
        "getRange",
        3,
        3,
        "getRange(string, left, right)",
    ),
    (Text::Replace, "replace", 3, 3, "replace(string, old, new)"),
    (
        Text::FileExtension,
        "fileExtension",
        1,
        1,
        "fileExtension(path)",
    ),
    (Text::FileName, "fileName", 1, 1, "fileName(path)"),
    (
        Text::FileBasename,
        "fileBasename",
        1,
        1,
        "fileBasename(path)",
    ),
    (
        Text::FileDirectory,
        "fileDirectory",
        1,
        1,
        "fileDirectory(path)",
    ),
    (
        Text::SplitString,
        "splitString",
        2,
        2,
        "splitString(string, delimiter)",
    ),
    (Text::ListSize, "listSize", 1, 1, "listSize(list)"),
    (Text::ListItem, "listItem", 2, 2, "listItem(list, index)"),
    (Text::ListFirst, "listFirst", 1, 1, "listFirst(list)"),
    (Text::ListLast, "listLast", 1, 1, "listLast(list)"),
    (Text::ListRandom, "listRandom", 1, 1, "listRandom(list)"),
    (
        Text::ListRange,
        "listRange",
        3,
        3,
        "listRange(list, start, end)",
    ),
    (Text::ListIndex, "listIndex", 2, 2, "listIndex(list, item)"),
    (Text::ListCount, "listCount", 2, 2, "listCount(list, item)"),
    (Text::ListAdd, "listAdd", 2, 2, "listAdd(list, items)"),
    (
        Text::ListRemove,
        "listRemove",
        2,
        2,
        "listRemove(list, item)",
    ),
    (
        Text::ListRemoveAll,
        "listRemoveAll",
        2,
        2,
        "listRemoveAll(list, items)",
    ),
    (
        Text::ListRetainAll,
        "listRetainAll",
        2,
        2,
        "listRetainAll(list, items)",
    ),
    (Text::ListClean, "listClean", 1, 1, "listClean(list)"),
    (
        Text::ListTerminate,
        "listTerminate",
        1,
        1,
        "listTerminate(list)",
    ),
    (Text::ListToArray, "listToArray", 1, 1, "listToArray(list)"),
    (
        Text::ListFromArray,
        "listFromArray",
        1,
        1,
        "listFromArray(array)",
    ),
];

/// Most parts `splitString` makes, as in CityEngine.
const MAX_PARTS: usize = 100_000;

/// The value of a text function: a number, a string, or an array of strings.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Out {
    Number(f64),
    Str(String),
    Strings(Vec<String>),
}

impl Text {
    /// Every function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        TABLE.iter().map(|t| t.1)
    }

    /// The function with this name.
    pub fn from_name(name: &str) -> Option<Self> {
        TABLE.iter().find(|t| t.1 == name).map(|t| t.0)
    }

    fn entry(self) -> &'static (Text, &'static str, usize, usize, &'static str) {
        TABLE
            .iter()
            .find(|t| t.0 == self)
            .expect("every function is in the table")
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        let e = self.entry();
        (e.2, e.3)
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        self.entry().4
    }

    /// Which arguments are numbers (the others are strings): indices and counts.
    pub fn numeric(self, i: usize) -> bool {
        matches!(
            (self, i),
            (Text::Find, 2)
                | (Text::Substring, 1 | 2)
                | (Text::ListItem, 1)
                | (Text::ListRange, 1 | 2)
        )
    }

    /// Applies the function to its string arguments `s` and numeric arguments `n` (each in
    /// argument order); `draw` is a number in [0, 1) from the shape's stream, for
    /// `listRandom`. An error is a message for the call's place.
    pub fn apply(self, s: &[&str], n: &[f64], draw: impl FnOnce() -> f64) -> Result<Out, String> {
        Ok(match self {
            Text::Find => Out::Number(find(s[0], s[1], n[0])),
            Text::FindFirst => Out::Number(find(s[0], s[1], 0.0)),
            Text::FindLast => Out::Number(find(s[0], s[1], count(s[0], s[1]) - 1.0)),
            Text::Count => Out::Number(count(s[0], s[1])),
            Text::Substring => Out::Str(substring(s[0], n[0], n[1])),
            Text::Len => Out::Number(s[0].chars().count() as f64),
            Text::GetPrefix => Out::Str(s[0].find(s[1]).map_or(s[0], |i| &s[0][..i]).into()),
            Text::GetSuffix => Out::Str(
                s[0].rfind(s[1])
                    .map_or(s[0], |i| &s[0][i + s[1].len()..])
                    .into(),
            ),
            Text::GetRange => Out::Str(range(s[0], s[1], s[2])),
            Text::Replace if s[1].is_empty() => Out::Str(s[0].into()),
            Text::Replace => Out::Str(s[0].replace(s[1], s[2])),
            Text::FileExtension => Out::Str(
                file_name(s[0])
                    .rfind('.')
                    .map_or("", |i| &file_name(s[0])[i + 1..])
                    .into(),
            ),
            Text::FileName => Out::Str(file_name(s[0]).into()),
            Text::FileBasename => {
                let name = file_name(s[0]);
                Out::Str(name.rfind('.').map_or(name, |i| &name[..i]).into())
            }
            Text::FileDirectory => Out::Str(s[0][..s[0].len() - file_name(s[0]).len()].into()),
            Text::SplitString => Out::Strings(split_string(s[0], s[1])?),
            Text::ListSize => Out::Number(items(s[0]).len() as f64),
            Text::ListItem => Out::Str(item(s[0], n[0])),
            Text::ListFirst => Out::Str(item(s[0], 0.0)),
            Text::ListLast => {
                let all = items(s[0]);
                Out::Str(all.last().copied().unwrap_or("").into())
            }
            Text::ListRandom => {
                let size = items(s[0]).len() as f64;
                Out::Str(item(s[0], (draw() * (size - 1e-7)).floor()))
            }
            Text::ListRange => {
                let all = items(s[0]);
                let from = n[0].floor().max(0.0) as usize;
                let to = (n[1].floor().max(0.0) as usize).min(all.len());
                Out::Str(if from < to {
                    list(&all[from..to])
                } else {
                    String::new()
                })
            }
            Text::ListIndex => Out::Number(
                items(s[0])
                    .iter()
                    .position(|i| matches(i, s[1]))
                    .map_or(-1.0, |i| i as f64),
            ),
            Text::ListCount => {
                Out::Number(items(s[0]).iter().filter(|i| matches(i, s[1])).count() as f64)
            }
            Text::ListAdd => Out::Str(terminate(s[0]) + &terminate(s[1])),
            Text::ListRemove => {
                let mut all = items(s[0]);
                if let Some(i) = all.iter().position(|i| matches(i, s[1])) {
                    all.remove(i);
                }
                Out::Str(list(&all))
            }
            Text::ListRemoveAll => {
                let remove = items(s[1]);
                let kept: Vec<&str> = items(s[0])
                    .into_iter()
                    .filter(|i| !remove.iter().any(|r| matches(i, r)))
                    .collect();
                Out::Str(list(&kept))
            }
            Text::ListRetainAll => {
                let retain = items(s[1]);
                let kept: Vec<&str> = items(s[0])
                    .into_iter()
                    .filter(|i| retain.iter().any(|r| matches(i, r)))
                    .collect();
                Out::Str(list(&kept))
            }
            Text::ListClean => {
                let kept: Vec<&str> = items(s[0]).into_iter().filter(|i| !i.is_empty()).collect();
                Out::Str(list(&kept))
            }
            Text::ListTerminate => Out::Str(terminate(s[0])),
            Text::ListToArray => Out::Strings(items(s[0]).into_iter().map(String::from).collect()),
            Text::ListFromArray => unreachable!("takes an array: handled by the evaluator"),
        })
    }
}

/// The character index of the `n`-th (from 0) non-overlapping match of `m` in `s`, or −1.
fn find(s: &str, m: &str, n: f64) -> f64 {
    if m.is_empty() || n < 0.0 || !n.is_finite() {
        return -1.0;
    }
    s.match_indices(m)
        .nth(n.floor() as usize)
        .map_or(-1.0, |(at, _)| s[..at].chars().count() as f64)
}

/// Non-overlapping matches of `m` in `s` (0 for an empty `m`).
fn count(s: &str, m: &str) -> f64 {
    if m.is_empty() {
        0.0
    } else {
        s.matches(m).count() as f64
    }
}

/// Characters `a` (clamped up to 0) to `b` (excluded, clamped down to the length).
fn substring(s: &str, a: f64, b: f64) -> String {
    let len = s.chars().count() as f64;
    let (a, b) = (a.floor().max(0.0), b.floor().min(len));
    // Also empty when either end is not a number.
    if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) {
        return String::new();
    }
    s.chars().skip(a as usize).take((b - a) as usize).collect()
}

/// From the end of the first `l` to the start of the last `r`; with only one of them present
/// from or to the end; with neither, all of `s`; "" when they overlap.
fn range(s: &str, l: &str, r: &str) -> String {
    let start = s
        .find(l)
        .filter(|_| !l.is_empty())
        .map_or(0, |i| i + l.len());
    let end = s.rfind(r).filter(|_| !r.is_empty()).unwrap_or(s.len());
    if start <= end {
        s[start..end].into()
    } else {
        String::new()
    }
}

/// The part of a path after its last `\` (looked for first) or `/`.
fn file_name(path: &str) -> &str {
    let at = path.rfind('\\').or_else(|| path.rfind('/'));
    at.map_or(path, |i| &path[i + 1..])
}

/// `s` split at every `delim` (an empty input gives one empty part).
fn split_string(s: &str, delim: &str) -> Result<Vec<String>, String> {
    if delim.starts_with('$') && delim != "$\\$" {
        return Err("splitting at a regular expression (`$…`) is not supported yet".into());
    }
    let delim = if delim == "$\\$" { "$" } else { delim };
    if delim.is_empty() {
        return Ok(vec![s.into()]);
    }
    let parts: Vec<String> = s.split(delim).map(String::from).collect();
    if parts.len() > MAX_PARTS {
        return Err(format!("more than {MAX_PARTS} parts"));
    }
    Ok(parts)
}

/// The items of a string list: the text before each `;`, and what follows the last `;`.
fn items(l: &str) -> Vec<&str> {
    let mut all: Vec<&str> = l.split(';').collect();
    if all.last() == Some(&"") {
        all.pop();
    }
    all
}

/// Item `i` of a list, or "" past its end.
fn item(l: &str, i: f64) -> String {
    if i < 0.0 || !i.is_finite() {
        return String::new();
    }
    items(l)
        .get(i.floor() as usize)
        .copied()
        .unwrap_or("")
        .into()
}

/// The list of these items.
fn list(items: &[&str]) -> String {
    items.iter().map(|i| format!("{i};")).collect()
}

/// The list with its last item terminated.
fn terminate(l: &str) -> String {
    if l.is_empty() || l.ends_with(';') {
        l.into()
    } else {
        format!("{l};")
    }
}

/// Whether an item matches a pattern: `*x` ends with x, `x*` starts with it, `*x*` holds it.
fn matches(item: &str, pattern: &str) -> bool {
    let (start, end) = (
        pattern.starts_with('*'),
        pattern.len() > 1 && pattern.ends_with('*'),
    );
    let core = &pattern[usize::from(start)..pattern.len() - usize::from(end)];
    match (start, end) {
        (true, true) => item.contains(core),
        (true, false) => item.ends_with(core),
        (false, true) => item.starts_with(core),
        (false, false) => item == pattern,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn str1(t: Text, s: &[&str], n: &[f64]) -> Out {
        t.apply(s, n, || 0.5).unwrap()
    }

    fn s(v: &str) -> Out {
        Out::Str(v.into())
    }

    #[test]
    fn string_functions_follow_cityengine() {
        assert_eq!(
            str1(Text::Find, &["abcabc", "bc"], &[1.0]),
            Out::Number(4.0)
        );
        assert_eq!(str1(Text::Find, &["abc", "x"], &[0.0]), Out::Number(-1.0));
        assert_eq!(str1(Text::FindLast, &["a.b.c", "."], &[]), Out::Number(3.0));
        assert_eq!(str1(Text::Count, &["aaaa", "aa"], &[]), Out::Number(2.0));
        assert_eq!(str1(Text::Substring, &["hello"], &[-2.0, 3.0]), s("hel"));
        assert_eq!(str1(Text::Substring, &["hello"], &[4.0, 2.0]), s(""));
        assert_eq!(str1(Text::GetPrefix, &["a_b_c", "_"], &[]), s("a"));
        assert_eq!(str1(Text::GetPrefix, &["abc", "_"], &[]), s("abc"));
        assert_eq!(str1(Text::GetSuffix, &["a_b_c", "_"], &[]), s("c"));
        assert_eq!(str1(Text::GetRange, &["[a](b)", "[", ")"], &[]), s("a](b"));
        assert_eq!(str1(Text::GetRange, &["abc", "x", "y"], &[]), s("abc"));
        assert_eq!(str1(Text::Replace, &["a-b-c", "-", "+"], &[]), s("a+b+c"));
        assert_eq!(
            str1(Text::FileBasename, &["tex/wall.01.jpg"], &[]),
            s("wall.01")
        );
        assert_eq!(
            str1(Text::FileExtension, &["tex/wall.01.jpg"], &[]),
            s("jpg")
        );
        assert_eq!(str1(Text::FileDirectory, &["tex/wall.jpg"], &[]), s("tex/"));
        assert_eq!(str1(Text::FileName, &["a\\b/c.obj"], &[]), s("b/c.obj"));
        assert_eq!(
            str1(Text::SplitString, &["a,b,,c", ","], &[]),
            Out::Strings(vec!["a".into(), "b".into(), "".into(), "c".into()])
        );
        assert!(
            Text::SplitString
                .apply(&["a", "$[,]"], &[], || 0.0)
                .is_err()
        );
    }

    #[test]
    fn string_lists_follow_cityengine_s_library() {
        assert_eq!(str1(Text::ListSize, &[""], &[]), Out::Number(0.0));
        assert_eq!(str1(Text::ListSize, &["a;b"], &[]), Out::Number(2.0));
        assert_eq!(str1(Text::ListItem, &["a;b;c;"], &[1.0]), s("b"));
        assert_eq!(str1(Text::ListItem, &["a;b;c;"], &[7.0]), s(""));
        assert_eq!(str1(Text::ListFirst, &["a"], &[]), s("a"));
        assert_eq!(str1(Text::ListLast, &["a;b;c;"], &[]), s("c"));
        assert_eq!(str1(Text::ListRandom, &["a;b;c;"], &[]), s("b"));
        assert_eq!(
            str1(Text::ListRange, &["a;b;c;d;"], &[1.0, 9.0]),
            s("b;c;d;")
        );
        assert_eq!(str1(Text::ListRange, &["a;b;"], &[2.0, 1.0]), s(""));
        assert_eq!(
            str1(Text::ListIndex, &["oak;elm;ash;", "*lm"], &[]),
            Out::Number(1.0)
        );
        assert_eq!(
            str1(Text::ListIndex, &["oak;", "pine"], &[]),
            Out::Number(-1.0)
        );
        assert_eq!(
            str1(Text::ListCount, &["a1;b;a2;", "a*"], &[]),
            Out::Number(2.0)
        );
        assert_eq!(str1(Text::ListAdd, &["a;b", "c"], &[]), s("a;b;c;"));
        assert_eq!(str1(Text::ListRemove, &["a;b;a;", "a"], &[]), s("b;a;"));
        assert_eq!(
            str1(Text::ListRemoveAll, &["a;b;a;c;", "a;c;"], &[]),
            s("b;")
        );
        assert_eq!(
            str1(Text::ListRetainAll, &["a;b;a;c;", "*a*"], &[]),
            s("a;a;")
        );
        assert_eq!(str1(Text::ListClean, &[";a;;b"], &[]), s("a;b;"));
        assert_eq!(str1(Text::ListTerminate, &["a;b"], &[]), s("a;b;"));
    }
}
