//! The compiler's frame: name tables built from a grammar's declarations, the pass that
//! compiles them into a [`Program`], and the diagnostics it gathers.

use rustc_hash::FxHashMap;
use shapegram_syntax::{
    Diagnostic,
    ast::{self, Grammar},
};

use super::*;
use crate::fingerprint::Fingerprints;
use crate::goals::GoalRules;
use crate::imports::Origins;

impl<'g> Compiler<'g> {
    pub(super) fn new(grammar: &'g Grammar) -> Self {
        let mut c = Self {
            diagnostics: Vec::new(),
            symbols: Vec::new(),
            symbol_ids: FxHashMap::default(),
            rule_by_name: FxHashMap::default(),
            attr_by_name: FxHashMap::default(),
            const_by_name: FxHashMap::default(),
            function_by_name: FxHashMap::default(),
            rule_arity: grammar.rules.iter().map(|r| r.params.len()).collect(),
            uses: Uses::default(),
            warned: FxHashMap::default(),
            kinematic: false,
            solids: false,
            derives_now: false,
            tagged: false,
            tree_keys: false,
            goal: None,
            origins: None,
            diagnostic_files: Vec::new(),
        };
        for (i, rule) in grammar.rules.iter().enumerate() {
            let list = c.rule_by_name.entry(rule.name.name.clone()).or_default();
            if list
                .iter()
                .any(|&r| grammar.rules[r as usize].params.len() == rule.params.len())
            {
                c.diagnostics.push(
                    Diagnostic::error(
                        format!(
                            "rule `{}` is defined twice with {} parameters",
                            rule.name.name,
                            rule.params.len()
                        ),
                        rule.name.span,
                    )
                    .with_hint("rules of the same name must differ in their number of parameters"),
                );
            }
            list.push(i as RuleId);
        }
        for (i, attr) in grammar.attrs.iter().enumerate() {
            if c.attr_by_name
                .insert(attr.name.name.clone(), i as u32)
                .is_some()
            {
                c.diagnostics.push(Diagnostic::error(
                    format!("attribute `{}` is declared twice", attr.name.name),
                    attr.name.span,
                ));
            }
        }
        for (i, constant) in grammar.consts.iter().enumerate() {
            if c.const_by_name
                .insert(&constant.name.name, i as u32)
                .is_some()
            {
                c.diagnostics.push(Diagnostic::error(
                    format!("`{}` is defined twice", constant.name.name),
                    constant.name.span,
                ));
            }
        }
        for (i, function) in grammar.functions.iter().enumerate() {
            c.function_by_name
                .entry(&function.name.name)
                .or_default()
                .push((function.params.len(), i as u32));
        }
        c
    }

    pub(super) fn run(&mut self, grammar: &Grammar) -> Program {
        let mut attr_uses = Vec::new();
        let attrs: Vec<CAttr> = grammar
            .attrs
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let value = self.expr(&a.value, &[]);
                self.attribute(|o| o.attrs[i]);
                attr_uses.push(std::mem::take(&mut self.uses));
                CAttr {
                    name: a.name.name.clone(),
                    value,
                }
            })
            .collect();
        let mut const_uses = Vec::new();
        let consts = grammar
            .consts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let value = self.expr(&c.value, &[]);
                self.attribute(|o| o.consts[i]);
                const_uses.push(std::mem::take(&mut self.uses));
                CConst {
                    value,
                    cached: c.is_const,
                }
            })
            .collect();
        let mut function_uses = Vec::new();
        let functions = grammar
            .functions
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let body = self.expr(&f.body, &f.params);
                self.attribute(|o| o.functions[i]);
                function_uses.push(std::mem::take(&mut self.uses));
                CFunction {
                    name: f.name.name.clone(),
                    body,
                }
            })
            .collect();
        let mut rule_uses = Vec::new();
        let rules = grammar
            .rules
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let rule = CRule {
                    symbol: self.intern(&r.name.name),
                    params: r.params.len(),
                    body: self.body(&r.body, &r.params),
                };
                self.attribute(|o| o.rules[i]);
                rule_uses.push(std::mem::take(&mut self.uses));
                rule
            })
            .collect();
        let closure = ContextClosure::new(&function_uses, &const_uses);
        for (i, (attr, uses)) in grammar.attrs.iter().zip(&attr_uses).enumerate() {
            if closure.asks(uses) {
                self.attribute(|_| 0);
                self.diagnostics.push(
                    Diagnostic::error(
                        "attribute values cannot ask about other shapes",
                        attr.value.span,
                    )
                    .with_label("uses an occlusion query")
                    .with_hint(
                        "ask in a rule instead: `Tile --> case inside(): Wall else: Window`",
                    ),
                );
                self.attribute(|o| o.attrs[i]);
            }
        }
        let context_rules = rule_uses.iter().map(|u| closure.asks(u)).collect();
        let named_poses = crate::named_poses::compile(grammar, &mut self.diagnostics);
        // Without `@StartRule`, the first rule a shape can start from: one without parameters.
        let start_rule = grammar
            .rules
            .iter()
            .position(ast::Rule::is_start_rule)
            .or_else(|| grammar.rules.iter().position(|r| r.params.is_empty()))
            .or((!grammar.rules.is_empty()).then_some(0))
            .map(|i| i as RuleId);
        Program {
            symbols: std::mem::take(&mut self.symbols),
            rules,
            attrs,
            consts,
            functions,
            rule_by_name: std::mem::take(&mut self.rule_by_name),
            attr_by_name: std::mem::take(&mut self.attr_by_name),
            start_rule,
            context_rules,
            kinematic: self.kinematic,
            solids: self.solids,
            derives_now: self.derives_now,
            tagged: self.tagged,
            tree_keys: self.tree_keys,
            named_poses,
            fingerprints: Fingerprints::of(grammar),
            goals: None,
            origins: self.origins.take(),
        }
    }

    /// Gives the diagnostics reported since the last call the file `file` picks from the
    /// declarations' origins (when compiling a grammar with imports).
    pub(super) fn attribute(&mut self, file: impl Fn(&Origins) -> u16) {
        if let Some(origins) = &self.origins {
            let file = file(origins);
            self.diagnostic_files.resize(self.diagnostics.len(), file);
        }
    }

    /// A compiler for goal grammars (whose rules come in through [`crate::library`]).
    pub(crate) fn new_for_goals(empty: &'g Grammar) -> Self {
        let mut c = Self::new(empty);
        c.goal = Some(Box::default());
        c
    }

    /// The program of a goal library.
    pub(crate) fn finish_goals(&mut self, rules: Vec<CRule>, goals: GoalRules) -> Program {
        Program {
            symbols: std::mem::take(&mut self.symbols),
            context_rules: vec![false; rules.len()],
            rules,
            attrs: Vec::new(),
            consts: Vec::new(),
            functions: Vec::new(),
            rule_by_name: FxHashMap::default(),
            attr_by_name: FxHashMap::default(),
            start_rule: None,
            kinematic: self.kinematic,
            solids: self.solids,
            derives_now: self.derives_now,
            tagged: self.tagged,
            tree_keys: self.tree_keys,
            named_poses: Vec::new(),
            fingerprints: Fingerprints::default(),
            goals: Some(Box::new(goals)),
            origins: None,
        }
    }

    pub(crate) fn intern(&mut self, name: &str) -> Sym {
        if let Some(&s) = self.symbol_ids.get(name) {
            return s;
        }
        let s = self.symbols.len() as Sym;
        self.symbols.push(name.to_owned());
        self.symbol_ids.insert(name.to_owned(), s);
        s
    }

    pub(super) fn rule_arity(&self, rule: RuleId) -> Option<usize> {
        self.rule_arity.get(rule as usize).copied()
    }

    /// Whether `name` is a parameter, attribute, constant or function the grammar declares (so
    /// a selector by that name is a condition, not an unknown selector word).
    pub(crate) fn knows_name(&self, name: &str, params: &[ast::Ident]) -> bool {
        params.iter().any(|p| p.name == name)
            || self.attr_by_name.contains_key(name)
            || self.const_by_name.contains_key(name)
            || self.function_by_name.contains_key(name)
    }

    /// Attribute names, for hints.
    pub(crate) fn attr_names(&self) -> impl Iterator<Item = &str> {
        self.attr_by_name.keys().map(String::as_str)
    }

    /// Reports a diagnostic.
    pub(crate) fn report(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    /// How many errors have been reported so far.
    pub(crate) fn error_count(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    /// Reports a warning once per `key`.
    pub(crate) fn warn_once(&mut self, key: &str, d: Diagnostic) {
        if self.warned.insert(key.to_owned(), ()).is_none() {
            self.diagnostics.push(d);
        }
    }
}

/// Which functions and constants ask about other shapes, directly or through each other.
struct ContextClosure {
    functions: Vec<bool>,
    consts: Vec<bool>,
}

impl ContextClosure {
    fn new(functions: &[Uses], consts: &[Uses]) -> Self {
        let mut closure = Self {
            functions: vec![false; functions.len()],
            consts: vec![false; consts.len()],
        };
        // Each pass marks at least one more item or ends: at most one pass per item.
        loop {
            let mut changed = false;
            for (i, uses) in functions.iter().enumerate() {
                if !closure.functions[i] && closure.asks(uses) {
                    closure.functions[i] = true;
                    changed = true;
                }
            }
            for (i, uses) in consts.iter().enumerate() {
                if !closure.consts[i] && closure.asks(uses) {
                    closure.consts[i] = true;
                    changed = true;
                }
            }
            if !changed {
                return closure;
            }
        }
    }

    fn asks(&self, uses: &Uses) -> bool {
        uses.context
            || uses.functions.iter().any(|&f| self.functions[f as usize])
            || uses.consts.iter().any(|&c| self.consts[c as usize])
    }
}
