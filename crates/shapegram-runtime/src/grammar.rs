//! A grammar of any kind the engine runs, loaded from text, and one derivation of it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use shapegram_eval::{Derivation, DeriveControl, DeriveOptions, InitialShape, Program, Value};
use shapegram_export::Buffers;
use shapegram_geom::{Color, DVec2, DVec3, Model};
use shapegram_load::{FileAssets, Files, MissingAssets, RulePackage};
use shapegram_syntax::{Diagnostic, Dialect, SourceFile, ast};

use crate::error::Error;
use crate::topo::{TopoGrammar, TopoMesh};

/// The kinds of grammar, as `sg_state_load_text` takes them (`SG_KIND_…`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// CGA and the notations it reads (`.cga`, `.mul`, `.sgl`), goal grammars (`.goal`).
    Shape(Option<Dialect>),
    /// An L-system (`.lsys`).
    LSystem,
    /// An implicit cave grammar (`.cave`).
    Cave,
    /// A compiled topological grammar (`.grammar`, JSON).
    Topo,
}

impl Kind {
    /// The kind a file name's extension says, if it says one.
    pub fn of_name(name: &str) -> Option<Kind> {
        let extension = name.rsplit_once('.')?.1.to_ascii_lowercase();
        Some(match extension.as_str() {
            "cga" => Kind::Shape(Some(Dialect::Cga)),
            "mul" => Kind::Shape(Some(Dialect::Muller2006)),
            "sgl" => Kind::Shape(Some(Dialect::Sgl)),
            // Native or Michelangelo notation: the text tells.
            "goal" => Kind::Shape(None),
            "lsys" => Kind::LSystem,
            "cave" => Kind::Cave,
            "grammar" => Kind::Topo,
            _ => return None,
        })
    }
}

/// The type an attribute's default value has, when its declaration makes it plain.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttrType {
    /// A number.
    Number,
    /// A string.
    String,
    /// A boolean.
    Bool,
}

impl AttrType {
    /// The type of a value set through the ABI.
    pub fn of(value: &Value) -> Option<AttrType> {
        match value {
            Value::Number(_) => Some(AttrType::Number),
            Value::Str(_) => Some(AttrType::String),
            Value::Bool(_) => Some(AttrType::Bool),
            Value::Array(_) => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            AttrType::Number => "a number",
            AttrType::String => "a string",
            AttrType::Bool => "a boolean",
        }
    }
}

/// An attribute a CGA-style or goal grammar declares (`attr name = value`), as a host's form
/// shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct AttrDecl {
    /// Its name.
    pub name: String,
    /// Its default value when it is a literal (or a negated one); `None` for an expression,
    /// whose value only deriving tells.
    pub default: Option<Value>,
    /// Where it is declared: `file:line:column` of its name.
    pub location: String,
}

impl AttrDecl {
    /// The type its default shows, when it is a literal.
    pub fn ty(&self) -> Option<AttrType> {
        self.default.as_ref().and_then(AttrType::of)
    }
}

/// The value of a default written as a literal (or a negated one).
fn literal(expr: &ast::Expr) -> Option<Value> {
    match &expr.kind {
        ast::ExprKind::Number(n) => Some(Value::Number(*n)),
        ast::ExprKind::String(s) => Some(Value::string(s)),
        ast::ExprKind::Bool(b) => Some(Value::Bool(*b)),
        ast::ExprKind::Unary { op, operand } => match (op, literal(operand)?) {
            (ast::UnaryOp::Neg, Value::Number(n)) => Some(Value::Number(-n)),
            (ast::UnaryOp::Not, Value::Bool(b)) => Some(Value::Bool(!b)),
            _ => None,
        },
        _ => None,
    }
}

/// A loaded grammar.
pub enum Grammar {
    /// CGA-style and goal grammars: a compiled program and its source, for messages.
    Shape {
        /// The program.
        program: Program,
        /// The grammar's file and the files it imports, what derivation errors point into.
        sources: Vec<SourceFile>,
        /// Where `i("file")` finds files: beside the grammar; kept, so each is read once.
        assets: Arc<FileAssets>,
        /// The attributes the grammar's file declares.
        attrs: Vec<AttrDecl>,
        /// Whether it is a goal grammar (which starts from its axioms, not from a lot).
        goal: bool,
    },
    /// An L-system, with its name and text for messages.
    LSystem(shapegram_lsystem::LSystem, String, String),
    /// An implicit cave grammar.
    Cave(shapegram_implicit::CaveProgram),
    /// A topological grammar, with its symbol to start from and its textures.
    Topo(TopoGrammar),
}

/// What a derivation is asked to do besides the grammar; by default seed 0, the grammar's own
/// attributes and generations, the default lot.
#[derive(Default)]
pub struct Settings {
    /// The seed.
    pub seed: u64,
    /// Attribute values overriding the grammar's.
    pub attrs: Vec<(String, Value)>,
    /// The lots; the default 20 × 30 lot when empty.
    pub lots: Vec<InitialShape>,
    /// Generations (L-system iterations, topological generations, generations of a CGA
    /// derivation); the grammar's own when `None`.
    pub generations: Option<u32>,
    /// Cancellation and progress, shared with `sg_state_cancel` and `sg_state_progress`.
    pub control: Arc<DeriveControl>,
}

/// The cave's colour, as `shapegram cave` paints it.
const ROCK: Color = Color::rgb(0.55, 0.48, 0.42);

impl Grammar {
    /// Parses and compiles `text`, named `name` in messages, as `kind` (`None`: by the name's
    /// extension, else CGA or the notation the text is in).
    pub fn load(name: &str, text: &str, kind: Option<Kind>) -> Result<Grammar, Error> {
        Self::load_with_library(name, text, kind, &[])
    }

    /// [`Grammar::load`] for a goal grammar with its library: other goal grammars, each given
    /// by its name (its file's path; the file's stem names the grammar) and its text, whose
    /// rules fulfil the main grammar's goals. They compile with it into one program in the order
    /// given, as `shapegram derive --library` compiles them ([`crate::read_library`] reads them
    /// from paths in the command's order); an error in one is rendered with its name, line and
    /// column. A library given to a grammar that is not a goal grammar, and two library
    /// grammars of one name, are errors of kind [`crate::ErrorKind::Grammar`].
    pub fn load_with_library(
        name: &str,
        text: &str,
        kind: Option<Kind>,
        library: &[(String, String)],
    ) -> Result<Grammar, Error> {
        let kind = kind
            .or_else(|| Kind::of_name(name))
            .unwrap_or(Kind::Shape(None));
        if !library.is_empty() && !matches!(kind, Kind::Shape(_)) {
            return Err(not_goal(name));
        }
        match kind {
            Kind::Shape(dialect) => {
                let library = library
                    .iter()
                    .map(|(name, text)| SourceFile::new(name.clone(), text.clone()))
                    .collect();
                Self::load_shape(SourceFile::new(name, text), dialect, library, Origin::Disk)
            }
            Kind::LSystem => shapegram_lsystem::LSystem::parse(text)
                .map(|system| Grammar::LSystem(system, name.to_owned(), text.to_owned()))
                .map_err(|e| lsystem_error(Error::grammar(e.render(name, text)), e)),
            Kind::Cave => shapegram_implicit::text::parse(text)
                .map(Grammar::Cave)
                .map_err(|e| Error::grammar(format!("{name}:{e}")).at(e.line, e.column, e.message)),
            Kind::Topo => TopoGrammar::load(name, text).map(Grammar::Topo),
        }
    }

    /// A CGA-style grammar with the files it imports (as `shapegram derive` reads them), or a
    /// goal grammar with its library, its files read from `origin`.
    pub(crate) fn load_shape(
        source: SourceFile,
        dialect: Option<Dialect>,
        library: Vec<SourceFile>,
        origin: Origin,
    ) -> Result<Grammar, Error> {
        let CompiledShape {
            grammar,
            program,
            diagnostics,
            sources,
            goal,
        } = match shapegram_load::goal_dialect(&source, dialect) {
            Some(_) => compile_goals(source, dialect, library)?,
            None if !library.is_empty() => return Err(not_goal(source.name())),
            None => compile_cga_style(&source, dialect, &origin),
        };
        let errors: Vec<String> = diagnostics
            .iter()
            .filter(|(_, d)| d.is_error())
            .map(|(file, d)| sources[*file].render(d))
            .collect();
        match program {
            Some(program) if errors.is_empty() => {
                let assets = origin.assets(sources[0].name());
                Ok(Grammar::Shape {
                    program,
                    attrs: grammar
                        .attrs
                        .iter()
                        .map(|a| {
                            let (line, column) = sources[0].line_col(a.name.span.start);
                            AttrDecl {
                                name: a.name.name.clone(),
                                default: literal(&a.value),
                                location: format!("{}:{line}:{column}", sources[0].name()),
                            }
                        })
                        .collect(),
                    assets: Arc::new(assets),
                    sources,
                    goal,
                })
            }
            _ => Err(Error::grammar(if errors.is_empty() {
                format!("{}: the grammar does not compile", sources[0].name())
            } else {
                errors.join("\n")
            })),
        }
    }

    /// The attributes the grammar declares, in order (none for L-systems, caves and
    /// topological grammars).
    pub fn attrs(&self) -> &[AttrDecl] {
        match self {
            Grammar::Shape { attrs, .. } => attrs,
            _ => &[],
        }
    }

    /// Checks that the grammar has an attribute `name` that takes `value`; a value of another
    /// type than the declaration's is an error at the declaration's place.
    pub fn check_attr(&self, name: &str, value: &Value) -> Result<(), Error> {
        let Grammar::Shape { attrs, .. } = self else {
            return Err(Error::attribute(format!(
                "only CGA-style and goal grammars have attributes, not `{name}`"
            )));
        };
        let Some(declared) = attrs.iter().find(|a| a.name == name) else {
            let mut message = format!("the grammar has no attribute `{name}`");
            if let Some(close) =
                shapegram_syntax::suggest(name, attrs.iter().map(|a| a.name.as_str()))
            {
                message.push_str(&format!(" (did you mean `{close}`?)"));
            }
            return Err(Error::attribute(message));
        };
        match (declared.ty(), AttrType::of(value)) {
            (Some(ty), Some(given)) if ty != given => Err(Error::attribute_type(format!(
                "{}: the attribute `{name}` is {}, not {}",
                declared.location,
                ty.name(),
                given.name()
            ))),
            _ => Ok(()),
        }
    }

    /// Derives the grammar as `settings` say: a model with its skeletons (unposed: the buffers
    /// [`Derived::fill`] makes are posed), or a topological grammar's triangles.
    pub fn derive(&self, settings: &Settings) -> Result<Derived, Error> {
        let model = match self {
            Grammar::Shape { goal, .. } => {
                let lots = match (settings.lots.is_empty(), goal) {
                    (false, _) => settings.lots.clone(),
                    // Goal grammars start from their axioms.
                    (true, true) => Vec::new(),
                    (true, false) => vec![default_lot()],
                };
                self.derivation(&lots, settings)?.to_model()
            }
            Grammar::LSystem(system, name, text) => {
                let options = shapegram_lsystem::DeriveOptions {
                    iterations: settings.generations,
                    seed: Some(settings.seed),
                    ..shapegram_lsystem::DeriveOptions::default()
                };
                let failed = |e: shapegram_lsystem::Error| {
                    if settings.control.is_cancelled() {
                        return Error::cancelled();
                    }
                    lsystem_error(Error::derive(e.render(name, text)), e)
                };
                let word = system
                    .derive_until(&options, |_, _| {}, || settings.control.is_cancelled())
                    .map_err(failed)?;
                let shown = system.interpretation(&word, &options).map_err(failed)?;
                let drawing = shapegram_lsystem::interpret(system, &shown);
                shapegram_lsystem::drawing_to_model_within(
                    &drawing,
                    &system.settings,
                    shapegram_lsystem::DEFAULT_MAX_VERTICES,
                )
                .map_err(failed)?
            }
            Grammar::Cave(program) => {
                let run = program
                    .run(Some(settings.seed))
                    .map_err(|e| Error::derive(e.to_string()).at(e.line, e.column, e.message))?;
                let lod = program
                    .lod
                    .unwrap_or(shapegram_implicit::CaveParams::default().lod);
                let options = shapegram_implicit::MeshOptions::with_cell_size(1.0 / f64::from(lod));
                let solid = run.builder.solid();
                let meshing = shapegram_implicit::mesh_until(solid, &options, &|_, _| {}, &|| {
                    settings.control.is_cancelled()
                })
                .map_err(|e| {
                    if settings.control.is_cancelled() {
                        Error::cancelled()
                    } else {
                        Error::derive(e.to_string())
                    }
                })?;
                let mut model = Model::single("cave", ROCK, meshing.mesh);
                model.parts[0].normals = shapegram_implicit::surface_normals(
                    solid,
                    &model.parts[0].mesh,
                    options.cell_size / 2.0,
                );
                model
            }
            // Already flat triangles: they go to the buffers as they are.
            Grammar::Topo(topo) => return topo.derive(settings).map(Derived::Triangles),
        };
        Ok(Derived::Model(model))
    }
}

impl Grammar {
    /// Derives a CGA-style or goal grammar from `lots` (`settings.lots` is not read) with
    /// `settings`' seed, attributes, generations and control, as `shapegram derive` does; other
    /// kinds of grammar derive no lots and are an [`ErrorKind::InvalidArgument`] error.
    ///
    /// [`ErrorKind::InvalidArgument`]: crate::ErrorKind::InvalidArgument
    pub fn derivation(
        &self,
        lots: &[InitialShape],
        settings: &Settings,
    ) -> Result<Derivation, Error> {
        self.derive_lots(lots, settings, false)
    }

    /// [`Grammar::derivation`] that keeps the derivation tree, from which each lot's metadata
    /// is read ([`Derivation::lot_metadata`]): what tiles with metadata are derived with.
    pub fn derivation_with_tree(
        &self,
        lots: &[InitialShape],
        settings: &Settings,
    ) -> Result<Derivation, Error> {
        self.derive_lots(lots, settings, true)
    }

    /// The grammar's attribute names, as metadata lists them (`Program::attr_names`); none
    /// for grammars that are not CGA-style.
    pub fn attr_names(&self) -> Vec<String> {
        match self {
            Grammar::Shape { program, .. } => program.attr_names().map(str::to_owned).collect(),
            _ => Vec::new(),
        }
    }

    /// [`Grammar::derivation`], keeping the tree when `keep_tree` says so.
    fn derive_lots(
        &self,
        lots: &[InitialShape],
        settings: &Settings,
        keep_tree: bool,
    ) -> Result<Derivation, Error> {
        let Grammar::Shape {
            program,
            sources,
            assets,
            ..
        } = self
        else {
            return Err(Error::invalid(
                "only CGA-style grammars derive lots: this grammar is an L-system, a cave or a \
                 topological grammar",
            ));
        };
        let options = DeriveOptions {
            seed: settings.seed,
            attrs: settings.attrs.clone(),
            generations: settings.generations,
            control: Some(Arc::clone(&settings.control)),
            assets: Some(Arc::clone(assets) as Arc<dyn shapegram_eval::AssetLoader>),
            keep_tree,
            ..DeriveOptions::default()
        };
        shapegram_eval::derive(program, lots, &options).map_err(|e| {
            if settings.control.is_cancelled() {
                return Error::cancelled();
            }
            let source = e.file.and_then(|i| sources.get(i)).unwrap_or(&sources[0]);
            match e.to_diagnostic() {
                Some(d) => Error::derive(source.render(&d)),
                None => Error::derive(format!("{}: {}", source.name(), e.message)),
            }
        })
    }

    /// Whether it is a goal grammar, which starts from its axioms rather than from lots.
    pub fn is_goal(&self) -> bool {
        matches!(self, Grammar::Shape { goal: true, .. })
    }

    /// Whether a rule asks about other shapes (occlusion, snapping), so that a lot's result
    /// depends on the lots around it.
    pub fn has_context_rules(&self) -> bool {
        matches!(self, Grammar::Shape { program, .. } if program.has_context_rules())
    }
}

/// A CGA-style or goal grammar parsed and compiled, its errors not yet looked at.
struct CompiledShape {
    /// The grammar's own file, parsed: the attributes a host sets are its.
    grammar: ast::Grammar,
    /// The program, `None` when there were errors.
    program: Option<Program>,
    /// Errors and warnings, each with the index of its file in `sources`.
    diagnostics: Vec<(usize, Diagnostic)>,
    /// The grammar's file, then the files it imports or its library.
    sources: Vec<SourceFile>,
    /// Whether it is a goal grammar.
    goal: bool,
}

/// A goal grammar and its library compiled together, named and ordered as
/// `shapegram derive --library` compiles them.
fn compile_goals(
    source: SourceFile,
    dialect: Option<Dialect>,
    library: Vec<SourceFile>,
) -> Result<CompiledShape, Error> {
    let mut sources = vec![source];
    sources.extend(library);
    shapegram_load::check_library_names(sources.iter().map(SourceFile::name)).map_err(|clash| {
        Error::grammar(format!("{clash} ({})", shapegram_load::NameClash::HINT))
    })?;
    let options = shapegram_eval::LibraryOptions::closed(sources.len());
    let compiled = shapegram_load::compile_library(sources, dialect, &options);
    Ok(CompiledShape {
        grammar: compiled.grammar,
        program: compiled.program,
        diagnostics: compiled.diagnostics,
        sources: compiled.sources,
        goal: true,
    })
}

/// Where a grammar's imports and assets are read from.
pub(crate) enum Origin {
    /// The file system: beside the grammar, whose name is its path.
    Disk,
    /// A rule package, the grammar being its rule file at `entry`.
    Package(Arc<RulePackage>, PathBuf),
}

impl Origin {
    /// The files, and the grammar's path among them (`name` on disk).
    fn files(&self, name: &str) -> (Files, PathBuf) {
        match self {
            Origin::Disk => (Files::Disk, PathBuf::from(name)),
            Origin::Package(package, entry) => (Files::Package(Arc::clone(package)), entry.clone()),
        }
    }

    /// The assets of the grammar named `name`, found as CityEngine finds them.
    fn assets(&self, name: &str) -> FileAssets {
        match self {
            Origin::Disk => {
                let folder = Path::new(name).parent().unwrap_or(Path::new(""));
                FileAssets::new(folder.to_path_buf(), MissingAssets::Error)
            }
            Origin::Package(package, entry) => FileAssets::in_package(
                Arc::clone(package),
                &entry.to_string_lossy(),
                MissingAssets::Error,
            ),
        }
    }
}

/// A CGA-style grammar (in `dialect`, else the notation its text is in) with the files it
/// imports, read from `origin`.
fn compile_cga_style(
    source: &SourceFile,
    dialect: Option<Dialect>,
    origin: &Origin,
) -> CompiledShape {
    let dialect = dialect.unwrap_or_else(|| shapegram_syntax::detect(source.text()));
    let (files, path) = origin.files(source.name());
    let compiled = shapegram_load::compile_in(source, Some(dialect), &files, &path);
    CompiledShape {
        grammar: compiled.grammar,
        program: compiled.program,
        diagnostics: compiled.diagnostics,
        sources: compiled.sources,
        goal: false,
    }
}

/// The error for a library given to `name`, which is not a goal grammar.
fn not_goal(name: &str) -> Error {
    Error::grammar(format!(
        "{name} is not a goal grammar: a library gives goal grammars their rules"
    ))
}

/// `error` at the place of the L-system error `e`, if it has one.
fn lsystem_error(error: Error, e: shapegram_lsystem::Error) -> Error {
    match e.position {
        Some(p) => error.at(p.line as usize, p.column as usize, e.message),
        None => error,
    }
}

/// What a derivation made.
pub enum Derived {
    /// A model.
    Model(Model),
    /// A topological grammar's shapes, in flat-shaded triangles with its textures.
    Triangles(TopoMesh),
}

impl Derived {
    /// Replaces the contents of `buffers` with the derived mesh.
    pub fn fill(&self, buffers: &mut Buffers) {
        match self {
            Derived::Model(model) => buffers.fill(model),
            Derived::Triangles(topo) => topo.fill(buffers),
        }
    }

    /// The name of part `part` (see [`shapegram_export::PartRange::part`]).
    pub fn part_name(&self, part: usize) -> &str {
        match self {
            Derived::Model(model) => &model.parts[part].name,
            Derived::Triangles(topo) => &topo.mesh.parts[part].name,
        }
    }

    /// The material name the grammar gave part `part` (`set(material.name, …)`, a topological
    /// grammar's material), if any.
    pub fn part_material(&self, part: usize) -> Option<&str> {
        match self {
            Derived::Model(model) => model.parts[part].material.as_deref(),
            Derived::Triangles(topo) => topo.part_material(part),
        }
    }
}

/// A lot from its corners (a planar polygon, counter-clockwise seen from above, y up), checked:
/// three corners or more, all finite, with an area.
pub fn lot(footprint: Vec<DVec3>) -> Result<InitialShape, Error> {
    if footprint.len() < 3 {
        return Err(Error::invalid(format!(
            "a lot needs 3 corners or more, not {}",
            footprint.len()
        )));
    }
    if !footprint.iter().all(|p| p.is_finite()) {
        return Err(Error::invalid("a lot's corner is not finite"));
    }
    if shapegram_geom::mesh::newell(footprint.iter().copied()).length() <= 0.0 {
        return Err(Error::invalid("the lot has no area"));
    }
    Ok(InitialShape {
        footprint,
        index: None,
    })
}

/// The lot a CGA-style grammar derives on when none is set: 20 × 30, as `shapegram derive`'s.
pub fn default_lot() -> InitialShape {
    let corners =
        [(0.0, 0.0), (20.0, 0.0), (20.0, 30.0), (0.0, 30.0)].map(|(x, z)| DVec2::new(x, z));
    InitialShape::from_xz(&corners).expect("the default lot has an area")
}
