//! The derivation engine: rewriting shapes with rules until only leaves are left.
//!
//! [`derive`](derive()) (`derive.rs`) derives the lots, in batches and phases; `machine.rs` is
//! the engine of one lot (its work queue, rules, statements and limits); the operations are
//! applied here.

mod derive;
mod machine;

use std::rc::Rc;
use std::sync::Arc;
use std::time::Duration;

use rustc_hash::FxHashMap;
use shapegram_geom::{
    Color, DAffine3, DMat3, DVec3, FaceClass, Mesh, Model, Part as ModelPart, Pivot, Scope,
    component,
    extrude::{extrude_along, extrude_polygon},
    mesh::newell,
    primitives,
    split::split_slabs,
};
use shapegram_implicit::Solid;
use shapegram_syntax::Span;

use crate::context::{Occluder, snap_planes};
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::ops::{
    CompEntry, CompKind, CompSelector, CsgKind, Depths, EdgeChoice, FaceChoice, ImplicitKind,
    OffsetKeep, Op, Primitive, RoofKind, SetTarget,
};
use crate::program::{CExpr, CKind, CStmt};
use crate::rng::child_seed;
use crate::shape::{
    Csg, FaceTag, Geometry, Implicit, State, box_mesh, fills_box, flat_axis, moved,
};
use crate::split::Layout;
use crate::value::Value;

pub use derive::derive;
use machine::{Engine, Phase, Work};

/// Loads the assets that `i("path")` inserts (built-in assets are handled by the engine) and
/// the implicit grammars that `implicit("path")` runs.
pub trait AssetLoader: Send + Sync {
    /// The mesh stored at `path`, or a one-line reason why it cannot be had.
    fn load(&self, path: &str) -> Result<Arc<Mesh>, String>;

    /// What `i("path")` inserts in a shape that asks for variant `variant` (below
    /// [`ASSET_VARIANTS`]) of assets grown from a seed, such as stochastic L-systems; fixed
    /// files ignore it. By default [`load`](Self::load)'s mesh, stretched to the scope.
    fn asset(&self, path: &str, _variant: u32) -> Result<Asset, String> {
        Ok(Asset {
            mesh: self.load(path)?,
            proportional: false,
        })
    }

    /// The implicit solid that the grammar at `path` makes, or a one-line reason why it cannot
    /// be had.
    fn solid(&self, path: &str) -> Result<Solid, String> {
        Err(format!("cannot read `{path}` as an implicit grammar here"))
    }
}

/// How many variants of a seeded asset (see [`AssetLoader::asset`]) the shapes of a derivation
/// choose among, each by its own random stream: enough for a varied park, few enough that a
/// city of trees grows each variant once.
pub const ASSET_VARIANTS: u32 = 8;

/// An asset for `i()` and how it is placed.
#[derive(Clone, Debug)]
pub struct Asset {
    /// The geometry, in the asset's own coordinates.
    pub mesh: Arc<Mesh>,
    /// Scaled uniformly to fit inside the scope, centred in x and z and standing on the scope's
    /// floor (a planted tree keeps its shape), instead of stretched to the scope as CGA's `i()`.
    pub proportional: bool,
}

/// How to derive.
#[derive(Clone)]
pub struct DeriveOptions {
    /// The run's seed: with the grammar and attributes it fixes every random choice.
    pub seed: u64,
    /// Attribute values overriding the grammar's defaults.
    pub attrs: Vec<(String, Value)>,
    /// The rule to start from; the grammar's `@StartRule` (or first rule) when `None`.
    pub start_rule: Option<String>,
    /// Stop with an error after this many shapes (per initial shape and in total).
    pub max_shapes: usize,
    /// Stop with an error when a shape is this many successors deep.
    pub max_depth: u32,
    /// Stop with an error after this much time per initial shape.
    pub time_budget: Option<Duration>,
    /// Rewrite in parallel generations and stop after this many (shapes left become leaves).
    pub generations: Option<u32>,
    /// Where `i("file.obj")` finds files.
    pub assets: Option<Arc<dyn AssetLoader>>,
    /// Keep the derivation tree (every shape that existed) in [`Derivation::tree`].
    pub keep_tree: bool,
    /// Edge length of the grid cells implicit solids are meshed with; `None` picks one per
    /// group from its size and its smallest member.
    pub implicit_cell: Option<f64>,
}

impl Default for DeriveOptions {
    fn default() -> Self {
        Self {
            seed: 0,
            attrs: Vec::new(),
            start_rule: None,
            max_shapes: 10_000_000,
            max_depth: 1_000,
            time_budget: None,
            generations: None,
            assets: None,
            keep_tree: false,
            implicit_cell: None,
        }
    }
}

/// An initial shape: a planar footprint polygon in world coordinates, counter-clockwise about
/// its up side (a lot faces +y).
#[derive(Clone, Debug, PartialEq)]
pub struct InitialShape {
    /// The polygon's corners.
    pub footprint: Vec<DVec3>,
}

impl InitialShape {
    /// A lot from `(x, z)` corners in either winding, at y = 0, facing up.
    pub fn from_xz(points: &[shapegram_geom::DVec2]) -> Option<Self> {
        let mesh = primitives::footprint(points)?;
        Some(Self {
            footprint: mesh.face_points(0).collect(),
        })
    }
}

/// A finished shape: part of the model.
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    /// The symbol of the shape (the rule that made it).
    pub name: Arc<str>,
    /// Its scope.
    pub scope: Scope,
    /// Its geometry, relative to the scope.
    pub geometry: Geometry,
    /// Its colour.
    pub color: Color,
    /// Its material name, when one was set.
    pub material: Option<Arc<str>>,
    /// Its node in [`Derivation::tree`], when the tree is kept.
    pub node: Option<u32>,
    /// The initial shape it grew from, as an index into the derivation's initial shapes.
    pub lot: u32,
}

/// A shape in the derivation tree.
#[derive(Clone, Debug, PartialEq)]
pub struct TreeNode {
    /// The shape's symbol when it was made.
    pub name: Arc<str>,
    /// The shape it came from (`None` for initial shapes).
    pub parent: Option<u32>,
    /// Its scope when it was made (its birth snapshot).
    pub scope: Scope,
}

impl Leaf {
    /// The leaf's geometry in world coordinates (`None` when it has none).
    pub fn world_mesh(&self) -> Option<Mesh> {
        self.geometry.world_mesh(&self.scope)
    }
}

/// Counts of a derivation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Shapes created (initial shapes, successors and parts of splits).
    pub shapes: usize,
    /// Leaves in the model.
    pub leaves: usize,
    /// How often each rule was applied, by rule name, in rule order.
    pub rules: Vec<(String, usize)>,
}

/// The result of a derivation.
#[derive(Clone, Debug, Default)]
pub struct Derivation {
    /// The leaves, initial shape by initial shape, in derivation order.
    pub leaves: Vec<Leaf>,
    /// `report(key, value)` calls in derivation order.
    pub reports: Vec<(String, Value)>,
    /// `print(value)` output in derivation order.
    pub prints: Vec<String>,
    /// Every shape that existed, parents before children, when [`DeriveOptions::keep_tree`]
    /// is set; empty otherwise.
    pub tree: Vec<TreeNode>,
    /// The implicit solids of the leaves, meshed with smooth normals: a part per CSG group of
    /// each initial shape, then a part per solid that belongs to no group.
    pub solids: Vec<ModelPart>,
    /// Counts.
    pub stats: Stats,
}

impl Derivation {
    /// The leaves as a model: one part per (symbol, colour) in order of first appearance, each
    /// holding the world-space geometry of its leaves, then the meshed implicit [`solids`].
    ///
    /// [`solids`]: Derivation::solids
    pub fn to_model(&self) -> Model {
        let mut parts: Vec<ModelPart> = Vec::new();
        let mut slot: FxHashMap<(&str, [u32; 4]), usize> = FxHashMap::default();
        for leaf in &self.leaves {
            if matches!(leaf.geometry, Geometry::Implicit(_)) {
                continue;
            }
            let Some(mesh) = leaf.world_mesh() else {
                continue;
            };
            let key = (&*leaf.name, leaf.color.to_array().map(f32::to_bits));
            let i = *slot.entry(key).or_insert_with(|| {
                parts.push(ModelPart {
                    name: leaf.name.to_string(),
                    color: leaf.color,
                    mesh: Mesh::new(),
                    normals: Vec::new(),
                });
                parts.len() - 1
            });
            parts[i].mesh.append(&mesh);
        }
        parts.extend(self.solids.iter().cloned());
        Model {
            parts,
            lines: Vec::new(),
        }
    }
}

/// What engine steps return.
type Fallible<T> = std::result::Result<T, DeriveError>;

impl<'p> Engine<'p> {
    /// Evaluates three operation arguments, resolving relative ones against the scope size.
    fn vector(&mut self, exprs: &[CExpr; 3], state: &mut State, args: &[Value]) -> Fallible<DVec3> {
        let mut v = DVec3::ZERO;
        for (i, e) in exprs.iter().enumerate() {
            v[i] = match &e.kind {
                CKind::Relative(inner) => self.ev.number(inner, state, args)? * state.scope.size[i],
                _ => self.ev.number(e, state, args)?,
            };
        }
        Ok(v)
    }

    /// Applies an operation. Returns whether it made new shapes (splits), which ends the
    /// current shape's chance of becoming a leaf.
    fn op(
        &mut self,
        op: &'p Op,
        span: Span,
        state: &mut State,
        anchor: &Scope,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<bool> {
        match op {
            Op::Extrude { world_up, distance } => {
                let d = self.ev.number(distance, state, args)?;
                extrude(state, d, *world_up, span)?;
            }
            Op::Translate(v) => {
                let v = self.vector(v, state, args)?;
                state.scope.translate(v);
            }
            Op::Rotate {
                about_center,
                degrees,
            } => {
                let v = self.vector(degrees, state, args)?;
                let pivot = if *about_center {
                    Pivot::Center
                } else {
                    Pivot::Origin
                };
                state.scope.rotate_euler_degrees(v, pivot);
            }
            Op::Size(v) => {
                let v = self.vector(v, state, args)?;
                state.resize(v.abs());
                // A negative size mirrors: the axis turns around the scope's origin, and the
                // geometry with it.
                for i in 0..3 {
                    if v[i] < 0.0 {
                        state.mirror_axis(i);
                    }
                }
            }
            Op::Center(axes) => {
                let target = anchor.center();
                state.scope.center_on(target, *axes);
            }
            Op::Mirror(flags) => {
                let mut f = [false; 3];
                for (i, e) in flags.iter().enumerate() {
                    f[i] = match self.ev.eval(e, state, args)? {
                        Value::Bool(b) => b,
                        Value::Number(n) => n != 0.0,
                        other => {
                            return Err(DeriveError::at(
                                format!("expected a boolean, found a {}", other.type_name()),
                                e.span,
                            ));
                        }
                    };
                }
                mirror(state, f);
            }
            Op::AlignScopeToAxes(axis) => align_scope(state, *axis),
            Op::AlignScopeToGeometry { z_up, face, edge } => {
                no_solid(state, "alignScopeToGeometry", span)?;
                let face = match face {
                    FaceChoice::Index(e) => FacePick::Index(self.index(e, state, args)?),
                    FaceChoice::Lowest => FacePick::Lowest,
                    FaceChoice::Largest => FacePick::Largest,
                    FaceChoice::Any => FacePick::Any,
                };
                let edge = match edge {
                    EdgeChoice::Index(e) => EdgePick::Index(self.index(e, state, args)?),
                    EdgeChoice::Lowest => EdgePick::Lowest,
                    EdgeChoice::Longest => EdgePick::Longest,
                };
                if let Some(axes) = geometry_axes(state, *z_up, face, edge) {
                    refit(state, axes);
                }
            }
            Op::AlignScopeToGeometryBBox { first, second } => {
                if let Some(axes) = bbox_axes(state, *first, *second) {
                    refit(state, axes);
                }
            }
            Op::RotateScope(v) => {
                let v = self.vector(v, state, args)?;
                let mut turned = state.scope;
                turned.rotate_euler_degrees(v, Pivot::Origin);
                refit(state, turned.axes);
            }
            Op::Insert(path) => {
                let file = self.ev.string(path, state, args)?;
                // From the shape's seed, not its stream, so asking for a variant draws nothing
                // that later random choices of the shape would miss.
                let variant = (child_seed(state.seed, u64::MAX) % u64::from(ASSET_VARIANTS)) as u32;
                let asset = self.asset(&file, variant, path.span)?;
                insert(state, &asset);
            }
            Op::Primitive(kind, params) => {
                let counts = self.numbers(params, state, args)?;
                primitive(state, *kind, &counts, span)?;
            }
            Op::Split {
                axis,
                adjust,
                snap,
                block,
            } => {
                let snaps = match snap {
                    Some(tag) => Some(self.snap_positions(state, *axis, tag.as_ref(), args)?),
                    None => None,
                };
                self.split(state, *axis, *adjust, snaps, block, span, args, out)?;
                return Ok(true);
            }
            Op::Snap { axes, tag } => {
                if self.phase == Phase::Gather {
                    let tag = tag.as_ref().map(|t| self.ev.string(t, state, args));
                    let planes = snap_planes(&state.scope, *axes, tag.transpose()?, self.ev.lot);
                    self.snaps.extend(planes);
                }
            }
            Op::Label(name) => {
                let name = self.ev.string(name, state, args)?;
                if self.phase == Phase::Gather {
                    self.occlude(state, Some(name), None);
                }
            }
            Op::Comp { kind, entries } => {
                self.comp(state, *kind, entries, span, args, out)?;
                return Ok(true);
            }
            Op::Setback {
                depths,
                entries,
                shape,
                remainder,
            } => {
                let depth = |ev: &mut Evaluator, e: &CExpr, state: &mut State| {
                    let d = ev.number(e, state, args)?;
                    if d < 0.0 {
                        return Err(DeriveError::at(
                            format!("setback distance {d}: expected 0 or more"),
                            e.span,
                        ));
                    }
                    Ok(d)
                };
                let depths = match depths {
                    Depths::Selected(e) => EdgeDepths::Selected(depth(&mut self.ev, e, state)?),
                    Depths::ByClass(list) => EdgeDepths::ByClass(
                        list.iter()
                            .map(|(class, e)| Ok((*class, depth(&mut self.ev, e, state)?)))
                            .collect::<Fallible<Vec<_>>>()?,
                    ),
                };
                let outputs = SetbackOutputs {
                    entries,
                    shape: shape.as_ref(),
                    remainder: remainder.as_ref(),
                };
                self.setback(state, &depths, outputs, span, args, out)?;
                return Ok(true);
            }
            Op::Color(params) => state.color = self.color(params, state, args)?,
            Op::Set(target, value) => {
                let v = self.ev.eval(value, state, args)?;
                set(state, target, v, value.span)?;
            }
            Op::Report(key, value) => {
                let key = self.ev.eval(key, state, args)?.to_string();
                let value = self.ev.eval(value, state, args)?;
                self.ev.reports.push((key, value));
            }
            Op::Print(value) => {
                let text = self.ev.eval(value, state, args)?.to_string();
                self.ev.prints.push(text);
            }
            Op::ReverseNormals => {
                no_solid(state, "reverseNormals", span)?;
                if let Some(mut mesh) = state.geometry.local_mesh(state.scope.size) {
                    mesh.flip();
                    let tags = state.geometry.tags().map(Arc::from);
                    state.geometry = Geometry::Mesh(Arc::new(mesh), tags);
                }
            }
            Op::Offset { distance, keep } => {
                let d = self.ev.number(distance, state, args)?;
                offset(state, d, *keep, span)?;
            }
            Op::Roof(kind, params) => {
                let values = self.numbers(params, state, args)?;
                roof(state, *kind, &values, span)?;
            }
            Op::Implicit(kind) => implicit(state, *kind, span)?,
            Op::ImplicitFile(path) => {
                let file = self.ev.string(path, state, args)?;
                let solid = self.implicit_file(&file, path.span)?;
                implicit_in_scope(state, &solid, &file, span)?;
            }
            Op::Csg {
                kind,
                group,
                amount,
            } => {
                let group = match self.ev.eval(group, state, args)? {
                    Value::Str(name) => name,
                    v => {
                        return Err(DeriveError::at(
                            format!(
                                "expected a group name (a string), found a {}",
                                v.type_name()
                            ),
                            group.span,
                        ));
                    }
                };
                let amount = match amount {
                    Some(e) => Some((self.ev.number(e, state, args)?, e.span)),
                    None => None,
                };
                join_group(state, *kind, group, amount, span)?;
            }
            Op::Ignored => {}
        }
        Ok(false)
    }

    /// Evaluates a face or edge index: a whole number, negative ones counting from the end.
    fn index(&mut self, e: &CExpr, state: &mut State, args: &[Value]) -> Fallible<i64> {
        let n = self.ev.number(e, state, args)?;
        if n.fract() != 0.0 || n.abs() > 1e15 {
            return Err(DeriveError::at(
                format!("index {n}: expected a whole number"),
                e.span,
            ));
        }
        Ok(n as i64)
    }

    /// Evaluates operation arguments that must all be numbers.
    fn numbers(
        &mut self,
        params: &[CExpr],
        state: &mut State,
        args: &[Value],
    ) -> Fallible<Vec<f64>> {
        params
            .iter()
            .map(|p| self.ev.number(p, state, args))
            .collect()
    }

    fn color(&mut self, params: &[CExpr], state: &mut State, args: &[Value]) -> Fallible<Color> {
        if let [one] = params {
            if let CKind::Value(Value::Str(text)) = &one.kind {
                // Most colours are literals: no need to go through the evaluator.
                if let Some(c) = Color::from_hex(text) {
                    return Ok(c);
                }
            }
            let text = self.ev.string(one, state, args)?;
            return Color::from_hex(&text).ok_or_else(|| {
                DeriveError::at(
                    format!("`{text}` is not a colour like \"#3a6ea5\""),
                    one.span,
                )
            });
        }
        let mut c = [1.0f32; 4];
        for (i, p) in params.iter().enumerate() {
            c[i] = self.ev.number(p, state, args)?.clamp(0.0, 1.0) as f32;
        }
        Ok(Color {
            r: c[0],
            g: c[1],
            b: c[2],
            a: c[3],
        })
    }

    fn asset(&self, path: &str, variant: u32, span: Span) -> Fallible<Asset> {
        if let Some(mesh) = builtin_asset(path) {
            return Ok(Asset {
                mesh: Arc::new(mesh),
                proportional: false,
            });
        }
        let Some(loader) = &self.options.assets else {
            return Err(DeriveError::at(
                format!("cannot insert `{path}`: no asset folder is set"),
                span,
            )
            .with_hint("use a built-in asset such as \"builtin:cube\""));
        };
        loader
            .asset(path, variant)
            .map_err(|why| DeriveError::at(format!("cannot insert `{path}`: {why}"), span))
    }

    /// The solid of the implicit grammar at `path`.
    fn implicit_file(&self, path: &str, span: Span) -> Fallible<Solid> {
        let Some(loader) = &self.options.assets else {
            return Err(DeriveError::at(
                format!("cannot run `{path}`: no asset folder is set"),
                span,
            ));
        };
        loader
            .solid(path)
            .map_err(|why| DeriveError::at(format!("cannot run `{path}`: {why}"), span))
    }

    /// Records the shape as an occluder (when its geometry is a closed solid); its descendants
    /// will not see it in their queries.
    fn occlude(&mut self, state: &mut State, label: Option<Arc<str>>, world: Option<&Mesh>) {
        let (scope, geometry, symbol) = (&state.scope, &state.geometry, state.symbol);
        let (lot, parent) = (self.ev.lot, state.occluder);
        if let Some(occluder) = Occluder::new(scope, geometry, world, symbol, label, lot, parent) {
            state.occluder = self.occluders.len() as u32;
            self.occluders.push(occluder);
        }
    }

    /// Where a snapping split of the shape along `axis` moves its boundaries to.
    fn snap_positions(
        &mut self,
        state: &mut State,
        axis: usize,
        tag: Option<&CExpr>,
        args: &[Value],
    ) -> Fallible<Vec<f64>> {
        let tag = tag.map(|t| self.ev.string(t, state, args)).transpose()?;
        Ok(match self.ev.context {
            Some(context) => {
                context.snap_positions(&state.scope, axis, self.ev.lot, tag.as_deref())
            }
            None => Vec::new(),
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn split(
        &mut self,
        state: &mut State,
        axis: usize,
        adjust: bool,
        snaps: Option<Vec<f64>>,
        block: &'p crate::ops::SplitBlock,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let length = state.scope.size[axis];
        let mut layout = self.layouts.pop().unwrap_or_default();
        layout.lay_out(block, length, span, &mut self.ev, state, args)?;
        if let Some(positions) = snaps {
            layout.snap(&positions);
        }
        let result = self.split_parts(state, axis, adjust, &layout, span, args, out);
        self.layouts.push(layout);
        result
    }

    #[allow(clippy::too_many_arguments)]
    fn split_parts(
        &mut self,
        state: &mut State,
        axis: usize,
        adjust: bool,
        layout: &Layout<'p>,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let parts = &layout.parts;
        let total = parts.len() as u32;
        let slabs = match &state.geometry {
            Geometry::Mesh(mesh, _) => {
                let mut cuts: Vec<f64> = parts
                    .iter()
                    .flat_map(|p| [p.start, p.start + p.size])
                    .collect();
                cuts.dedup();
                let pieces = split_slabs(mesh, DVec3::AXES[axis], &cuts);
                Some((cuts, pieces))
            }
            _ => None,
        };
        let solid = match &state.geometry {
            Geometry::Implicit(implicit) => Some(implicit.solid.clone()),
            _ => None,
        };
        for (i, part) in parts.iter().enumerate() {
            // The part's scope, worked out from the parent's.
            let mut scope = state.scope;
            scope.translate(DVec3::AXES[axis] * part.start);
            scope.size[axis] = part.size;
            if slabs.is_none()
                && solid.is_none()
                && self.leaf_part(state, part.body, scope, span, out)?
            {
                continue;
            }
            let mut child = state.spawn();
            child.split = (i as u32, total);
            child.scope = scope;
            if let Some(solid) = &solid {
                let Some(slab) = slab_of(solid, axis, part.start, part.size) else {
                    continue;
                };
                child.geometry = state.geometry.with_solid(slab);
                if adjust {
                    let axes = child.scope.axes;
                    refit(&mut child, axes);
                }
            }
            if let Some((cuts, pieces)) = &slabs {
                let at = cuts.iter().position(|&c| c == part.start).unwrap_or(0);
                let mut piece = pieces[at + 1].clone();
                if piece.is_empty() {
                    continue;
                }
                piece.transform(&DAffine3::from_translation(-DVec3::AXES[axis] * part.start));
                child.geometry = Geometry::mesh(piece);
                if adjust {
                    let axes = child.scope.axes;
                    refit(&mut child, axes);
                }
            }
            self.admit(&mut child, span)?;
            self.run_stmts(part.body, &mut child, args, out)?;
        }
        Ok(())
    }

    /// The common part of a box split that is at once a leaf (`{ 1 : Wall. }`), made without
    /// making the part's shape and its successor: only their counts and the leaf are left of
    /// them, and the parent's count of children. Returns whether the part was such a part.
    fn leaf_part(
        &mut self,
        state: &mut State,
        body: &[CStmt],
        scope: Scope,
        span: Span,
        out: &[Work],
    ) -> Fallible<bool> {
        let [
            CStmt::Successor {
                symbol,
                rule,
                args,
                terminal,
                span: successor_span,
            },
        ] = body
        else {
            return Ok(false);
        };
        if !args.is_empty()
            || (rule.is_some() && !terminal)
            || self.tree.is_some()
            || out.len() != self.base
        {
            return Ok(false);
        }
        // The part, as `State::spawn` would have made it.
        state.children += 1;
        self.count(state.depth + 1, state.symbol, span)?;
        // Its successor, as `State::make_child` would have made it.
        self.count(state.depth + 2, *symbol, *successor_span)?;
        if self.phase == Phase::Gather {
            let (lot, parent) = (self.ev.lot, state.occluder);
            let leaf = Occluder::new(&scope, &state.geometry, None, *symbol, None, lot, parent);
            self.occluders.extend(leaf);
        }
        if !matches!(state.geometry, Geometry::Empty) {
            self.leaves.push(Leaf {
                name: self.names[*symbol as usize].clone(),
                scope,
                geometry: state.geometry.clone(),
                color: state.color,
                material: state.material.clone(),
                node: None,
                lot: self.ev.lot,
            });
        }
        Ok(true)
    }

    fn comp(
        &mut self,
        state: &mut State,
        kind: CompKind,
        entries: &'p [CompEntry],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        no_solid(state, "comp", span)?;
        let Some(world) = state.geometry.world_mesh(&state.scope) else {
            return Ok(());
        };
        if self.phase == Phase::Gather {
            self.occlude(state, None, Some(&world));
        }
        let components = match kind {
            CompKind::Faces => component::faces(&world),
            CompKind::Edges => component::edges(&world),
            CompKind::Vertices => component::vertices(&world),
        };
        let tags = state.geometry.tags();
        let mut assigned: Vec<Vec<usize>> = vec![Vec::new(); entries.len()];
        for (c, comp) in components.iter().enumerate() {
            let tag = tags
                .and_then(|t| t.get(comp.source))
                .copied()
                .unwrap_or(FaceTag::None);
            if let Some(e) = entries
                .iter()
                .position(|e| selects(&e.selector, comp, c, tag, &state.scope, kind))
            {
                assigned[e].push(c);
            }
        }
        for (entry, chosen) in entries.iter().zip(&assigned) {
            if chosen.is_empty() {
                continue;
            }
            if entry.merge {
                let mut merged = Mesh::new();
                for &c in chosen {
                    merged.append(&Mesh::from_polygon(&components[c].points));
                }
                let mut child = state.spawn();
                child.comp = (0, 1);
                child.comp_sel = entry.selector.code();
                child.scope = Scope::fit(
                    components[chosen[0]].scope.axes,
                    merged.positions().iter().copied(),
                );
                merged.transform(&child.scope.world_to_local());
                child.geometry = Geometry::mesh(merged);
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
                continue;
            }
            for (i, &c) in chosen.iter().enumerate() {
                let comp = &components[c];
                let mut child = state.spawn();
                child.comp = (i as u32, chosen.len() as u32);
                child.comp_sel = entry.selector.code();
                child.scope = comp.scope;
                child.geometry = match kind {
                    CompKind::Faces => {
                        let local: Vec<DVec3> = comp
                            .points
                            .iter()
                            .map(|&p| comp.scope.to_local(p))
                            .collect();
                        if fills_box(&local, comp.scope.size) {
                            Geometry::Box
                        } else {
                            Geometry::mesh(Mesh::from_polygon(&local))
                        }
                    }
                    CompKind::Edges | CompKind::Vertices => Geometry::Empty,
                };
                self.admit(&mut child, span)?;
                self.run_stmts(&entry.body, &mut child, args, out)?;
            }
        }
        Ok(())
    }
}

impl<'p> Engine<'p> {
    /// CGA `setback` and `shapeL/U/O`: each face of a flat shape is cut into strips along the
    /// edges that move, their outline and the remainder. A strip goes to the first entry that
    /// selects its edge, with its scope's x along the edge, y along the face's normal and z into
    /// the strip; the outline
    /// (`shape`) and the remainder keep the shape's axes.
    fn setback(
        &mut self,
        state: &mut State,
        depths: &EdgeDepths,
        outputs: SetbackOutputs<'p>,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let entries = outputs.entries;
        let world = flat_faces(state, "setback", span)?;
        let scope = state.scope;
        // Strips by entry, the outline's pieces (each its polygons) and remainder loops.
        let mut strips: Vec<Vec<(DVec3, Vec<DVec3>)>> = vec![Vec::new(); entries.len()];
        let (mut outline, mut rest): (Vec<Vec<Vec<DVec3>>>, Vec<Vec<DVec3>>) =
            (Vec::new(), Vec::new());
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let normal = world.face_normal(f);
            let outward = |a: DVec3, b: DVec3| (b - a).cross(normal);
            let taker = |i: usize, a: DVec3, b: DVec3| {
                entries
                    .iter()
                    .position(|e| takes_edge(&e.selector, outward(a, b), i, &scope))
            };
            let distance = |i: usize, a: DVec3, b: DVec3| match depths {
                EdgeDepths::Selected(d) => taker(i, a, b).map_or(0.0, |_| *d),
                EdgeDepths::ByClass(list) => {
                    let class = FaceClass::of(outward(a, b), &scope);
                    list.iter()
                        .find(|(c, _)| *c == class)
                        .map_or(0.0, |(_, d)| *d)
                }
            };
            let cut = shapegram_geom::offset::setback(&points, distance).ok_or_else(|| {
                DeriveError::at(
                    "setback cannot cut this shape: a polygon that is not simple, or a setback so deep that an edge that moves runs onto one that moves slower",
                    span,
                )
            })?;
            // Faces hold no holes: an outline around a hole (shapeO's ring) stays as its strips.
            let holed = cut
                .outline
                .iter()
                .any(|l| newell(l.iter().copied()).dot(normal) < 0.0);
            if holed {
                outline.push(cut.strips.iter().map(|s| s.polygon.clone()).collect());
            } else {
                outline.extend(cut.outline.into_iter().map(|l| vec![l]));
            }
            for strip in cut.strips {
                let [a, b] = strip.ends;
                if let Some(e) = taker(strip.edge, a, b) {
                    strips[e].push((normal, strip.polygon));
                }
            }
            rest.extend(cut.remainder);
        }
        for (entry, chosen) in entries.iter().zip(&strips) {
            let pieces: Vec<Piece> = chosen
                .iter()
                .filter_map(|(normal, polygon)| {
                    // Like a lot along its front edge: x along the edge, z into the strip.
                    let x = (polygon[0] - polygon[1]).try_normalize()?;
                    let y = normal.try_normalize()?;
                    Some((DMat3::from_cols(x, y, x.cross(y)), vec![polygon.as_slice()]))
                })
                .collect();
            let code = entry.selector.code();
            self.flat_children(
                state,
                pieces,
                entry.merge,
                code,
                &entry.body,
                span,
                args,
                out,
            )?;
        }
        if let Some((merge, body)) = outputs.shape {
            let pieces = outline
                .iter()
                .map(|polygons| (scope.axes, polygons.iter().map(Vec::as_slice).collect()))
                .collect();
            self.flat_children(state, pieces, *merge, 0, body, span, args, out)?;
        }
        if let Some((merge, body)) = outputs.remainder {
            let pieces = rest
                .iter()
                .map(|p| (scope.axes, vec![p.as_slice()]))
                .collect();
            self.flat_children(state, pieces, *merge, 0, body, span, args, out)?;
        }
        Ok(())
    }

    /// Derives a child per piece (or one for all when `merge`), each a set of polygons with a
    /// scope of the given axes fitted around them.
    #[allow(clippy::too_many_arguments)]
    fn flat_children(
        &mut self,
        state: &mut State,
        pieces: Vec<Piece>,
        merge: bool,
        selector: u8,
        body: &'p [CStmt],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let pieces = match pieces.first() {
            Some(&(axes, _)) if merge => {
                vec![(axes, pieces.into_iter().flat_map(|p| p.1).collect())]
            }
            _ => pieces,
        };
        let total = pieces.len() as u32;
        for (i, (axes, polygons)) in pieces.into_iter().enumerate() {
            let mut mesh = Mesh::new();
            for polygon in &polygons {
                mesh.append(&Mesh::from_polygon(polygon));
            }
            let mut child = state.spawn();
            child.comp = (i as u32, total);
            child.comp_sel = selector;
            child.scope = Scope::fit(axes, mesh.positions().iter().copied());
            mesh.transform(&child.scope.world_to_local());
            let single = polygons.len() == 1;
            child.geometry = if single && fills_box(mesh.positions(), child.scope.size) {
                Geometry::Box
            } else {
                Geometry::mesh(mesh)
            };
            self.admit(&mut child, span)?;
            self.run_stmts(body, &mut child, args, out)?;
        }
        Ok(())
    }
}

/// Polygons that become one shape, with the axes of its scope.
type Piece<'a> = (DMat3, Vec<&'a [DVec3]>);

/// How far the edges of a setback move, evaluated.
enum EdgeDepths {
    /// The edges that entries select, by this distance.
    Selected(f64),
    /// Edges by the class of their outward direction.
    ByClass(Vec<(FaceClass, f64)>),
}

/// Where the pieces of a setback go.
struct SetbackOutputs<'p> {
    entries: &'p [CompEntry],
    shape: Option<&'p (bool, Vec<CStmt>)>,
    remainder: Option<&'p (bool, Vec<CStmt>)>,
}

/// Whether a setback entry's selector takes the edge `index` whose outward direction (in the
/// face's plane) is `outward`.
fn takes_edge(selector: &CompSelector, outward: DVec3, index: usize, scope: &Scope) -> bool {
    match selector {
        CompSelector::All => true,
        CompSelector::Index(i) => *i == index,
        CompSelector::Class(class) => FaceClass::of(outward, scope) == *class,
        CompSelector::Side => FaceClass::of(outward, scope).is_side(),
        _ => false,
    }
}

/// Whether an entry's selector takes a component.
fn selects(
    selector: &CompSelector,
    comp: &component::Component,
    index: usize,
    tag: FaceTag,
    scope: &Scope,
    kind: CompKind,
) -> bool {
    // Angle of the normal from world up decides vertical, horizontal and aslant.
    let up = comp.normal.y.abs();
    match selector {
        CompSelector::All => true,
        CompSelector::Index(i) => *i == index,
        CompSelector::Never => false,
        _ if kind != CompKind::Faces => false,
        CompSelector::Class(class) => FaceClass::of(comp.normal, scope) == *class,
        CompSelector::Side => FaceClass::of(comp.normal, scope).is_side(),
        CompSelector::Horizontal => up >= 30f64.to_radians().cos(),
        CompSelector::Vertical => up <= 60f64.to_radians().cos(),
        CompSelector::Aslant => up < 30f64.to_radians().cos() && up > 60f64.to_radians().cos(),
        CompSelector::Inside => tag == FaceTag::Inside,
        CompSelector::Border => tag == FaceTag::Border,
    }
}

/// CGA's built-in assets, each filling the unit box.
fn builtin_asset(path: &str) -> Option<Mesh> {
    let name = path.strip_prefix("builtin:")?;
    let name = name.split(':').next().unwrap_or(name);
    Some(match name {
        "cube" => primitives::cuboid(DVec3::ONE),
        "cylinder" => primitives::cylinder(DVec3::ONE, 32),
        "cone" => primitives::cone(DVec3::ONE, 32),
        "sphere" => primitives::sphere(DVec3::ONE, 32, 16),
        "pyramid" => primitives::pyramid(DVec3::ONE),
        "quad" => box_mesh(DVec3::new(1.0, 1.0, 0.0))?,
        _ => return None,
    })
}

/// Fits an asset into the scope (CGA `i`, see `shapegram_geom::fit`), stretched or keeping its
/// proportions; along axes where the scope has no size the scope takes the asset's fitted
/// extent.
fn insert(state: &mut State, asset: &Asset) {
    if asset.mesh.is_empty() {
        state.geometry = Geometry::Empty;
        return;
    }
    let mut local = if asset.proportional {
        shapegram_geom::fit::fit_proportionally_into_scope(&asset.mesh, &state.scope)
    } else {
        shapegram_geom::fit::fit_into_scope(&asset.mesh, &state.scope)
    };
    local.transform(&state.scope.world_to_local());
    if let Some(bounds) = local.bounds() {
        let size = &mut state.scope.size;
        for i in 0..3 {
            if size[i] == 0.0 {
                size[i] = bounds.max[i];
            }
        }
    }
    state.geometry = Geometry::mesh(local);
}

fn primitive(state: &mut State, kind: Primitive, counts: &[f64], span: Span) -> Fallible<()> {
    // A primitive in a flat scope gets unit size along the flat axes.
    let size = DVec3::select(
        state.scope.size.cmpeq(DVec3::ZERO),
        DVec3::ONE,
        state.scope.size,
    );
    let count = |i: usize, default: u32| -> Fallible<u32> {
        match counts.get(i) {
            None => Ok(default),
            Some(&n) if (3.0..=100_000.0).contains(&n) => Ok(n as u32),
            Some(&n) => Err(DeriveError::at(
                format!("{n} subdivisions: expected 3 to 100000"),
                span,
            )),
        }
    };
    state.scope.size = size;
    state.geometry = match kind {
        Primitive::Cube => Geometry::Box,
        Primitive::Quad => {
            state.scope.size.z = 0.0;
            Geometry::Box
        }
        Primitive::Pyramid => Geometry::mesh(primitives::pyramid(size)),
        Primitive::Cylinder => Geometry::mesh(primitives::cylinder(size, count(0, 16)?)),
        Primitive::Cone => Geometry::mesh(primitives::cone(size, count(0, 16)?)),
        Primitive::Sphere => {
            let rings = count(0, 16)?;
            Geometry::mesh(primitives::sphere(size, count(1, 2 * rings)?, rings))
        }
    };
    Ok(())
}

/// An error for operations that need faces on a shape that holds an implicit solid.
fn no_solid(state: &State, op: &str, span: Span) -> Fallible<()> {
    if !matches!(state.geometry, Geometry::Implicit(_)) {
        return Ok(());
    }
    Err(DeriveError::at(
        format!("{op} needs faces, but an implicit solid has none until the model is made"),
        span,
    )
    .with_hint("split the shape into parts first, then make the parts implicit"))
}

/// The part of `solid` between `start` and `start + size` along `axis`, in the frame of a part
/// starting there (`None` when nothing of the solid lies there).
fn slab_of(
    solid: &shapegram_implicit::Solid,
    axis: usize,
    start: f64,
    size: f64,
) -> Option<shapegram_implicit::Solid> {
    let shifted = solid.translate(-DVec3::AXES[axis] * start).ok()?;
    let bounds = shifted.bounds()?;
    // The slab spans the solid's bounds (with a margin) across the split axis.
    let mut lo = bounds.min - DVec3::ONE;
    let mut hi = bounds.max + DVec3::ONE;
    lo[axis] = 0.0;
    hi[axis] = size;
    if lo[axis] >= bounds.max[axis] || hi[axis] <= bounds.min[axis] || size <= 0.0 {
        return None;
    }
    let slab = shapegram_implicit::Solid::cuboid(hi - lo)
        .and_then(|b| b.translate((lo + hi) / 2.0))
        .ok()?;
    Some(shifted.intersection(&slab))
}

/// `implicit(kind)`: the shape becomes the solid `kind` filling its scope.
fn implicit(state: &mut State, kind: ImplicitKind, span: Span) -> Fallible<()> {
    let size = state.scope.size;
    if !size.cmpgt(DVec3::ZERO).all() {
        return Err(DeriveError::at(
            format!(
                "implicit({}) needs a scope with volume, but its size is {} × {} × {}",
                kind.name(),
                size.x,
                size.y,
                size.z
            ),
            span,
        )
        .with_hint("extrude the shape first, or give it a size with `s(…)`"));
    }
    let solid = crate::solids::fitted(kind, size)
        .map_err(|e| DeriveError::at(format!("implicit({}): {e}", kind.name()), span))?;
    set_solid(state, solid, span);
    Ok(())
}

/// Makes the shape's geometry `solid`, in no group, made by the operation at `span`.
fn set_solid(state: &mut State, solid: Solid, span: Span) {
    let csg = None;
    state.geometry = Geometry::Implicit(Arc::new(Implicit { solid, csg, span }));
}

/// `implicit("file.cave")`: the shape becomes `solid` with its bounds stretched to the scope,
/// which must have volume.
fn implicit_in_scope(state: &mut State, solid: &Solid, file: &str, span: Span) -> Fallible<()> {
    let size = state.scope.size;
    let bounds = solid.bounds().filter(|b| b.size().cmpgt(DVec3::ZERO).all());
    let (true, Some(bounds)) = (size.cmpgt(DVec3::ZERO).all(), bounds) else {
        return Err(DeriveError::at(
            format!(
                "implicit(\"{file}\") needs a scope with volume and a grammar that makes a solid"
            ),
            span,
        ));
    };
    let map = DAffine3::from_scale(size / bounds.size()) * DAffine3::from_translation(-bounds.min);
    let solid = solid
        .transform(&map)
        .map_err(|e| DeriveError::at(format!("implicit(\"{file}\"): {}", e.message()), span))?;
    set_solid(state, solid, span);
    Ok(())
}

/// `csg("group", union)` and friends: the shape's solid (a box becomes one) joins `group`.
fn join_group(
    state: &mut State,
    kind: CsgKind,
    group: Arc<str>,
    amount: Option<(f64, Span)>,
    span: Span,
) -> Fallible<()> {
    let name = kind.name();
    let value = match amount {
        None => 0.0,
        Some((a, at)) if kind == CsgKind::Morph && !(0.0..=1.0).contains(&a) => {
            return Err(DeriveError::at(
                format!(
                    "morph amount {a}: expected 0 (the group as it is) to 1 (the member added)"
                ),
                at,
            ));
        }
        Some((k, at)) if !(k.is_finite() && k >= 0.0) => {
            return Err(DeriveError::at(
                format!("fillet radius {k}: expected a finite number of at least 0"),
                at,
            ));
        }
        Some((a, _)) => a,
    };
    let op = kind.op(value);
    let solid = match &state.geometry {
        Geometry::Implicit(implicit) => implicit.solid.clone(),
        Geometry::Box if state.scope.size.cmpgt(DVec3::ZERO).all() => {
            crate::solids::fitted(ImplicitKind::Box, state.scope.size)
                .map_err(|e| DeriveError::at(format!("csg(\"{group}\", {name}): {e}"), span))?
        }
        _ => {
            return Err(DeriveError::at(
                format!("csg(\"{group}\", {name}) needs an implicit solid or a box with volume"),
                span,
            )
            .with_hint(
                "polygon meshes are not solids: fill the scope with one first, e.g. `implicit(box)`",
            ));
        }
    };
    let csg = Some(Csg { group, op, span });
    state.geometry = Geometry::Implicit(Arc::new(Implicit { solid, csg, span }));
    Ok(())
}

fn set(state: &mut State, target: &SetTarget, value: Value, span: Span) -> Fallible<()> {
    let wrong = |what: &str, v: &Value| {
        DeriveError::at(format!("expected {what}, found a {}", v.type_name()), span)
    };
    match target {
        SetTarget::Attr(i) => Rc::make_mut(&mut state.attrs)[*i as usize] = value,
        SetTarget::Color(None) => match &value {
            Value::Str(s) => {
                state.color = Color::from_hex(s).ok_or_else(|| {
                    DeriveError::at(format!("`{s}` is not a colour like \"#3a6ea5\""), span)
                })?;
            }
            v => return Err(wrong("a colour string", v)),
        },
        SetTarget::Color(Some(channel)) => match value {
            Value::Number(n) => {
                let c = n.clamp(0.0, 1.0) as f32;
                match channel {
                    0 => state.color.r = c,
                    1 => state.color.g = c,
                    2 => state.color.b = c,
                    _ => state.color.a = c,
                }
            }
            v => return Err(wrong("a number", &v)),
        },
        SetTarget::MaterialName => state.material = Some(Arc::from(value.to_string().as_str())),
        SetTarget::Ignored => {}
    }
    Ok(())
}

/// Moves the scope to new axes, fitted around the geometry, which stays where it is.
fn refit(state: &mut State, axes: DMat3) {
    // A solid is fitted by a coarse mesh of it (to within a cell), not by its bounds, which
    // would grow with every turn.
    let scope = match state.geometry.world_mesh(&state.scope) {
        Some(mesh) => Scope::fit(axes, mesh.positions().iter().copied()),
        None => Scope::new(state.scope.origin, axes, state.scope.size),
    };
    state.rescope(scope);
}

/// The face `alignScopeToGeometry` takes, evaluated.
enum FacePick {
    Index(i64),
    Lowest,
    Largest,
    Any,
}

/// The edge `alignScopeToGeometry` takes, evaluated.
enum EdgePick {
    Index(i64),
    Lowest,
    Longest,
}

/// CGA `alignScopeToGeometry`: x along the picked edge of the picked face, the face's normal as
/// y (`yUp`) or z (`zUp`); `None` for shapes without faces or a degenerate edge.
fn geometry_axes(state: &State, z_up: bool, face: FacePick, edge: EdgePick) -> Option<DMat3> {
    let world = state.geometry.world_mesh(&state.scope)?;
    let n = world.face_count();
    if n == 0 {
        return None;
    }
    let wrap = |i: i64, len: usize| i.rem_euclid(len as i64) as usize;
    // Edges of face `f` as (start, end).
    let edges = |f: usize| {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let k = points.len();
        (0..k).map(move |j| (points[j], points[(j + 1) % k]))
    };
    // How an edge selector ranks edges: smaller is better.
    let rank = |(a, b): (DVec3, DVec3)| match edge {
        EdgePick::Lowest => (a.y + b.y) / 2.0,
        EdgePick::Longest => -a.distance(b),
        EdgePick::Index(_) => 0.0,
    };
    let best = |scores: &mut dyn Iterator<Item = (f64, usize)>| {
        scores
            .fold(None, |best: Option<(f64, usize)>, (v, i)| match best {
                Some((w, _)) if w <= v => best,
                _ => Some((v, i)),
            })
            .map(|(_, i)| i)
    };
    let f = match face {
        FacePick::Index(i) => wrap(i, n),
        // The lowest by its centre: a box's walls reach down as far as its bottom does.
        FacePick::Lowest => best(&mut (0..n).map(|f| (world.face_centroid(f).y, f)))?,
        FacePick::Largest => best(&mut (0..n).map(|f| (-world.face_area(f), f)))?,
        FacePick::Any => best(&mut (0..n).map(|f| {
            let score = edges(f).map(rank).fold(f64::INFINITY, f64::min);
            (score, f)
        }))?,
    };
    let (a, b) = match edge {
        EdgePick::Index(j) => edges(f).nth(wrap(j, world.face(f).len()))?,
        _ => {
            let all: Vec<(DVec3, DVec3)> = edges(f).collect();
            all[best(&mut all.iter().enumerate().map(|(j, &e)| (rank(e), j)))?]
        }
    };
    let normal = world.face_normal(f).try_normalize()?;
    let x = (b - a).reject_from(normal).try_normalize()?;
    Some(if z_up {
        DMat3::from_cols(x, normal.cross(x), normal)
    } else {
        DMat3::from_cols(x, normal, x.cross(normal))
    })
}

/// CGA `alignScopeToGeometryBBox`: the scope's axes `first` and `second` turned about the third
/// so that they span the minimum-area rectangle around the geometry seen along it, `first` along
/// its longer side (pointing the way the old `first` axis did, as far as it can).
fn bbox_axes(state: &State, first: usize, second: usize) -> Option<DMat3> {
    let world = state.geometry.world_mesh(&state.scope)?;
    let fixed = 3 - first - second;
    let axes = state.scope.axes;
    let (u, v) = (axes.col(first), axes.col(second));
    let flat: Vec<shapegram_geom::DVec2> = world
        .positions()
        .iter()
        .map(|p| shapegram_geom::DVec2::new(p.dot(u), p.dot(v)))
        .collect();
    let rectangle = shapegram_geom::rectangle::min_area_rectangle(&flat)?;
    let mut along = rectangle.long_axis;
    if along.x < 0.0 {
        along = -along;
    }
    let mut cols = [DVec3::ZERO; 3];
    cols[fixed] = axes.col(fixed);
    cols[first] = u * along.x + v * along.y;
    // The remaining axis completes a right-handed frame (x = y × z, y = z × x, z = x × y).
    cols[second] = cols[(second + 1) % 3].cross(cols[(second + 2) % 3]);
    Some(DMat3::from_cols(cols[0], cols[1], cols[2]))
}

/// CGA `alignScopeToAxes`: all axes to the world's, or one axis to the world's keeping the
/// others as close as possible.
fn align_scope(state: &mut State, axis: Option<usize>) {
    let axes = match axis {
        None => DMat3::IDENTITY,
        Some(k) => {
            let target = DVec3::AXES[k];
            let (next, _) = ((k + 1) % 3, (k + 2) % 3);
            let keep = state
                .scope
                .axes
                .col(next)
                .reject_from(target)
                .try_normalize()
                .unwrap_or(DVec3::AXES[next]);
            let mut cols = [DVec3::ZERO; 3];
            cols[k] = target;
            cols[next] = keep;
            cols[(k + 2) % 3] = target.cross(keep);
            DMat3::from_cols(cols[0], cols[1], cols[2])
        }
    };
    refit(state, axes);
}

fn mirror(state: &mut State, flags: [bool; 3]) {
    if !flags.contains(&true) {
        return;
    }
    let size = state.scope.size;
    let mut scale = DVec3::ONE;
    let mut shift = DVec3::ZERO;
    for i in 0..3 {
        if flags[i] {
            scale[i] = -1.0;
            shift[i] = size[i];
        }
    }
    let map = DAffine3::from_translation(shift) * DAffine3::from_scale(scale);
    if let Geometry::Implicit(implicit) = &state.geometry {
        state.geometry = state.geometry.with_solid(moved(&implicit.solid, map));
        return;
    }
    let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
        return;
    };
    let tags = state.geometry.tags().map(Arc::from);
    state.geometry = Geometry::Mesh(Arc::new(mesh.transformed(&map)), tags);
}

/// CGA `extrude`: every face pushed along its normal (or world up); the new scope keeps x as
/// far as it can, takes y along the extrusion and is fitted around the result.
fn extrude(state: &mut State, distance: f64, world_up: bool, span: Span) -> Fallible<()> {
    if distance == 0.0 {
        return Ok(());
    }
    let scope = state.scope;
    let flat = flat_axis(scope.size);
    let world = flat_faces(state, "extrude", span)?;
    let mut solid = Mesh::new();
    let mut direction = DVec3::ZERO;
    for f in 0..world.face_count() {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let normal = world.face_normal(f);
        let prism = if world_up {
            extrude_along(&points, DVec3::Y * distance)
        } else {
            extrude_polygon(&points, distance)
        };
        if let Some(prism) = prism {
            if direction == DVec3::ZERO {
                direction = if world_up { DVec3::Y } else { normal };
            }
            solid.append(&prism);
        }
    }
    if solid.is_empty() {
        return Ok(());
    }
    let fitted = Scope::fit(
        grown_axes(&scope, direction),
        solid.positions().iter().copied(),
    );
    // A flat box extruded along its own axis stays a box.
    let stays_box = state.geometry == Geometry::Box
        && flat.is_some_and(|k| scope.axes.col(k).abs_diff_eq(direction, 1e-12));
    state.geometry = if stays_box {
        Geometry::Box
    } else {
        solid.transform(&fitted.world_to_local());
        Geometry::mesh(solid)
    };
    state.scope = fitted;
    Ok(())
}

/// The faces of a flat shape in world coordinates, for the operations that build on polygons
/// (`extrude`, `offset`, roofs); an error for shapes without geometry and for volumes.
fn flat_faces(state: &State, op: &str, span: Span) -> Fallible<Mesh> {
    let Some(world) = state.geometry.world_mesh(&state.scope) else {
        return Err(DeriveError::at(
            format!("{op} needs a polygon, but the shape has no geometry"),
            span,
        ));
    };
    let volume = flat_axis(state.scope.size).is_none() && state.geometry == Geometry::Box;
    if volume || world.is_watertight() {
        return Err(DeriveError::at(
            format!("{op} needs a flat shape (a polygon), but this shape is a volume"),
            span,
        )
        .with_hint(format!(
            "apply it to a face: `comp(f) {{ top : {op}(…) X }}`"
        )));
    }
    Ok(world)
}

/// The scope axes for a solid grown from faces along `up`: x kept as far as it can be, y up.
fn grown_axes(scope: &Scope, up: DVec3) -> DMat3 {
    let x = scope
        .x_axis()
        .reject_from(up)
        .try_normalize()
        .unwrap_or_else(|| up.any_orthonormal_vector());
    DMat3::from_cols(x, up, x.cross(up))
}

/// CGA `offset(d)`: every face shrunk (negative `d`) or grown (positive) by `d`, the ring between
/// old and new outline kept as border faces; `inside` or `border` keeps only those.
fn offset(state: &mut State, distance: f64, keep: OffsetKeep, span: Span) -> Fallible<()> {
    let world = flat_faces(state, "offset", span)?;
    let mut mesh = Mesh::new();
    let mut tags = Vec::new();
    for f in 0..world.face_count() {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let (inside, border) = shapegram_geom::offset::inset_border(&points, distance);
        for (loops, tag, wanted) in [
            (inside, FaceTag::Inside, keep != OffsetKeep::Border),
            (border, FaceTag::Border, keep != OffsetKeep::Inside),
        ] {
            for points in loops.iter().filter(|_| wanted) {
                mesh.append(&Mesh::from_polygon(points));
                tags.push(tag);
            }
        }
    }
    if mesh.is_empty() {
        state.geometry = Geometry::Empty;
        return Ok(());
    }
    let scope = Scope::fit(state.scope.axes, mesh.positions().iter().copied());
    mesh.transform(&scope.world_to_local());
    state.scope = scope;
    state.geometry = Geometry::Mesh(Arc::new(mesh), Some(tags.into()));
    Ok(())
}

/// CGA's roofs on every face of a flat shape; the result is a closed solid whose scope keeps x
/// and has y along the faces' normal.
fn roof(state: &mut State, kind: RoofKind, params: &[f64], span: Span) -> Fallible<()> {
    let world = flat_faces(state, "roof", span)?;
    let angle = params[0];
    let extra = params.get(1).copied();
    let mut solid = Mesh::new();
    let mut up = DVec3::ZERO;
    for f in 0..world.face_count() {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let built = match kind {
            RoofKind::Gable => {
                shapegram_geom::roof::roof_gable(&points, angle, extra.unwrap_or(0.0))
            }
            RoofKind::Hip => shapegram_geom::roof::roof_hip(&points, angle, extra.unwrap_or(0.0)),
            RoofKind::Pyramid => shapegram_geom::roof::roof_pyramid(&points, angle),
            RoofKind::Shed => {
                let edge = extra.unwrap_or(0.0);
                if edge < 0.0 || edge.fract() != 0.0 {
                    return Err(DeriveError::at(
                        format!("roofShed's edge index must be a whole number ≥ 0, not {edge}"),
                        span,
                    ));
                }
                shapegram_geom::roof::roof_shed(&points, angle, edge as usize)
            }
        };
        let Some(built) = built else {
            return Err(DeriveError::at(
                format!(
                    "cannot build this roof: the angle must be between 0 and 90 degrees (it is \
                     {angle}), any overhang not negative, and the face a simple polygon"
                ),
                span,
            ));
        };
        if up == DVec3::ZERO {
            up = world.face_normal(f);
        }
        solid.append(&built);
    }
    let fitted = Scope::fit(
        grown_axes(&state.scope, up),
        solid.positions().iter().copied(),
    );
    solid.transform(&fitted.world_to_local());
    state.scope = fitted;
    state.geometry = Geometry::mesh(solid);
    Ok(())
}
