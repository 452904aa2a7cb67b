//! A static bounding-volume hierarchy over axis-aligned boxes: built once, then asked which boxes
//! meet a query box in time logarithmic in their number.

use crate::{Aabb, DVec3};

/// Items per leaf node: small enough that a query tests few boxes it does not need, large enough
/// that the tree stays shallow.
const LEAF_SIZE: usize = 4;

/// A bounding-volume hierarchy over boxes numbered `0..n` in the order they were given.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Item numbers, grouped so that every node covers a contiguous range.
    items: Vec<u32>,
    /// The boxes, by item number.
    boxes: Vec<Aabb>,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    /// For a leaf, the first of its items; for an inner node, the index of its second child
    /// (the first child follows the node directly).
    index: u32,
    /// Number of items of a leaf; 0 for an inner node.
    count: u32,
}

impl Bvh {
    /// Builds the hierarchy over `boxes` (median splits along the longest axis of the centres).
    /// The shape of the tree depends only on the boxes and their order.
    pub fn new(boxes: &[Aabb]) -> Self {
        let mut bvh = Self {
            nodes: Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1),
            items: (0..boxes.len() as u32).collect(),
            boxes: boxes.to_vec(),
        };
        if !boxes.is_empty() {
            let centres: Vec<DVec3> = boxes.iter().map(Aabb::center).collect();
            bvh.build(boxes, &centres, 0, boxes.len());
        }
        bvh
    }

    /// Number of boxes in the hierarchy.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the hierarchy holds no boxes.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    fn build(&mut self, boxes: &[Aabb], centres: &[DVec3], start: usize, end: usize) -> usize {
        let range = &mut self.items[start..end];
        let bounds = range
            .iter()
            .map(|&i| boxes[i as usize])
            .reduce(Aabb::union)
            .expect("a node covers at least one item");
        let at = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            index: start as u32,
            count: (end - start) as u32,
        });
        if end - start <= LEAF_SIZE {
            return at;
        }
        let spread = range
            .iter()
            .map(|&i| centres[i as usize])
            .fold(
                Aabb::new(centres[range[0] as usize], centres[range[0] as usize]),
                |b, p| b.including(p),
            )
            .size();
        let axis = if spread.x >= spread.y && spread.x >= spread.z {
            0
        } else if spread.y >= spread.z {
            1
        } else {
            2
        };
        let mid = (end - start) / 2;
        // Ties are broken by item number, so the tree does not depend on the sort's internals.
        range.select_nth_unstable_by(mid, |&a, &b| {
            centres[a as usize][axis]
                .total_cmp(&centres[b as usize][axis])
                .then(a.cmp(&b))
        });
        self.build(boxes, centres, start, start + mid);
        let second = self.build(boxes, centres, start + mid, end);
        self.nodes[at].index = second as u32;
        self.nodes[at].count = 0;
        at
    }

    /// Calls `visit` with every box that meets `query` (touching counts), in a fixed order for a
    /// given hierarchy; stops early when `visit` returns `false`.
    pub fn query(&self, query: &Aabb, mut visit: impl FnMut(u32) -> bool) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let id = stack[top];
            let node = self.nodes[id as usize];
            if !meets(&node.bounds, query) {
                continue;
            }
            if node.count > 0 {
                let first = node.index as usize;
                for &item in &self.items[first..first + node.count as usize] {
                    if meets(&self.boxes[item as usize], query) && !visit(item) {
                        return;
                    }
                }
            } else {
                // Median splits keep the depth near log2(n), far below the stack's 64 slots.
                stack[top] = node.index;
                stack[top + 1] = id + 1;
                top += 2;
            }
        }
    }
}

/// Whether two boxes share at least one point.
fn meets(a: &Aabb, b: &Aabb) -> bool {
    a.min.cmple(b.max).all() && b.min.cmple(a.max).all()
}
