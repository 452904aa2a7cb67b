//! KHR_mesh_quantization: positions as i16 on a grid that the mesh's node scales back, unit
//! normals as normalised i8, uvs in `0..=1` as normalised u16.

/// The extension's name, which goes into `extensionsUsed` and `extensionsRequired`.
pub(crate) const EXTENSION: &str = "KHR_mesh_quantization";

/// The largest i16 magnitude used, so that the grid is symmetric about its centre.
const STEPS: f32 = i16::MAX as f32;

/// An evenly spaced grid of positions: `centre + step · q` for integer `q` in
/// `-32767..=32767` on each axis; the node that holds the mesh gets `centre` as translation and
/// `step` as uniform scale, so that viewers place the integers where the floats were.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Grid {
    pub(crate) centre: [f32; 3],
    pub(crate) step: f32,
}

impl Grid {
    /// The grid that spans `min..=max` (component-wise bounds of the positions to hold).
    pub(crate) fn spanning(min: [f32; 3], max: [f32; 3]) -> Self {
        let centre: [f32; 3] = std::array::from_fn(|k| min[k] / 2.0 + max[k] / 2.0);
        let reach = (0..3)
            .map(|k| (max[k] - centre[k]).max(centre[k] - min[k]))
            .fold(0.0f32, f32::max);
        // Rounding may leave the extreme positions a hair beyond ±32767 steps; clamping
        // moves them by less than a step.
        let step = if reach > 0.0 && reach.is_finite() {
            reach / STEPS
        } else {
            1.0
        };
        Self { centre, step }
    }

    /// `p`'s nearest grid point, as integers.
    pub(crate) fn quantize(&self, p: [f32; 3]) -> [i16; 3] {
        std::array::from_fn(|k| {
            let q = ((f64::from(p[k]) - f64::from(self.centre[k])) / f64::from(self.step)).round();
            q.clamp(-f64::from(STEPS), f64::from(STEPS)) as i16
        })
    }
}

/// A unit normal as normalised i8 (a signed byte `b` means `b / 127`).
pub(crate) fn normal(n: [f32; 3]) -> [i8; 3] {
    n.map(|x| (x * 127.0).round().clamp(-127.0, 127.0) as i8)
}

/// A uv as normalised u16 (`b / 65535`), for uvs in `0..=1` only ([`fits_unorm`]).
pub(crate) fn uv(uv: [f32; 2]) -> [u16; 2] {
    uv.map(|x| (x * 65535.0).round() as u16)
}

/// Whether every uv lies in `0..=1`, as normalised u16 can hold; repeating textures reach
/// beyond and keep float uvs.
pub(crate) fn fits_unorm(uvs: &[[f32; 2]]) -> bool {
    uvs.iter().flatten().all(|x| (0.0..=1.0).contains(x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_holds_its_span_to_half_a_step() {
        let grid = Grid::spanning([-10.0, 0.0, 5.0], [30.0, 2.0, 6.0]);
        assert_eq!(grid.centre, [10.0, 1.0, 5.5]);
        assert_eq!(grid.step, 20.0 / 32767.0);
        assert_eq!(grid.quantize([-10.0, 0.0, 5.0]), [-32767, -1638, -819]);
        assert_eq!(grid.quantize([30.0, 2.0, 6.0])[0], 32767);
        let p = [12.345f32, 1.5, 5.75];
        let q = grid.quantize(p);
        for k in 0..3 {
            let back = grid.centre[k] + grid.step * f32::from(q[k]);
            assert!((back - p[k]).abs() <= grid.step / 2.0 + 1e-6);
        }
        // A single point still gets a usable scale.
        assert_eq!(Grid::spanning([1.0; 3], [1.0; 3]).step, 1.0);
    }

    #[test]
    fn normals_and_uvs_round_to_the_nearest_code() {
        assert_eq!(normal([0.0, -1.0, 1.0]), [0, -127, 127]);
        assert_eq!(normal([0.6, 0.8, 0.0]), [76, 102, 0]);
        assert_eq!(uv([0.0, 1.0]), [0, 65535]);
        assert!(fits_unorm(&[[0.0, 1.0], [0.5, 0.25]]));
        assert!(!fits_unorm(&[[0.0, 1.5]]));
    }
}
