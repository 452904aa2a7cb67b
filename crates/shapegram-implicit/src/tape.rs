//! A solid compiled to a flat list of instructions that evaluates whole blocks of points at a
//! time: one dispatch per instruction per block instead of one per node per point.

use std::sync::Arc;

use glam::{DAffine3, DVec3};
use rustc_hash::FxHashMap;

use crate::primitive::Primitive;
use crate::solid::{Node, Solid, morph, smooth_max, smooth_min};

/// One instruction. Point sets and values are numbered in the order the instructions make them,
/// each by one instruction; point set 0 is the input.
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
    /// A value times a factor, as a new value: pruning reads bounds of the value before and of
    /// the one after, which one value changed in place could not both give.
    Scale {
        src: usize,
        out: usize,
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
    /// Number of point sets and values the instructions make: a pruned tape counts only its own.
    point_sets: usize,
    values: usize,
    result: usize,
    /// A bound on how fast each value changes per unit of distance in world space.
    lipschitz: Vec<f64>,
    registers: Registers,
}

/// Where each point set and value is kept during evaluation. Storage that nothing will read
/// again is handed on to the next point set or value made, so a workspace holds only as many as
/// are live at once, not one per instruction of a long tape.
#[derive(Clone, Debug, Default)]
struct Registers {
    point_set: Vec<u32>,
    value: Vec<u32>,
    point_sets: usize,
    values: usize,
}

/// Where an already emitted node's value lives, keyed by the node's address and its point set:
/// a subtree shared by several parents (as a morphic production shares the base) is evaluated
/// once per point instead of once per use.
type Emitted = FxHashMap<(*const Node, usize), usize>;

/// Scratch memory for evaluating tapes on blocks of up to `capacity` points; one per thread. It
/// grows to fit the tapes it evaluates.
#[derive(Debug)]
pub struct Workspace {
    capacity: usize,
    points: Vec<[Vec<f64>; 3]>,
    values: Vec<Vec<f64>>,
    /// Every point set and value of a tape at one point, each in storage of its own: pruning
    /// compares them all.
    probe_points: Vec<[Vec<f64>; 3]>,
    probe_values: Vec<Vec<f64>>,
}

impl Workspace {
    /// Scratch memory for blocks of up to `capacity` points, holding nothing yet.
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity,
            points: Vec::new(),
            values: Vec::new(),
            probe_points: Vec::new(),
            probe_values: Vec::new(),
        }
    }
}

/// Grows `points` and `values` to at least `sets` and `slots` entries of `capacity` samples.
fn fit(
    points: &mut Vec<[Vec<f64>; 3]>,
    values: &mut Vec<Vec<f64>>,
    (sets, slots): (usize, usize),
    capacity: usize,
) {
    if points.len() < sets {
        points.resize_with(sets, || std::array::from_fn(|_| vec![0.0; capacity]));
    }
    if values.len() < slots {
        values.resize_with(slots, || vec![0.0; capacity]);
    }
}

impl Tape {
    /// Compiles `solid`.
    pub fn new(solid: &Solid) -> Self {
        let mut tape = Self {
            ops: Vec::new(),
            point_sets: 1,
            values: 0,
            result: 0,
            lipschitz: Vec::new(),
            registers: Registers::default(),
        };
        tape.result = tape.emit(solid.shared_node(), 0, 1.0, &mut Emitted::default());
        tape.registers = Registers::allocate(&tape.ops, tape.point_sets, tape.values, tape.result);
        tape
    }

    /// The field at one point.
    pub fn value(&self, ws: &mut Workspace, p: DVec3) -> f64 {
        // One sample per value is little memory, and saves looking up where each is kept.
        self.probe(ws, p)[self.result][0]
    }

    /// Evaluates every value at `p` into storage of its own; returns the values.
    fn probe<'w>(&self, ws: &'w mut Workspace, p: DVec3) -> &'w [Vec<f64>] {
        let (points, values) = (&mut ws.probe_points, &mut ws.probe_values);
        fit(points, values, (self.point_sets, self.values), 1);
        let c = p.to_array();
        let at = [&c[0..1], &c[1..2], &c[2..3]];
        self.run(points, values, at, 1, |p| p, |v| v);
        values
    }

    /// Scratch memory for blocks of up to `capacity` points, sized for this tape.
    pub fn workspace(&self, capacity: usize) -> Workspace {
        let mut ws = Workspace::new(capacity);
        let r = &self.registers;
        fit(
            &mut ws.points,
            &mut ws.values,
            (r.point_sets, r.values),
            capacity,
        );
        ws
    }

    /// Emits the instructions of `node` evaluated on point set `points` (once); returns its
    /// value.
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
                let src = self.emit(child, dst, lip / factor, emitted);
                if *factor == 1.0 {
                    return src;
                }
                let out = self.slot();
                self.ops.push(Op::Scale {
                    src,
                    out,
                    factor: *factor,
                });
                out
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
        self.values += 1;
        self.lipschitz.push(1.0);
        self.values - 1
    }

    /// The tape specialised to the ball of `radius` around `centre`, giving exactly the same
    /// result everywhere in the ball: where an operand of a maximum or minimum cannot win
    /// anywhere in the ball (by Lipschitz bounds around the values at the centre), it and
    /// everything only it needs are dropped. A cave of fifty primitives keeps the few near each
    /// block. The pruned tape numbers only what it keeps, so its workspace is as small as it is.
    pub fn pruned(&self, ws: &mut Workspace, centre: DVec3, radius: f64) -> Tape {
        let values = self.probe(ws, centre);
        let range = |slot: usize| {
            let v = values[slot][0];
            let spread = self.lipschitz[slot] * radius;
            (v - spread, v + spread)
        };
        // First compare siblings; then, on what is left (where chains of sums are no longer
        // shared with morphs that turned out to blend a shape with itself), bound each operand
        // by the whole chain above it.
        let (ops, result) = self.prune_pass(&self.ops, self.result, &range, None);
        let (ops, result) = self.live(ops, result);
        let limits = self.limits_from_above(&ops, result, &range);
        let (ops, result) = self.prune_pass(&ops, result, &range, Some(&limits));
        let (ops, result) = self.live(ops, result);
        self.renumbered(ops, result)
    }

    /// The tape of `ops`, a subsequence of this tape's with `result` among their values, with
    /// point sets and values numbered afresh from 0 in the order they are made, so that a small
    /// tape's bookkeeping is small too.
    fn renumbered(&self, mut ops: Vec<Op>, result: usize) -> Tape {
        let mut point_set = vec![usize::MAX; self.point_sets];
        let mut value = vec![usize::MAX; self.values];
        point_set[0] = 0;
        let mut point_sets = 1;
        let mut lipschitz = Vec::new();
        for op in &mut ops {
            // What an instruction reads was made earlier and has its new number already; what it
            // makes takes the next.
            let made = match op {
                Op::Map { src, dst, .. } => {
                    *src = point_set[*src];
                    point_set[*dst] = point_sets;
                    *dst = point_sets;
                    point_sets += 1;
                    continue;
                }
                Op::Primitive { points, out, .. } => {
                    *points = point_set[*points];
                    out
                }
                Op::Fill { out, .. } => out,
                Op::Scale { src, out, .. } => {
                    *src = value[*src];
                    out
                }
                Op::Binary { a, b, out, .. } => {
                    (*a, *b) = (value[*a], value[*b]);
                    out
                }
            };
            value[*made] = lipschitz.len();
            lipschitz.push(self.lipschitz[*made]);
            *made = value[*made];
        }
        let values = lipschitz.len();
        let result = value[result];
        let registers = Registers::allocate(&ops, point_sets, values, result);
        Tape {
            ops,
            point_sets,
            values,
            result,
            lipschitz,
            registers,
        }
    }

    /// One pass of pruning: each binary operation whose outcome is decided in the ball becomes an
    /// alias of the operand that decides it. `limits` are the floors and ceilings of
    /// [`Tape::limits_from_above`], if any.
    fn prune_pass(
        &self,
        ops: &[Op],
        result: usize,
        range: &impl Fn(usize) -> (f64, f64),
        limits: Option<&(Vec<f64>, Vec<f64>)>,
    ) -> (Vec<Op>, usize) {
        let mut alias: Vec<usize> = (0..self.values).collect();
        let mut kept = Vec::with_capacity(ops.len());
        for op in ops {
            let mut op = op.clone();
            match &mut op {
                Op::Binary { kind, a, b, out } => {
                    (*a, *b) = (alias[*a], alias[*b]);
                    let ((a_lo, a_hi), (b_lo, b_hi)) = (range(*a), range(*b));
                    let (f, c) = limits.map_or((f64::NEG_INFINITY, f64::INFINITY), |(f, c)| {
                        (f[*out], c[*out])
                    });
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
                Op::Scale { src, .. } => *src = alias[*src],
                _ => {}
            }
            kept.push(op);
        }
        (kept, alias[result])
    }

    /// `ops` without what nothing reads on the way to `result`.
    fn live(&self, ops: Vec<Op>, result: usize) -> (Vec<Op>, usize) {
        let mut live_slot = vec![false; self.values];
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
                Op::Fill { out, .. } => live_slot[out],
                Op::Scale { src, out, .. } => {
                    live_slot[src] |= live_slot[out];
                    live_slot[out]
                }
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
    /// nothing else reads, but not the root's. No bound is passed on through a transform's scale:
    /// dividing it by the factor would round.
    fn limits_from_above(
        &self,
        ops: &[Op],
        result: usize,
        range: &impl Fn(usize) -> (f64, f64),
    ) -> (Vec<f64>, Vec<f64>) {
        let mut uses = vec![0u32; self.values];
        uses[result] += 1;
        for op in ops {
            match *op {
                Op::Binary { a, b, .. } => {
                    uses[a] += 1;
                    uses[b] += 1;
                }
                Op::Scale { src, .. } => uses[src] += 1,
                _ => {}
            }
        }
        let mut floor = vec![f64::NEG_INFINITY; self.values];
        let mut ceiling = vec![f64::INFINITY; self.values];
        for op in ops.iter().rev() {
            let Op::Binary { kind, a, b, out } = *op else {
                continue;
            };
            let (lo, hi) = range(out);
            let only = |slot: usize| uses[slot] == 1;
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
        let r = &self.registers;
        fit(
            &mut ws.points,
            &mut ws.values,
            (r.point_sets, r.values),
            ws.capacity,
        );
        let point_set = |p: usize| r.point_set[p] as usize;
        let value = |v: usize| r.value[v] as usize;
        self.run(
            &mut ws.points,
            &mut ws.values,
            [xs, ys, zs],
            n,
            point_set,
            value,
        );
        out.copy_from_slice(&ws.values[value(self.result)][..n]);
    }

    /// Runs the instructions on the first `n` of `input`, keeping point set `p` in
    /// `points[point_set(p)]` and value `v` in `values[value(v)]`.
    fn run(
        &self,
        points: &mut [[Vec<f64>; 3]],
        values: &mut [Vec<f64>],
        input: [&[f64]; 3],
        n: usize,
        point_set: impl Fn(usize) -> usize,
        value: impl Fn(usize) -> usize,
    ) {
        for (axis, src) in input.into_iter().enumerate() {
            points[point_set(0)][axis][..n].copy_from_slice(&src[..n]);
        }
        for op in &self.ops {
            match *op {
                Op::Map { src, dst, ref map } => {
                    let (from, to) = two_mut(points, point_set(src), point_set(dst));
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
                    points: at,
                    out,
                    primitive,
                } => {
                    let [x, y, z] = &points[point_set(at)];
                    primitive.values(x, y, z, &mut values[value(out)][..n]);
                }
                Op::Fill { out, value: v } => values[value(out)][..n].fill(v),
                Op::Scale { src, out, factor } => {
                    let (from, to) = two_mut(values, value(src), value(out));
                    for (t, &f) in to[..n].iter_mut().zip(&from[..n]) {
                        *t = f * factor;
                    }
                }
                Op::Binary { kind, a, b, out } => {
                    // Registers never give an instruction's result the storage of an operand.
                    let mut result = std::mem::take(&mut values[value(out)]);
                    let (va, vb) = (&values[value(a)][..n], &values[value(b)][..n]);
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
                    values[value(out)] = result;
                }
            }
        }
    }
}

impl Registers {
    /// Storage for the point sets and values of `ops` (`result` is read after the last): each
    /// holds its storage from the instruction that makes it to its last reader, and storage is
    /// handed on once its holder is dead. Walking back from the end, a value becomes live at its
    /// last reader and dead at its maker, so one pass suffices.
    fn allocate(ops: &[Op], point_sets: usize, values: usize, result: usize) -> Self {
        let mut sets = Pool::default();
        let mut slots = Pool::default();
        let mut point_set = vec![NONE; point_sets];
        let mut value = vec![NONE; values];
        slots.hold(&mut value[result]);
        for op in ops.iter().rev() {
            // What an instruction makes keeps its storage while what it reads takes some, so
            // the two never share.
            let (made_set, read_set, made, read) = match *op {
                Op::Map { src, dst, .. } => (Some(dst), Some(src), None, [None; 2]),
                Op::Primitive { points, out, .. } => (None, Some(points), Some(out), [None; 2]),
                Op::Fill { out, .. } => (None, None, Some(out), [None; 2]),
                Op::Scale { src, out, .. } => (None, None, Some(out), [Some(src), None]),
                Op::Binary { a, b, out, .. } => (None, None, Some(out), [Some(a), Some(b)]),
            };
            if let Some(p) = made_set {
                sets.hold(&mut point_set[p]);
            }
            if let Some(v) = made {
                slots.hold(&mut value[v]);
            }
            if let Some(p) = read_set {
                sets.hold(&mut point_set[p]);
            }
            for v in read.into_iter().flatten() {
                slots.hold(&mut value[v]);
            }
            if let Some(p) = made_set {
                sets.free(point_set[p]);
            }
            if let Some(v) = made {
                slots.free(value[v]);
            }
        }
        // The input is copied in before the first instruction, wherever it is kept.
        sets.hold(&mut point_set[0]);
        Self {
            point_set,
            value,
            point_sets: sets.made as usize,
            values: slots.made as usize,
        }
    }
}

/// No storage yet.
const NONE: u32 = u32::MAX;

/// Numbers of storage, made as needed and handed out again once freed.
#[derive(Default)]
struct Pool {
    made: u32,
    free: Vec<u32>,
}

impl Pool {
    /// Gives `register` storage unless it has some: the most recently freed (likeliest to be in
    /// cache) or a new one.
    fn hold(&mut self, register: &mut u32) {
        if *register == NONE {
            *register = self.free.pop().unwrap_or_else(|| {
                self.made += 1;
                self.made - 1
            });
        }
    }

    fn free(&mut self, register: u32) {
        self.free.push(register);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `tape` on `input` with every point set and value in storage of its own, as tapes ran
    /// before storage was shared: what evaluation must reproduce bit for bit.
    fn unshared(tape: &Tape, input: [&[f64]; 3]) -> Vec<u64> {
        let n = input[0].len();
        let (mut points, mut values) = (Vec::new(), Vec::new());
        fit(&mut points, &mut values, (tape.point_sets, tape.values), n);
        tape.run(&mut points, &mut values, input, n, |p| p, |v| v);
        values[tape.result][..n]
            .iter()
            .map(|v| v.to_bits())
            .collect()
    }

    fn evaluated(tape: &Tape, ws: &mut Workspace, [xs, ys, zs]: [&[f64]; 3]) -> Vec<u64> {
        let mut out = vec![0.0; xs.len()];
        tape.eval(ws, xs, ys, zs, &mut out);
        out.iter().map(|v| v.to_bits()).collect()
    }

    /// Samples of block storage a workspace holds.
    fn samples(ws: &Workspace) -> usize {
        (ws.points.len() * 3 + ws.values.len()) * ws.capacity
    }

    /// Sixty-four hollowed, scaled and turned cubes ten units apart along x, joined by a
    /// balanced tree of unions, morphed with itself plus a ball (so the tree is shared).
    fn row() -> Solid {
        let mut members: Vec<Solid> = (0..64)
            .map(|i| {
                Solid::cuboid(DVec3::splat(2.0))
                    .unwrap()
                    .difference(&Solid::sphere(1.2).unwrap())
                    .scale(DVec3::splat(1.5))
                    .unwrap()
                    .rotate(DVec3::Y, 7.0 * f64::from(i))
                    .unwrap()
                    .translate(DVec3::new(10.0 * f64::from(i), 0.0, 0.0))
                    .unwrap()
            })
            .collect();
        while members.len() > 1 {
            members = members.chunks(2).map(|p| p[0].union(&p[1])).collect();
        }
        let tree = members.pop().unwrap();
        let ball = Solid::sphere(1.0)
            .unwrap()
            .translate(DVec3::new(300.0, 5.0, 0.0))
            .unwrap();
        tree.morph(&tree.union(&ball), 0.4).unwrap()
    }

    #[test]
    fn a_pruned_tape_has_a_workspace_of_its_own_size_and_the_same_values() {
        let full = Tape::new(&row());
        // A block of 5³ points around the eleventh cube, all inside the ball pruned to.
        let centre = DVec3::new(100.0, 0.0, 0.0);
        let block: Vec<DVec3> = (0..125)
            .map(|i| {
                let step = DVec3::new(f64::from(i % 5), f64::from(i / 5 % 5), f64::from(i / 25));
                centre + 0.7 * step - 1.4
            })
            .collect();
        let coords = [0, 1, 2].map(|a| block.iter().map(|p| p[a]).collect::<Vec<f64>>());
        let input = coords.each_ref().map(|c| &c[..]);
        let mut full_ws = full.workspace(125);
        let pruned = full.pruned(&mut full_ws, centre, 2.5);

        // The whole tape runs in 2 point sets and 9 values of storage, not one per instruction.
        assert_eq!((full.len(), full.point_sets, full.values), (387, 66, 322));
        assert_eq!((full.registers.point_sets, full.registers.values), (2, 9));
        // Pruned to the one cube, whose tape numbers only its own point sets and values.
        assert_eq!((pruned.len(), pruned.point_sets, pruned.values), (5, 2, 4));
        assert_eq!(pruned.lipschitz.len(), 4);
        let mut pruned_ws = pruned.workspace(125);
        assert_eq!(samples(&full_ws), (2 * 3 + 9) * 125);
        assert_eq!(samples(&pruned_ws), (2 * 3 + 3) * 125);

        let expected = unshared(&full, input);
        let inside = expected.iter().filter(|&&v| f64::from_bits(v) > 0.0);
        assert_eq!(inside.count(), 16);
        assert_eq!(evaluated(&full, &mut full_ws, input), expected);
        assert_eq!(unshared(&pruned, input), expected);
        assert_eq!(evaluated(&pruned, &mut pruned_ws, input), expected);
        // A workspace grows to fit a longer tape than its own, and serves shorter ones as is.
        assert_eq!(evaluated(&full, &mut pruned_ws, input), expected);
        assert_eq!(samples(&pruned_ws), (2 * 3 + 9) * 125);
        let again = pruned.pruned(&mut full_ws, centre, 2.5);
        assert_eq!(evaluated(&again, &mut full_ws, input), expected);
    }

    #[test]
    fn pruning_inside_a_scaled_transform_bounds_the_scaled_value() {
        // The difference is decided for the far ball `a` alone; halved, `a` comes within 4 of
        // the origin, nearer than `c`, though unscaled it is 10 away.
        let a = Solid::sphere(1.0)
            .unwrap()
            .translate(DVec3::new(11.0, 0.0, 0.0))
            .unwrap();
        let b = Solid::sphere(0.1)
            .unwrap()
            .translate(DVec3::new(-60.0, 0.0, 0.0))
            .unwrap();
        let c = Solid::sphere(1.0)
            .unwrap()
            .translate(DVec3::new(-7.0, 0.0, 0.0))
            .unwrap();
        let solid = c.union(&a.difference(&b).scale(DVec3::splat(0.5)).unwrap());
        let full = Tape::new(&solid);
        let mut ws = full.workspace(1);
        let pruned = full.pruned(&mut ws, DVec3::ZERO, 1.0);
        // Only `b` and the difference go.
        assert_eq!((full.len(), pruned.len()), (10, 7));
        // Around x = 0.5 the halved `a` alone is left (two maps, the ball and the scale).
        let again = pruned.pruned(&mut ws, DVec3::X * 0.5, 0.5);
        assert_eq!(again.len(), 4);
        for (x, expected) in [
            (-1.0, -5.0),
            (-0.5, -5.5),
            (0.0, -5.0),
            (0.5, -4.5),
            (1.0, -4.0),
        ] {
            let p = DVec3::X * x;
            assert_eq!(full.value(&mut ws, p), expected);
            assert_eq!(pruned.value(&mut ws, p), expected);
            if x >= 0.0 {
                assert_eq!(again.value(&mut ws, p), expected);
            }
        }
    }
}
