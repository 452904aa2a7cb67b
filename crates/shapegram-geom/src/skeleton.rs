//! Straight skeletons of simple polygons by wavefront propagation.
//!
//! Every edge of the polygon moves towards its left side (the inside of a counter-clockwise
//! polygon) at unit speed, keeping its direction; corners slide along the bisectors of their edges.
//! The wavefront changes shape at events, found one at a time (the earliest first):
//! - an **edge event**: an edge shrinks to nothing and its two corners merge;
//! - a **split event**: a reflex corner runs into another part of the wavefront, which splits in
//!   two there (a corner meeting a corner is the same event).
//!
//! After the wavefront is advanced to an event, everything that coincides within a tolerance is
//! resolved together, so the many simultaneous events of rectilinear footprints (an L collapsing
//! into its ridge) need no special cases: runs of coinciding neighbours merge, a loop is cut in two
//! where a corner touches one of its edges or another of its corners, two-corner loops are ridges
//! and loops without area points. Nodes go where the lines involved meet, and surviving corners
//! back onto the crossing of their two lines, so rounding does not pile up from event to event.
//!
//! Each corner traces a path from the node where it appeared to the node where it ends; that path
//! bounds the faces of its two edges, so collecting the paths per edge gives the skeleton's faces,
//! and every path is shared by exactly two faces in opposite directions.
//!
//! The same propagation stopped at a distance gives the mitred offset (the wavefront) and the
//! border faces swept on the way; run on the reversed polygon, it grows the polygon outward.
//! Each event costs a scan over all corner–edge pairs: O(n³) for n corners, fine for footprints.

use rustc_hash::FxHashMap as HashMap;

use crate::{
    DVec2,
    planar::{perimeter, point_segment_distance, signed_area},
};

/// Coincidence tolerance relative to the polygon's size. Coarser than the validation tolerance,
/// as corners arrive at a shared event along different paths with their own rounding.
const RELATIVE_TOLERANCE: f64 = 1e-8;

/// A node of the skeleton: a point where a corner path starts or ends.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    /// Position in the plane.
    pub p: DVec2,
    /// Distance the wavefront had travelled when it made the node (the height of a roof is this
    /// times the slope).
    pub time: f64,
}

/// The result of a propagation.
#[derive(Clone, Debug)]
pub(crate) struct Skeleton {
    /// Nodes; the first ones are the polygon's corners, in order, at time zero.
    pub nodes: Vec<Node>,
    /// For each polygon edge, the face it swept as a counter-clockwise node loop that starts with
    /// the edge itself.
    pub faces: Vec<Vec<usize>>,
    /// The wavefront where the propagation stopped, as node loops (empty when it ran to the end).
    pub front: Vec<Vec<usize>>,
}

/// The line an input edge lies on at time zero.
#[derive(Clone, Copy, Debug)]
struct Line {
    /// A point of the line.
    point: DVec2,
    /// Unit direction.
    dir: DVec2,
    /// Unit normal pointing away from the side the wavefront moves into.
    out: DVec2,
    /// How fast the edge moves (1 for a straight skeleton; 0 keeps it where it is).
    speed: f64,
}

impl Line {
    /// How far the edge has moved by `time`.
    fn moved(&self, time: f64) -> f64 {
        // Unit speeds skip the product, so plain skeletons round exactly as they always did.
        if self.speed == 1.0 {
            time
        } else {
            time * self.speed
        }
    }
}

/// A corner of the moving wavefront, between the edges of input edges `e_in` and `e_out`.
#[derive(Clone, Copy, Debug)]
struct Corner {
    p: DVec2,
    vel: DVec2,
    /// The node where this corner appeared.
    node: usize,
    e_in: usize,
    e_out: usize,
}

/// State of one propagation.
struct Propagation {
    lines: Vec<Line>,
    nodes: Vec<Node>,
    /// Directed node pairs bounding each input edge's face, the edge itself first.
    face_edges: Vec<Vec<(usize, usize)>>,
    eps: f64,
    now: f64,
    /// Nodes from this index on were made at the current time and may be reused.
    fresh_nodes: usize,
    /// Whether every loop must stay counter-clockwise (true for insets and roofs; a growing
    /// polygon's outer loop runs clockwise).
    require_ccw: bool,
}

/// Propagates the wavefront of a simple polygon (no repeated corners) towards the left of its
/// edges for a distance `until` (> 0; infinity to run until it vanishes). Returns `None` when the
/// input has a zero-length edge or a corner that turns back, or when the propagation cannot
/// resolve an event consistently.
pub(crate) fn propagate(polygon: &[DVec2], until: f64, require_ccw: bool) -> Option<Skeleton> {
    propagate_weighted(polygon, &vec![1.0; polygon.len()], until, require_ccw)
}

/// Like [`propagate`], with edge `i` moving at `speeds[i]` (0 or more): a weighted straight
/// skeleton. Edges of speed 0 stay put and the corners beside them slide along them, which is
/// how a setback moves some edges of a lot and not others.
pub(crate) fn propagate_weighted(
    polygon: &[DVec2],
    speeds: &[f64],
    until: f64,
    require_ccw: bool,
) -> Option<Skeleton> {
    let n = polygon.len();
    if n < 3 || until.is_nan() || until <= 0.0 || speeds.len() != n {
        return None;
    }
    if speeds.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
        return None;
    }
    let lines = (0..n)
        .map(|i| {
            let dir = (polygon[(i + 1) % n] - polygon[i]).try_normalize()?;
            Some(Line {
                point: polygon[i],
                dir,
                out: DVec2::new(dir.y, -dir.x),
                speed: speeds[i],
            })
        })
        .collect::<Option<Vec<_>>>()?;
    let (lo, hi) = polygon.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let mut state = Propagation {
        lines,
        nodes: polygon.iter().map(|&p| Node { p, time: 0.0 }).collect(),
        face_edges: (0..n).map(|i| vec![(i, (i + 1) % n)]).collect(),
        eps: RELATIVE_TOLERANCE * lo.distance(hi),
        now: 0.0,
        fresh_nodes: n,
        require_ccw,
    };
    let first = (0..n)
        .map(|i| {
            let e_in = (i + n - 1) % n;
            Some(Corner {
                p: polygon[i],
                vel: state.velocity(e_in, i)?,
                node: i,
                e_in,
                e_out: i,
            })
        })
        .collect::<Option<Vec<_>>>()?;
    let mut loops = vec![first];
    let mut front = Vec::new();
    // A straight skeleton has O(n) events; the budget only stops a propagation that stalls.
    let mut budget = 20 * n + 100;
    while !loops.is_empty() {
        budget = budget.checked_sub(1)?;
        let remaining = until - state.now;
        let (step, last) = match state.next_event(&loops) {
            Some(t) if t < remaining => (t, false),
            _ if remaining.is_finite() => (remaining, true),
            _ => return None,
        };
        for c in loops.iter_mut().flatten() {
            c.p += c.vel * step;
        }
        state.now = if last { until } else { state.now + step };
        loops = state.resolve(loops)?;
        if last {
            front = loops.iter().map(|l| state.close_off(l)).collect();
            break;
        }
    }
    let faces = state
        .face_edges
        .iter()
        .map(|edges| chain(edges))
        .collect::<Option<Vec<_>>>()?;
    Some(Skeleton {
        nodes: state.nodes,
        faces,
        front,
    })
}

impl Propagation {
    /// Velocity of a corner between two edges: it stays on both moving lines. `None` when the
    /// edges run in opposite directions to within about 10⁻⁸ rad (a hair-thin spike, whose corner
    /// would run at a speed that rounding makes meaningless).
    fn velocity(&self, e_in: usize, e_out: usize) -> Option<DVec2> {
        let (a, b) = (self.lines[e_in], self.lines[e_out]);
        let (o1, o2) = (a.out, b.out);
        let cosine = o1.dot(o2);
        if a.speed == b.speed {
            let denominator = 1.0 + cosine;
            let unit = (denominator > 1e-16).then(|| -(o1 + o2) / denominator)?;
            return Some(if a.speed == 1.0 { unit } else { unit * a.speed });
        }
        // v·o1 = −w1 and v·o2 = −w2, solved for v = α·o1 + β·o2; edges of different speeds
        // meeting in a straight line have no corner that keeps to both.
        let sine2 = 1.0 - cosine * cosine;
        if sine2 <= 1e-16 {
            return None;
        }
        let alpha = (-a.speed + b.speed * cosine) / sine2;
        let beta = (-b.speed + a.speed * cosine) / sine2;
        Some(o1 * alpha + o2 * beta)
    }

    /// The node at `p` made at the current time, reusing one within tolerance.
    fn node_at(&mut self, p: DVec2) -> usize {
        if let Some(i) =
            (self.fresh_nodes..self.nodes.len()).find(|&i| self.nodes[i].p.distance(p) <= self.eps)
        {
            return i;
        }
        self.nodes.push(Node { p, time: self.now });
        self.nodes.len() - 1
    }

    /// Ends a corner at a node: its path bounds the faces of its two edges, running up the face
    /// of the incoming edge and down the face of the outgoing one.
    fn end(&mut self, c: &Corner, node: usize) {
        if c.node != node {
            self.face_edges[c.e_in].push((c.node, node));
            self.face_edges[c.e_out].push((node, c.node));
        }
    }

    /// A new corner at a node (its velocity is set once its loop is settled).
    fn start(&self, node: usize, e_in: usize, e_out: usize) -> Corner {
        Corner {
            p: self.nodes[node].p,
            vel: DVec2::ZERO,
            node,
            e_in,
            e_out,
        }
    }

    /// Time until the earliest event, `None` if nothing will ever happen.
    fn next_event(&self, loops: &[Vec<Corner>]) -> Option<f64> {
        let mut best: Option<f64> = None;
        let mut consider = |t: f64| {
            if t.is_finite() && best.is_none_or(|b| t < b) {
                best = Some(t.max(0.0));
            }
        };
        for lp in loops {
            let m = lp.len();
            for (i, a) in lp.iter().enumerate() {
                let b = &lp[(i + 1) % m];
                let dir = self.lines[a.e_out].dir;
                let rate = (b.vel - a.vel).dot(dir);
                if rate < 0.0 {
                    consider((b.p - a.p).dot(dir) / -rate);
                }
            }
            for (i, c) in lp.iter().enumerate() {
                let turn = self.lines[c.e_in].dir.perp_dot(self.lines[c.e_out].dir);
                if turn >= -1e-12 {
                    // Only reflex corners can run into the rest of the wavefront.
                    continue;
                }
                for j in 0..m {
                    let k = (j + 1) % m;
                    if j == i || k == i {
                        continue;
                    }
                    let (a, b) = (&lp[j], &lp[k]);
                    let line = self.lines[a.e_out];
                    let gap = (c.p - a.p).dot(line.out);
                    let closing = line.speed + c.vel.dot(line.out);
                    if gap >= 0.0 || closing <= 1e-12 {
                        continue;
                    }
                    let t = -gap / closing;
                    let hit = c.p + c.vel * t;
                    let (pa, pb) = (a.p + a.vel * t, b.p + b.vel * t);
                    let along = (hit - pa).dot(line.dir);
                    if along >= -self.eps && along <= (pb - pa).dot(line.dir) + self.eps {
                        consider(t);
                    }
                }
            }
        }
        best
    }

    /// Resolves everything that coincides at the current time; returns the loops that go on.
    fn resolve(&mut self, loops: Vec<Vec<Corner>>) -> Option<Vec<Vec<Corner>>> {
        self.fresh_nodes = self.nodes.len();
        let mut work = loops;
        let mut settled = Vec::new();
        while let Some(lp) = work.pop() {
            let Some(mut lp) = self.merge_runs(lp) else {
                continue;
            };
            if let Some((i, j)) = self.touching(&lp) {
                let (a, b) = self.split_at_edge(&lp, i, j);
                work.push(a);
                work.push(b);
                continue;
            }
            if let Some((i, j)) = self.coinciding(&lp) {
                let (a, b) = self.split(&lp, i, j);
                work.push(a);
                work.push(b);
                continue;
            }
            let points: Vec<DVec2> = lp.iter().map(|c| c.p).collect();
            let area = signed_area(&points);
            if lp.len() < 3 {
                // Two corners: the loop has become a ridge between them.
                self.close_off(&lp);
                continue;
            }
            // A loop without area left after the steps above is a point whose corners arrived a
            // little apart by rounding; ending them all at one node keeps the faces around it
            // closed. A small loop with real area goes on to collapse where it should.
            let inverted = self.require_ccw && area < 0.0;
            if area.abs() <= self.eps * self.eps
                || (inverted && -area <= self.eps * perimeter(&points))
            {
                self.shrink_to_point(&lp);
                continue;
            }
            if inverted {
                return None;
            }
            if let Some(k) = lp
                .iter()
                .position(|c| self.velocity(c.e_in, c.e_out).is_none())
            {
                work.push(self.retract_spike(&lp, k));
                continue;
            }
            for c in &mut lp {
                c.vel = self.velocity(c.e_in, c.e_out)?;
                if let Some(p) = self.meet(c.e_in, c.e_out) {
                    c.p = p;
                }
            }
            settled.push(lp);
        }
        Some(settled)
    }

    /// Merges runs of neighbouring corners that coincide (edge events) into one corner each.
    /// Returns `None` when the whole loop shrank to a point.
    fn merge_runs(&mut self, lp: Vec<Corner>) -> Option<Vec<Corner>> {
        let m = lp.len();
        let close: Vec<bool> = (0..m)
            .map(|i| lp[i].p.distance(lp[(i + 1) % m].p) <= self.eps)
            .collect();
        if !close.contains(&true) {
            return Some(lp);
        }
        if close.iter().all(|&c| c) {
            self.shrink_to_point(&lp);
            return None;
        }
        // Start at a corner that does not coincide with its predecessor, so no run wraps around.
        let start = (0..m).find(|&i| !close[(i + m - 1) % m])?;
        let mut merged = Vec::with_capacity(m);
        let mut i = 0;
        while i < m {
            let mut last = i;
            while close[(start + last) % m] {
                last += 1;
            }
            if last == i {
                merged.push(lp[(start + i) % m]);
            } else {
                let run: Vec<Corner> = (i..=last).map(|k| lp[(start + k) % m]).collect();
                let node = self.node_at(self.meeting_point(&run, None));
                for c in &run {
                    self.end(c, node);
                }
                merged.push(self.start(node, run[0].e_in, run[run.len() - 1].e_out));
            }
            i = last + 1;
        }
        Some(merged)
    }

    /// Ends every corner of a loop at one node where they meet.
    fn shrink_to_point(&mut self, lp: &[Corner]) {
        let node = self.node_at(self.meeting_point(lp, None));
        for c in lp {
            self.end(c, node);
        }
    }

    /// Where corners that coincide within tolerance really meet: the point closest (least
    /// squares) to the moved lines of their edges and of edge `extra` (the edge a corner runs
    /// into), which all pass through it when the event is exact. Placing nodes there rather than at the corners' mean keeps the
    /// roof faces planar to rounding even where corners arrived almost a tolerance apart. Falls
    /// back to the mean when the lines are nearly parallel or do not meet within tolerance of it.
    fn meeting_point(&self, corners: &[Corner], extra: Option<usize>) -> DVec2 {
        let mean = corners.iter().map(|c| c.p).sum::<DVec2>() / corners.len() as f64;
        let mut lines: Vec<usize> = corners
            .iter()
            .flat_map(|c| [c.e_in, c.e_out])
            .chain(extra)
            .collect();
        lines.sort_unstable();
        lines.dedup();
        // Normal equations of min Σ (x·out − offset)² over the lines: [[a, b], [b, c]] x = r.
        let (mut a, mut b, mut c, mut r) = (0.0, 0.0, 0.0, DVec2::ZERO);
        for line in lines.iter().map(|&e| self.lines[e]) {
            let o = line.out;
            a += o.x * o.x;
            b += o.x * o.y;
            c += o.y * o.y;
            r += o * (line.point.dot(o) - line.moved(self.now));
        }
        let det = a * c - b * b;
        if det <= 1e-6 * (a + c) * (a + c) {
            return mean;
        }
        let x = DVec2::new(c * r.x - b * r.y, a * r.y - b * r.x) / det;
        if x.distance(mean) <= self.eps {
            x
        } else {
            mean
        }
    }

    /// Where the lines of two input edges, both moved in by the current time, cross; `None` when
    /// they are too close to parallel for that to be accurate. Corners are put there after each
    /// event, so rounding does not pile up from event to event.
    fn meet(&self, e_in: usize, e_out: usize) -> Option<DVec2> {
        let (a, b) = (self.lines[e_in], self.lines[e_out]);
        let sine = a.dir.dot(b.out);
        if sine.abs() < 1e-3 {
            return None;
        }
        let start = a.point - a.out * a.moved(self.now);
        let along = (-b.moved(self.now) - (start - b.point).dot(b.out)) / sine;
        Some(start + a.dir * along)
    }

    /// A corner `i` lying on the inside of a non-neighbouring edge `j → j + 1`.
    fn touching(&self, lp: &[Corner]) -> Option<(usize, usize)> {
        let m = lp.len();
        (0..m).find_map(|i| {
            let p = lp[i].p;
            (0..m)
                .find(|&j| {
                    let k = (j + 1) % m;
                    let (a, b) = (lp[j].p, lp[k].p);
                    j != i
                        && k != i
                        && a.distance(p) > self.eps
                        && b.distance(p) > self.eps
                        && point_segment_distance(p, a, b) <= self.eps
                })
                .map(|j| (i, j))
        })
    }

    /// Two corners `i < j`, not neighbours, at the same place.
    fn coinciding(&self, lp: &[Corner]) -> Option<(usize, usize)> {
        let m = lp.len();
        (0..m).find_map(|i| {
            (i + 2..m)
                .find(|&j| !(i == 0 && j == m - 1) && lp[i].p.distance(lp[j].p) <= self.eps)
                .map(|j| (i, j))
        })
    }

    /// Retracts the hair-thin spike at corner `k`: its tip would run down the spike almost at
    /// once, so it merges with its nearer neighbour now, leaving a level ridge along the spike.
    fn retract_spike(&mut self, lp: &[Corner], k: usize) -> Vec<Corner> {
        let m = lp.len();
        let (prev, next) = ((k + m - 1) % m, (k + 1) % m);
        let tip = lp[k];
        let keep = if tip.p.distance(lp[prev].p) <= tip.p.distance(lp[next].p) {
            prev
        } else {
            next
        };
        let node = self.node_at(self.meeting_point(&lp[keep..=keep], None));
        self.end(&tip, node);
        self.end(&lp[keep], node);
        let merged = if keep == prev {
            self.start(node, lp[prev].e_in, tip.e_out)
        } else {
            self.start(node, tip.e_in, lp[next].e_out)
        };
        (0..m)
            .filter(|&i| i != k && i != keep)
            .map(|i| lp[i])
            .chain([merged])
            .collect()
    }

    /// Cuts a loop where corner `i` touches the inside of edge `j → j + 1` into the two loops on
    /// either side (a split event).
    fn split_at_edge(&mut self, lp: &[Corner], i: usize, j: usize) -> (Vec<Corner>, Vec<Corner>) {
        let m = lp.len();
        let e = lp[j].e_out;
        let node = self.node_at(self.meeting_point(&lp[i..=i], Some(e)));
        self.end(&lp[i], node);
        let cyclic = |from: usize, to: usize| {
            let count = (to + m - from) % m + 1;
            (0..count).map(move |k| lp[(from + k) % m])
        };
        let mut first = vec![self.start(node, e, lp[i].e_out)];
        first.extend(cyclic((i + 1) % m, j));
        let mut second = vec![self.start(node, lp[i].e_in, e)];
        second.extend(cyclic((j + 1) % m, (i + m - 1) % m));
        (first, second)
    }

    /// Cuts a loop that touches itself at corners `i < j` into the two loops on either side.
    fn split(&mut self, lp: &[Corner], i: usize, j: usize) -> (Vec<Corner>, Vec<Corner>) {
        let node = self.node_at(self.meeting_point(&[lp[i], lp[j]], None));
        self.end(&lp[i], node);
        self.end(&lp[j], node);
        let mut first = vec![self.start(node, lp[j].e_in, lp[i].e_out)];
        first.extend_from_slice(&lp[i + 1..j]);
        let mut second = vec![self.start(node, lp[i].e_in, lp[j].e_out)];
        second.extend_from_slice(&lp[j + 1..]);
        second.extend_from_slice(&lp[..i]);
        (first, second)
    }

    /// Ends every corner of a loop at a node and closes the faces of its edges along it (a ridge
    /// for a loop without area, the offset outline when the propagation stops). Returns the loop's
    /// nodes.
    fn close_off(&mut self, lp: &[Corner]) -> Vec<usize> {
        let nodes: Vec<usize> = lp
            .iter()
            .map(|c| {
                let node = self.node_at(self.meeting_point(&[*c], None));
                self.end(c, node);
                node
            })
            .collect();
        let m = lp.len();
        for k in 0..m {
            let (a, b) = (nodes[k], nodes[(k + 1) % m]);
            if a != b {
                // The face lies behind the wavefront edge, so its boundary runs back along it.
                self.face_edges[lp[k].e_out].push((b, a));
            }
        }
        nodes
    }
}

/// Chains a face's directed node pairs into one loop, starting with the first pair. Pairs that run
/// back and forth along the same nodes cancel. `None` unless the pairs form exactly one loop.
fn chain(edges: &[(usize, usize)]) -> Option<Vec<usize>> {
    let mut count: HashMap<(usize, usize), i32> = HashMap::default();
    for &(a, b) in edges.iter().filter(|(a, b)| a != b) {
        let back = count.entry((b, a)).or_default();
        if *back > 0 {
            *back -= 1;
        } else {
            *count.entry((a, b)).or_default() += 1;
        }
    }
    let mut next: HashMap<usize, usize> = HashMap::default();
    let mut total = 0;
    for (&(a, b), &k) in &count {
        if k > 1 || (k == 1 && next.insert(a, b).is_some()) {
            return None;
        }
        total += usize::try_from(k).ok()?;
    }
    let start = edges.first()?.0;
    let mut face = vec![start];
    let mut at = *next.get(&start)?;
    while at != start {
        if face.len() >= total {
            return None;
        }
        face.push(at);
        at = *next.get(&at)?;
    }
    (face.len() == total).then_some(face)
}

/// The outline of the union of `faces` (node loops at `positions` that share nodes and tile a
/// region): the directed edges that no other face runs back along, chained into loops in the
/// order their first edges appear. Where the region touches itself at a node, each loop turns
/// as far left as it can there, so every loop comes out simple. `None` if the edges do not
/// close into loops.
pub(crate) fn outline(faces: &[&[usize]], positions: &[DVec2]) -> Option<Vec<Vec<usize>>> {
    let edges: Vec<(usize, usize)> = faces
        .iter()
        .flat_map(|f| (0..f.len()).map(move |i| (f[i], f[(i + 1) % f.len()])))
        .filter(|(a, b)| a != b)
        .collect();
    let all: rustc_hash::FxHashSet<(usize, usize)> = edges.iter().copied().collect();
    let boundary: Vec<(usize, usize)> = edges
        .into_iter()
        .filter(|&(a, b)| !all.contains(&(b, a)))
        .collect();
    let mut leaving: HashMap<usize, Vec<usize>> = HashMap::default();
    for &(a, b) in &boundary {
        leaving.entry(a).or_default().push(b);
    }
    let mut used: rustc_hash::FxHashSet<(usize, usize)> = rustc_hash::FxHashSet::default();
    let mut loops = Vec::new();
    for &first in &boundary {
        if used.contains(&first) {
            continue;
        }
        let mut loop_ = Vec::new();
        let (mut from, mut at) = first;
        used.insert(first);
        loop {
            loop_.push(from);
            if at == first.0 {
                break;
            }
            if loop_.len() > boundary.len() {
                return None;
            }
            let incoming = positions[at] - positions[from];
            let next = leaving
                .get(&at)?
                .iter()
                .copied()
                .filter(|&b| !used.contains(&(at, b)))
                .max_by(|&b, &c| {
                    let turn = |b: usize| {
                        let out = positions[b] - positions[at];
                        incoming.perp_dot(out).atan2(incoming.dot(out))
                    };
                    turn(b).total_cmp(&turn(c))
                })?;
            used.insert((at, next));
            (from, at) = (at, next);
        }
        loops.push(loop_);
    }
    Some(loops)
}
