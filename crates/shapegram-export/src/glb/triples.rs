//! A vertex attribute of three f32 components as the writer reads it: values of a primitive's
//! own, or a smooth part's f64 positions or normals, rounded to f32 as they are read. Reading
//! the model's vertices in place spares a tube model an f32 copy of hundreds of megabytes.

use shapegram_geom::DVec3;

use crate::flat::unit;

/// Three-component values borrowed from where they are kept.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Triples<'a> {
    /// f32 values as written.
    F32(&'a [[f32; 3]]),
    /// A model's positions, each rounded to f32.
    Points(&'a [DVec3]),
    /// A model's normals (none zero or infinite), each made a unit f32 vector.
    Normals(&'a [DVec3]),
}

impl Triples<'_> {
    /// How many values there are.
    pub(crate) fn len(&self) -> usize {
        match self {
            Self::F32(values) => values.len(),
            Self::Points(values) | Self::Normals(values) => values.len(),
        }
    }

    /// Whether there are none.
    pub(crate) fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value `i` as written.
    pub(crate) fn get(&self, i: usize) -> [f32; 3] {
        match self {
            Self::F32(values) => values[i],
            Self::Points(values) => point(values[i]),
            Self::Normals(values) => unit(values[i]),
        }
    }

    /// Calls `visit` with every value as written, in order.
    pub(crate) fn for_each(&self, visit: impl FnMut([f32; 3])) {
        match self {
            Self::F32(values) => values.iter().copied().for_each(visit),
            Self::Points(values) => values.iter().map(|&p| point(p)).for_each(visit),
            Self::Normals(values) => values.iter().map(|&n| unit(n)).for_each(visit),
        }
    }
}

/// A model's position as the writers round it.
pub(crate) fn point(p: DVec3) -> [f32; 3] {
    p.as_vec3().to_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn model_values_read_as_their_f32_copies() {
        let points = [
            DVec3::new(0.1, -2.5e7, 1.0 / 3.0),
            DVec3::new(1e-9, 0.0, -7.25),
        ];
        let normals = [DVec3::new(0.0, 3.0, 4.0), DVec3::new(-1e-3, 0.0, 0.0)];
        let copied: Vec<[f32; 3]> = points.iter().map(|p| p.as_vec3().to_array()).collect();
        let units = [[0.0, 0.6, 0.8], [-1.0, 0.0, 0.0]];
        for (triples, expected) in [
            (Triples::Points(&points), &copied[..]),
            (Triples::Normals(&normals), &units[..]),
            (Triples::F32(&units), &units[..]),
        ] {
            assert_eq!(triples.len(), 2);
            assert!(!triples.is_empty());
            let mut seen = Vec::new();
            triples.for_each(|v| seen.push(v));
            assert_eq!(seen, expected);
            assert_eq!([triples.get(0), triples.get(1)], expected);
        }
        assert!(Triples::Normals(&[]).is_empty());
    }
}
