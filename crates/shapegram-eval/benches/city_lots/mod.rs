//! The city benchmark's lots, shared by the benchmarks that derive its grammar.

use shapegram_eval::InitialShape;
use shapegram_geom::DVec2;

/// `count` lots of 20 × 30 m in rows of 40, `gap` m apart.
pub fn lots_apart(count: usize, gap: f64) -> Vec<InitialShape> {
    (0..count)
        .map(|i| {
            let (x, z) = (
                (i % 40) as f64 * (20.0 + gap),
                (i / 40) as f64 * (30.0 + gap),
            );
            InitialShape::from_xz(&[
                DVec2::new(x, z),
                DVec2::new(x + 20.0, z),
                DVec2::new(x + 20.0, z + 30.0),
                DVec2::new(x, z + 30.0),
            ])
            .expect("a rectangle is a lot")
        })
        .collect()
}

/// `count` lots of 20 × 30 m in rows of 40, 5 m apart.
pub fn lots(count: usize) -> Vec<InitialShape> {
    lots_apart(count, 5.0)
}
