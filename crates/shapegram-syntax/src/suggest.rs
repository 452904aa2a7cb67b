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

/// Edit distance counting a swap of two neighbouring characters as one edit (optimal string
/// alignment): `chiar` is one typo away from `chair`.
fn distance(a: &[char], b: &[char]) -> usize {
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut row = vec![0; b.len() + 1];
    for i in 0..a.len() {
        row[0] = i + 1;
        for j in 0..b.len() {
            let mut d = (previous[j] + usize::from(a[i] != b[j]))
                .min(row[j] + 1)
                .min(previous[j + 1] + 1);
            if i > 0 && j > 0 && a[i] == b[j - 1] && a[i - 1] == b[j] {
                d = d.min(before[j - 1] + 1);
            }
            row[j + 1] = d;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut row);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swapped_neighbours_are_one_edit() {
        let d = |a: &str, b: &str| {
            distance(
                &a.chars().collect::<Vec<_>>(),
                &b.chars().collect::<Vec<_>>(),
            )
        };
        assert_eq!(d("chiar", "chair"), 1);
        assert_eq!(d("kitten", "sitting"), 3);
        assert_eq!(d("", "abc"), 3);
        assert_eq!(d("abc", ""), 3);
        assert_eq!(d("ca", "abc"), 3);
        assert_eq!(suggest("chiar", ["chair", "table"]), Some("chair"));
    }
}
