//! Bracket-aware context matching (ABOP §1.8; the paper's section 3.2.4 and example 3.2.3).
//!
//! - Left context is read along the path towards the root: a complete bracketed branch to the
//!   left (a sibling) is skipped, and the `[` that opens the branch a module sits in is stepped
//!   over, so the module before the branch counts as its left neighbour.
//! - Right context is read towards the tips: a `[` in the word may be entered (the context
//!   continues into that branch) or skipped as a whole (the context continues after it), and the
//!   first that works wins (a `[` without a partner can only be entered); a `]` ends the
//!   branch, so nothing after it is right context. A `[`
//!   in the pattern must match a branch (the first sibling branch that fits) and a `]` in the
//!   pattern skips what is left of the current branch in the word.
//! - Symbols in the ignore set are skipped on both sides.

use crate::alphabet::SymbolId;

/// Marks "no matching bracket" in [`Structure::partners`].
pub(crate) const UNMATCHED: u32 = u32::MAX;

/// A word with what context matching needs to know about its branch structure.
pub(crate) struct Structure<'a> {
    pub symbols: &'a [SymbolId],
    /// For each bracket, the index of its partner; [`UNMATCHED`] for everything else.
    pub partners: &'a [u32],
    pub ignored: &'a [bool],
    pub open: SymbolId,
    pub close: SymbolId,
}

/// The partner of each bracket of `symbols` (`UNMATCHED` for other modules and for brackets
/// without a partner), written into `partners`.
pub(crate) fn pair_brackets(
    symbols: &[SymbolId],
    open: SymbolId,
    close: SymbolId,
    partners: &mut Vec<u32>,
    stack: &mut Vec<u32>,
) {
    partners.clear();
    partners.resize(symbols.len(), UNMATCHED);
    stack.clear();
    for (i, &s) in symbols.iter().enumerate() {
        if s == open {
            stack.push(i as u32);
        } else if s == close
            && let Some(j) = stack.pop()
        {
            partners[i] = j;
            partners[j as usize] = i as u32;
        }
    }
}

impl Structure<'_> {
    fn is_ignored(&self, s: SymbolId) -> bool {
        self.ignored[s as usize]
    }

    /// Whether `pattern` (in reading order) is the left context of the module at `at`; the
    /// positions of the matched modules go to `found`.
    pub fn matches_left(&self, at: usize, pattern: &[SymbolId], found: &mut [usize]) -> bool {
        let mut i = at;
        for k in (0..pattern.len()).rev() {
            loop {
                if i == 0 {
                    return false;
                }
                i -= 1;
                let s = self.symbols[i];
                if s == self.close {
                    match self.partners[i] {
                        UNMATCHED => return false,
                        j => i = j as usize,
                    }
                } else if s == self.open || self.is_ignored(s) {
                    continue;
                } else if s == pattern[k] {
                    found[k] = i;
                    break;
                } else {
                    return false;
                }
            }
        }
        true
    }

    /// Whether `pattern` (in reading order, brackets allowed) is the right context of the module
    /// at `at`; the positions of the matched modules go to `found` (brackets' entries unused).
    /// `backtrack` is scratch space.
    pub fn matches_right(
        &self,
        at: usize,
        pattern: &[SymbolId],
        found: &mut [usize],
        backtrack: &mut Vec<(usize, usize)>,
    ) -> bool {
        backtrack.clear();
        let n = self.symbols.len();
        let mut i = at + 1;
        let mut k = 0;
        loop {
            if self.run_right(&mut i, &mut k, pattern, found, backtrack, n) {
                return true;
            }
            // Resume at the last branch that was entered, this time skipping it.
            match backtrack.pop() {
                Some((after, kk)) => {
                    i = after;
                    k = kk;
                }
                None => return false,
            }
        }
    }

    /// Matches forward from word index `i` and pattern index `k` until the pattern is done
    /// (true) or a mismatch (false); every branch entered leaves a way back in `backtrack`.
    fn run_right(
        &self,
        i: &mut usize,
        k: &mut usize,
        pattern: &[SymbolId],
        found: &mut [usize],
        backtrack: &mut Vec<(usize, usize)>,
        n: usize,
    ) -> bool {
        while *k < pattern.len() {
            let want = pattern[*k];
            if want == self.close {
                // Skip the rest of the current branch, then its `]`.
                loop {
                    if *i >= n {
                        return false;
                    }
                    let s = self.symbols[*i];
                    if s == self.close {
                        break;
                    }
                    if s == self.open {
                        match self.partners[*i] {
                            UNMATCHED => return false,
                            j => *i = j as usize + 1,
                        }
                    } else {
                        *i += 1;
                    }
                }
                *i += 1;
                *k += 1;
                continue;
            }
            if *i >= n {
                return false;
            }
            let s = self.symbols[*i];
            if s == self.open {
                // A branch that never closes can be entered but not skipped.
                if let Some(&j) = self.partners.get(*i).filter(|&&j| j != UNMATCHED) {
                    backtrack.push((j as usize + 1, *k));
                }
                *i += 1;
                if want == self.open {
                    *k += 1;
                }
                continue;
            }
            if s == self.close || want == self.open && !self.is_ignored(s) {
                return false;
            }
            if self.is_ignored(s) {
                *i += 1;
                continue;
            }
            if s != want {
                return false;
            }
            found[*k] = *i;
            *i += 1;
            *k += 1;
        }
        true
    }
}
