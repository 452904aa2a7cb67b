//! Coplanar merge by sorting, for the planes most of a city lies in: a plane of constant x, y or
//! z whose rectangles run along the other two axes (the facades and roofs of boxes). Each such
//! rectangle is an interval on each in-plane axis; sorting them by the interval they span
//! across an axis and then along it lines neighbours up, so merging is a scan. This gives the
//! same kind of result as the edge map of [`super::coplanar`] (rectangles that share a whole edge
//! become one) with sequential memory access instead of a hash lookup per edge.

use super::coplanar::Rectangle;

/// A rectangle of an axis-aligned plane: the plane's coordinate `w` on its normal's axis and
/// the intervals `u0..u1`, `v0..v1` on the other two (in the order x, y, z after the normal's).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    w: f32,
    u: [f32; 2],
    v: [f32; 2],
}

/// Merges the rectangles of one plane that share whole edges, when the plane is axis-aligned and
/// every rectangle runs along its axes; `None` otherwise (the caller merges them another way).
pub(crate) fn merge(rectangles: &[Rectangle]) -> Option<Vec<Rectangle>> {
    let normal = rectangles.first()?.normal;
    let axis = (0..3).find(|&k| normal[k] != 0.0)?;
    if (0..3).any(|k| k != axis && normal[k] != 0.0) {
        return None;
    }
    let (ua, va) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut spans: Vec<Span> = rectangles
        .iter()
        .map(|r| span(r, axis, ua, va))
        .collect::<Option<_>>()?;
    // Rows along u, then columns of those along v, then the rows those columns make.
    for along_u in [true, false, true] {
        spans = merge_along(spans, along_u);
    }
    // u × v points along +axis: corners in (u, v) order wind counter-clockwise about a normal
    // that does too.
    let counter_clockwise = normal[axis] > 0.0;
    Some(
        spans
            .iter()
            .map(|s| {
                let point = |u: f32, v: f32| {
                    let mut p = [0.0; 3];
                    (p[axis], p[ua], p[va]) = (s.w, u, v);
                    p
                };
                let (a, b, c, d) = (
                    point(s.u[0], s.v[0]),
                    point(s.u[1], s.v[0]),
                    point(s.u[1], s.v[1]),
                    point(s.u[0], s.v[1]),
                );
                let corners = if counter_clockwise {
                    [a, b, c, d]
                } else {
                    [a, d, c, b]
                };
                Rectangle { corners, normal }
            })
            .collect(),
    )
}

/// The rectangle as intervals, when its corners lie at one `w` and each edge runs along `ua` or
/// `va`.
fn span(rectangle: &Rectangle, axis: usize, ua: usize, va: usize) -> Option<Span> {
    let c = &rectangle.corners;
    let w = c[0][axis];
    if c.iter().any(|p| p[axis].to_bits() != w.to_bits()) {
        return None;
    }
    for k in 0..4 {
        let (p, q) = (c[k], c[(k + 1) % 4]);
        let along_u = p[va] == q[va] && p[ua] != q[ua];
        let along_v = p[ua] == q[ua] && p[va] != q[va];
        if !(along_u || along_v) {
            return None;
        }
    }
    // -0.0 and 0.0 are one coordinate: + 0.0 makes the first the second.
    let interval = |a: f32, b: f32| [a.min(b) + 0.0, a.max(b) + 0.0];
    Some(Span {
        w: w + 0.0,
        u: interval(c[0][ua], c[2][ua]),
        v: interval(c[0][va], c[2][va]),
    })
}

/// `x`'s bits, in an order that agrees with the numbers' order.
fn key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// A span's interval along u and across (on v), or along v and across (on u).
fn along_across(span: &Span, along_u: bool) -> ([f32; 2], [f32; 2]) {
    if along_u {
        (span.u, span.v)
    } else {
        (span.v, span.u)
    }
}

/// The order [`merge_along`] sorts spans in: by plane, interval across, then interval along,
/// the five keys packed into two integers so that a comparison is two integer compares.
fn sort_key(span: &Span, along_u: bool) -> (u128, u32) {
    let (along, across) = along_across(span, along_u);
    let high = [key(span.w), key(across[0]), key(across[1]), key(along[0])]
        .into_iter()
        .fold(0u128, |high, k| high << 32 | u128::from(k));
    (high, key(along[1]))
}

/// Joins spans that continue one another along u (or along v): same plane, same interval
/// across, one ending where the next begins. The result is in sorted order.
fn merge_along(spans: Vec<Span>, along_u: bool) -> Vec<Span> {
    // Keys and indices are sorted rather than the spans: spans with equal keys are equal, so
    // the order among them changes nothing.
    let mut order: Vec<(u128, u64)> = spans
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let (high, low) = sort_key(s, along_u);
            (high, u64::from(low) << 32 | i as u64)
        })
        .collect();
    order.sort_unstable();
    let spans = order
        .iter()
        .map(|&(_, i)| spans[(i & u64::from(u32::MAX)) as usize]);
    let mut merged: Vec<Span> = Vec::with_capacity(spans.len());
    for span in spans {
        if let Some(last) = merged.last_mut() {
            let (last_along, last_across) = along_across(last, along_u);
            let (span_along, span_across) = along_across(&span, along_u);
            if last.w == span.w && last_across == span_across && last_along[1] == span_along[0] {
                let end = if along_u {
                    &mut last.u[1]
                } else {
                    &mut last.v[1]
                };
                *end = span_along[1];
                continue;
            }
        }
        merged.push(span);
    }
    merged
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `merge_along` as it was before its keys were packed: sorting by the five keys as a
    /// tuple, the order the packed keys must reproduce.
    fn merge_along_by_tuples(mut spans: Vec<Span>, along_u: bool) -> Vec<Span> {
        spans.sort_unstable_by_key(|s| {
            let (along, across) = along_across(s, along_u);
            let keys = [s.w, across[0], across[1], along[0], along[1]];
            keys.map(key)
        });
        let mut merged: Vec<Span> = Vec::new();
        for span in spans {
            if let Some(last) = merged.last_mut() {
                let (last_along, last_across) = along_across(last, along_u);
                let (span_along, span_across) = along_across(&span, along_u);
                if last.w == span.w && last_across == span_across && last_along[1] == span_along[0]
                {
                    let end = if along_u {
                        &mut last.u[1]
                    } else {
                        &mut last.v[1]
                    };
                    *end = span_along[1];
                    continue;
                }
            }
            merged.push(span);
        }
        merged
    }

    #[test]
    fn packed_keys_sort_and_merge_as_the_five_keys_do() {
        // Coordinates of both signs, on a few planes, with repeats and neighbours.
        let values = [-3.5f32, -1.0, -0.25, 0.0, 0.5, 1.0, 2.0, 1e6];
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
            values[(state >> 16) as usize % values.len()]
        };
        let spans: Vec<Span> = (0..2000)
            .map(|_| {
                let (a, b, c, d, w) = (next(), next(), next(), next(), next());
                Span {
                    w: w / 1e6,
                    u: [a.min(b), a.max(b)],
                    v: [c.min(d), c.max(d)],
                }
            })
            .collect();
        for along_u in [true, false] {
            let packed = merge_along(spans.clone(), along_u);
            assert!(packed.len() < spans.len(), "some spans merge");
            assert_eq!(packed, merge_along_by_tuples(spans.clone(), along_u));
        }
    }

    /// The unit square at (x, y) in the plane z = `z`, facing `facing` along z.
    fn square(x: f32, y: f32, z: f32, facing: f32) -> Rectangle {
        let corners = [
            [x, y, z],
            [x + 1.0, y, z],
            [x + 1.0, y + 1.0, z],
            [x, y + 1.0, z],
        ];
        Rectangle::new(corners, [0.0, 0.0, facing]).unwrap()
    }

    fn area(rectangles: &[Rectangle]) -> f32 {
        rectangles
            .iter()
            .map(|r| {
                let [a, b, _, d] = r.corners;
                let side = |p: [f32; 3], q: [f32; 3]| {
                    (0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f32>().sqrt()
                };
                side(a, b) * side(a, d)
            })
            .sum()
    }

    #[test]
    fn a_grid_becomes_one_rectangle_facing_the_same_way() {
        for facing in [1.0, -1.0] {
            let grid: Vec<Rectangle> = (0..12)
                .map(|i| square((i % 4) as f32, (i / 4) as f32, 2.0, facing))
                .collect();
            let merged = merge(&grid).unwrap();
            assert_eq!(merged.len(), 1);
            assert_eq!(area(&merged), 12.0);
            // Counter-clockwise about the normal, as the squares were.
            let [a, b, _, d] = merged[0].corners;
            let cross = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
            assert_eq!(cross.signum(), facing);
            assert!(merged[0].corners.iter().all(|p| p[2] == 2.0));
        }
    }

    #[test]
    fn an_l_shape_stays_two_and_other_planes_stay_apart() {
        let l_shape = [
            square(0.0, 0.0, 0.0, 1.0),
            square(1.0, 0.0, 0.0, 1.0),
            square(0.0, 1.0, 0.0, 1.0),
        ];
        let merged = merge(&l_shape).unwrap();
        assert_eq!(merged.len(), 2);
        assert_eq!(area(&merged), 3.0);
        // A hair apart in z: not one plane, though the caller's plane key rounds them together.
        let apart = [square(0.0, 0.0, 0.0, 1.0), square(1.0, 0.0, 1e-6, 1.0)];
        assert_eq!(merge(&apart).unwrap().len(), 2);
    }

    #[test]
    fn turned_planes_and_rectangles_are_left_to_the_edge_map() {
        let tilted = Rectangle {
            normal: [0.0, 0.6, 0.8],
            ..square(0.0, 0.0, 0.0, 1.0)
        };
        assert_eq!(merge(&[tilted]), None);
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let diamond = Rectangle::new(
            [
                [0.0, 0.0, 0.0],
                [h, h, 0.0],
                [0.0, 2.0 * h, 0.0],
                [-h, h, 0.0],
            ],
            [0.0, 0.0, 1.0],
        )
        .unwrap();
        assert_eq!(merge(&[square(0.0, 0.0, 0.0, 1.0), diamond]), None);
    }
}
