//! The C#-style notation of goal grammars in Michelangelo (Ilčík and Wimmer), lowered to the
//! goal rules of the common AST.

use super::{PResult, Parser, Start};
use crate::Diagnostic;
use crate::ast::Grammar;
use crate::lexer::TokenKind;

impl Parser<'_> {
    /// A file in the Michelangelo notation.
    pub(super) fn michelangelo_file(&mut self, _grammar: &mut Grammar) {
        let d = Diagnostic::error("the Michelangelo notation is not read yet", self.span());
        self.report(d);
        while !self.at(&TokenKind::Eof) {
            self.bump();
        }
    }

    /// Whether a declaration of the Michelangelo notation starts at token `i`.
    pub(super) fn michelangelo_declaration_start(&self, i: usize) -> Option<Start> {
        match self.kind_at(i) {
            TokenKind::Eof => Some(Start::Strong),
            _ => None,
        }
    }

    #[allow(dead_code)]
    fn michelangelo_placeholder(&mut self) -> PResult<()> {
        Ok(())
    }
}
