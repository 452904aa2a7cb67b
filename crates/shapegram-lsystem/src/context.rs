//! Bracket-aware context matching (ABOP §1.8; the paper's section 3.2.4 and example 3.2.3).
//!
//! - Left context is read along the path towards the root: a complete bracketed branch to the
//!   left (a sibling) is skipped, and the `[` that opens the branch a module sits in is stepped
//!   over, so the module before the branch counts as its left neighbour.
//! - Right context is read towards the tips, along the axis first: a complete branch is skipped
//!   (ABOP's convention, after Hogeweg and Hesper), and a `]` ends the current branch, so nothing
//!   after it is right context. A `[` in the pattern must match a branch in the word (the first
//!   sibling branch that fits) and a `]` in the pattern skips what is left of the current branch.
//!   A `[` without a partner can only be entered.
//! - The paper's reading goes further: its example 3.2.3 matches `JJF` in `[J[J[JF]F]` by
//!   entering two branches and skipping one. So when no production of a symbol matches along the
//!   axis, the rewriting engine tries again in *branch mode*, where each branch the axis would
//!   skip may be entered instead when the axis does not fit (axis first, then the branch, by
//!   backtracking).
//! - Symbols in the ignore set are skipped on both sides.

use std::cell::Cell;

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
    /// Symbols looked at so far, so that the caller can stop pathological searches (long runs
    /// of ignored symbols or sibling branches scanned again for every module, or backtracking
    /// through thousands of branches for one module).
    pub work: Cell<u64>,
    /// The work after which every search gives up at once (and the caller reports it).
    pub budget: u64,
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

    /// Counts one symbol looked at; false once the budget is spent.
    fn tick(&self) -> bool {
        let work = self.work.get() + 1;
        self.work.set(work);
        work <= self.budget
    }

    /// Whether `pattern` (in reading order) is the left context of the module at `at`; the
    /// positions of the matched modules go to `found`.
    pub fn matches_left(&self, at: usize, pattern: &[SymbolId], found: &mut [usize]) -> bool {
        let mut i = at;
        for k in (0..pattern.len()).rev() {
            loop {
                if !self.tick() || i == 0 {
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
    /// With `enter` false, the context follows the axis (branches are skipped); with `enter`
    /// true, a branch may also be entered when the axis does not fit.
    pub fn matches_right(
        &self,
        at: usize,
        pattern: &[SymbolId],
        found: &mut [usize],
        backtrack: &mut Vec<(usize, usize)>,
        enter: bool,
    ) -> bool {
        backtrack.clear();
        let n = self.symbols.len();
        let mut i = at + 1;
        let mut k = 0;
        loop {
            if self.run_right(&mut i, &mut k, pattern, found, backtrack, n, enter) {
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
    /// (true) or a mismatch (false); every choice between a branch and what follows it leaves
    /// the other way in `backtrack`.
    #[allow(clippy::too_many_arguments)]
    fn run_right(
        &self,
        i: &mut usize,
        k: &mut usize,
        pattern: &[SymbolId],
        found: &mut [usize],
        backtrack: &mut Vec<(usize, usize)>,
        n: usize,
        enter: bool,
    ) -> bool {
        while *k < pattern.len() {
            if !self.tick() {
                return false;
            }
            let want = pattern[*k];
            if want == self.close {
                // Skip the rest of the current branch, then its `]`.
                loop {
                    if !self.tick() || *i >= n {
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
                let partner = self.partners[*i];
                if want == self.open {
                    // Enter the branch; should it not fit, try its next sibling.
                    if partner != UNMATCHED {
                        backtrack.push((partner as usize + 1, *k));
                    }
                    *i += 1;
                    *k += 1;
                } else if partner == UNMATCHED {
                    // A branch that never closes holds the rest of the word: go on inside.
                    *i += 1;
                } else {
                    // Follow the axis past the branch; in branch mode, the branch is the
                    // alternative should the axis not fit.
                    if enter {
                        backtrack.push((*i + 1, *k));
                    }
                    *i = partner as usize + 1;
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
