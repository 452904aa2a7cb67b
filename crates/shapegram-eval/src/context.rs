//! Context-sensitive rules: occlusion queries and snap planes, in two phases.
//!
//! A rule that asks about other shapes (`inside()`, `overlaps()`, `touches()`, `occ(…)`) or
//! splits with `snap` is a *context rule*. Deriving a grammar with context rules takes two
//! phases, so that no answer depends on the order in which shapes are derived:
//!
//! 1. Every lot derives as usual, except that a shape whose rule is a context rule waits. The
//!    shapes of this phase leave *occluders* behind: every shape that a component split took
//!    apart, every leaf, and every shape given a `label`, whose geometry is a closed solid
//!    (a box with volume, or a watertight mesh). `snap(…)` leaves snap planes.
//! 2. Once all lots are through phase 1, the waiting shapes derive, in order, lot by lot.
//!    Their queries look at the occluders and snap planes of phase 1 only: shapes made in phase
//!    2 neither occlude nor snap.
//!
//! CGA's context functions `contextCount`, `contextCompare` and `minimumDistance` look at the
//! same occluders, chosen by label.
//!
//! A query never sees the querying shape's own ancestors (the mass a facade came from always
//! "occludes" it); it sees every other occluder of its lot (`intra`), of the other lots
//! (`inter`) or both (`all`, the default), optionally only those with a given label or rule name.

use std::sync::Arc;

use shapegram_geom::occlusion::{Contact, ConvexSolid, Probe, contact, convex_pieces};
use shapegram_geom::{Aabb, Bvh, DMat3, DVec3, Mesh, Scope};
use shapegram_implicit::Solid;
use shapegram_kinematics::{Frame, Skeleton};

use crate::expr::ConstMemo;
use crate::program::{RuleId, Sym};
use crate::shape::{FrozenState, Geometry, NO_OCCLUDER, State};
use crate::value::Value;

/// Most convex pieces a non-convex solid is cut into for occlusion tests. An occluder that
/// needs more is not an occluder; a probe that needs more is tested by its surface only.
const MAX_PIECES: usize = 32;

/// Two boxes closer than this, relative to the size of the querying shape, touch.
const RELATIVE_TOLERANCE: f64 = 1e-6;

/// A closed solid left by phase 1, for occlusion queries.
#[derive(Clone, Debug)]
pub(crate) struct Occluder {
    pieces: Vec<ConvexSolid>,
    bounds: Aabb,
    label: Option<Arc<str>>,
    symbol: Sym,
    /// The occluder this one's shape descends from ([`NO_OCCLUDER`] when none).
    pub parent: u32,
    lot: u32,
    /// In a grammar with a skeleton: the shape's section, and its scope and geometry in the
    /// rest pose, to place the occluder where the pose puts it once phase 1 is done.
    posable: Option<Box<(u32, Scope, Geometry)>>,
}

impl Occluder {
    /// The occluder of a shape, or `None` when its geometry is not a closed solid.
    pub fn of(state: &State, label: Option<Arc<str>>, lot: u32) -> Option<Self> {
        let (scope, geometry) = (&state.scope, &state.geometry);
        Self::new(
            scope,
            geometry,
            None,
            state.symbol,
            label,
            lot,
            state.occluder,
        )
    }

    /// The occluder of a scope and geometry descending from occluder `parent`, if they form a
    /// closed solid; `world` is the geometry's world mesh when the caller has made it already (a
    /// component split needs it too).
    pub fn new(
        scope: &Scope,
        geometry: &Geometry,
        world: Option<&Mesh>,
        symbol: Sym,
        label: Option<Arc<str>>,
        lot: u32,
        parent: u32,
    ) -> Option<Self> {
        let pieces = match geometry {
            Geometry::Box => vec![ConvexSolid::from_scope(scope)?],
            Geometry::Mesh(..) => match world {
                Some(mesh) => convex_pieces(mesh, MAX_PIECES)?,
                None => convex_pieces(&geometry.world_mesh(scope)?, MAX_PIECES)?,
            },
            // Members that carve or trim a group add nothing to occlude.
            Geometry::Implicit(implicit) if implicit.csg.as_ref().is_some_and(|c| !c.op.adds()) => {
                return None;
            }
            Geometry::Implicit(implicit) => {
                vec![ConvexSolid::from_scope(&solid_box(
                    scope,
                    &implicit.solid,
                )?)?]
            }
            Geometry::Empty => return None,
        };
        let bounds = pieces.iter().map(ConvexSolid::bounds).reduce(Aabb::union)?;
        Some(Self {
            pieces,
            bounds,
            label,
            symbol,
            parent,
            lot,
            posable: None,
        })
    }

    /// The lot it belongs to.
    pub fn lot(&self) -> u32 {
        self.lot
    }

    /// The occluder of a shape hanging from `section`, to be posed with it (see
    /// [`Occluder::pose`]).
    pub fn hanging_from(mut self, section: u32, scope: &Scope, geometry: &Geometry) -> Self {
        self.posable = Some(Box::new((section, *scope, geometry.clone())));
        self
    }

    /// Moves the occluder to where the skeleton's pose puts it: `motions` are the rigid
    /// motions from the rest pose of its lot's sections.
    pub fn pose(&mut self, motions: &[Frame]) {
        let Some((section, scope, geometry)) = self.posable.as_deref() else {
            return;
        };
        let Some(motion) = motions
            .get(*section as usize)
            .filter(|m| **m != Frame::IDENTITY)
        else {
            return;
        };
        let posed = posed_scope(scope, motion);
        if let Some(moved) = Self::new(
            &posed,
            geometry,
            None,
            self.symbol,
            None,
            self.lot,
            self.parent,
        ) {
            self.pieces = moved.pieces;
            self.bounds = moved.bounds;
        }
    }
}

/// A scope moved rigidly by `motion` (its geometry, relative to it, moves along).
pub(crate) fn posed_scope(scope: &Scope, motion: &Frame) -> Scope {
    Scope::new(
        motion.transform_point(scope.origin),
        DMat3::from_quat(motion.rotation) * scope.axes,
        scope.size,
    )
}

/// A snap plane left by `snap(…)` in phase 1: `normal · p = offset`.
#[derive(Clone, Debug)]
pub(crate) struct SnapPlane {
    pub normal: DVec3,
    pub offset: f64,
    pub tag: Option<Arc<str>>,
    pub lot: u32,
    /// The section of the shape that left it (0 without a skeleton).
    pub section: u32,
}

impl SnapPlane {
    /// Moves the plane to where the skeleton's pose puts it (see [`Occluder::pose`]).
    pub fn pose(&mut self, motions: &[Frame]) {
        if let Some(motion) = motions.get(self.section as usize) {
            self.normal = motion.transform_vector(self.normal);
            self.offset += self.normal.dot(motion.translation);
        }
    }
}

/// A shape waiting for phase 2.
#[derive(Debug)]
pub(crate) struct Parked {
    /// The generation it waited at (generations mode).
    pub generation: u32,
    pub rule: RuleId,
    pub args: Vec<Value>,
    pub state: FrozenState,
}

/// The shapes of one lot waiting for phase 2, in the order they started waiting, with the lot's
/// constants as far as phase 1 evaluated them, so that phase 2 sees the same values.
#[derive(Debug)]
pub(crate) struct Waiting {
    pub lot: u32,
    pub origin: DVec3,
    /// The initial shape's axes (`object.*` selectors).
    pub object_axes: shapegram_geom::DMat3,
    /// The initial shape's scope and geometry (`resetGeometry`).
    pub initial: (shapegram_geom::Scope, crate::shape::Geometry),
    pub consts: ConstMemo,
    pub shapes: Vec<Parked>,
    /// The lot's skeleton as phase 1 left it, which phase 2 goes on building.
    pub skeleton: Option<Skeleton>,
}

/// Which occluders a query looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Target {
    /// All lots.
    All,
    /// The querying shape's lot.
    Intra,
    /// The other lots.
    Inter,
}

impl Target {
    /// The target named by a query argument.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "all" => Some(Self::All),
            "intra" => Some(Self::Intra),
            "inter" => Some(Self::Inter),
            _ => None,
        }
    }
}

/// A direction `contextCompare` ranks shapes in (`world.northernmost`, …); north is −z.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Extreme {
    North,
    South,
    East,
    West,
    Highest,
    Lowest,
}

impl Extreme {
    /// The direction named by `contextCompare`'s key.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "world.northernmost" => Self::North,
            "world.southernmost" => Self::South,
            "world.easternmost" => Self::East,
            "world.westernmost" => Self::West,
            "world.highest" => Self::Highest,
            "world.lowest" => Self::Lowest,
            _ => return None,
        })
    }

    /// How far bounds reach in the direction: the larger, the more extreme.
    fn reach(self, b: &Aabb) -> f64 {
        match self {
            Self::North => -b.min.z,
            Self::South => b.max.z,
            Self::East => b.max.x,
            Self::West => -b.min.x,
            Self::Highest => b.max.y,
            Self::Lowest => -b.min.y,
        }
    }
}

/// The occluders and snap planes of phase 1, indexed for the queries of phase 2.
#[derive(Debug, Default)]
pub(crate) struct Context {
    occluders: Vec<Occluder>,
    bvh: Bvh,
    /// Snap planes, by lot.
    snaps: Vec<SnapPlane>,
    names: Vec<Arc<str>>,
}

impl Context {
    /// Indexes the occluders (numbered as their `parent` links expect) and snap planes;
    /// `names` are the program's symbol names, which labels may also match.
    pub fn new(occluders: Vec<Occluder>, mut snaps: Vec<SnapPlane>, names: &[Arc<str>]) -> Self {
        let bounds: Vec<Aabb> = occluders.iter().map(|o| o.bounds).collect();
        snaps.sort_by_key(|s| s.lot);
        Self {
            bvh: Bvh::new(&bounds),
            occluders,
            snaps,
            names: names.to_vec(),
        }
    }

    /// How the shape meets the occluders the target and label select (each of `inside`,
    /// `overlaps`, `touches` holds if it holds for one of them), placed by `motion` when its
    /// skeleton poses it.
    pub fn query(
        &self,
        state: &State,
        motion: Option<&Frame>,
        lot: u32,
        target: Target,
        label: Option<&str>,
    ) -> Contact {
        let mut found = Contact::default();
        let scope = match motion {
            Some(motion) if *motion != Frame::IDENTITY => posed_scope(&state.scope, motion),
            _ => state.scope,
        };
        let geometry = &state.geometry;
        let Some(bounds) = bounds(&scope, geometry) else {
            return found;
        };
        let eps = RELATIVE_TOLERANCE * bounds.diagonal().max(1.0);
        // Most queries find no occluder near them but their own ancestors: they are answered
        // without building the probe's geometry.
        let mut near = Vec::new();
        let reach = Aabb::new(bounds.min - eps, bounds.max + eps);
        self.bvh.query(&reach, |i| {
            let occluder = &self.occluders[i as usize];
            let selected = match target {
                Target::All => true,
                Target::Intra => occluder.lot == lot,
                Target::Inter => occluder.lot != lot,
            } && label.is_none_or(|l| {
                occluder.label.as_deref() == Some(l) || &*self.names[occluder.symbol as usize] == l
            }) && !self.is_ancestor(i, state.occluder);
            if selected {
                near.push(i);
            }
            true
        });
        if near.is_empty() {
            return found;
        }
        let Some(probe) = probe(&scope, geometry) else {
            return found;
        };
        for i in near {
            let c = contact(&probe, &self.occluders[i as usize].pieces, eps);
            found.inside |= c.inside;
            found.overlaps |= c.overlaps;
            found.touches |= c.touches;
            if found.inside && found.overlaps && found.touches {
                break;
            }
        }
        found
    }

    /// The occluders the target and label select for the shape, its own ancestors aside: the
    /// labelled shapes that CGA's context functions look at.
    fn labelled<'a>(
        &'a self,
        state: &'a State,
        lot: u32,
        target: Target,
        label: &'a str,
    ) -> impl Iterator<Item = &'a Occluder> + 'a {
        self.occluders
            .iter()
            .enumerate()
            .filter(move |(i, o)| {
                let in_target = match target {
                    Target::All => true,
                    Target::Intra => o.lot == lot,
                    Target::Inter => o.lot != lot,
                };
                let named =
                    o.label.as_deref() == Some(label) || &*self.names[o.symbol as usize] == label;
                in_target && named && !self.is_ancestor(*i as u32, state.occluder)
            })
            .map(|(_, o)| o)
    }

    /// `contextCount`: how many shapes the target and label select.
    pub fn count(&self, state: &State, lot: u32, target: Target, label: &str) -> usize {
        self.labelled(state, lot, target, label).count()
    }

    /// `minimumDistance`: the least distance between the world bounds of the shape and those
    /// of the shapes the target and label select; infinite when there are none.
    pub fn nearest(&self, state: &State, lot: u32, target: Target, label: &str) -> f64 {
        let Some(own) = bounds(&state.scope, &state.geometry) else {
            return f64::INFINITY;
        };
        self.labelled(state, lot, target, label)
            .map(|o| {
                let gap = (o.bounds.min - own.max)
                    .max(own.min - o.bounds.max)
                    .max(DVec3::ZERO);
                gap.length()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// `contextCompare`: how many of the shapes the target and label select lie further
    /// towards `extreme` than the shape (by their world bounds); ties count as not further.
    pub fn rank(
        &self,
        state: &State,
        lot: u32,
        target: Target,
        label: &str,
        extreme: Extreme,
    ) -> usize {
        let Some(own) = bounds(&state.scope, &state.geometry) else {
            return 0;
        };
        let reach = |b: &Aabb| extreme.reach(b);
        self.labelled(state, lot, target, label)
            .filter(|o| reach(&o.bounds) > reach(&own))
            .count()
    }

    /// Whether occluder `i` is `of` or one of its ancestors. Parents come before their
    /// children, so the walk up ends.
    fn is_ancestor(&self, i: u32, of: u32) -> bool {
        let mut at = of;
        while at != NO_OCCLUDER && at >= i {
            if at == i {
                return true;
            }
            at = self.occluders[at as usize].parent;
        }
        false
    }

    /// Where the snap planes of the lot (with the tag, if one is given) cross the scope's axis
    /// strictly inside the scope, as distances from its origin, ascending and without repeats.
    pub fn snap_positions(
        &self,
        scope: &Scope,
        axis: usize,
        lot: u32,
        tag: Option<&str>,
    ) -> Vec<f64> {
        let direction = scope.axes.col(axis);
        let length = scope.size[axis];
        let eps = RELATIVE_TOLERANCE * length.max(1.0);
        let start = self.snaps.partition_point(|s| s.lot < lot);
        let mut positions: Vec<f64> = self.snaps[start..]
            .iter()
            .take_while(|s| s.lot == lot)
            .filter(|s| tag.is_none_or(|t| s.tag.as_deref() == Some(t)))
            .filter_map(|s| {
                let along = s.normal.dot(direction);
                (along.abs() >= 1.0 - 1e-9)
                    .then(|| (s.offset - s.normal.dot(scope.origin)) / along)
                    .filter(|&t| t > eps && t < length - eps)
            })
            .collect();
        positions.sort_by(f64::total_cmp);
        positions.dedup_by(|a, b| (*a - *b).abs() <= eps);
        positions
    }
}

/// The snap planes of `snap(…)` on a scope hanging from `section`: across each chosen axis, at
/// both ends of the scope.
pub(crate) fn snap_planes(
    scope: &Scope,
    axes: [bool; 3],
    tag: Option<Arc<str>>,
    lot: u32,
    section: u32,
) -> Vec<SnapPlane> {
    (0..3)
        .filter(|&a| axes[a])
        .flat_map(|a| {
            let normal = scope.axes.col(a);
            let near = normal.dot(scope.origin);
            [near, near + scope.size[a]].map(|offset| SnapPlane {
                normal,
                offset,
                tag: tag.clone(),
                lot,
                section,
            })
        })
        .collect()
}

/// The world bounds of a shape's geometry (`None` without geometry).
fn bounds(scope: &Scope, geometry: &Geometry) -> Option<Aabb> {
    match geometry {
        Geometry::Box => Some(scope.aabb()),
        Geometry::Mesh(mesh, _) => {
            Aabb::from_points(mesh.positions().iter().map(|&p| scope.to_world(p)))
        }
        Geometry::Implicit(implicit) => Some(solid_box(scope, &implicit.solid)?.aabb()),
        Geometry::Empty => None,
    }
}

/// The box around an implicit solid in the frame of its scope: what stands for it in occlusion.
fn solid_box(scope: &Scope, solid: &Solid) -> Option<Scope> {
    let local = solid.bounds()?;
    Some(Scope::new(
        scope.to_world(local.min),
        scope.axes,
        local.size(),
    ))
}

/// The probe of a shape: its box or its mesh, in world coordinates.
fn probe(scope: &Scope, geometry: &Geometry) -> Option<Probe> {
    match geometry {
        Geometry::Box => Probe::from_scope(scope),
        Geometry::Mesh(..) => Probe::from_mesh(&geometry.world_mesh(scope)?, MAX_PIECES),
        Geometry::Implicit(implicit) => Probe::from_scope(&solid_box(scope, &implicit.solid)?),
        Geometry::Empty => None,
    }
}
