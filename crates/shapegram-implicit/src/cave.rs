//! The SG+M cave grammar: a base shape grown by classic productions (sum, difference,
//! intersection at a label) and morphic productions (the base blended with itself plus a new
//! shape), and the random cave generator driven by the paper's parameters.

use std::fmt;
use std::str::FromStr;

use glam::DVec3;

use crate::bond::{Bond, Label, matching_bond};
use crate::error::{ImplicitError, Result};
use crate::primitive::Primitive;
use crate::rng::Rng;
use crate::shape::Shape;
use crate::solid::Solid;
use crate::tape::Tape;

/// The labelling direction `L_B`: which open bond of the base the next shape is joined to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// An open bond facing −x.
    NegX,
    /// An open bond facing +x.
    PosX,
    /// An open bond facing −y.
    NegY,
    /// An open bond facing +y.
    PosY,
    /// An open bond facing −z.
    NegZ,
    /// An open bond facing +z.
    PosZ,
    /// Any open bond, chosen by the seed.
    Random,
}

impl Direction {
    /// The unit vector, `None` for [`Direction::Random`].
    pub fn vector(self) -> Option<DVec3> {
        Some(match self {
            Self::NegX => DVec3::NEG_X,
            Self::PosX => DVec3::X,
            Self::NegY => DVec3::NEG_Y,
            Self::PosY => DVec3::Y,
            Self::NegZ => DVec3::NEG_Z,
            Self::PosZ => DVec3::Z,
            Self::Random => return None,
        })
    }
}

impl FromStr for Direction {
    type Err = ImplicitError;

    fn from_str(text: &str) -> Result<Self> {
        Ok(match text.to_ascii_lowercase().as_str() {
            "-x" => Self::NegX,
            "+x" | "x" => Self::PosX,
            "-y" => Self::NegY,
            "+y" | "y" => Self::PosY,
            "-z" => Self::NegZ,
            "+z" | "z" => Self::PosZ,
            "random" => Self::Random,
            _ => {
                return Err(ImplicitError::new(format!(
                    "invalid direction '{}': expected -x, +x, -y, +y, -z, +z or random",
                    text.escape_debug()
                )));
            }
        })
    }
}

impl fmt::Display for Direction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::NegX => "-x",
            Self::PosX => "+x",
            Self::NegY => "-y",
            Self::PosY => "+y",
            Self::NegZ => "-z",
            Self::PosZ => "+z",
            Self::Random => "random",
        })
    }
}

/// What a production does with its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operation {
    /// Classic production, eq. (2).
    Sum,
    /// Classic production, eq. (3).
    Difference,
    /// Classic production, eq. (4).
    Intersection,
    /// Morphic production: `base := morph(base, base ∪ shape, a)`, eq. (5).
    Morph(f64),
}

impl Operation {
    /// The name used in the text form and in reports.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Sum => "sum",
            Self::Difference => "difference",
            Self::Intersection => "intersection",
            Self::Morph(_) => "morph",
        }
    }
}

/// Where a production puts its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Attach {
    /// At an open bond of the base facing this way. Sums and morphs form a label with the shape's
    /// opposite bond (pushed into the base by the overlap); differences and intersections centre
    /// the shape on the bond.
    Bond(Direction),
    /// The shape's centre at the centre of the base's bounds: both are free bonds.
    Centre,
}

/// Where a production's shape ended up.
struct Placement {
    /// The shape, moved.
    shape: Shape,
    /// The bonds that met, for reports.
    label: Option<(Bond, Bond)>,
    /// The label, when bonds were used up (sums and morphs).
    used: Option<Label>,
}

/// One applied production, for reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Applied {
    /// What it did.
    pub operation: Operation,
    /// The label it formed: the base's bond and the shape's bond, after moving the shape.
    pub label: Option<(Bond, Bond)>,
    /// Primitives the shape brought.
    pub elements: usize,
}

/// The base shape of an SG+M derivation and its open bonds.
#[derive(Clone, Debug)]
pub struct CaveBuilder {
    base: Solid,
    open: Vec<Bond>,
    overlap: f64,
    elements: usize,
    applied: Vec<Applied>,
}

impl CaveBuilder {
    /// An empty base. `overlap` (0 to 1) is how far a joined shape reaches into the base, as a
    /// fraction of its own extent along the label: 0 is the paper's exact gluing of the bond
    /// points; a little overlap fuses round shapes that would touch at a single point.
    pub fn new(overlap: f64) -> Result<Self> {
        if !(0.0..=1.0).contains(&overlap) {
            return Err(ImplicitError::new(format!(
                "invalid overlap {overlap}: expected 0 to 1"
            )));
        }
        Ok(Self {
            base: Solid::empty(),
            open: Vec::new(),
            overlap,
            elements: 0,
            applied: Vec::new(),
        })
    }

    /// The base shape.
    pub fn solid(&self) -> &Solid {
        &self.base
    }

    /// The bonds of the base not yet used by a label.
    pub fn open_bonds(&self) -> &[Bond] {
        &self.open
    }

    /// Primitives added so far.
    pub fn elements(&self) -> usize {
        self.elements
    }

    /// The productions applied so far.
    pub fn applied(&self) -> &[Applied] {
        &self.applied
    }

    /// The base as a shape: its solid, its open bonds and a free bond at the centre of its bounds.
    pub fn to_shape(&self) -> Shape {
        let mut bonds = self.open.clone();
        if let Some(b) = self.base.bounds() {
            bonds.insert(0, Bond::new(b.center(), DVec3::ZERO));
        }
        Shape {
            solid: self.base.clone(),
            bonds,
        }
    }

    /// Applies one production: `shape` (with `elements` primitives) joined where `attach` says and
    /// combined with the base by `operation`. `rng` picks among equally good bonds.
    pub fn apply(
        &mut self,
        shape: &Shape,
        elements: usize,
        operation: Operation,
        attach: Attach,
        rng: &mut Rng,
    ) -> Result<()> {
        let placement = self.place(shape, operation, attach, rng)?;
        self.commit(placement, elements, operation)
    }

    /// Combines a placed shape with the base by `operation` and updates the open bonds.
    fn commit(
        &mut self,
        placement: Placement,
        elements: usize,
        operation: Operation,
    ) -> Result<()> {
        let joins = matches!(operation, Operation::Sum | Operation::Morph(_));
        let Placement {
            shape: placed,
            label,
            used,
        } = placement;
        let before = self.base.clone();
        self.base = match operation {
            Operation::Sum => before.union(&placed.solid),
            Operation::Difference => before.difference(&placed.solid),
            Operation::Intersection => before.intersection(&placed.solid),
            // Morphing with nothing would erase the shape (−∞ blends to −∞): place it.
            Operation::Morph(_) if before.is_empty() => placed.solid.clone(),
            Operation::Morph(a) => before.morph(&before.union(&placed.solid), a)?,
        };
        if let Some(label) = used {
            self.open.remove(label.base);
        }
        if joins {
            let skip = used.map(|l| l.shape);
            self.open.extend(
                placed
                    .bonds
                    .iter()
                    .enumerate()
                    .filter(|&(j, b)| Some(j) != skip && !b.is_free())
                    .map(|(_, b)| *b),
            );
        }
        self.snap_bonds(&placed.solid, operation);
        self.elements += elements;
        self.applied.push(Applied {
            operation,
            label,
            elements,
        });
        Ok(())
    }

    /// Carves a notch (a difference) at a random open bond that cannot cut the base in two:
    /// `carver` is centred `lift` times its half-extent outside the bond, along the bond's
    /// direction, and shrunk so that it reaches no more than `depth` times as far behind the bond
    /// as the solid does. A carver centred on the bond at full size could bite through a thin
    /// part and leave pieces floating.
    fn bite(
        &mut self,
        carver: &Shape,
        elements: usize,
        (lift, depth): (f64, f64),
        rng: &mut Rng,
    ) -> Result<()> {
        let i = self
            .pick_open(Direction::Random, rng)
            .ok_or_else(|| ImplicitError::new("the base has no open bond for a difference"))?;
        let b1 = self.open[i];
        let extent = carver
            .solid
            .bounds()
            .map_or(0.0, |b| b.size().dot(b1.dir.abs()));
        let full = Tape::new(&self.base);
        let mut ws = full.workspace(1);
        let tape = full.pruned(&mut ws, b1.point, extent * 1.01);
        // How far the solid reaches behind the bond, in 48 steps up to the carver's extent.
        let steps = 48;
        let thickness = (1..=steps)
            .map(|s| extent * f64::from(s) / f64::from(steps))
            .find(|&t| tape.value(&mut ws, b1.point - b1.dir * t) <= 0.0)
            .unwrap_or(extent);
        let reach = 0.5 * extent * (1.0 - lift);
        let scale = if reach > 0.0 {
            (depth * thickness / reach).min(1.0)
        } else {
            1.0
        };
        let scaled = carver.scale(DVec3::splat(scale))?;
        let target = b1.point + b1.dir * (0.5 * lift * extent * scale);
        let placement = Placement {
            shape: scaled.translate(target - scaled.centre())?,
            label: Some((b1, Bond::new(b1.point, DVec3::ZERO))),
            used: None,
        };
        self.commit(placement, elements, Operation::Difference)
    }

    /// Where a production puts `shape` (see [`Attach`]).
    fn place(
        &self,
        shape: &Shape,
        operation: Operation,
        attach: Attach,
        rng: &mut Rng,
    ) -> Result<Placement> {
        if self.base.is_empty() {
            // The first shape stays where it is: there is nothing to join it to.
            return Ok(Placement {
                shape: shape.clone(),
                label: None,
                used: None,
            });
        }
        let i = match attach {
            Attach::Centre => {
                let target = self.base.bounds().map_or(DVec3::ZERO, |b| b.center());
                let free = Bond::new(target, DVec3::ZERO);
                return Ok(Placement {
                    shape: shape.translate(target - shape.centre())?,
                    label: Some((free, free)),
                    used: None,
                });
            }
            Attach::Bond(direction) => self.pick_open(direction, rng).ok_or_else(|| {
                ImplicitError::new(format!(
                    "the base has no open bond facing {direction} for a {}",
                    operation.name()
                ))
            })?,
        };
        let b1 = self.open[i];
        if !matches!(operation, Operation::Sum | Operation::Morph(_)) {
            // Cutting shapes are centred on the bond (their free centre bond labels with it).
            return Ok(Placement {
                shape: shape.translate(b1.point - shape.centre())?,
                label: Some((b1, Bond::new(b1.point, DVec3::ZERO))),
                used: None,
            });
        }
        let j = matching_bond(&b1, &shape.bonds).ok_or_else(|| {
            ImplicitError::new(format!(
                "the shape has no bond that labels with a bond facing {}",
                Direction::from_vector(b1.dir)
            ))
        })?;
        let extent = shape
            .solid
            .bounds()
            .map_or(0.0, |b| b.size().dot(b1.dir.abs()));
        let offset = b1.point - shape.bonds[j].point - b1.dir * (self.overlap * extent);
        let moved = shape.translate(offset)?;
        Ok(Placement {
            label: Some((b1, moved.bonds[j])),
            shape: moved,
            used: Some(Label { base: i, shape: j }),
        })
    }

    /// Whether some open bond faces `direction` (any directed one for random).
    pub fn has_open(&self, direction: Direction) -> bool {
        self.open.iter().any(|b| faces(b, direction))
    }

    /// Index of an open bond facing `direction`, chosen by `rng` among those at the front: no
    /// more than [`FRONT_DEPTH`] behind the one furthest along the direction, so the cave grows
    /// on along `L_B` (as a tunnel) instead of filling in around old bonds. For random, any
    /// directed open bond.
    fn pick_open(&self, direction: Direction, rng: &mut Rng) -> Option<usize> {
        let facing = (0..self.open.len()).filter(|&i| faces(&self.open[i], direction));
        let candidates: Vec<usize> = match direction.vector() {
            None => facing.collect(),
            Some(v) => {
                let reach = |i: usize| self.open[i].point.dot(v);
                let front = facing.clone().map(reach).fold(f64::NEG_INFINITY, f64::max);
                facing
                    .filter(|&i| reach(i) >= front - FRONT_DEPTH)
                    .collect()
            }
        };
        if candidates.is_empty() {
            return None;
        }
        Some(candidates[rng.index(candidates.len())])
    }

    /// Moves the open bonds that the production left outside the solid (carved away by a
    /// difference or an intersection, or on a shape a morph only half grew) back along their
    /// directions onto the surface, and drops those buried inside it or too far out: a shape
    /// joined there would sit inside rock or in mid-air. Only bonds the new shape touches can
    /// have moved off the surface (inside it for the other operations, outside or on it for an
    /// intersection), so only those are looked at, with the base's tape cut down to the shape's
    /// surroundings where it is local.
    fn snap_bonds(&mut self, shape: &Solid, operation: Operation) {
        let Some(bounds) = self.base.bounds() else {
            self.open.clear();
            return;
        };
        let Some(region) = shape.bounds() else {
            // An empty shape changed nothing (an intersection with it left no bounds above).
            return;
        };
        let shape_tape = Tape::new(shape);
        let mut shape_ws = shape_tape.workspace(1);
        let intersection = operation == Operation::Intersection;
        let eps = bounds.size().max_element() * 1e-9;
        let mut touched = |p: DVec3| {
            let g = shape_tape.value(&mut shape_ws, p);
            if intersection { g < eps } else { g > -eps }
        };
        let full = Tape::new(&self.base);
        let mut ws = full.workspace(1);
        let (tape, reach) = if intersection {
            // An intersection may move the surface anywhere.
            (full, bounds.size().max_element().max(1e-9))
        } else {
            // Touched bonds lie in the shape's bounds: search as far as the shape is long.
            let reach = region.size().max_element().max(1e-9);
            let radius = (region.diagonal() * 0.5 + eps + reach) * 1.01;
            (full.pruned(&mut ws, region.center(), radius), reach)
        };
        let mut field = |p: DVec3| tape.value(&mut ws, p);
        self.open.retain_mut(|bond| {
            if !touched(bond.point) {
                return true;
            }
            match surface_along(&mut field, bond.point, bond.dir, reach) {
                Some(p) => {
                    bond.point = p;
                    true
                }
                None => false,
            }
        });
    }
}

/// How far behind the foremost open bond facing the labelling direction another may be and still
/// be chosen, in units of length (about half a generated primitive).
pub const FRONT_DEPTH: f64 = 1.5;

/// Whether `bond` faces `direction` (any direction but none for random).
fn faces(bond: &Bond, direction: Direction) -> bool {
    match direction.vector() {
        Some(v) => (bond.dir - v).length_squared() < 1e-9,
        None => !bond.is_free(),
    }
}

/// Where the line from `p` inward (along `−dir`) first meets the surface, up to `reach` away;
/// `p` itself when it is on the surface, `None` when it is inside the solid (buried) or the line
/// misses. Found by stepping, then bisection.
fn surface_along(
    field: &mut impl FnMut(DVec3) -> f64,
    p: DVec3,
    dir: DVec3,
    reach: f64,
) -> Option<DVec3> {
    let here = field(p);
    if here.abs() <= reach * 1e-12 {
        // Bonds of untouched primitives lie exactly on the surface.
        return Some(p);
    }
    if here > 0.0 {
        return None;
    }
    let steps = 32;
    let step = reach / f64::from(steps);
    let mut near = 0.0;
    for s in 1..=steps {
        let far = f64::from(s) * step;
        if field(p - dir * far) > 0.0 {
            let (mut lo, mut hi) = (near, far);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if field(p - dir * mid) > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(p - dir * hi);
        }
        near = far;
    }
    None
}

impl Direction {
    /// The axis direction nearest to `v`, for messages.
    fn from_vector(v: DVec3) -> Self {
        let a = v.abs();
        if a.x >= a.y && a.x >= a.z {
            if v.x < 0.0 { Self::NegX } else { Self::PosX }
        } else if a.y >= a.z {
            if v.y < 0.0 { Self::NegY } else { Self::PosY }
        } else if v.z < 0.0 {
            Self::NegZ
        } else {
            Self::PosZ
        }
    }
}

/// The parameters of the SG+M cave generator (Section 3 of the paper).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaveParams {
    /// Level of detail `L_D`, 1 to 32: the grid has `L_D` cells per unit of length.
    pub lod: u32,
    /// Classic productions `P_C`.
    pub classic: u32,
    /// Morphic productions `P_M`.
    pub morphic: u32,
    /// Labelling direction `L_B`.
    pub direction: Direction,
    /// Morphing parameter `M_P` in percent, 0 to 100.
    pub morph_percent: f64,
    /// Productions per shape `P_S`, 0 to 10: how many sub-productions assemble each shape.
    pub per_shape: u32,
    /// Seed of the random choices.
    pub seed: u64,
}

impl Default for CaveParams {
    /// The paper's experiment: `L_D = 10, P_C = 10, P_M = 2, L_B = +X, M_P = 52 %, P_S = 3`.
    fn default() -> Self {
        Self {
            lod: 10,
            classic: 10,
            morphic: 2,
            direction: Direction::PosX,
            morph_percent: 52.0,
            per_shape: 3,
            seed: 1,
        }
    }
}

/// Most productions a generated cave may have (`P_C + P_M`).
pub const MAX_PRODUCTIONS: u32 = 1000;
/// How far joined shapes reach into the base in generated caves (see [`CaveBuilder::new`]).
pub const GENERATED_OVERLAP: f64 = 0.25;

impl CaveParams {
    /// Checks every parameter's range.
    pub fn validate(&self) -> Result<()> {
        if !(1..=32).contains(&self.lod) {
            return Err(ImplicitError::new(format!(
                "invalid level of detail {}: expected 1 to 32",
                self.lod
            )));
        }
        if !(0.0..=100.0).contains(&self.morph_percent) {
            return Err(ImplicitError::new(format!(
                "invalid morphing parameter {}%: expected 0 to 100",
                self.morph_percent
            )));
        }
        if self.per_shape > 10 {
            return Err(ImplicitError::new(format!(
                "invalid productions per shape {}: expected 0 to 10",
                self.per_shape
            )));
        }
        let total = u64::from(self.classic) + u64::from(self.morphic);
        if total == 0 || total > u64::from(MAX_PRODUCTIONS) {
            return Err(ImplicitError::new(format!(
                "invalid number of productions {total} (classic + morphic): expected 1 to \
                 {MAX_PRODUCTIONS}"
            )));
        }
        Ok(())
    }

    /// The grid's cell edge `C_E = 1 / L_D`.
    pub fn cell_size(&self) -> f64 {
        1.0 / f64::from(self.lod)
    }

    /// Whether production `i` (0-based) of `P_T = P_C + P_M` is morphic: the morphic ones are
    /// spread evenly, the last production being morphic whenever there is one.
    pub fn is_morphic(&self, i: u32) -> bool {
        let (m, t) = (
            u64::from(self.morphic),
            u64::from(self.classic + self.morphic),
        );
        let i = u64::from(i);
        (i + 1) * m / t > i * m / t
    }
}

/// A generated cave: the final solid and the derivation that built it.
#[derive(Clone, Debug)]
pub struct Cave {
    /// The base shape after the last production.
    pub builder: CaveBuilder,
    /// The parameters it was generated with.
    pub params: CaveParams,
}

impl Cave {
    /// The cave's solid.
    pub fn solid(&self) -> &Solid {
        self.builder.solid()
    }
}

/// Generates a cave: `P_C + P_M` productions, each joining a shape assembled from one primitive
/// and `P_S` sub-productions, on an empty base (see [`grow`]). The same parameters always give
/// the same cave.
pub fn generate(params: &CaveParams) -> Result<Cave> {
    params.validate()?;
    let mut rng = Rng::new(params.seed);
    let mut builder = CaveBuilder::new(GENERATED_OVERLAP)?;
    grow(&mut builder, params, &mut rng)?;
    Ok(Cave {
        builder,
        params: *params,
    })
}

/// The classic productions of the generator in percent: sums, differences (notches), and
/// intersections.
const CLASSIC_MIX: [u32; 3] = [50, 40, 10];
/// The sub-productions that assemble a shape in percent: sums, notches and trims.
const SUB_MIX: [u32; 3] = [45, 45, 10];
/// The primitives a production's shape starts from: box, cylinder, cone, pyramid and torus (the
/// indices of [`random_primitive`]). Balls and capsules only come as smaller pieces and notches:
/// as whole chambers their round sides, bent on every edge of coarse grids, would push the
/// convexity factor above the paper's range at `L_D` up to 10.
const MAIN_KINDS: [usize; 5] = [1, 2, 3, 4, 5];
/// Every primitive kind, for the pieces and notches of a shape.
const ALL_KINDS: [usize; 7] = [0, 1, 2, 3, 4, 5, 6];
/// A classic notch: an ellipsoid with semi-axes this fraction of the production's shape's
/// bounds (round, so the hollow it leaves is concave all over)…
const NOTCH_COVER: f64 = 0.45;
/// …centred 0.4 of its semi-axis outside the bond and reaching at most half as deep as the rock
/// behind it (see [`CaveBuilder::bite`]).
const NOTCH_BITE: (f64, f64) = (0.4, 0.5);
/// A shape's notches: primitives this fraction of the size of the one the shape starts from…
const SUB_NOTCH_SCALE: f64 = 0.48;
/// …centred on the bond and reaching at most half as deep as the shape behind it.
const SUB_NOTCH_BITE: (f64, f64) = (0.0, 0.5);

/// Applies `P_C + P_M` random productions to `builder`. Classic productions are sums at an open
/// bond facing `L_B` (half of them), notches carved by an ellipsoid at a random open bond (4 in
/// 10) or intersections with an ellipsoid fitted over the base (1 in 10), dealt in these numbers
/// and shuffled; morphic productions join a shape like a sum and blend it in by `M_P`.
/// `params.lod` and `params.seed` are not used here.
pub fn grow(builder: &mut CaveBuilder, params: &CaveParams, rng: &mut Rng) -> Result<()> {
    params.validate()?;
    let a = params.morph_percent / 100.0;
    let total = params.classic + params.morphic;
    let mut decks = Decks {
        classic: Deck::new(&apportion(params.classic, &CLASSIC_MIX)),
        sub: Deck::new(&apportion(total * params.per_shape, &SUB_MIX)),
        main: Deck::of(&MAIN_KINDS),
        piece: Deck::of(&ALL_KINDS),
        notch: Deck::of(&ALL_KINDS),
    };
    for i in 0..total {
        let (shape, elements) = assemble(rng, params.per_shape, &mut decks)?;
        let (operation, attach, shape) = if params.is_morphic(i) {
            (Operation::Morph(a), Attach::Bond(params.direction), shape)
        } else if builder.solid().is_empty() {
            // The first shape is always summed: use up a sum, so the mix stays as dealt.
            decks.classic.take(0);
            (Operation::Sum, Attach::Bond(params.direction), shape)
        } else {
            match decks.classic.draw(rng) {
                0 => (Operation::Sum, Attach::Bond(params.direction), shape),
                1 => {
                    let size = shape.solid.bounds().map_or(DVec3::ONE, |b| b.size());
                    let carver = Shape::primitive(Primitive::Sphere { radius: 1.0 })?
                        .scale(size * NOTCH_COVER)?
                        .translate(shape.centre())?;
                    (
                        Operation::Difference,
                        Attach::Bond(Direction::Random),
                        carver,
                    )
                }
                _ => {
                    let trim = fitted_ellipsoid(builder.solid(), 1.2)?;
                    (Operation::Intersection, Attach::Centre, trim)
                }
            }
        };
        let stuck = match attach {
            Attach::Bond(d) => !builder.has_open(d) && !builder.solid().is_empty(),
            Attach::Centre => false,
        };
        if stuck && builder.open_bonds().is_empty() {
            continue;
        }
        if operation == Operation::Difference {
            builder.bite(&shape, elements, NOTCH_BITE, rng)?;
        } else if stuck {
            // No open bond faces L_B any more (carved or trimmed away): grow from any open bond.
            builder.apply(
                &shape,
                elements,
                operation,
                Attach::Bond(Direction::Random),
                rng,
            )?;
        } else {
            builder.apply(&shape, elements, operation, attach, rng)?;
        }
    }
    Ok(())
}

/// The draws of one run of the generator.
struct Decks {
    /// Classic productions: indices into [`CLASSIC_MIX`].
    classic: Deck,
    /// Sub-productions: indices into [`SUB_MIX`].
    sub: Deck,
    /// Primitive kinds of the shapes.
    main: Deck,
    /// Primitive kinds of the pieces summed to them.
    piece: Deck,
    /// Primitive kinds of their notches.
    notch: Deck,
}

/// Choices dealt from a shuffled round that holds each as often as its share says, dealt again
/// when it runs out. Drawn independently at 4 in 10, ten classic productions would now and then
/// carve no notch or seven, and the convexity factor would swing with them; dealt, every cave
/// gets the intended mix.
struct Deck {
    round: Vec<usize>,
    left: Vec<usize>,
}

impl Deck {
    /// A deck whose round holds choice `i` `counts[i]` times.
    fn new(counts: &[usize]) -> Self {
        let round = counts
            .iter()
            .enumerate()
            .flat_map(|(i, &n)| std::iter::repeat_n(i, n))
            .collect();
        Self {
            round,
            left: Vec::new(),
        }
    }

    /// A deck whose round holds each of `choices` once.
    fn of(choices: &[usize]) -> Self {
        Self {
            round: choices.to_vec(),
            left: Vec::new(),
        }
    }

    /// The next choice (the round must not be empty).
    fn draw(&mut self, rng: &mut Rng) -> usize {
        self.refill();
        let i = rng.index(self.left.len());
        self.left.swap_remove(i)
    }

    /// Removes one `choice` from the round, if it still holds one.
    fn take(&mut self, choice: usize) {
        self.refill();
        if let Some(i) = self.left.iter().position(|&c| c == choice) {
            self.left.swap_remove(i);
        }
    }

    /// Deals a new round when the last one is used up.
    fn refill(&mut self) {
        if self.left.is_empty() {
            self.left.clone_from(&self.round);
        }
    }
}

/// `total` split in the proportions `percent` (which sum to 100) by largest remainders, ties to
/// the earlier share.
fn apportion(total: u32, percent: &[u32]) -> Vec<usize> {
    let total = u64::from(total);
    let mut counts: Vec<usize> = percent
        .iter()
        .map(|&p| (total * u64::from(p) / 100) as usize)
        .collect();
    let given: usize = counts.iter().sum();
    let mut order: Vec<usize> = (0..percent.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(total * u64::from(percent[i]) % 100));
    for &i in order.iter().take(total as usize - given) {
        counts[i] += 1;
    }
    counts
}

/// A shape of one random primitive grown by `per_shape` random sub-productions (notches carved
/// at its open bonds, sums at them, a trim by a fitted ellipsoid); returns it and its primitive
/// count. The notches come first: carved after the sums, they could cut a piece off.
fn assemble(rng: &mut Rng, per_shape: u32, decks: &mut Decks) -> Result<(Shape, usize)> {
    let mut part = CaveBuilder::new(GENERATED_OVERLAP)?;
    let kind = decks.main.draw(rng);
    let first = random_primitive(rng, 1.0, kind)?;
    part.apply(&first, 1, Operation::Sum, Attach::Centre, rng)?;
    let mut picks: Vec<usize> = (0..per_shape).map(|_| decks.sub.draw(rng)).collect();
    picks.sort_by_key(|&p| [1, 0, 2][p]);
    for pick in picks {
        if pick == 2 {
            let trim = fitted_ellipsoid(part.solid(), 1.3)?;
            part.apply(&trim, 1, Operation::Intersection, Attach::Centre, rng)?;
            continue;
        }
        if part.open_bonds().is_empty() {
            continue;
        }
        if pick == 0 {
            let kind = decks.piece.draw(rng);
            let piece = random_primitive(rng, 0.6, kind)?;
            let attach = Attach::Bond(Direction::Random);
            part.apply(&piece, 1, Operation::Sum, attach, rng)?;
        } else {
            let kind = decks.notch.draw(rng);
            let notch = random_primitive(rng, SUB_NOTCH_SCALE, kind)?;
            part.bite(&notch, 1, SUB_NOTCH_BITE, rng)?;
        }
    }
    Ok((part.to_shape(), part.elements()))
}

/// A random primitive of kind `kind` (0 to 6: sphere, box, cylinder, cone, pyramid, torus,
/// capsule) about `scale` × 2 units across, turned a random number of quarter turns (so its
/// bonds stay axis-aligned).
fn random_primitive(rng: &mut Rng, scale: f64, kind: usize) -> Result<Shape> {
    let mut size = |lo: f64, hi: f64| rng.range(lo, hi) * scale;
    let primitive = match kind {
        0 => Primitive::Sphere {
            radius: size(0.9, 1.5),
        },
        1 => Primitive::Cuboid {
            size: DVec3::new(size(1.6, 3.0), size(1.6, 3.0), size(1.6, 3.0)),
        },
        2 => Primitive::Cylinder {
            radius: size(0.8, 1.3),
            height: size(1.6, 3.0),
        },
        3 => Primitive::Cone {
            radius: size(1.0, 1.6),
            height: size(2.0, 3.0),
        },
        4 => Primitive::Pyramid {
            size: DVec3::new(size(1.8, 3.0), size(1.8, 3.0), size(1.8, 3.0)),
        },
        5 => {
            let major = size(1.0, 1.5);
            Primitive::Torus {
                major,
                minor: major * size(0.45, 0.65) / scale,
            }
        }
        _ => Primitive::Capsule {
            radius: size(0.7, 1.1),
            length: size(0.5, 2.0),
        },
    };
    let turns = rng.index(4) as f64 * 90.0;
    let axis = [DVec3::X, DVec3::Y, DVec3::Z][rng.index(3)];
    Shape::primitive(primitive)?.rotate(axis, turns)
}

/// An ellipsoid centred on the base's bounds whose semi-axes are `cover` times the bounds' half
/// diagonal projected on each axis: with `cover` of 1 it passes through the bounds' corners, with
/// more (as the generator uses) it holds the whole base and trims only what lies beyond.
fn fitted_ellipsoid(base: &Solid, cover: f64) -> Result<Shape> {
    let size = base
        .bounds()
        .map_or(DVec3::ONE, |b| b.size())
        .max(DVec3::splat(1e-3));
    let radii = size * 0.5 * cover * 3f64.sqrt();
    Shape::primitive(Primitive::Sphere { radius: 1.0 })?.scale(radii)
}
