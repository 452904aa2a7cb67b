//! Section names: the rule that made a section and a tag from its place in the derivation,
//! shown as `Floor_3fa91c`. A city has millions of sections, so a name is kept as its two parts
//! and written out only when shown.

use std::collections::HashMap;

use rustc_hash::FxHashMap;
use std::fmt;
use std::sync::Arc;

/// A section's name.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Name {
    base: Arc<str>,
    tag: Option<u32>,
}

impl Name {
    /// A name without a tag (a root's).
    pub fn new(base: impl Into<Arc<str>>) -> Self {
        Self {
            base: base.into(),
            tag: None,
        }
    }

    /// `base` and the low 24 bits of `tag`, written as six hex digits after an underscore.
    pub fn tagged(base: Arc<str>, tag: u32) -> Self {
        Self {
            base,
            tag: Some(tag & 0xFF_FFFF),
        }
    }

    /// The rule part of the name.
    pub fn base(&self) -> &str {
        &self.base
    }

    /// Whether the name reads `text`, without writing it out.
    pub fn matches(&self, text: &str) -> bool {
        reads(&self.base, self.tag, text)
    }
}

impl fmt::Display for Name {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.tag {
            None => f.write_str(&self.base),
            Some(tag) => write!(f, "{}_{tag:06x}", self.base),
        }
    }
}

impl From<&str> for Name {
    fn from(base: &str) -> Self {
        Self::new(base)
    }
}

impl From<String> for Name {
    fn from(base: String) -> Self {
        Self::new(base)
    }
}

/// Whether the name of `base` and `tag` reads `text`.
fn reads(base: &str, tag: Option<u32>, text: &str) -> bool {
    let Some(rest) = text.strip_prefix(base) else {
        return false;
    };
    match tag {
        None => rest.is_empty(),
        Some(tag) => rest
            .strip_prefix('_')
            .filter(|hex| {
                hex.len() == 6 && hex.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
            })
            .and_then(|hex| u32::from_str_radix(hex, 16).ok())
            .is_some_and(|t| t == tag),
    }
}

/// A stored name without a tag (tags have 24 bits).
const NO_TAG: u32 = u32::MAX;

/// A rule name's place in a skeleton's table of names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
struct Base(u32);

/// A section's name as a skeleton keeps it: eight bytes, its rule name in the skeleton's
/// table and its tag, so that a section holds no pointer and costs nothing to drop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NameKey {
    base: Base,
    tag: u32,
}

/// A skeleton's table of rule names, each kept once.
#[derive(Clone, Debug, Default)]
pub struct Names {
    bases: Vec<Arc<str>>,
    ids: HashMap<Arc<str>, Base>,
    /// The same by the address of the kept text: the engine names every section with one of
    /// a few shared strings, found here without hashing them. The table keeps each of these
    /// strings alive, so an address cannot come to stand for another text.
    by_address: FxHashMap<usize, Base>,
    /// The strings looked up last, by address (a few slots picked by address bits): the parts
    /// of a split are of one or two rules.
    recent: [(usize, Base); 4],
    /// Strings of texts already in the table, kept for their addresses in `by_address`.
    aliases: Vec<Arc<str>>,
}

impl Names {
    /// The rule name's place in the table, adding it when new.
    fn intern(&mut self, base: &Arc<str>) -> Base {
        let address = Arc::as_ptr(base).cast::<u8>() as usize;
        // Allocations are 16-byte aligned: the bits above those pick the slot.
        let slot = (address >> 4) & 3;
        let (known, id) = self.recent[slot];
        if known == address {
            return id;
        }
        if let Some(&id) = self.by_address.get(&address) {
            self.recent[slot] = (address, id);
            return id;
        }
        if let Some(&id) = self.ids.get(base) {
            // Another string of the same text, as when copying from another skeleton: kept,
            // so that its address can be cached too.
            self.aliases.push(Arc::clone(base));
            self.by_address.insert(address, id);
            self.recent[slot] = (address, id);
            return id;
        }
        let id = Base(u32::try_from(self.bases.len()).expect("fewer than 2³² rule names"));
        self.bases.push(Arc::clone(base));
        self.ids.insert(Arc::clone(base), id);
        self.by_address.insert(address, id);
        self.recent[slot] = (address, id);
        id
    }

    /// The name a key stands for.
    pub(crate) fn name(&self, key: NameKey) -> Name {
        Name {
            base: Arc::clone(&self.bases[key.base.0 as usize]),
            tag: (key.tag != NO_TAG).then_some(key.tag),
        }
    }

    /// The rule part of a key's name.
    pub(crate) fn base(&self, key: NameKey) -> &str {
        &self.bases[key.base.0 as usize]
    }

    /// A key's name in the table `names` (interning its rule name there).
    pub(crate) fn copy_to(&self, key: NameKey, names: &mut Names) -> NameKey {
        NameKey {
            base: names.intern(&self.bases[key.base.0 as usize]),
            tag: key.tag,
        }
    }

    /// Whether a key's name reads `text`.
    pub(crate) fn reads(&self, key: NameKey, text: &str) -> bool {
        reads(self.base(key), (key.tag != NO_TAG).then_some(key.tag), text)
    }
}

/// What names a new section: a [`Name`] or text, or a rule name already in the skeleton's table
/// with a tag ([`Tagged`], what the engine passes, since it costs no lookup).
pub trait SectionName {
    /// The stored form of the name, interning its rule name in `names`.
    fn key(self, names: &mut Names) -> NameKey;
}

impl<N: Into<Name>> SectionName for N {
    fn key(self, names: &mut Names) -> NameKey {
        let name = self.into();
        NameKey {
            base: names.intern(&name.base),
            tag: name.tag.unwrap_or(NO_TAG),
        }
    }
}

/// A rule name and a tag, shown like [`Name::tagged`]: what the engine names sections with,
/// since it costs neither a reference count nor, for a string the skeleton has seen, a hash of
/// the text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tagged<'a> {
    /// The rule name.
    pub rule: &'a Arc<str>,
    /// The tag; its low 24 bits are kept.
    pub tag: u32,
}

impl SectionName for Tagged<'_> {
    #[inline]
    fn key(self, names: &mut Names) -> NameKey {
        NameKey {
            base: names.intern(self.rule),
            tag: self.tag & 0xFF_FFFF,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_show_their_tag_in_six_hex_digits_and_match_only_that_text() {
        let name = Name::tagged("Floor".into(), 0x3f_a91c);
        assert_eq!(name.to_string(), "Floor_3fa91c");
        assert!(name.matches("Floor_3fa91c"));
        for other in [
            "Floor_3FA91C",
            "Floor_3fa91",
            "Floor",
            "Floo_3fa91c",
            "Floor_3fa91d",
        ] {
            assert!(!name.matches(other), "{other}");
        }
        assert_eq!(
            Name::tagged("A".into(), 0x1234_5678).to_string(),
            "A_345678"
        );
        let root = Name::new("Lot");
        assert!(root.matches("Lot") && !root.matches("Lot_000000"));
        assert_eq!(root.base(), "Lot");
    }
}
