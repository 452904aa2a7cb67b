//! Top-level declarations: `version`, annotations, `attr`, `const`, functions, rules, and the
//! `import`, and the recognised-but-unsupported `style`.

use super::{Fail, PResult, Parser};
use crate::ast::{
    Annotation, Argument, Attr, Const, ExprKind, Function, Grammar, Ident, Import, ImportAttribute,
    Rule, Spanned, Style, Unsupported,
};
use crate::lexer::TokenKind;
use crate::{Diagnostic, Span};

/// Type names CGA allows before a parameter (`Facade(float h)`); the type is not kept.
const PARAMETER_TYPES: [&str; 3] = ["float", "string", "bool"];

impl Parser<'_> {
    /// Declarations up to the end of the file, or (inside a style section) up to the next
    /// `style`.
    pub(super) fn declarations(&mut self, grammar: &mut Grammar, in_style: bool) {
        while !self.at(&TokenKind::Eof) {
            let before = self.checkpoint();
            let result = self.annotations().and_then(|annotations| {
                if in_style && self.at_word("style") {
                    return Ok(None);
                }
                self.declaration(grammar, annotations).map(Some)
            });
            match result {
                Ok(Some(())) => {}
                Ok(None) => {
                    // Let the caller start the next style section, annotations included.
                    self.rewind(before);
                    return;
                }
                Err(Fail) => self.recover_to_declaration(),
            }
            if self.pos == before.pos {
                self.bump();
            }
        }
    }

    pub(super) fn annotations(&mut self) -> PResult<Vec<Annotation>> {
        let mut annotations = Vec::new();
        while let Some(at) = self.eat(&TokenKind::At) {
            if *self.peek() != TokenKind::Ident {
                return Err(self.error_expected("an annotation name", "after `@`"));
            }
            let name = self.ident();
            let args = if self.at(&TokenKind::LParen) && name.name == "Handle" {
                self.skip_parenthesised();
                Vec::new()
            } else if self.at(&TokenKind::LParen) {
                self.call_args()?.0
            } else {
                Vec::new()
            };
            annotations.push(Annotation {
                name,
                args,
                span: self.span_from(at),
            });
        }
        Ok(annotations)
    }

    /// Skips a `( … )` with whatever it holds, nested brackets included. `@Handle`'s arguments
    /// (`shape=Rule^2`, `translate={.1,0,0}`) only place a handle in CityEngine's viewport, and
    /// are not expressions.
    fn skip_parenthesised(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.peek() {
                TokenKind::Eof => return,
                TokenKind::LParen => depth += 1,
                TokenKind::RParen => {
                    depth -= 1;
                    if depth == 0 {
                        self.bump();
                        return;
                    }
                }
                _ => {}
            }
            self.bump();
        }
    }

    pub(super) fn declaration(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
    ) -> PResult<()> {
        match self.peek() {
            TokenKind::Eof if !annotations.is_empty() => {
                Err(self.error_expected("a declaration", "after the annotation"))
            }
            TokenKind::Ident => match self.text() {
                "attr" => self.attr(grammar, annotations),
                "const" => self.constant(grammar, annotations),
                "version" => self.version(grammar),
                "import" => self.import(grammar),
                "style" => self.style(grammar),
                // `extension Ext --> …` is a rule that importers may redefine; `start S --> …`
                // the file's start rule.
                "extension" | "start" if self.is_rule_head(self.pos + 1) => {
                    let keyword = self.bump();
                    let mut annotations = annotations;
                    if &self.src[keyword.range()] == "start" {
                        annotations.push(Annotation {
                            name: Ident {
                                name: "StartRule".to_owned(),
                                span: keyword,
                            },
                            args: Vec::new(),
                            span: keyword,
                        });
                    }
                    self.rule_or_function(grammar, annotations)
                }
                _ if self.is_name_at(self.pos) => self.rule_or_function(grammar, annotations),
                _ => Err(self.not_a_declaration()),
            },
            _ => Err(self.not_a_declaration()),
        }
    }

    fn not_a_declaration(&mut self) -> Fail {
        let d = self.expected("a declaration", "").with_hint(
            "a grammar consists of rules `Name --> …`, `attr`, `const` and functions `name = …`",
        );
        self.report(d);
        Fail
    }

    /// A declared name (not a keyword), or an error naming what it was expected after.
    fn declared_name(&mut self, what: &str, after: &str) -> PResult<Ident> {
        if self.is_name_at(self.pos) {
            Ok(self.ident())
        } else {
            Err(self.error_expected(what, after))
        }
    }

    /// Checks that a value is followed by the next declaration.
    fn end_of_value(&mut self, name: &Ident) -> PResult<()> {
        if self.at_declaration_start() {
            return Ok(());
        }
        let context = format!("after the value of `{}`", name.name);
        Err(self.error_expected("an operator or the next declaration", &context))
    }

    fn attr(&mut self, grammar: &mut Grammar, annotations: Vec<Annotation>) -> PResult<()> {
        let start = self.bump();
        let name = self.declared_name("an attribute name", "after `attr`")?;
        self.expect(&TokenKind::Eq, "`=`", "after the attribute name")?;
        let value = self.expr()?;
        grammar.attrs.push(Attr {
            annotations,
            span: self.span_from(start),
            name: name.clone(),
            value,
        });
        self.end_of_value(&name)
    }

    fn constant(&mut self, grammar: &mut Grammar, annotations: Vec<Annotation>) -> PResult<()> {
        let start = self.bump();
        let name = self.declared_name("a constant name", "after `const`")?;
        // `const f(x) = …` is a function whose results CGA may cache: a plain function here.
        let params = self.optional_params()?;
        self.expect(&TokenKind::Eq, "`=`", "after the constant name")?;
        self.value_declaration(grammar, annotations, name, params, true, start)
    }

    /// The value after the `=` (already consumed) of `name = …` or `name(params) = …`, recorded
    /// as a function when there are parameters, else as a constant. `const` declarations and
    /// plain ones are read alike: they differ only in `is_const` and where their span `start`s.
    fn value_declaration(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
        name: Ident,
        params: Option<Vec<Ident>>,
        is_const: bool,
        start: Span,
    ) -> PResult<()> {
        let value = self.expr()?;
        let span = self.span_from(start);
        match params {
            Some(params) => grammar.functions.push(Function {
                annotations,
                name: name.clone(),
                params,
                body: value,
                span,
            }),
            None => grammar.consts.push(Const {
                annotations,
                name: name.clone(),
                value,
                is_const,
                span,
            }),
        }
        self.end_of_value(&name)
    }

    fn version(&mut self, grammar: &mut Grammar) -> PResult<()> {
        self.bump();
        match self.peek().clone() {
            TokenKind::Str(value) => {
                let span = self.bump();
                grammar.version = Some(Spanned { value, span });
                Ok(())
            }
            _ => Err(self.error_expected("a version string", "after `version`")),
        }
    }

    /// `import id : "file.cga"`, optionally with `(a = value, b, …)`.
    fn import(&mut self, grammar: &mut Grammar) -> PResult<()> {
        let start = self.bump();
        let id = if matches!(self.peek(), TokenKind::Str(_)) {
            None
        } else {
            let id = self.declared_name("a name for the imported file", "after `import`")?;
            if self.at(&TokenKind::LParen) {
                let d = Diagnostic::error(
                    "imports of chosen styles are not supported yet",
                    self.span(),
                )
                .with_hint("import the file whole: `import id : \"file.cga\"`");
                self.report(d);
                return Err(Fail);
            }
            self.expect(&TokenKind::Colon, "`:`", "after the import's name")?;
            Some(id)
        };
        let TokenKind::Str(file) = self.peek().clone() else {
            return Err(self.error_expected("a file name string", "in the import"));
        };
        let path = Spanned {
            value: file,
            span: self.bump(),
        };
        let attributes = if self.at(&TokenKind::LParen) {
            let args = self.import_arguments(id.as_ref())?;
            let mut list = Vec::new();
            for arg in args {
                match (arg.name, &arg.value.kind) {
                    (Some(name), _) => list.push(ImportAttribute::Set(name, arg.value)),
                    (None, ExprKind::Name(name)) if !name.contains('.') => {
                        list.push(ImportAttribute::Keep(Ident {
                            name: name.clone(),
                            span: arg.value.span,
                        }));
                    }
                    (None, _) => {
                        let d = Diagnostic::error(
                            "expected an attribute to keep (`a`) or to set (`a = value`)",
                            arg.value.span,
                        );
                        self.report(d);
                    }
                }
            }
            Some(list)
        } else {
            None
        };
        grammar.imports.push(Import {
            id,
            path,
            attributes,
            span: self.span_from(start),
        });
        Ok(())
    }

    /// The `( … )` of an import: attributes to keep (`a`) or set (`a = v`), as arguments, and
    /// extension rules redefined (`Ext --> ops`), which become the importer's rules `id.Ext`
    /// (replacing the file's `Ext`, as an importer's `id.Ext -->` does).
    fn import_arguments(&mut self, id: Option<&Ident>) -> PResult<Vec<Argument>> {
        let open = self.bump();
        let mut args = Vec::new();
        while !self.at(&TokenKind::RParen) {
            if self.is_name_at(self.pos) && *self.kind_at(self.pos + 1) == TokenKind::Arrow {
                let name = self.ident();
                self.bump();
                let body = self.body()?;
                let Some(id) = id else {
                    let d = Diagnostic::error(
                        "only an import with a name can redefine the file's rules",
                        name.span,
                    )
                    .with_hint("name the import: `import id : \"file.cga\" (Ext --> …)`");
                    self.report(d);
                    return Err(Fail);
                };
                self.import_rules.push(Rule {
                    annotations: Vec::new(),
                    name: Ident {
                        name: format!("{}.{}", id.name, name.name),
                        span: name.span,
                    },
                    params: Vec::new(),
                    body,
                    span: self.span_from(name.span),
                });
            } else if self.is_name_at(self.pos) && *self.kind_at(self.pos + 1) == TokenKind::Eq {
                let name = self.ident();
                self.bump();
                args.push(Argument {
                    name: Some(name),
                    value: self.expr()?,
                });
            } else {
                args.push(Argument {
                    name: None,
                    value: self.expr()?,
                });
            }
            if self.eat(&TokenKind::Comma).is_none() {
                break;
            }
        }
        self.close(&TokenKind::RParen, open, "`,` or `)`", "in the import")?;
        Ok(args)
    }

    /// `style Name [extends Base]` and the declarations after it, kept as the style's.
    fn style(&mut self, grammar: &mut Grammar) -> PResult<()> {
        let start = self.bump();
        let name = self.declared_name("a style name", "after `style`")?;
        let mut span = start.to(name.span);
        let mut base = None;
        if self.at_word("extends") {
            self.bump();
            let b = self.declared_name("the name of the style it extends", "after `extends`")?;
            span = span.to(b.span);
            base = Some(b);
        }
        self.report(
            Diagnostic::warning("`style` is derived only when chosen", span)
                .with_label("not derived by default")
                .with_hint(format!(
                    "the default style is derived; `shapegram derive --style {}` derives this one",
                    name.name
                )),
        );
        let mut section = Grammar::default();
        self.declarations(&mut section, true);
        grammar.unsupported.push(Unsupported {
            what: "style".to_string(),
            span,
        });
        grammar.unsupported.append(&mut section.unsupported);
        grammar.styles.push(Style {
            name,
            base,
            declarations: section,
            span,
        });
        Ok(())
    }

    /// `Name(params) --> body`, `name(params) = expr` or `name = expr`.
    pub(super) fn rule_or_function(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
    ) -> PResult<()> {
        let name = self.ident();
        let params = self.optional_params()?;
        match self.peek() {
            TokenKind::Arrow => {
                self.bump();
            }
            TokenKind::Eq => {
                self.bump();
                let start = name.span;
                return self.value_declaration(grammar, annotations, name, params, false, start);
            }
            // `->` for `-->`: report it, then read the body as intended.
            TokenKind::Minus
                if *self.peek_nth(1) == TokenKind::Gt
                    && self.token_at(self.pos + 1).span.start == self.span().end =>
            {
                let arrow = self.span().to(self.token_at(self.pos + 1).span);
                self.report(
                    Diagnostic::error("expected `-->`, found `->`", arrow)
                        .with_label("expected `-->` here")
                        .with_hint("rules are written with a long arrow: `Name --> body`"),
                );
                self.bump();
                self.bump();
            }
            // A body right after the name: the arrow was forgotten.
            _ if self.at_statement_start() => {
                let context = format!("after the rule name `{}`", name.name);
                let d = self
                    .expected("`-->`", &context)
                    .with_hint(format!("rules are written `{} --> body`", name.name));
                self.report(d);
            }
            _ => {
                let context = format!("after `{}`", name.name);
                let d = self
                    .expected("`-->` or `=`", &context)
                    .with_hint("a rule is written `Name --> body`, a function `name = expression`");
                self.report(d);
                return Err(Fail);
            }
        }
        let body = self.body()?;
        grammar.rules.push(Rule {
            annotations,
            span: self.span_from(name.span),
            name,
            params: params.unwrap_or_default(),
            body,
        });
        self.end_of_body()
    }

    /// Checks that a rule body is followed by the next declaration.
    fn end_of_body(&mut self) -> PResult<()> {
        if self.at_declaration_start() {
            return Ok(());
        }
        let d = if self.at_word("else") {
            Diagnostic::error(
                "`else` without a matching `case` or percentage",
                self.span(),
            )
            .with_label("unexpected `else`")
        } else if self.at_word("case") {
            self.expected("a statement or the next declaration", "in the rule body")
                .with_hint("`case` must start a rule body or a branch; move the statements before it into a rule of their own")
        } else {
            self.expected("a statement or the next declaration", "in the rule body")
        };
        self.report(d);
        Err(Fail)
    }

    /// Whether a rule body could start at the current token.
    fn at_statement_start(&self) -> bool {
        match self.peek() {
            TokenKind::LBracket => true,
            TokenKind::Ident => {
                self.at_word("NIL")
                    || self.at_word("case")
                    || (self.is_name_at(self.pos) && !self.at_declaration_start())
            }
            _ => false,
        }
    }

    /// `(a, b)` after a rule or function name, if present.
    pub(super) fn optional_params(&mut self) -> PResult<Option<Vec<Ident>>> {
        if !self.at(&TokenKind::LParen) {
            return Ok(None);
        }
        self.bump();
        let mut params = Vec::new();
        if self.eat(&TokenKind::RParen).is_some() {
            return Ok(Some(params));
        }
        loop {
            if self.is_name_at(self.pos)
                && PARAMETER_TYPES.contains(&self.text())
                && *self.peek_nth(1) != TokenKind::Comma
                && *self.peek_nth(1) != TokenKind::RParen
            {
                self.bump();
                if self.at(&TokenKind::LBracket) && *self.peek_nth(1) == TokenKind::RBracket {
                    self.bump();
                    self.bump();
                }
            }
            params.push(self.declared_name("a parameter name", "")?);
            if self.eat(&TokenKind::Comma).is_none() {
                self.expect(&TokenKind::RParen, "`,` or `)`", "in the parameter list")?;
                return Ok(Some(params));
            }
        }
    }
}
