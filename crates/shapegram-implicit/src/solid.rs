//! Implicit solids as expression trees: primitives, rigid and scaling transforms, CSG and morphing.
//!
//! The convention is the paper's (Definition 1): the field is positive inside, zero on the surface
//! and negative outside. Every solid built here has a 1-Lipschitz field (it changes by at most the
//! distance moved), which the mesher relies on to skip empty space.

use std::sync::Arc;

use glam::{DAffine3, DMat3, DQuat, DVec3};
use shapegram_geom::Aabb;

use crate::error::{ImplicitError, Result, finite, positive};
use crate::primitive::Primitive;

/// A node of the expression tree. Children are shared, so copying a solid is cheap.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// Nothing: the field is −∞ everywhere.
    Empty,
    /// A primitive in its local frame.
    Primitive(Primitive),
    /// `factor · child(inverse(p))`: the child moved by the affine map whose inverse is stored.
    /// The factor (the smallest scale, 1 for rigid maps) keeps the field 1-Lipschitz.
    Transform {
        /// World-to-local map.
        inverse: DAffine3,
        /// What the child's value is multiplied by.
        factor: f64,
        /// The transformed solid.
        child: Arc<Node>,
        /// The child's bounds in its own frame, kept so folding maps stays exact and cheap.
        child_bounds: Option<Aabb>,
        /// The child's [`Reach`] in its own frame, for the same reason (boxed: it is needed only
        /// when maps fold, and would make every node larger).
        child_reach: Option<Box<Reach>>,
    },
    /// Sum, eq. (2): `max(f, g)`.
    Union(Arc<Node>, Arc<Node>),
    /// Difference, eq. (3): `min(f, −g)`.
    Difference(Arc<Node>, Arc<Node>),
    /// Intersection, eq. (4): `min(f, g)`.
    Intersection(Arc<Node>, Arc<Node>),
    /// Morphing, eq. (5): `f·(1 − a) + g·a`.
    Morph(Arc<Node>, Arc<Node>, f64),
    /// Smooth sum: `max` with a round fillet of radius about `k`.
    SmoothUnion(Arc<Node>, Arc<Node>, f64),
    /// Smooth difference: `min(f, −g)` with a round fillet.
    SmoothDifference(Arc<Node>, Arc<Node>, f64),
    /// Smooth intersection: `min` with a round fillet.
    SmoothIntersection(Arc<Node>, Arc<Node>, f64),
}

/// An implicit solid: an expression tree over points of R³.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    root: Arc<Node>,
    /// Worked out when the node is made, from the children's: asking is O(1) however large
    /// the tree and however often subtrees are shared (a morphic production uses the base
    /// twice, so walking the tree would double with every one).
    bounds: Option<Aabb>,
    /// Where the field comes near zero from below, for the bounds of smooth sums.
    reach: Option<Reach>,
}

/// Where a field exceeds any level below zero: every point where it is above `−c` (for any
/// `c ≥ 0`) lies in the box `[min − c·rate, max + c·rate]`. The bounds of a solid hold only
/// where its field is positive; a smooth sum raises fields by up to `k/4`, so it must know where
/// its members exceed `−k/4`. That is not within `k/4` of their bounds unless the fields are
/// exact distances: a field scaled by the smallest factor of a stretch, or the cone's distance
/// to its planes near the apex, falls behind the distance, and `rate` says by how much.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reach {
    /// The box's lower corner at level 0 (it may lie above `max` on an axis: a disjoint
    /// intersection reaches nothing at level 0 but something lower down).
    min: DVec3,
    /// The box's upper corner at level 0.
    max: DVec3,
    /// How far the box grows on each side per unit the level goes down, along each axis.
    rate: DVec3,
}

impl Reach {
    /// The reach of a primitive in its own frame.
    fn primitive(primitive: &Primitive) -> Self {
        let h = primitive.half_extent();
        Self {
            min: -h,
            max: h,
            rate: primitive.level_rate(),
        }
    }

    /// The box holding every point where the field exceeds `−c`, `None` when it is empty.
    fn at(&self, c: f64) -> Option<Aabb> {
        let (min, max) = (self.min - self.rate * c, self.max + self.rate * c);
        min.cmple(max).all().then_some(Aabb { min, max })
    }

    /// The reach of `factor · f(map⁻¹(p))`: `{f' > −c}` is the map of `{f > −c/factor}`, and a
    /// box of half-size `w` maps into one of half-size `|M|·w` (which holds for the negative
    /// half-sizes of a box that is empty at level 0 too, at every level where it is not).
    fn mapped(&self, map: &DAffine3, factor: f64) -> Self {
        let m = map.matrix3.abs();
        let centre = map.transform_point3((self.min + self.max) * 0.5);
        let half = m * ((self.max - self.min) * 0.5);
        Self {
            min: centre - half,
            max: centre + half,
            rate: m * self.rate / factor,
        }
    }

    /// The reach of a field `k` above this one at most: its level `−c` lies within this one's
    /// level `−c − k`.
    fn lowered(&self, k: f64) -> Self {
        Self {
            min: self.min - self.rate * k,
            max: self.max + self.rate * k,
            rate: self.rate,
        }
    }

    /// A reach holding both (for maxima and morphs, which never exceed the larger input).
    fn hull(a: Option<Self>, b: Option<Self>) -> Option<Self> {
        match (a, b) {
            (Some(a), Some(b)) => Some(Self {
                min: a.min.min(b.min),
                max: a.max.max(b.max),
                rate: a.rate.max(b.rate),
            }),
            (a, b) => a.or(b),
        }
    }

    /// A reach holding where both reach (for minima): on each side the tighter limit, growing
    /// at the faster rate, stays outside both limits at every level.
    fn meet(a: Option<Self>, b: Option<Self>) -> Option<Self> {
        let (a, b) = (a?, b?);
        Some(Self {
            min: a.min.max(b.min),
            max: a.max.min(b.max),
            rate: a.rate.max(b.rate),
        })
    }
}

impl Default for Solid {
    fn default() -> Self {
        Self::empty()
    }
}

impl Solid {
    fn from_node(node: Node, bounds: Option<Aabb>, reach: Option<Reach>) -> Self {
        Self {
            root: Arc::new(node),
            bounds,
            reach,
        }
    }

    /// The empty solid, where every production starts.
    pub fn empty() -> Self {
        Self::from_node(Node::Empty, None, None)
    }

    /// A checked primitive.
    pub fn primitive(primitive: Primitive) -> Result<Self> {
        let primitive = primitive.validate()?;
        let h = primitive.half_extent();
        Ok(Self::from_node(
            Node::Primitive(primitive),
            Some(Aabb::new(-h, h)),
            Some(Reach::primitive(&primitive)),
        ))
    }

    /// A ball of radius `radius` centred at the origin.
    pub fn sphere(radius: f64) -> Result<Self> {
        Self::primitive(Primitive::Sphere { radius })
    }

    /// A cuboid with side lengths `size`, centred at the origin.
    pub fn cuboid(size: DVec3) -> Result<Self> {
        Self::primitive(Primitive::Cuboid { size })
    }

    /// A cylinder around the y axis, centred at the origin.
    pub fn cylinder(radius: f64, height: f64) -> Result<Self> {
        Self::primitive(Primitive::Cylinder { radius, height })
    }

    /// A cone around the y axis with its base at `y = -height/2` and apex at `y = +height/2`.
    pub fn cone(radius: f64, height: f64) -> Result<Self> {
        Self::primitive(Primitive::Cone { radius, height })
    }

    /// A pyramid on a `size.x` × `size.z` base at `y = -size.y/2` with its apex above the centre.
    pub fn pyramid(size: DVec3) -> Result<Self> {
        Self::primitive(Primitive::Pyramid { size })
    }

    /// A ring torus in the xz-plane.
    pub fn torus(major: f64, minor: f64) -> Result<Self> {
        Self::primitive(Primitive::Torus { major, minor })
    }

    /// A capsule around the y axis: `length` between the centres of its round caps.
    pub fn capsule(radius: f64, length: f64) -> Result<Self> {
        Self::primitive(Primitive::Capsule { radius, length })
    }

    /// The root of the expression tree.
    pub fn node(&self) -> &Node {
        &self.root
    }

    /// The root as shared, so evaluators can recognise subtrees used more than once.
    pub(crate) fn shared_node(&self) -> &Arc<Node> {
        &self.root
    }

    /// Whether this is the empty solid (by construction, not by evaluation).
    pub fn is_empty(&self) -> bool {
        matches!(*self.root, Node::Empty)
    }

    /// This solid moved by `offset`.
    pub fn translate(&self, offset: DVec3) -> Result<Self> {
        for (axis, v) in ["x", "y", "z"].iter().zip(offset.to_array()) {
            finite(&format!("translation {axis}"), v)?;
        }
        Ok(self.mapped(DAffine3::from_translation(offset), 1.0))
    }

    /// This solid turned by `degrees` around `axis` (right-handed, through the origin).
    pub fn rotate(&self, axis: DVec3, degrees: f64) -> Result<Self> {
        finite("rotation angle", degrees)?;
        if !axis.is_finite() || axis.length_squared() == 0.0 {
            return Err(ImplicitError::new(format!(
                "invalid rotation axis {axis}: expected a finite non-zero vector"
            )));
        }
        let turn = DQuat::from_axis_angle(axis.normalize(), degrees.to_radians());
        Ok(self.mapped(DAffine3::from_quat(turn), 1.0))
    }

    /// This solid scaled by `scale` along each axis (about the origin). Negative factors mirror.
    pub fn scale(&self, scale: DVec3) -> Result<Self> {
        for (axis, v) in ["x", "y", "z"].iter().zip(scale.to_array()) {
            if !(v.is_finite() && v != 0.0) {
                return Err(ImplicitError::new(format!(
                    "invalid scale {axis} {v}: expected a finite non-zero number"
                )));
            }
        }
        let smallest = scale.abs().min_element();
        Ok(self.mapped(DAffine3::from_mat3(DMat3::from_diagonal(scale)), smallest))
    }

    /// This solid under any invertible affine map (for example a scope's local-to-world map):
    /// rotations, non-uniform scales, shears and mirrors alike. The field is multiplied by the
    /// map's smallest singular value, which keeps it 1-Lipschitz.
    pub fn transform(&self, map: &DAffine3) -> Result<Self> {
        let m = map.matrix3;
        let finite = m.to_cols_array().iter().all(|v| v.is_finite()) && map.translation.is_finite();
        let det = m.determinant();
        if !finite || det == 0.0 || !det.is_finite() {
            return Err(ImplicitError::new(
                "invalid transform: expected a finite map that can be inverted",
            ));
        }
        let smallest = smallest_singular_value(m);
        if !(smallest > 0.0 && smallest.is_finite()) {
            return Err(ImplicitError::new(
                "invalid transform: expected a finite map that can be inverted",
            ));
        }
        Ok(self.mapped(*map, smallest))
    }

    /// This solid under an affine map (`factor` as in [`Node::Transform`]). Nested maps fold into
    /// one so evaluation pays for one transform however many were applied.
    fn mapped(&self, map: DAffine3, factor: f64) -> Self {
        let inverse = map.inverse();
        match &*self.root {
            Node::Empty => self.clone(),
            Node::Transform {
                inverse: inner,
                factor: inner_factor,
                child,
                child_bounds,
                child_reach,
            } => {
                let combined = *inner * inverse;
                let (map, factor) = (combined.inverse(), factor * inner_factor);
                Self::from_node(
                    Node::Transform {
                        inverse: combined,
                        factor,
                        child: child.clone(),
                        child_bounds: *child_bounds,
                        child_reach: child_reach.clone(),
                    },
                    child_bounds.map(|b| mapped_box(b, &map)),
                    child_reach.as_ref().map(|r| r.mapped(&map, factor)),
                )
            }
            _ => Self::from_node(
                Node::Transform {
                    inverse,
                    factor,
                    child: self.root.clone(),
                    child_bounds: self.bounds,
                    child_reach: self.reach.map(Box::new),
                },
                self.bounds.map(|b| mapped_box(b, &map)),
                self.reach.map(|r| r.mapped(&map, factor)),
            ),
        }
    }

    /// Sum (eq. 2): points in either solid.
    pub fn union(&self, other: &Solid) -> Self {
        Self::from_node(
            Node::Union(self.root.clone(), other.root.clone()),
            union_bounds(self.bounds, other.bounds),
            Reach::hull(self.reach, other.reach),
        )
    }

    /// Difference (eq. 3): points of this solid outside `other`.
    pub fn difference(&self, other: &Solid) -> Self {
        Self::from_node(
            Node::Difference(self.root.clone(), other.root.clone()),
            self.bounds,
            self.reach,
        )
    }

    /// Intersection (eq. 4): points in both solids.
    pub fn intersection(&self, other: &Solid) -> Self {
        Self::from_node(
            Node::Intersection(self.root.clone(), other.root.clone()),
            intersect_bounds(self.bounds, other.bounds),
            Reach::meet(self.reach, other.reach),
        )
    }

    /// Morphing (eq. 5): `f·(1 − a) + g·a`, so `a = 0` is this solid and `a = 1` is `other`.
    pub fn morph(&self, other: &Solid, a: f64) -> Result<Self> {
        if !(0.0..=1.0).contains(&a) {
            return Err(ImplicitError::new(format!(
                "invalid morphing parameter {a}: expected 0 to 1 (0 % to 100 %)"
            )));
        }
        // A blend never exceeds the larger input, so it lies where either does.
        Ok(Self::from_node(
            Node::Morph(self.root.clone(), other.root.clone(), a),
            union_bounds(self.bounds, other.bounds),
            Reach::hull(self.reach, other.reach),
        ))
    }

    /// Smooth sum with a fillet of radius `k` where the surfaces meet.
    pub fn smooth_union(&self, other: &Solid, k: f64) -> Result<Self> {
        positive("smoothing radius", k)?;
        // The smooth maximum exceeds the larger input only where the inputs differ by less than
        // k, and by at most k/4: past the members' own solids it reaches only where the larger
        // exceeds −k/4 and both exceed −5k/4. That is where their reaches say, not within k/4 of
        // their bounds (which is as far only when the fields are exact distances).
        let q = 0.25 * k;
        let sharp = Reach::hull(self.reach, other.reach);
        let near = Reach::meet(
            self.reach.map(|r| r.lowered(5.0 * q)),
            other.reach.map(|r| r.lowered(5.0 * q)),
        );
        let swell = Reach::meet(sharp.map(|r| r.lowered(q)), near);
        Ok(Self::from_node(
            Node::SmoothUnion(self.root.clone(), other.root.clone(), k),
            union_bounds(
                union_bounds(self.bounds, other.bounds),
                swell.and_then(|r| r.at(0.0)),
            ),
            Reach::hull(sharp, swell),
        ))
    }

    /// Smooth difference with a fillet of radius `k`.
    pub fn smooth_difference(&self, other: &Solid, k: f64) -> Result<Self> {
        positive("smoothing radius", k)?;
        // The smooth minimum never exceeds the smaller input: no larger than this solid.
        Ok(Self::from_node(
            Node::SmoothDifference(self.root.clone(), other.root.clone(), k),
            self.bounds,
            self.reach,
        ))
    }

    /// Smooth intersection with a fillet of radius `k`.
    pub fn smooth_intersection(&self, other: &Solid, k: f64) -> Result<Self> {
        positive("smoothing radius", k)?;
        // The smooth minimum never exceeds the smaller input: within both solids.
        Ok(Self::from_node(
            Node::SmoothIntersection(self.root.clone(), other.root.clone(), k),
            intersect_bounds(self.bounds, other.bounds),
            Reach::meet(self.reach, other.reach),
        ))
    }

    /// The field at `p`: positive inside, zero on the surface, negative outside, −∞ for the
    /// empty solid. This walks the tree once per use of each subtree; for many points compile a
    /// [`crate::tape::Tape`], which evaluates shared subtrees once.
    pub fn value(&self, p: DVec3) -> f64 {
        value(&self.root, p)
    }

    /// A box holding every point where the field is positive, `None` when there is none for
    /// certain (the empty solid, disjoint intersections).
    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    /// Number of distinct primitive nodes in the tree (a shared subtree counts once).
    pub fn primitive_count(&self) -> usize {
        let mut seen = rustc_hash::FxHashSet::default();
        count_primitives(&self.root, &mut seen)
    }
}

/// The field of `node` at `p`.
pub(crate) fn value(node: &Node, p: DVec3) -> f64 {
    match node {
        Node::Empty => f64::NEG_INFINITY,
        Node::Primitive(prim) => prim.value(p),
        Node::Transform {
            inverse,
            factor,
            child,
            ..
        } => factor * value(child, inverse.transform_point3(p)),
        Node::Union(a, b) => value(a, p).max(value(b, p)),
        Node::Difference(a, b) => value(a, p).min(-value(b, p)),
        Node::Intersection(a, b) => value(a, p).min(value(b, p)),
        Node::Morph(a, b, t) => morph(value(a, p), value(b, p), *t),
        Node::SmoothUnion(a, b, k) => smooth_max(value(a, p), value(b, p), *k),
        Node::SmoothDifference(a, b, k) => smooth_min(value(a, p), -value(b, p), *k),
        Node::SmoothIntersection(a, b, k) => smooth_min(value(a, p), value(b, p), *k),
    }
}

/// Eq. (5), exact at the ends so `a = 0` and `a = 1` reproduce the inputs even where one of them
/// is −∞ (the empty solid), and exact when both inputs are equal.
pub(crate) fn morph(f: f64, g: f64, a: f64) -> f64 {
    if a == 0.0 || f == g {
        f
    } else if a == 1.0 {
        g
    } else if f.is_finite() && g.is_finite() {
        // The same as f·(1 − a) + g·a, written so that blending a value with itself gives it
        // back exactly (which lets evaluators skip a morph of a shape with itself).
        f + (g - f) * a
    } else {
        f * (1.0 - a) + g * a
    }
}

/// The polynomial smooth maximum: equal to `max` when the values differ by more than `k`, and at
/// most `k/4` above it in between. Its gradient is a convex combination of the inputs' gradients,
/// so it stays 1-Lipschitz.
pub(crate) fn smooth_max(f: f64, g: f64, k: f64) -> f64 {
    if f == g {
        // Also covers −∞ on both sides, where the blend below would be NaN.
        return f + 0.25 * k;
    }
    let h = (0.5 + 0.5 * (f - g) / k).clamp(0.0, 1.0);
    if h == 0.0 {
        g
    } else if h == 1.0 {
        f
    } else {
        g + (f - g) * h + k * h * (1.0 - h)
    }
}

/// The polynomial smooth minimum, the mirror of [`smooth_max`].
pub(crate) fn smooth_min(f: f64, g: f64, k: f64) -> f64 {
    -smooth_max(-f, -g, k)
}

/// The smallest singular value of `m` (the square root of the smallest eigenvalue of `mᵀm`, by the
/// closed form for symmetric 3 × 3 matrices), shaded down a little so rounding cannot overstate
/// it.
fn smallest_singular_value(m: DMat3) -> f64 {
    let a = m.transpose() * m;
    let (a00, a11, a22) = (a.x_axis.x, a.y_axis.y, a.z_axis.z);
    let (a01, a02, a12) = (a.y_axis.x, a.z_axis.x, a.z_axis.y);
    let off = a01 * a01 + a02 * a02 + a12 * a12;
    let q = (a00 + a11 + a22) / 3.0;
    let smallest = if off <= f64::EPSILON * q * q {
        a00.min(a11).min(a22)
    } else {
        let p2 = (a00 - q).powi(2) + (a11 - q).powi(2) + (a22 - q).powi(2) + 2.0 * off;
        let p = (p2 / 6.0).sqrt();
        let b = (a - DMat3::from_diagonal(DVec3::splat(q))) * (1.0 / p);
        let r = (b.determinant() / 2.0).clamp(-1.0, 1.0);
        let phi = r.acos() / 3.0;
        // The eigenvalues are q + 2p·cos(φ + 2πk/3); k = 1 gives the smallest.
        q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos()
    };
    smallest.max(0.0).sqrt() * (1.0 - 1e-9)
}

/// The box holding `b` mapped by `map`.
fn mapped_box(b: Aabb, map: &DAffine3) -> Aabb {
    let corners = (0..8).map(|i| {
        let pick = |bit: usize, lo: f64, hi: f64| if i >> bit & 1 == 0 { lo } else { hi };
        map.transform_point3(DVec3::new(
            pick(0, b.min.x, b.max.x),
            pick(1, b.min.y, b.max.y),
            pick(2, b.min.z, b.max.z),
        ))
    });
    Aabb::from_points(corners).expect("eight corners")
}

fn intersect_bounds(a: Option<Aabb>, b: Option<Aabb>) -> Option<Aabb> {
    let (a, b) = (a?, b?);
    let (min, max) = (a.min.max(b.min), a.max.min(b.max));
    min.cmple(max).all().then_some(Aabb { min, max })
}

fn union_bounds(a: Option<Aabb>, b: Option<Aabb>) -> Option<Aabb> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.union(b)),
        (a, b) => a.or(b),
    }
}

fn count_primitives(node: &Arc<Node>, seen: &mut rustc_hash::FxHashSet<*const Node>) -> usize {
    if !seen.insert(Arc::as_ptr(node)) {
        return 0;
    }
    match &**node {
        Node::Empty => 0,
        Node::Primitive(_) => 1,
        Node::Transform { child, .. } => count_primitives(child, seen),
        Node::Union(a, b)
        | Node::Difference(a, b)
        | Node::Intersection(a, b)
        | Node::Morph(a, b, _)
        | Node::SmoothUnion(a, b, _)
        | Node::SmoothDifference(a, b, _)
        | Node::SmoothIntersection(a, b, _) => {
            count_primitives(a, seen) + count_primitives(b, seen)
        }
    }
}
