//! The interpreter (thesis 3.2.1–3.2.2): a grammar state rewritten one generation at a time.
//!
//! Every non-terminal shape of a generation is rewritten in parallel (L-system style): one of its
//! symbol's rules is chosen with the shape's own random stream, the rule's virtual vertices are
//! built from the shape's vertices, and the sub-shapes are cut out of that vertex array. Terminal
//! sub-shapes (symbols without rules) go to the terminal list and stay; the others make up the
//! next generation.

use std::fmt;

use shapegram_geom::DVec3;

use crate::grammar::{Grammar, GrammarRule};
use crate::polyhedron::Index;
use crate::rng::{child_seed, mix, unit};

/// Seeds are 48-bit numbers, as in the thesis's plugin; higher bits are dropped.
pub const SEED_MASK: u64 = (1 << 48) - 1;
/// How close to an end of its edge an offset cut's vertex may fall: nearer, the cut would leave
/// a part without volume.
const OFFSET_T_MARGIN: f64 = 1e-9;
/// The default limit on live shapes (terminal plus non-terminal).
pub const DEFAULT_MAX_SHAPES: usize = 1_000_000;
/// The default limit on the vertex positions all live shapes hold together (about 800 MB), so
/// that a few shapes of huge symbols cannot exhaust memory either.
pub const DEFAULT_MAX_VERTICES: usize = 1 << 25;

/// Shapes stored back to back: a symbol, a seed, a run of positions and (when the grammar has
/// materials) a run of face materials each.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeList {
    symbols: Vec<Index>,
    seeds: Vec<u64>,
    /// Shape `i` has `positions[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    positions: Vec<DVec3>,
    /// Shape `i` has `materials[material_starts[i]..material_starts[i + 1]]`.
    material_starts: Vec<usize>,
    materials: Vec<Option<Index>>,
}

impl ShapeList {
    /// Number of shapes.
    pub fn len(&self) -> usize {
        self.symbols.len()
    }

    /// Whether there is no shape.
    pub fn is_empty(&self) -> bool {
        self.symbols.is_empty()
    }

    /// The symbol of shape `i`.
    pub fn symbol(&self, i: usize) -> Index {
        self.symbols[i]
    }

    /// The random seed of shape `i`.
    pub fn seed(&self, i: usize) -> u64 {
        self.seeds[i]
    }

    /// The vertex positions of shape `i`, in its symbol's canonical order.
    pub fn vertices(&self, i: usize) -> &[DVec3] {
        let end = self
            .starts
            .get(i + 1)
            .copied()
            .unwrap_or(self.positions.len());
        &self.positions[self.starts[i]..end]
    }

    /// The material of each face of shape `i` (in its symbol's face order, indices into
    /// [`Grammar::materials`]); empty when the grammar has no materials.
    pub fn face_materials(&self, i: usize) -> &[Option<Index>] {
        let end = self
            .material_starts
            .get(i + 1)
            .copied()
            .unwrap_or(self.materials.len());
        &self.materials[self.material_starts[i]..end]
    }

    /// Total number of vertices over all shapes.
    pub fn vertex_total(&self) -> usize {
        self.positions.len()
    }

    fn push(
        &mut self,
        symbol: Index,
        seed: u64,
        positions: impl IntoIterator<Item = DVec3>,
        materials: impl IntoIterator<Item = Option<Index>>,
    ) {
        self.symbols.push(symbol);
        self.seeds.push(seed);
        self.starts.push(self.positions.len());
        self.positions.extend(positions);
        self.material_starts.push(self.materials.len());
        self.materials.extend(materials);
    }

    fn clear(&mut self) {
        self.truncate(0, 0, 0);
    }

    /// Keeps the first `shapes` shapes, which hold `positions` positions and `materials` face
    /// materials.
    fn truncate(&mut self, shapes: usize, positions: usize, materials: usize) {
        self.symbols.truncate(shapes);
        self.seeds.truncate(shapes);
        self.starts.truncate(shapes);
        self.positions.truncate(positions);
        self.material_starts.truncate(shapes);
        self.materials.truncate(materials);
    }
}

/// Why generation stopped or could not start.
#[derive(Clone, Debug, PartialEq)]
pub enum GenerateError {
    /// The initial symbol is not in the grammar.
    UnknownSymbol {
        /// The name asked for.
        name: String,
        /// The named symbols there are.
        available: Vec<String>,
    },
    /// The initial shape has the wrong number of vertices, or a non-finite one.
    BadInitialShape(String),
    /// The next generation would hold more vertex positions than allowed.
    TooManyVertices {
        /// The limit.
        limit: usize,
        /// The generation that would have exceeded it.
        generation: u32,
    },
    /// The next generation would hold more shapes than allowed: usually a symbol whose rules
    /// keep producing itself.
    TooManyShapes {
        /// The limit.
        limit: usize,
        /// The generation that would have exceeded it (1 is the first rewrite).
        generation: u32,
        /// The non-terminal symbol with the most shapes in that generation.
        symbol: String,
    },
    /// A cut at a fixed distance from a face lies past the far side of the shape it cuts (or
    /// on it, leaving no volume): the shape is smaller than the rule was drawn for.
    OffsetPastShape {
        /// The rule's name.
        rule: String,
        /// The symbol it rewrites.
        symbol: String,
        /// The cut's number among the rule's cuts.
        step: u32,
        /// The distance from the face, in metres.
        distance: f64,
        /// How deep the shape is from the face along the edge the cut missed, in metres.
        depth: f64,
        /// The generation that failed.
        generation: u32,
    },
}

/// `x` metres to the millimetre, without trailing zeros.
fn metres(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0 + 0.0
}

impl fmt::Display for GenerateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownSymbol { name, available } => write!(
                f,
                "the grammar has no symbol '{}' (symbols: {})",
                name.escape_debug(),
                available.join(", ")
            ),
            Self::BadInitialShape(reason) => write!(f, "bad initial shape: {reason}"),
            Self::TooManyVertices { limit, generation } => write!(
                f,
                "generation {generation} would hold more than {limit} vertices (use fewer \
                 generations or a higher vertex limit)"
            ),
            Self::TooManyShapes {
                limit,
                generation,
                symbol,
            } => write!(
                f,
                "generation {generation} would make more than {limit} shapes, most of them \
                 '{symbol}' (symbols that keep producing themselves never stop: use fewer \
                 generations or a higher shape limit)"
            ),
            Self::OffsetPastShape {
                rule,
                symbol,
                step,
                distance,
                depth,
                generation,
            } => write!(
                f,
                "rule '{}' of symbol '{}', cut {step}: a cut {} m inside its face leaves no \
                 volume beyond it, the shape being {} m deep there (generation {generation})",
                rule.escape_debug(),
                symbol.escape_debug(),
                metres(*distance),
                metres(*depth)
            ),
        }
    }
}

impl std::error::Error for GenerateError {}

/// A grammar's state: the settings of a run and its terminal and non-terminal shapes.
#[derive(Clone, Debug)]
pub struct GrammarState<'g> {
    grammar: &'g Grammar,
    seed: u64,
    /// How many generations [`GrammarState::generate_all`] runs.
    pub generations: u32,
    /// Most live shapes allowed; exceeding it is [`GenerateError::TooManyShapes`].
    pub max_shapes: usize,
    /// Most vertex positions all live shapes may hold; exceeding it is
    /// [`GenerateError::TooManyVertices`].
    pub max_vertices: usize,
    initial_symbol: Index,
    initial_shape: Vec<DVec3>,
    generation: u32,
    terminals: ShapeList,
    non_terminals: ShapeList,
    next: ShapeList,
    scratch: Vec<DVec3>,
}

impl<'g> GrammarState<'g> {
    /// A state starting from the prototype shape of the symbol called `symbol`, with seed 0 and
    /// one generation; call [`GrammarState::start`] or [`GrammarState::generate_all`] next.
    pub fn new(grammar: &'g Grammar, symbol: &str) -> Result<Self, GenerateError> {
        let unknown = || GenerateError::UnknownSymbol {
            name: symbol.to_owned(),
            available: grammar
                .symbol_names()
                .into_iter()
                .map(str::to_owned)
                .collect(),
        };
        let index = grammar.symbol_named(symbol).ok_or_else(unknown)?;
        let shape = grammar.shape_of(index).ok_or_else(|| {
            GenerateError::BadInitialShape(format!(
                "the grammar has no prototype shape for symbol '{}'",
                symbol.escape_debug()
            ))
        })?;
        Ok(Self {
            grammar,
            seed: 0,
            generations: 1,
            max_shapes: DEFAULT_MAX_SHAPES,
            max_vertices: DEFAULT_MAX_VERTICES,
            initial_symbol: index,
            initial_shape: shape.vertices.clone(),
            generation: 0,
            terminals: ShapeList::default(),
            non_terminals: ShapeList::default(),
            next: ShapeList::default(),
            scratch: Vec::new(),
        })
    }

    /// Starts from another instance of the initial symbol: `vertices` in its canonical order,
    /// for example the prototype scaled, sheared or moved. Rules interpolate between vertices,
    /// so any affine image of the prototype gives the same image of the result, except that
    /// offset cuts keep their distances in metres; other deformations give what interpolation
    /// gives (faces may bend).
    pub fn with_initial_shape(mut self, vertices: Vec<DVec3>) -> Result<Self, GenerateError> {
        let expected = self.grammar.symbols[self.initial_symbol as usize].vertex_count as usize;
        if vertices.len() != expected {
            return Err(GenerateError::BadInitialShape(format!(
                "{} vertices for a symbol of {expected}",
                vertices.len()
            )));
        }
        if vertices.iter().any(|p| !p.is_finite()) {
            return Err(GenerateError::BadInitialShape(
                "a vertex is not a finite point".into(),
            ));
        }
        self.initial_shape = vertices;
        Ok(self)
    }

    /// The same state with another seed (only its low 48 bits count).
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed & SEED_MASK;
        self
    }

    /// The same state running `generations` generations in [`GrammarState::generate_all`].
    pub fn with_generations(mut self, generations: u32) -> Self {
        self.generations = generations;
        self
    }

    /// The grammar.
    pub fn grammar(&self) -> &'g Grammar {
        self.grammar
    }

    /// The 48-bit seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The initial symbol.
    pub fn initial_symbol(&self) -> Index {
        self.initial_symbol
    }

    /// How many generations have been run since [`GrammarState::start`].
    pub fn generation(&self) -> u32 {
        self.generation
    }

    /// Shapes that will never be rewritten.
    pub fn terminals(&self) -> &ShapeList {
        &self.terminals
    }

    /// Shapes the next generation rewrites.
    pub fn non_terminals(&self) -> &ShapeList {
        &self.non_terminals
    }

    /// Resets the state to the initial shape alone.
    pub fn start(&mut self) {
        self.terminals.clear();
        self.non_terminals.clear();
        self.generation = 0;
        let list = if self.grammar.is_terminal(self.initial_symbol) {
            &mut self.terminals
        } else {
            &mut self.non_terminals
        };
        let faces = if self.grammar.materials.is_empty() {
            0
        } else {
            self.grammar.symbols[self.initial_symbol as usize]
                .faces
                .len()
        };
        list.push(
            self.initial_symbol,
            mix(self.seed),
            self.initial_shape.iter().copied(),
            std::iter::repeat_n(None, faces),
        );
    }

    /// Rewrites every non-terminal shape once. Nothing changes when there is none; on an error
    /// the state is left as it was.
    pub fn next_generation(&mut self) -> Result<(), GenerateError> {
        if self.non_terminals.is_empty() {
            return Ok(());
        }
        self.next.clear();
        let before = (
            self.terminals.len(),
            self.terminals.positions.len(),
            self.terminals.materials.len(),
        );
        let has_materials = !self.grammar.materials.is_empty();
        for i in 0..self.non_terminals.len() {
            let symbol = self.non_terminals.symbol(i);
            let seed = self.non_terminals.seed(i);
            let rule = self.choose_rule(symbol, seed);
            self.scratch.clear();
            self.scratch
                .extend_from_slice(self.non_terminals.vertices(i));
            if let Err(mut error) = build_virtual_vertices(rule, &mut self.scratch) {
                if let GenerateError::OffsetPastShape {
                    symbol, generation, ..
                } = &mut error
                {
                    *symbol = self.grammar.display_name(rule.symbol).to_owned();
                    *generation = self.generation + 1;
                }
                self.terminals.truncate(before.0, before.1, before.2);
                return Err(error);
            }
            let parent_materials = self.non_terminals.face_materials(i);
            for (ordinal, sub) in rule.sub_shapes.iter().enumerate() {
                let list = if self.grammar.is_terminal(sub.symbol) {
                    &mut self.terminals
                } else {
                    &mut self.next
                };
                let scratch = &self.scratch;
                let faces = if has_materials {
                    self.grammar.symbols[sub.symbol as usize].faces.len()
                } else {
                    0
                };
                list.push(
                    sub.symbol,
                    child_seed(seed, ordinal as u32),
                    sub.vertices.iter().map(|&v| scratch[v as usize]),
                    (0..faces).map(|j| {
                        let inherited = sub.from_faces.get(j).copied().flatten();
                        let inherited =
                            inherited.and_then(|f| parent_materials.get(f as usize).copied()?);
                        sub.materials.get(j).copied().flatten().or(inherited)
                    }),
                );
            }
            if self.terminals.positions.len() + self.next.positions.len() > self.max_vertices {
                self.terminals.truncate(before.0, before.1, before.2);
                return Err(GenerateError::TooManyVertices {
                    limit: self.max_vertices,
                    generation: self.generation + 1,
                });
            }
            if self.terminals.len() + self.next.len() > self.max_shapes {
                let error = GenerateError::TooManyShapes {
                    limit: self.max_shapes,
                    generation: self.generation + 1,
                    symbol: self.most_common(&self.next).to_owned(),
                };
                self.terminals.truncate(before.0, before.1, before.2);
                return Err(error);
            }
        }
        std::mem::swap(&mut self.non_terminals, &mut self.next);
        self.generation += 1;
        Ok(())
    }

    /// Starts over and runs [`GrammarState::generations`] generations (fewer when no
    /// non-terminal shape is left).
    pub fn generate_all(&mut self) -> Result<(), GenerateError> {
        self.start();
        for _ in 0..self.generations {
            if self.non_terminals.is_empty() {
                break;
            }
            self.next_generation()?;
        }
        Ok(())
    }

    fn choose_rule(&self, symbol: Index, seed: u64) -> &'g GrammarRule {
        let grammar = self.grammar;
        let rules = &grammar.symbols[symbol as usize].rules;
        if let [only] = rules.as_slice() {
            return &grammar.rules[*only as usize];
        }
        let total: f64 = rules
            .iter()
            .map(|&r| grammar.rules[r as usize].weight)
            .sum();
        let mut pick = unit(seed) * total;
        for &r in rules {
            let rule = &grammar.rules[r as usize];
            if pick < rule.weight {
                return rule;
            }
            pick -= rule.weight;
        }
        // Rounding can leave `pick` just above the last weight.
        &grammar.rules[rules[rules.len() - 1] as usize]
    }

    fn most_common(&self, list: &ShapeList) -> &str {
        let mut counts = vec![0usize; self.grammar.symbols.len()];
        for &s in &list.symbols {
            counts[s as usize] += 1;
        }
        let best = (0..counts.len())
            .max_by_key(|&s| (counts[s], std::cmp::Reverse(s)))
            .unwrap_or(0);
        self.grammar.display_name(best as Index)
    }
}

/// Appends `rule`'s virtual vertices to `vertices` (the rewritten shape's, in canonical order):
/// interpolated at the rule's fractions, or, for the vertices of an offset cut, where their
/// edges cross the plane the cut's distance inside its face. An offset cut that misses an edge
/// is [`GenerateError::OffsetPastShape`], with the symbol and generation left for the caller.
fn build_virtual_vertices(
    rule: &GrammarRule,
    vertices: &mut Vec<DVec3>,
) -> Result<(), GenerateError> {
    let mut offsets = rule.offset_cuts.iter().peekable();
    // The current offset cut's plane: a point on the face and the inward unit normal.
    let mut plane = (DVec3::ZERO, DVec3::ZERO);
    for (k, v) in rule.virtual_vertices.iter().enumerate() {
        let (a, b) = (vertices[v.from as usize], vertices[v.to as usize]);
        let t = match offsets.peek() {
            Some(cut) if k >= cut.vertices[0] as usize => {
                if k == cut.vertices[0] as usize {
                    let [p, q, r] = cut.face.map(|i| vertices[i as usize]);
                    plane = (p, (r - p).cross(q - p).normalize());
                }
                let (da, db) = (plane.1.dot(a - plane.0), plane.1.dot(b - plane.0));
                let t = (cut.distance - da) / (db - da);
                if !(t > OFFSET_T_MARGIN && t < 1.0 - OFFSET_T_MARGIN) {
                    return Err(GenerateError::OffsetPastShape {
                        rule: rule.name.clone(),
                        symbol: String::new(),
                        step: cut.step,
                        distance: cut.distance,
                        depth: da.max(db),
                        generation: 0,
                    });
                }
                if k + 1 == cut.vertices[0] as usize + cut.vertices.len() {
                    offsets.next();
                }
                t
            }
            _ => v.t,
        };
        vertices.push(a + (b - a) * t);
    }
    Ok(())
}
