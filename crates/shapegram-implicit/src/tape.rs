//! A solid compiled to a flat list of instructions that evaluates whole blocks of points at a
//! time: one dispatch per instruction per block instead of one per node per point.

use std::sync::Arc;

use glam::{DAffine3, DVec3};
use rustc_hash::FxHashMap;

use crate::primitive::Primitive;
use crate::solid::{Node, Solid, morph, smooth_max, smooth_min};

/// One instruction. Point sets and value slots are numbered; point set 0 is the input.
#[derive(Clone, Debug)]
enum Op {
    Map {
        src: usize,
        dst: usize,
        map: DAffine3,
    },
    Primitive {
        points: usize,
        out: usize,
        primitive: Primitive,
    },
    Fill {
        out: usize,
        value: f64,
    },
    Scale {
        slot: usize,
        factor: f64,
    },
    Binary {
        kind: Binary,
        a: usize,
        b: usize,
        out: usize,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Binary {
    Max,
    Min,
    MinNeg,
    Morph(f64),
    SmoothMax(f64),
    SmoothMin(f64),
    SmoothMinNeg(f64),
}

/// A compiled solid.
#[derive(Clone, Debug)]
pub struct Tape {
    ops: Vec<Op>,
    point_sets: usize,
    slots: usize,
    result: usize,
    /// A bound on how fast each slot's final value changes per unit of distance in world space.
    lipschitz: Vec<f64>,
}

/// Where an already emitted node's value lives, keyed by the node's address and its point set:
/// a subtree shared by several parents (as a morphic production shares the base) is evaluated
/// once per point instead of once per use.
type Emitted = FxHashMap<(*const Node, usize), usize>;

/// Scratch memory for evaluating a tape on blocks of up to `capacity` points; one per thread.
#[derive(Debug)]
pub struct Workspace {
    points: Vec<[Vec<f64>; 3]>,
    values: Vec<Vec<f64>>,
}

impl Tape {
    /// Compiles `solid`.
    pub fn new(solid: &Solid) -> Self {
        let mut tape = Self {
            ops: Vec::new(),
            point_sets: 1,
            slots: 0,
            result: 0,
            lipschitz: Vec::new(),
        };
        tape.result = tape.emit(solid.shared_node(), 0, 1.0, &mut Emitted::default());
        tape
    }

    /// The field at one point (a block of one).
    pub fn value(&self, ws: &mut Workspace, p: DVec3) -> f64 {
        let mut out = [0.0];
        self.eval(ws, &[p.x], &[p.y], &[p.z], &mut out);
        out[0]
    }

    /// Scratch memory for blocks of up to `capacity` points.
    pub fn workspace(&self, capacity: usize) -> Workspace {
        Workspace {
            points: (0..self.point_sets)
                .map(|_| std::array::from_fn(|_| vec![0.0; capacity]))
                .collect(),
            values: (0..self.slots).map(|_| vec![0.0; capacity]).collect(),
        }
    }

    /// Emits the instructions of `node` evaluated on point set `points` (once); returns its value
    /// slot.
    /// `lip` bounds the node's rate of change in world space.
    fn emit(&mut self, node: &Arc<Node>, points: usize, lip: f64, emitted: &mut Emitted) -> usize {
        let key = (Arc::as_ptr(node), points);
        if let Some(&slot) = emitted.get(&key) {
            return slot;
        }
        let slot = self.emit_new(node, points, lip, emitted);
        self.lipschitz[slot] = lip;
        emitted.insert(key, slot);
        slot
    }

    fn emit_new(&mut self, node: &Node, points: usize, lip: f64, emitted: &mut Emitted) -> usize {
        match node {
            Node::Empty => {
                let out = self.slot();
                self.ops.push(Op::Fill {
                    out,
                    value: f64::NEG_INFINITY,
                });
                out
            }
            Node::Primitive(primitive) => {
                let out = self.slot();
                self.ops.push(Op::Primitive {
                    points,
                    out,
                    primitive: *primitive,
                });
                out
            }
            Node::Transform {
                inverse,
                factor,
                child,
                ..
            } => {
                let dst = self.point_sets;
                self.point_sets += 1;
                self.ops.push(Op::Map {
                    src: points,
                    dst,
                    map: *inverse,
                });
                // The child sees points under the inverse map, which stretches distances by at
                // most 1 / factor; the factor then scales its values back.
                let slot = self.emit(child, dst, lip / factor, emitted);
                if *factor != 1.0 {
                    self.ops.push(Op::Scale {
                        slot,
                        factor: *factor,
                    });
                }
                slot
            }
            Node::Union(a, b) => self.binary(Binary::Max, [a, b], points, lip, emitted),
            Node::Difference(a, b) => self.binary(Binary::MinNeg, [a, b], points, lip, emitted),
            Node::Intersection(a, b) => self.binary(Binary::Min, [a, b], points, lip, emitted),
            Node::Morph(a, b, t) => self.binary(Binary::Morph(*t), [a, b], points, lip, emitted),
            Node::SmoothUnion(a, b, k) => {
                self.binary(Binary::SmoothMax(*k), [a, b], points, lip, emitted)
            }
            Node::SmoothDifference(a, b, k) => {
                self.binary(Binary::SmoothMinNeg(*k), [a, b], points, lip, emitted)
            }
            Node::SmoothIntersection(a, b, k) => {
                self.binary(Binary::SmoothMin(*k), [a, b], points, lip, emitted)
            }
        }
    }

    fn binary(
        &mut self,
        kind: Binary,
        [a, b]: [&Arc<Node>; 2],
        points: usize,
        lip: f64,
        emitted: &mut Emitted,
    ) -> usize {
        let a = self.emit(a, points, lip, emitted);
        let b = self.emit(b, points, lip, emitted);
        let out = self.slot();
        self.ops.push(Op::Binary { kind, a, b, out });
        out
    }

    fn slot(&mut self) -> usize {
        self.slots += 1;
        self.lipschitz.push(1.0);
        self.slots - 1
    }

    /// The tape specialised to the ball of `radius` around `centre`, giving exactly the same
    /// result everywhere in the ball: where an operand of a maximum or minimum cannot win
    /// anywhere in the ball (by Lipschitz bounds around the values at the centre), it and
    /// everything only it needs are dropped. A cave of fifty primitives keeps the few near each
    /// block.
    pub fn pruned(&self, ws: &mut Workspace, centre: DVec3, radius: f64) -> Tape {
        self.value(ws, centre);
        let range = |slot: usize| {
            let v = ws.values[slot][0];
            let spread = self.lipschitz[slot] * radius;
            (v - spread, v + spread)
        };
        // First compare siblings; then, on what is left (where chains of sums are no longer
        // shared with morphs that turned out to blend a shape with itself), bound each operand
        // by the whole chain above it.
        let unbounded = (
            vec![f64::NEG_INFINITY; self.slots],
            vec![f64::INFINITY; self.slots],
        );
        let (ops, result) = self.prune_pass(&self.ops, self.result, &range, &unbounded);
        let (ops, result) = self.live(ops, result);
        let limits = self.limits_from_above(&ops, result, &range);
        let (ops, result) = self.prune_pass(&ops, result, &range, &limits);
        let (ops, result) = self.live(ops, result);
        Tape {
            ops,
            point_sets: self.point_sets,
            slots: self.slots,
            result,
            lipschitz: self.lipschitz.clone(),
        }
    }

    /// One pass of pruning: each binary operation whose outcome is decided in the ball becomes an
    /// alias of the operand that decides it. `limits` are the floors and ceilings of
    /// [`Tape::limits_from_above`].
    fn prune_pass(
        &self,
        ops: &[Op],
        result: usize,
        range: &impl Fn(usize) -> (f64, f64),
        (floor, ceiling): &(Vec<f64>, Vec<f64>),
    ) -> (Vec<Op>, usize) {
        let mut alias: Vec<usize> = (0..self.slots).collect();
        let mut kept = Vec::with_capacity(ops.len());
        for op in ops {
            let mut op = op.clone();
            match &mut op {
                Op::Binary { kind, a, b, out } => {
                    (*a, *b) = (alias[*a], alias[*b]);
                    let ((a_lo, a_hi), (b_lo, b_hi)) = (range(*a), range(*b));
                    let (f, c) = (floor[*out], ceiling[*out]);
                    let winner = match *kind {
                        _ if a == b
                            && !matches!(kind, Binary::MinNeg | Binary::SmoothMinNeg(_)) =>
                        {
                            // max(f, f), min(f, f) and morph(f, f, t) are f exactly; the smooth
                            // ones are not (they bulge), so leave those.
                            matches!(kind, Binary::Max | Binary::Min | Binary::Morph(_))
                                .then_some(*a)
                        }
                        Binary::Max if a_lo >= b_hi || b_hi < f => Some(*a),
                        Binary::Max if b_lo >= a_hi || a_hi < f => Some(*b),
                        Binary::Min if a_hi <= b_lo || b_lo > c => Some(*a),
                        Binary::Min if b_hi <= a_lo || a_lo > c => Some(*b),
                        Binary::MinNeg if a_hi <= -b_hi || -b_hi > c => Some(*a),
                        Binary::SmoothMax(k) if a_lo - k >= b_hi => Some(*a),
                        Binary::SmoothMax(k) if b_lo - k >= a_hi => Some(*b),
                        Binary::SmoothMin(k) if a_hi + k <= b_lo => Some(*a),
                        Binary::SmoothMin(k) if b_hi + k <= a_lo => Some(*b),
                        Binary::SmoothMinNeg(k) if a_hi + k <= -b_hi => Some(*a),
                        _ => None,
                    };
                    if let Some(w) = winner {
                        alias[*out] = w;
                        continue;
                    }
                }
                Op::Scale { slot, .. } => *slot = alias[*slot],
                _ => {}
            }
            kept.push(op);
        }
        (kept, alias[result])
    }

    /// `ops` without what nothing reads on the way to `result`.
    fn live(&self, ops: Vec<Op>, result: usize) -> (Vec<Op>, usize) {
        let mut live_slot = vec![false; self.slots];
        let mut live_points = vec![false; self.point_sets];
        live_slot[result] = true;
        let mut needed = vec![false; ops.len()];
        for (i, op) in ops.iter().enumerate().rev() {
            needed[i] = match *op {
                Op::Map { src, dst, .. } => {
                    live_points[src] |= live_points[dst];
                    live_points[dst]
                }
                Op::Primitive { points, out, .. } => {
                    live_points[points] |= live_slot[out];
                    live_slot[out]
                }
                Op::Fill { out, .. } | Op::Scale { slot: out, .. } => live_slot[out],
                Op::Binary { a, b, out, .. } => {
                    if live_slot[out] {
                        live_slot[a] = true;
                        live_slot[b] = true;
                    }
                    live_slot[out]
                }
            };
        }
        let ops = ops
            .into_iter()
            .zip(needed)
            .filter_map(|(op, n)| n.then_some(op))
            .collect();
        (ops, result)
    }

    /// For every slot that is a maximum (minimum), a value below (above) which an operand cannot
    /// matter anywhere in the ball: its own lower (upper) bound, raised (lowered) by that of the
    /// maximum (minimum) it alone feeds. In a long chain of sums only the root's bound tells
    /// that a far-away part never wins; comparing siblings alone would keep the whole chain.
    /// Dropping such an operand changes the value of the slots between it and the root, which
    /// nothing else reads, but not the root's. Slots scaled in place by a transform are left out
    /// (their producing op sees them unscaled).
    fn limits_from_above(
        &self,
        ops: &[Op],
        result: usize,
        range: &impl Fn(usize) -> (f64, f64),
    ) -> (Vec<f64>, Vec<f64>) {
        let mut uses = vec![0u32; self.slots];
        let mut scaled = vec![false; self.slots];
        uses[result] += 1;
        for op in ops {
            match *op {
                Op::Binary { a, b, .. } => {
                    uses[a] += 1;
                    uses[b] += 1;
                }
                Op::Scale { slot, .. } => scaled[slot] = true,
                _ => {}
            }
        }
        let mut floor = vec![f64::NEG_INFINITY; self.slots];
        let mut ceiling = vec![f64::INFINITY; self.slots];
        for op in ops.iter().rev() {
            let Op::Binary { kind, a, b, out } = *op else {
                continue;
            };
            if scaled[out] {
                continue;
            }
            let (lo, hi) = range(out);
            let only = |slot: usize| uses[slot] == 1 && !scaled[slot];
            match kind {
                Binary::Max => {
                    floor[out] = floor[out].max(lo);
                    for child in [a, b] {
                        if only(child) {
                            floor[child] = floor[child].max(floor[out]);
                        }
                    }
                }
                Binary::Min | Binary::MinNeg => {
                    ceiling[out] = ceiling[out].min(hi);
                    if only(a) {
                        ceiling[a] = ceiling[a].min(ceiling[out]);
                    }
                    if only(b) {
                        if kind == Binary::Min {
                            ceiling[b] = ceiling[b].min(ceiling[out]);
                        } else {
                            // min(a, −b): −b matters only below the ceiling, b above its negation.
                            floor[b] = floor[b].max(-ceiling[out]);
                        }
                    }
                }
                _ => {}
            }
        }
        (floor, ceiling)
    }

    /// Number of instructions (a measure of evaluation cost).
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the tape has no instructions (never: even the empty solid fills its slot).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Evaluates the field at the points `(xs[i], ys[i], zs[i])` into `out`. All slices have
    /// `out`'s length, at most the workspace's capacity.
    pub fn eval(&self, ws: &mut Workspace, xs: &[f64], ys: &[f64], zs: &[f64], out: &mut [f64]) {
        let n = out.len();
        for (axis, src) in [xs, ys, zs].into_iter().enumerate() {
            ws.points[0][axis][..n].copy_from_slice(&src[..n]);
        }
        for op in &self.ops {
            match *op {
                Op::Map { src, dst, ref map } => {
                    let (from, to) = two_mut(&mut ws.points, src, dst);
                    let m = map.matrix3;
                    let t = map.translation;
                    let [x, y, z] = &from;
                    let [tx, ty, tz] = to;
                    for i in 0..n {
                        let (px, py, pz) = (x[i], y[i], z[i]);
                        tx[i] = m.x_axis.x * px + m.y_axis.x * py + m.z_axis.x * pz + t.x;
                        ty[i] = m.x_axis.y * px + m.y_axis.y * py + m.z_axis.y * pz + t.y;
                        tz[i] = m.x_axis.z * px + m.y_axis.z * py + m.z_axis.z * pz + t.z;
                    }
                }
                Op::Primitive {
                    points,
                    out,
                    primitive,
                } => {
                    let [x, y, z] = &ws.points[points];
                    primitive.values(x, y, z, &mut ws.values[out][..n]);
                }
                Op::Fill { out, value } => ws.values[out][..n].fill(value),
                Op::Scale { slot, factor } => {
                    for v in &mut ws.values[slot][..n] {
                        *v *= factor;
                    }
                }
                Op::Binary { kind, a, b, out } => {
                    let mut result = std::mem::take(&mut ws.values[out]);
                    let (va, vb) = (&ws.values[a][..n], &ws.values[b][..n]);
                    let r = &mut result[..n];
                    match kind {
                        Binary::Max => zip(r, va, vb, f64::max),
                        Binary::Min => zip(r, va, vb, f64::min),
                        Binary::MinNeg => zip(r, va, vb, |f, g| f.min(-g)),
                        Binary::Morph(t) => zip(r, va, vb, |f, g| morph(f, g, t)),
                        Binary::SmoothMax(k) => zip(r, va, vb, |f, g| smooth_max(f, g, k)),
                        Binary::SmoothMin(k) => zip(r, va, vb, |f, g| smooth_min(f, g, k)),
                        Binary::SmoothMinNeg(k) => zip(r, va, vb, |f, g| smooth_min(f, -g, k)),
                    }
                    ws.values[out] = result;
                }
            }
        }
        out.copy_from_slice(&ws.values[self.result][..n]);
    }
}

fn zip(out: &mut [f64], a: &[f64], b: &[f64], f: impl Fn(f64, f64) -> f64) {
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = f(x, y);
    }
}

/// A shared borrow of `v[a]` and a mutable one of `v[b]` (`a != b`).
fn two_mut<T>(v: &mut [T], a: usize, b: usize) -> (&T, &mut T) {
    assert_ne!(a, b);
    if a < b {
        let (lo, hi) = v.split_at_mut(b);
        (&lo[a], &mut hi[0])
    } else {
        let (lo, hi) = v.split_at_mut(a);
        (&hi[0], &mut lo[b])
    }
}
