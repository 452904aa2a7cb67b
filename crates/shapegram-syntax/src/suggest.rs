//! "Did you mean …?" suggestions by edit distance.

/// The candidate closest to `name` by edit distance, for "did you mean" hints; `None` when
/// nothing is close.
///
/// A candidate that differs from `name` only in letter case always counts as close. Otherwise a
/// candidate is close when at most a third of the characters (at least one) must change and
/// not all of them. Ties go to the candidate closer when case is ignored, then to the first one;
/// `name` itself, if it is a candidate, is the closest.
pub fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let name_chars: Vec<char> = name.chars().collect();
    let name_lower: Vec<char> = name.chars().flat_map(char::to_lowercase).collect();
    let limit = (name_chars.len().max(3) / 3).min(name_chars.len().saturating_sub(1));
    let mut best: Option<((usize, usize), &'a str)> = None;
    for candidate in candidates {
        let lower: Vec<char> = candidate.chars().flat_map(char::to_lowercase).collect();
        let folded = distance(&name_lower, &lower);
        let exact = distance(&name_chars, &candidate.chars().collect::<Vec<_>>());
        if folded != 0 && exact > limit {
            continue;
        }
        let key = (exact, folded);
        if best.is_none_or(|(b, _)| key < b) {
            best = Some((key, candidate));
        }
    }
    best.map(|(_, c)| c)
}

/// Levenshtein distance with one row of memory.
fn distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitution = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitution.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}
