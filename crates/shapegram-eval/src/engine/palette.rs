//! A derivation's paints: the distinct looks (colour, and whether the grammar set it) of its
//! leaves. A leaf names its paint by index, as it names its symbol, so that the common leaf
//! carries 4 bytes instead of a 16-byte colour and a flag.

use rustc_hash::FxHashMap;
use shapegram_geom::Color;

/// A leaf's look as the grammar left it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Paint {
    /// Its colour.
    pub color: Color,
    /// Whether the grammar set the colour (see [`crate::asset_look`]).
    pub painted: bool,
}

/// A leaf's paint: its index in [`Derivation::paints`](super::Derivation::paints).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PaintId(pub u32);

/// A paint as a hash key: colours compare by their bits, as parts of a model do.
type Key = ([u32; 4], bool);

fn key(paint: Paint) -> Key {
    (paint.color.to_array().map(f32::to_bits), paint.painted)
}

/// The paints of a batch of lots, numbered in order of first use.
#[derive(Clone, Debug, Default)]
pub(crate) struct Palette {
    paints: Vec<Paint>,
    index: FxHashMap<Key, u32>,
    /// The paint asked for last: leaves in a row mostly share it.
    last: Option<(Key, PaintId)>,
}

impl Palette {
    /// The number of `paint`, added when it is new.
    #[inline]
    pub(crate) fn id(&mut self, paint: Paint) -> PaintId {
        let key = key(paint);
        match self.last {
            Some((last, id)) if last == key => id,
            _ => self.id_slow(key, paint),
        }
    }

    #[inline(never)]
    fn id_slow(&mut self, key: Key, paint: Paint) -> PaintId {
        let paints = &mut self.paints;
        let id = PaintId(*self.index.entry(key).or_insert_with(|| {
            paints.push(paint);
            paints.len() as u32 - 1
        }));
        self.last = Some((key, id));
        id
    }

    /// The paints so far, by number.
    pub(crate) fn paints(&self) -> &[Paint] {
        &self.paints
    }
}

/// Appends to `paints` those of `other` it lacks: how `other`'s numbers map to the result's,
/// `None` when they stay the same (`other` starts as `paints` does). Batches of lots merged in
/// order thus number paints in order of first use over all their leaves.
pub(crate) fn merge(paints: &mut Vec<Paint>, other: &[Paint]) -> Option<Vec<PaintId>> {
    let common = paints.len().min(other.len());
    if paints[..common]
        .iter()
        .zip(other)
        .all(|(&a, &b)| key(a) == key(b))
    {
        paints.extend_from_slice(&other[common..]);
        return None;
    }
    let mut palette = Palette::default();
    for &paint in paints.iter() {
        palette.id(paint);
    }
    let map = other.iter().map(|&paint| palette.id(paint)).collect();
    *paints = palette.paints;
    Some(map)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paint(hex: &str, painted: bool) -> Paint {
        Paint {
            color: Color::from_hex(hex).unwrap(),
            painted,
        }
    }

    #[test]
    fn paints_are_numbered_in_order_of_first_use() {
        let mut palette = Palette::default();
        let (red, blue) = (paint("#ff0000", true), paint("#0000ff", true));
        let ids = [red, red, blue, red, paint("#ff0000", false), blue].map(|p| palette.id(p).0);
        assert_eq!(ids, [0, 0, 1, 0, 2, 1]);
        assert_eq!(palette.paints().len(), 3);
    }

    #[test]
    fn merging_renumbers_only_a_batch_that_starts_otherwise() {
        let (red, green, blue) = (
            paint("#ff0000", true),
            paint("#00ff00", true),
            paint("#0000ff", true),
        );
        let mut paints = vec![red, green];
        // The same start, and one more: the batch's numbers stand.
        assert_eq!(merge(&mut paints, &[red]), None);
        assert_eq!(merge(&mut paints, &[red, green, blue]), None);
        assert_eq!(paints, [red, green, blue]);
        // Another start: the batch's paints map to the first number of each.
        let white = paint("#ffffff", false);
        let map = merge(&mut paints, &[blue, white, red]);
        assert_eq!(map, Some(vec![PaintId(2), PaintId(3), PaintId(0)]));
        assert_eq!(paints, [red, green, blue, white]);
    }
}
