//! `import id : "file.cga"`: a grammar and the files it imports merged into one grammar, each
//! file's declarations in its own namespace, as CityEngine does it.
//!
//! - Every rule, attribute, constant and function of an imported file becomes `id.Name` in the
//!   importer (`a.b.Name` through nested imports), and names inside the file refer to its own
//!   declarations.
//! - An attribute of the imported file takes, in this order: the value the import statement
//!   sets (`import b : "b.cga" (h = 10)`, an expression of the importer); the importer's
//!   attribute of the same name, unless the statement keeps it (`(h)`) or keeps all (`()`);
//!   its own default.
//! - A rule the importer defines as `id.Name --> …` replaces the imported file's `Name`, and
//!   the imported file's references to `Name` go to it, even when the file leaves `Name`
//!   undefined.
//! - Only the importing grammar's `@StartRule` counts.
//!
//! Declarations remember the file they came from, so that diagnostics and derivation errors
//! point into it.

use rustc_hash::FxHashSet;
use shapegram_syntax::{
    Diagnostic,
    ast::{
        Attr, Block, BlockEntry, Body, Const, Expr, ExprKind, Function, Grammar, Ident,
        ImportAttribute, Rule, Stmt,
    },
};

/// A grammar and the files it imports, as the caller found and parsed them.
#[derive(Clone, Copy, Debug)]
pub struct ImportGraph<'a> {
    /// The files, the importing grammar first.
    pub files: &'a [&'a Grammar],
    /// For each file, the file each of its imports names, in the order of
    /// [`Grammar::imports`] (indices into `files`).
    pub links: &'a [Vec<usize>],
}

/// The file of each declaration of a merged grammar, by kind and position.
#[derive(Clone, Debug, Default)]
pub(crate) struct Origins {
    pub attrs: Vec<u16>,
    pub consts: Vec<u16>,
    pub functions: Vec<u16>,
    pub rules: Vec<u16>,
    /// Each file's folder, relative to the importing grammar's and `/`-separated (`""` for
    /// the grammar's own), when the caller told them: where the files a rule names (`i()`,
    /// `texture()`) are looked for first, as CityEngine looks next to the rule file.
    pub folders: Vec<std::sync::Arc<str>>,
}

/// How deeply imports may nest.
const MAX_DEPTH: usize = 32;

/// Merges the files of `graph` into one grammar with the origin of each declaration, or the
/// errors (import cycles, wrong links) with their files.
pub(crate) fn merge(
    graph: ImportGraph<'_>,
) -> Result<(Grammar, Origins), Vec<(usize, Diagnostic)>> {
    let mut merger = Merger {
        graph,
        grammar: Grammar {
            dialect: graph.files[0].dialect,
            version: graph.files[0].version.clone(),
            unsupported: graph.files[0].unsupported.clone(),
            ..Grammar::default()
        },
        origins: Origins::default(),
        errors: Vec::new(),
        stack: Vec::new(),
    };
    merger.add(0, "", None);
    if merger.errors.is_empty() {
        Ok((merger.grammar, merger.origins))
    } else {
        Err(merger.errors)
    }
}

struct Merger<'a> {
    graph: ImportGraph<'a>,
    grammar: Grammar,
    origins: Origins,
    errors: Vec<(usize, Diagnostic)>,
    /// The files being added, outermost first: a file on it imported again is a cycle.
    stack: Vec<usize>,
}

/// The file importing another, with its namespace and the import statement's index.
struct Importer<'p> {
    file: usize,
    names: &'p Names,
    import: usize,
}

/// What names a file declares, and the namespace its declarations go into.
struct Names {
    prefix: String,
    rules: FxHashSet<String>,
    values: FxHashSet<String>,
    attrs: FxHashSet<String>,
    imports: Vec<String>,
}

impl Names {
    fn of(grammar: &Grammar, prefix: &str) -> Self {
        Self {
            prefix: prefix.to_owned(),
            rules: grammar.rules.iter().map(|r| r.name.name.clone()).collect(),
            values: grammar
                .attrs
                .iter()
                .map(|a| a.name.name.clone())
                .chain(grammar.consts.iter().map(|c| c.name.name.clone()))
                .chain(grammar.functions.iter().map(|f| f.name.name.clone()))
                .collect(),
            attrs: grammar.attrs.iter().map(|a| a.name.name.clone()).collect(),
            imports: grammar
                .imports
                .iter()
                .filter_map(|i| i.id.as_ref().map(|id| format!("{}.", id.name)))
                .collect(),
        }
    }

    /// Whether `name` is declared in the file or reaches into one of its imports.
    fn owns(&self, name: &str) -> bool {
        self.values.contains(name)
            || self.rules.contains(name)
            || self.imports.iter().any(|i| name.starts_with(i.as_str()))
    }
}

impl<'a> Merger<'a> {
    fn add(&mut self, file: usize, prefix: &str, importer: Option<Importer<'_>>) {
        let grammar = self.graph.files[file];
        if self.stack.len() >= MAX_DEPTH {
            self.cycle_or_depth(file, &importer, "imports nest more than 32 files deep");
            return;
        }
        if self.stack.contains(&file) {
            self.cycle_or_depth(file, &importer, "import cycle: this file imports itself");
            return;
        }
        self.stack.push(file);
        let names = Names::of(grammar, prefix);
        let origin = file as u16;
        let main = importer.is_none();
        for attr in &grammar.attrs {
            let value = match &importer {
                None => attr.value.clone(),
                Some(importer) => match self.set_by_import(attr, importer) {
                    // Written in the importer: its names.
                    Some(value) => self.renamed_expr(value.clone(), importer.names, &[]),
                    None if self.propagated(attr, importer) => Expr {
                        kind: ExprKind::Name(format!(
                            "{}{}",
                            importer.names.prefix, attr.name.name
                        )),
                        span: attr.value.span,
                    },
                    None => self.renamed_expr(attr.value.clone(), &names, &[]),
                },
            };
            self.grammar.attrs.push(Attr {
                name: prefixed(&attr.name, prefix),
                value,
                ..attr.clone()
            });
            self.origins.attrs.push(origin);
        }
        for constant in &grammar.consts {
            self.grammar.consts.push(Const {
                name: prefixed(&constant.name, prefix),
                value: self.renamed_expr(constant.value.clone(), &names, &[]),
                ..constant.clone()
            });
            self.origins.consts.push(origin);
        }
        for function in &grammar.functions {
            self.grammar.functions.push(Function {
                name: prefixed(&function.name, prefix),
                body: self.renamed_expr(function.body.clone(), &names, &function.params),
                ..function.clone()
            });
            self.origins.functions.push(origin);
        }
        for rule in &grammar.rules {
            let name = prefixed(&rule.name, prefix);
            // The importer's `id.Name` replaces the file's own `Name`.
            let replaced = self
                .grammar
                .rules
                .iter()
                .any(|r| r.name.name == name.name && r.params.len() == rule.params.len());
            if replaced {
                continue;
            }
            let mut body = rule.body.clone();
            rename_body(&mut body, &|n| self.rename(n, &names), &rule.params);
            let mut annotations = rule.annotations.clone();
            if !main {
                annotations.retain(|a| a.name.name != "StartRule");
            }
            self.grammar.rules.push(Rule {
                annotations,
                name,
                body,
                ..rule.clone()
            });
            self.origins.rules.push(origin);
        }
        let links = self.graph.links.get(file).cloned().unwrap_or_default();
        for (j, import) in grammar.imports.iter().enumerate() {
            let Some(&target) = links.get(j).filter(|&&t| t < self.graph.files.len()) else {
                self.errors.push((
                    file,
                    Diagnostic::error("the imported file was not found", import.path.span),
                ));
                continue;
            };
            let inner = match &import.id {
                Some(id) => format!("{prefix}{}.", id.name),
                None => prefix.to_owned(),
            };
            let importer = Importer {
                file,
                names: &names,
                import: j,
            };
            self.add(target, &inner, Some(importer));
        }
        self.stack.pop();
    }

    fn cycle_or_depth(&mut self, file: usize, importer: &Option<Importer<'_>>, message: &str) {
        let Some(importer) = importer else {
            return;
        };
        let import = &self.graph.files[importer.file].imports[importer.import];
        let chain = if self.stack.contains(&file) {
            let from = self.stack.iter().position(|&f| f == file).unwrap_or(0);
            let files: Vec<String> = self.stack[from..]
                .iter()
                .chain(std::iter::once(&file))
                .map(|f| format!("file {f}"))
                .collect();
            format!(" ({})", files.join(" → "))
        } else {
            String::new()
        };
        let message = if chain.is_empty() {
            message.to_owned()
        } else {
            "import cycle: the file imports one of the files importing it".to_owned()
        };
        self.errors.push((
            importer.file,
            Diagnostic::error(message, import.span).with_hint(format!(
                "a file may not import, directly or through others, a file that imports it{chain}"
            )),
        ));
    }

    /// The value the import statement sets for `attr`, if any.
    fn set_by_import(&self, attr: &Attr, importer: &Importer<'_>) -> Option<&'a Expr> {
        let import = &self.graph.files[importer.file].imports[importer.import];
        import.attributes.iter().flatten().find_map(|a| match a {
            ImportAttribute::Set(name, value) if name.name == attr.name.name => Some(value),
            _ => None,
        })
    }

    /// Whether `attr` takes the importer's attribute of the same name.
    fn propagated(&self, attr: &Attr, importer: &Importer<'_>) -> bool {
        let import = &self.graph.files[importer.file].imports[importer.import];
        let kept = match &import.attributes {
            Some(list) if list.is_empty() => true,
            Some(list) => list
                .iter()
                .any(|a| matches!(a, ImportAttribute::Keep(n) if n.name == attr.name.name)),
            None => false,
        };
        !kept && importer.names.attrs.contains(&attr.name.name)
    }

    /// A name of the file `names` describes, as the merged grammar calls it.
    fn rename(&self, name: &str, names: &Names) -> Option<String> {
        if names.prefix.is_empty() {
            return None;
        }
        let full = format!("{}{name}", names.prefix);
        // A rule the importer defines for the file (`id.Name -->`) counts as the file's own.
        let overridden = self.grammar.rules.iter().any(|r| r.name.name == full);
        (names.owns(name) || overridden).then_some(full)
    }

    fn renamed_expr(&self, mut e: Expr, names: &Names, params: &[Ident]) -> Expr {
        rename_expr(&mut e, &|n| self.rename(n, names), params);
        e
    }
}

fn prefixed(name: &Ident, prefix: &str) -> Ident {
    Ident {
        name: format!("{prefix}{}", name.name),
        span: name.span,
    }
}

/// Renames, in a rule body, the names `rename` maps (parameters aside).
fn rename_body(body: &mut Body, rename: &dyn Fn(&str) -> Option<String>, params: &[Ident]) {
    match body {
        Body::Sequence(stmts) => rename_stmts(stmts, rename, params),
        Body::Cases {
            arms, otherwise, ..
        }
        | Body::Stochastic {
            arms, otherwise, ..
        } => {
            for (e, b) in arms {
                rename_expr(e, rename, params);
                rename_body(b, rename, params);
            }
            rename_body(otherwise, rename, params);
        }
    }
}

fn rename_stmts(stmts: &mut [Stmt], rename: &dyn Fn(&str) -> Option<String>, params: &[Ident]) {
    for stmt in stmts {
        let call = match stmt {
            Stmt::Call(call) => call,
            Stmt::Branch(body) => {
                rename_body(body, rename, params);
                continue;
            }
            _ => continue,
        };
        if let Some(name) = rename(&call.name.name) {
            call.name.name = name;
        }
        for arg in call.args.iter_mut().flatten() {
            rename_expr(&mut arg.value, rename, params);
        }
        if let Some(block) = &mut call.block {
            if call.name.name == "splitAndSetbackPerimeter" {
                // Sized sections in a group, then the `remainder` selector (see `ast::Call`).
                for entry in &mut block.entries {
                    match entry {
                        BlockEntry::Group(sections) => rename_block(sections, true, rename, params),
                        BlockEntry::Part { body, .. } => rename_stmts(body, rename, params),
                    }
                }
            } else {
                let sizes = call.name.name.starts_with("split");
                rename_block(block, sizes, rename, params);
            }
        }
    }
}

/// Renames in a block's entries. The keys of splits (`sizes`) are expressions; those of other
/// operations are selectors (`shape`, `front`, `street.back`), which no declared name hides:
/// `shapeL(…){ shape : … }` selects the L even in a file with an `attr shape`.
fn rename_block(
    block: &mut Block,
    sizes: bool,
    rename: &dyn Fn(&str) -> Option<String>,
    params: &[Ident],
) {
    for entry in &mut block.entries {
        match entry {
            BlockEntry::Part { key, body, .. } => {
                if sizes || !matches!(key.kind, ExprKind::Name(_)) {
                    rename_expr(key, rename, params);
                }
                rename_stmts(body, rename, params);
            }
            BlockEntry::Group(group) => rename_block(group, sizes, rename, params),
        }
    }
}

fn rename_expr(e: &mut Expr, rename: &dyn Fn(&str) -> Option<String>, params: &[Ident]) {
    e.walk_mut(&mut |x| match &mut x.kind {
        ExprKind::Name(name) if !params.iter().any(|p| p.name == *name) => {
            if let Some(full) = rename(name) {
                *name = full;
            }
        }
        ExprKind::Call { name, .. } => {
            if let Some(full) = rename(&name.name) {
                name.name = full;
            }
        }
        _ => {}
    });
}
