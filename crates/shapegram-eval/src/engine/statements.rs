//! Walking a rule's statements: the rule's own list and, after a `[ case … ]`, the chosen
//! branch's, which runs before the rest of the list that holds it.

use std::slice::Iter;

use crate::program::CStmt;

/// Where a rule application is in its statements. The rule's list is kept apart from the
/// branches' so that the common rule without bracketed branches allocates nothing.
pub(super) struct Cursor<'p> {
    rule: Iter<'p, CStmt>,
    /// The chosen branches under way, innermost last.
    branches: Vec<Iter<'p, CStmt>>,
}

impl<'p> Cursor<'p> {
    /// A cursor at the first of `stmts`.
    pub(super) fn new(stmts: &'p [CStmt]) -> Self {
        Self {
            rule: stmts.iter(),
            branches: Vec::new(),
        }
    }

    /// Runs `branch` next, then the rest of the statements.
    pub(super) fn enter(&mut self, branch: &'p [CStmt]) {
        self.branches.push(branch.iter());
    }

    /// Whether no statement is left.
    pub(super) fn at_end(&self) -> bool {
        self.rule.len() == 0 && self.branches.iter().all(|list| list.len() == 0)
    }

    /// The innermost list under way (the rule's when no branch is).
    fn innermost(&mut self) -> &mut Iter<'p, CStmt> {
        self.branches.last_mut().unwrap_or(&mut self.rule)
    }

    /// Drops the statements up to the `]` that closes the innermost open `[`, and leaves that
    /// `]` next.
    pub(super) fn skip_to_pop(&mut self) {
        let mut depth = 0usize;
        loop {
            let list = self.innermost();
            let Some(stmt) = list.as_slice().first() else {
                if self.branches.pop().is_none() {
                    return;
                }
                continue;
            };
            match stmt {
                CStmt::Pop(_) if depth == 0 => return,
                CStmt::Pop(_) => depth -= 1,
                CStmt::Push => depth += 1,
                _ => {}
            }
            list.next();
        }
    }
}

impl<'p> Iterator for Cursor<'p> {
    type Item = &'p CStmt;

    /// The next statement of the innermost list under way, dropping the branches that are
    /// done.
    fn next(&mut self) -> Option<&'p CStmt> {
        while let Some(list) = self.branches.last_mut() {
            if let Some(stmt) = list.next() {
                return Some(stmt);
            }
            self.branches.pop();
        }
        self.rule.next()
    }
}
