//! The compiled grammar (thesis 3.1.9): lean symbols, prototype shapes and rules of
//! virtual-vertex instructions, and its `.grammar` file (versioned JSON, see docs/topo.md).

use std::fmt;

use rustc_hash::FxHashSet;
use shapegram_geom::{Color, DVec3};

use crate::grammar_file::{GrammarFile, json_message};
use crate::material::Material;
use crate::polyhedron::{self, Index};

/// The `format` field of every `.grammar` file.
pub const GRAMMAR_FORMAT: &str = "shapegram-topo-grammar";
/// The newest version this library writes and reads (it reads all older ones too).
pub const GRAMMAR_VERSION: u32 = 2;
/// The version of files that use nothing newer than it: grammars without materials or offset
/// cuts are written as version 1, which older builds read too.
pub const GRAMMAR_VERSION_PLAIN: u32 = 1;
/// Most entries any one list of a grammar file may hold: a larger file is corrupt, not a grammar.
pub const MAX_ENTRIES: usize = 1 << 20;

/// A compiled grammar: symbols with their topology, one prototype shape per named symbol, rules.
#[derive(Clone, Debug, PartialEq)]
pub struct Grammar {
    /// Prototype shapes, used as initial shapes.
    pub shapes: Vec<GrammarShape>,
    /// Symbols: named ones first (in project order), then the anonymous terminals.
    pub symbols: Vec<GrammarSymbol>,
    /// Rules, grouped by symbol.
    pub rules: Vec<GrammarRule>,
    /// Materials that sub-shapes' faces name by index.
    pub materials: Vec<Material>,
}

/// Largest coordinate of a shape's vertex, in absolute value.
pub const MAX_COORDINATE: f64 = 1e15;

/// How far outside `0..=1` an interpolation coefficient may stray by rounding.
const T_TOLERANCE: f64 = 1e-9;

/// A shape's geometry: positions in the canonical order of its symbol.
#[derive(Clone, Debug, PartialEq)]
pub struct GrammarShape {
    /// The symbol it is an instance of.
    pub symbol: Index,
    /// One position per vertex of the symbol.
    pub vertices: Vec<DVec3>,
}

/// A symbol's topology and rules.
#[derive(Clone, Debug, PartialEq)]
pub struct GrammarSymbol {
    /// The name; `None` for an anonymous terminal.
    pub name: Option<String>,
    /// Colour of its shapes in meshes; `None` for the default grey.
    pub color: Option<Color>,
    /// Colours of single faces (one entry per face, in `faces` order), overriding `color`;
    /// empty when no face has its own colour.
    pub face_colors: Vec<Option<Color>>,
    /// Number of vertices.
    pub vertex_count: u32,
    /// Face loops in canonical vertex numbers, counter-clockwise seen from outside.
    pub faces: Vec<Vec<Index>>,
    /// Its rules (indices into [`Grammar::rules`]); none for a terminal.
    pub rules: Vec<Index>,
}

/// How to make a vertex that the rule's shape does not have yet: `from + t (to − from)`, both
/// ends indexing the rule's vertex array (the shape's vertices, then earlier virtual vertices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VirtualVertex {
    /// First end.
    pub from: Index,
    /// Second end.
    pub to: Index,
    /// Interpolation coefficient.
    pub t: f64,
}

/// A sub-shape a rule makes: its symbol and its vertices, in the symbol's canonical order, as
/// indices into the rule's vertex array, and where its faces' materials come from.
#[derive(Clone, Debug, PartialEq)]
pub struct SubShape {
    /// The symbol (named or anonymous terminal).
    pub symbol: Index,
    /// One index per vertex of the symbol.
    pub vertices: Vec<Index>,
    /// The material the rule gives each face (in the symbol's face order), overriding the
    /// inherited one; empty when it gives none.
    pub materials: Vec<Option<Index>>,
    /// For each face, the face of the rewritten shape it is a piece of (whose material it
    /// inherits); `None` for faces inside the shape. Empty when the grammar has no materials.
    pub from_faces: Vec<Option<Index>>,
}

/// A cut at a fixed distance from a face: its new vertices are not interpolated at the rule's
/// fixed fractions but placed where the edges they lie on cross the plane `distance` metres
/// inside the face, so a wall keeps its thickness on shapes of any size.
#[derive(Clone, Debug, PartialEq)]
pub struct OffsetCut {
    /// The cut's number among the rule's cuts (0 first), for messages.
    pub step: u32,
    /// Three vertices of the face (indices into the rule's vertex array), counter-clockwise
    /// seen from outside: they give the face's plane and its outward normal.
    pub face: [Index; 3],
    /// The distance in metres inside the face.
    pub distance: f64,
    /// The virtual vertices the cut makes: consecutive indices into the rule's
    /// `virtual_vertices`, ascending.
    pub vertices: Vec<Index>,
}

/// A rule on a symbol: virtual-vertex instructions and the sub-shapes built from them.
#[derive(Clone, Debug, PartialEq)]
pub struct GrammarRule {
    /// The symbol it rewrites.
    pub symbol: Index,
    /// Its name (for messages).
    pub name: String,
    /// Relative weight among the symbol's rules.
    pub weight: f64,
    /// Instructions for the vertices the shape does not have.
    pub virtual_vertices: Vec<VirtualVertex>,
    /// What the shape becomes; epsilon sub-shapes are left out.
    pub sub_shapes: Vec<SubShape>,
    /// The cuts made at a fixed distance from a face, in the order of their vertices.
    pub offset_cuts: Vec<OffsetCut>,
}

impl Grammar {
    /// The symbol called `name` (anonymous terminals have no name).
    pub fn symbol_named(&self, name: &str) -> Option<Index> {
        self.symbols
            .iter()
            .position(|s| s.name.as_deref() == Some(name))
            .map(|i| i as Index)
    }

    /// The prototype shape of `symbol`, if the grammar has one.
    pub fn shape_of(&self, symbol: Index) -> Option<&GrammarShape> {
        self.shapes.iter().find(|s| s.symbol == symbol)
    }

    /// Whether shapes of `symbol` are never rewritten.
    pub fn is_terminal(&self, symbol: Index) -> bool {
        self.symbols[symbol as usize].rules.is_empty()
    }

    /// Names of the named symbols, in order.
    pub fn symbol_names(&self) -> Vec<&str> {
        self.symbols
            .iter()
            .filter_map(|s| s.name.as_deref())
            .collect()
    }

    /// The display name of `symbol`: its name, or `terminal` for an anonymous one.
    pub fn display_name(&self, symbol: Index) -> &str {
        self.symbols[symbol as usize]
            .name
            .as_deref()
            .unwrap_or("terminal")
    }

    /// Whether the grammar uses what version 1 files cannot hold (materials, offset cuts).
    pub fn needs_version_2(&self) -> bool {
        !self.materials.is_empty() || self.rules.iter().any(|r| !r.offset_cuts.is_empty())
    }

    /// The grammar as `.grammar` JSON text (pretty-printed, ending in a newline).
    pub fn to_json(&self) -> String {
        let file = GrammarFile::from(self);
        crate::json::to_text(&file)
    }

    /// Reads `.grammar` JSON text and checks everything in it.
    pub fn from_json(text: &str) -> Result<Self, GrammarError> {
        let file: GrammarFile = serde_json::from_str(text).map_err(|e| GrammarError {
            location: format!("{}:{}", e.line(), e.column()),
            message: json_message(&e),
        })?;
        file.into_grammar()
    }

    /// Checks indices, counts, topology and numbers; the first problem found is returned.
    pub fn validate(&self) -> Result<(), GrammarError> {
        let err = |location: String, message: String| Err(GrammarError { location, message });
        for (name, len) in [
            ("shapes", self.shapes.len()),
            ("symbols", self.symbols.len()),
            ("rules", self.rules.len()),
            ("materials", self.materials.len()),
        ] {
            if len > MAX_ENTRIES {
                return err(name.into(), format!("{len} entries, at most {MAX_ENTRIES}"));
            }
        }
        let mut material_names: FxHashSet<&str> = FxHashSet::default();
        for (i, material) in self.materials.iter().enumerate() {
            if let Err(message) = material.check() {
                return err(format!("materials[{i}]"), message);
            }
            if !material_names.insert(&material.name) {
                return err(
                    format!("materials[{i}].name"),
                    format!("the name '{}' is used twice", material.name.escape_debug()),
                );
            }
        }
        // Names seen so far, and whether each rule is listed by its symbol: looked up, not
        // searched, so that lists of a million entries load in linear time.
        let mut names: FxHashSet<&str> = FxHashSet::default();
        let mut listed = vec![false; self.rules.len()];
        for (i, symbol) in self.symbols.iter().enumerate() {
            let at = |field: &str| format!("symbols[{i}].{field}");
            if let Some(name) = &symbol.name {
                if name.trim().is_empty() {
                    return err(at("name"), "a symbol name cannot be blank".into());
                }
                if !names.insert(name) {
                    return err(at("name"), format!("the name '{name}' is used twice"));
                }
            }
            let n = symbol.vertex_count as usize;
            if n > polyhedron::MAX_VERTICES {
                return err(at("vertex_count"), format!("{n} vertices is too many"));
            }
            if let Err(e) = polyhedron::check_topology(n, &symbol.faces) {
                return err(at("faces"), e.to_string());
            }
            if !symbol.face_colors.is_empty() && symbol.face_colors.len() != symbol.faces.len() {
                return err(
                    at("face_colors"),
                    format!(
                        "{} colours for {} faces (give one per face, null for none)",
                        symbol.face_colors.len(),
                        symbol.faces.len()
                    ),
                );
            }
            for (k, &r) in symbol.rules.iter().enumerate() {
                match self.rules.get(r as usize) {
                    None => {
                        return err(
                            at(&format!("rules[{k}]")),
                            format!("rule {r} does not exist (there are {})", self.rules.len()),
                        );
                    }
                    Some(rule) if rule.symbol as usize != i => {
                        return err(
                            at(&format!("rules[{k}]")),
                            format!("rule {r} rewrites symbol {}, not this one", rule.symbol),
                        );
                    }
                    Some(_) if listed[r as usize] => {
                        return err(
                            at(&format!("rules[{k}]")),
                            format!("rule {r} is listed twice"),
                        );
                    }
                    Some(_) => listed[r as usize] = true,
                }
            }
        }
        for (i, shape) in self.shapes.iter().enumerate() {
            let at = |field: &str| format!("shapes[{i}].{field}");
            let Some(symbol) = self.symbols.get(shape.symbol as usize) else {
                return err(at("symbol"), self.no_symbol(shape.symbol));
            };
            if shape.vertices.len() != symbol.vertex_count as usize {
                return err(
                    at("vertices"),
                    format!(
                        "{} positions for a symbol of {} vertices",
                        shape.vertices.len(),
                        symbol.vertex_count
                    ),
                );
            }
            if let Some(k) = shape.vertices.iter().position(|p| !p.is_finite()) {
                return err(at(&format!("vertices[{k}]")), "not a finite point".into());
            }
            // Beyond this, face normals and areas overflow f64 and faces vanish from meshes.
            if let Some(k) = shape
                .vertices
                .iter()
                .position(|p| p.abs().max_element() > MAX_COORDINATE)
            {
                return err(
                    at(&format!("vertices[{k}]")),
                    format!("a coordinate beyond ±{MAX_COORDINATE:e}"),
                );
            }
        }
        for (i, rule) in self.rules.iter().enumerate() {
            self.validate_rule(i, rule, listed[i])?;
        }
        Ok(())
    }

    /// Checks rule `i`; `listed`: whether its symbol lists it.
    fn validate_rule(
        &self,
        i: usize,
        rule: &GrammarRule,
        listed: bool,
    ) -> Result<(), GrammarError> {
        let err = |field: String, message: String| {
            Err(GrammarError {
                location: format!("rules[{i}].{field}"),
                message,
            })
        };
        let Some(symbol) = self.symbols.get(rule.symbol as usize) else {
            return err("symbol".into(), self.no_symbol(rule.symbol));
        };
        if !listed {
            return err(
                "symbol".into(),
                format!("symbol {} does not list this rule", rule.symbol),
            );
        }
        if !(rule.weight.is_finite() && rule.weight > 0.0) {
            return err(
                "weight".into(),
                format!("{} is not a positive number", rule.weight),
            );
        }
        let base = symbol.vertex_count as usize;
        for (k, v) in rule.virtual_vertices.iter().enumerate() {
            let available = base + k;
            for (end, index) in [("from", v.from), ("to", v.to)] {
                if index as usize >= available {
                    return err(
                        format!("virtual_vertices[{k}].{end}"),
                        format!(
                            "vertex {index} does not exist yet ({base} shape vertices and {k} \
                             earlier virtual vertices)"
                        ),
                    );
                }
            }
            // Cuts put new vertices on edges: between their two parents.
            if !(-T_TOLERANCE..=1.0 + T_TOLERANCE).contains(&v.t) {
                return err(
                    format!("virtual_vertices[{k}].t"),
                    format!("{:e} is not between 0 and 1", v.t),
                );
            }
        }
        let total = base + rule.virtual_vertices.len();
        for (k, sub) in rule.sub_shapes.iter().enumerate() {
            let Some(target) = self.symbols.get(sub.symbol as usize) else {
                return err(
                    format!("sub_shapes[{k}].symbol"),
                    self.no_symbol(sub.symbol),
                );
            };
            if sub.vertices.len() != target.vertex_count as usize {
                return err(
                    format!("sub_shapes[{k}].vertices"),
                    format!(
                        "{} vertices for symbol {} of {} vertices",
                        sub.vertices.len(),
                        sub.symbol,
                        target.vertex_count
                    ),
                );
            }
            if let Some(j) = sub.vertices.iter().position(|&v| v as usize >= total) {
                return err(
                    format!("sub_shapes[{k}].vertices[{j}]"),
                    format!(
                        "vertex {} does not exist (the rule has {base} shape and {} virtual \
                         vertices)",
                        sub.vertices[j],
                        rule.virtual_vertices.len()
                    ),
                );
            }
            let faces = target.faces.len();
            for (field, list, bound, what) in [
                (
                    "materials",
                    &sub.materials,
                    self.materials.len(),
                    "material",
                ),
                ("from_faces", &sub.from_faces, symbol.faces.len(), "face"),
            ] {
                if !list.is_empty() && list.len() != faces {
                    return err(
                        format!("sub_shapes[{k}].{field}"),
                        format!(
                            "{} entries for {faces} faces (give one per face, null for none)",
                            list.len()
                        ),
                    );
                }
                if let Some(j) = list
                    .iter()
                    .position(|m| m.is_some_and(|m| m as usize >= bound))
                {
                    return err(
                        format!("sub_shapes[{k}].{field}[{j}]"),
                        format!(
                            "{what} {} does not exist (there are {bound})",
                            list[j].unwrap_or(0)
                        ),
                    );
                }
            }
        }
        self.validate_offset_cuts(rule, base)
            .map_err(|(field, message)| GrammarError {
                location: format!("rules[{i}].{field}"),
                message,
            })
    }

    /// Checks a rule's offset cuts: faces of vertices made before the cut, positive finite
    /// distances, runs of virtual vertices in order that no two cuts share.
    fn validate_offset_cuts(
        &self,
        rule: &GrammarRule,
        base: usize,
    ) -> Result<(), (String, String)> {
        let mut next_free = 0usize;
        for (c, cut) in rule.offset_cuts.iter().enumerate() {
            let at = |field: &str| format!("offset_cuts[{c}].{field}");
            if !(cut.distance.is_finite() && cut.distance > 0.0) {
                return Err((
                    at("distance"),
                    format!("{} is not a positive number of metres", cut.distance),
                ));
            }
            let Some(&first) = cut.vertices.first() else {
                return Err((at("vertices"), "a cut makes at least one vertex".into()));
            };
            let consecutive = cut
                .vertices
                .iter()
                .enumerate()
                .all(|(k, &v)| v as usize == first as usize + k);
            if !consecutive || (first as usize) < next_free {
                return Err((
                    at("vertices"),
                    "the vertices must be consecutive, ascending and after the previous cut's"
                        .into(),
                ));
            }
            next_free = first as usize + cut.vertices.len();
            if next_free > rule.virtual_vertices.len() {
                return Err((
                    at("vertices"),
                    format!(
                        "the rule has {} virtual vertices",
                        rule.virtual_vertices.len()
                    ),
                ));
            }
            let available = base + first as usize;
            if let Some(j) = cut.face.iter().position(|&v| v as usize >= available) {
                return Err((
                    at(&format!("face[{j}]")),
                    format!(
                        "vertex {} does not exist before the cut ({available} do)",
                        cut.face[j]
                    ),
                ));
            }
        }
        Ok(())
    }

    fn no_symbol(&self, symbol: Index) -> String {
        format!(
            "symbol {symbol} does not exist (there are {})",
            self.symbols.len()
        )
    }
}

/// A problem in a grammar: where (a JSON path or line and column) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GrammarError {
    /// Where: `rules[3].sub_shapes[1].vertices[5]`, or `4:12` (line:column) for JSON syntax.
    pub location: String,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for GrammarError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

impl std::error::Error for GrammarError {}
