//! Section names: the rule that made a section and a tag from its place in the derivation,
//! shown as `Floor_3fa91c`. A city has millions of sections, so a name is kept as its two parts
//! and written out only when shown.

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
        let Some(rest) = text.strip_prefix(&*self.base) else {
            return false;
        };
        match self.tag {
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
