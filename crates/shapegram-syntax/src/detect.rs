//! Telling the notations apart by their text.

use crate::ast::Dialect;
use crate::lexer::{Token, TokenKind, lex};
use crate::parser::{PREDICATE_WORDS, RULE_KINDS};

/// The notation a grammar text is written in.
///
/// The text is read with the main syntax's lexer (so comments and strings are skipped) and the
/// first telltale construct decides:
///
/// - Müller et al. 2006: a rule arrow `~>`, `\leadsto`, `\rightarrow`, `→` or `⇝`; the empty word
///   `ϵ`, `ε` or `\epsilon`; `Subdiv("…`, `Repeat("…` or `Comp("…` with a quoted first argument;
///   or a numbered rule `1: lot -->`.
/// - SGL: `sgprod`, `PlaceShape(` or `AtDepth(`; or a rule `name: {` or `name: (w){`, or a
///   weighted alternative `(w){` at the start of a line.
///
/// - Michelangelo: `new Axiom(`, `new Rules.…`, `Rules.Split(` (or another rule kind),
///   `new Synchronize(` or `using (Predicates.…`.
/// - The native goal notation, at the start of a line: `axiom` or `local` followed by a name or
///   string, `sync` followed by a name, or a rule head of predicates (`fulfills(…)`, `goal(…)`,
///   `is(…)`, `tag(…)`, `has(…)`, `if(…)`, `adds(…)`, each possibly negated with `!`) followed
///   by `-->`, or by `{` after `using`.
///
/// Anything else is the main (CGA-style) syntax.
pub fn detect(text: &str) -> Dialect {
    let (tokens, diagnostics) = lex(text, Dialect::Cga);
    // Characters the main lexer does not know (LaTeX commands, arrows, ϵ) come back as
    // diagnostics: the first one that belongs to the Müller notation is a marker.
    let muller_symbol = diagnostics
        .iter()
        .map(|d| d.span.start as usize)
        .find(|&at| {
            let rest = &text[at..];
            [
                "\\leadsto",
                "\\rightarrow",
                "\\epsilon",
                "\\varepsilon",
                "→",
                "⇝",
                "ϵ",
            ]
            .iter()
            .any(|m| rest.starts_with(m))
        });
    let token_marker = (0..tokens.len()).find_map(|i| marker(text, &tokens, i));
    match (token_marker, muller_symbol) {
        (Some((at, dialect)), Some(symbol)) if at < symbol => dialect,
        (_, Some(_)) => Dialect::Muller2006,
        (Some((_, dialect)), None) => dialect,
        (None, None) => Dialect::Cga,
    }
}

/// The dialect whose telltale construct starts at token `i`, with its offset.
fn marker(text: &str, tokens: &[Token], i: usize) -> Option<(usize, Dialect)> {
    let kind = |j: usize| tokens.get(j).map_or(&TokenKind::Eof, |t| &t.kind);
    let word = |j: usize| match tokens.get(j) {
        Some(t) if t.kind == TokenKind::Ident => &text[t.span.range()],
        _ => "",
    };
    let token = &tokens[i];
    let at = token.span.start as usize;
    let found = match &token.kind {
        // `~>` written without a space.
        TokenKind::Tilde
            if *kind(i + 1) == TokenKind::Gt && tokens[i + 1].span.start == token.span.end =>
        {
            Some(Dialect::Muller2006)
        }
        TokenKind::Ident => match word(i) {
            "Subdiv" | "Repeat" | "Comp"
                if *kind(i + 1) == TokenKind::LParen
                    && matches!(kind(i + 2), TokenKind::Str(_)) =>
            {
                Some(Dialect::Muller2006)
            }
            "ε" | "ϵ" => Some(Dialect::Muller2006),
            "sgprod" if *kind(i + 1) == TokenKind::LBrace => Some(Dialect::Sgl),
            "new" if word(i + 1) == "Axiom" || word(i + 1) == "Synchronize" => {
                (*kind(i + 2) == TokenKind::LParen).then_some(Dialect::Michelangelo)
            }
            "new" if word(i + 1).starts_with("Rules.") => Some(Dialect::Michelangelo),
            "using"
                if *kind(i + 1) == TokenKind::LParen && word(i + 2).starts_with("Predicates.") =>
            {
                Some(Dialect::Michelangelo)
            }
            w if *kind(i + 1) == TokenKind::LParen
                && w.strip_prefix("Rules.")
                    .is_some_and(|k| RULE_KINDS.contains(&k)) =>
            {
                Some(Dialect::Michelangelo)
            }
            "axiom" | "local"
                if token.line_start
                    && matches!(kind(i + 1), TokenKind::Ident | TokenKind::Str(_)) =>
            {
                Some(Dialect::Goal)
            }
            "sync" if token.line_start && *kind(i + 1) == TokenKind::Ident => Some(Dialect::Goal),
            "using" if token.line_start => (predicate_head(text, tokens, i + 1)
                == Some(TokenKind::LBrace))
            .then_some(Dialect::Goal),
            _ if token.line_start && predicate_head(text, tokens, i) == Some(TokenKind::Arrow) => {
                Some(Dialect::Goal)
            }
            "PlaceShape" | "AtDepth" if *kind(i + 1) == TokenKind::LParen => Some(Dialect::Sgl),
            _ if token.line_start && *kind(i + 1) == TokenKind::Colon => match kind(i + 2) {
                TokenKind::LBrace => Some(Dialect::Sgl),
                TokenKind::LParen if weighted(tokens, i + 2) => Some(Dialect::Sgl),
                _ => None,
            },
            _ => None,
        },
        // `!is(ruin) -->`: a goal rule's head.
        TokenKind::Bang
            if token.line_start && predicate_head(text, tokens, i) == Some(TokenKind::Arrow) =>
        {
            Some(Dialect::Goal)
        }
        // `(w){` starting a line: a weighted alternative.
        TokenKind::LParen if token.line_start && weighted(tokens, i) => Some(Dialect::Sgl),
        // `1: lot -->`: a numbered rule.
        TokenKind::Number(_)
            if token.line_start
                && *kind(i + 1) == TokenKind::Colon
                && *kind(i + 2) == TokenKind::Ident
                && *kind(after_parens(tokens, i + 3)) == TokenKind::Arrow =>
        {
            Some(Dialect::Muller2006)
        }
        _ => None,
    };
    found.map(|d| (at, d))
}

/// When tokens from `i` are the predicates of a native goal rule head, `[!]word(…)` one or more
/// times on one line, the kind of the token after them.
fn predicate_head(text: &str, tokens: &[Token], mut i: usize) -> Option<TokenKind> {
    let mut first = true;
    loop {
        let bang = tokens.get(i)?.kind == TokenKind::Bang;
        let word = i + usize::from(bang);
        let is_predicate = tokens.get(word).is_some_and(|t| {
            t.kind == TokenKind::Ident && PREDICATE_WORDS.contains(&&text[t.span.range()])
        }) && tokens.get(word + 1).map(|t| &t.kind) == Some(&TokenKind::LParen);
        if !is_predicate {
            return if first {
                None
            } else {
                Some(tokens.get(i)?.kind.clone())
            };
        }
        i = after_parens(tokens, word + 1);
        if tokens.get(i)?.line_start {
            return None;
        }
        first = false;
    }
}

/// The index after the parenthesised group starting at `i`, or `i` when there is none.
fn after_parens(tokens: &[Token], i: usize) -> usize {
    if tokens.get(i).map(|t| &t.kind) != Some(&TokenKind::LParen) {
        return i;
    }
    let mut depth = 0usize;
    for (j, t) in tokens.iter().enumerate().skip(i) {
        // A rule head is on one line.
        if t.line_start && j > i {
            return j;
        }
        match t.kind {
            TokenKind::LParen => depth += 1,
            TokenKind::RParen => {
                depth -= 1;
                if depth == 0 {
                    return j + 1;
                }
            }
            TokenKind::Eof => return j,
            _ => {}
        }
    }
    tokens.len()
}

/// Whether tokens `i..` are `( number ) {`.
fn weighted(tokens: &[Token], i: usize) -> bool {
    matches!(
        tokens
            .get(i..i + 4)
            .map(|t| [&t[0].kind, &t[1].kind, &t[2].kind, &t[3].kind]),
        Some([
            TokenKind::LParen,
            TokenKind::Number(_),
            TokenKind::RParen,
            TokenKind::LBrace
        ])
    )
}
