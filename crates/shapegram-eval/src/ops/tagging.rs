//! The argument forms of the operations on component tags: `tag(name [, auto | faces |
//! edges | vertices])` and `deleteTags([query [, all | faces | edges | vertices]])`.

use super::Op;
use super::build::Ctx;
use crate::tags::TagTarget;

impl Ctx<'_, '_> {
    /// `tag` (`delete` false) or `deleteTags`: the name or query, and the components.
    pub(super) fn tagging(&mut self, delete: bool) -> Option<Op> {
        self.c.tagged = true;
        let (lo, words) = if delete {
            (0, "`all`, `faces`, `edges` or `vertices`")
        } else {
            (1, "`auto`, `faces`, `edges` or `vertices`")
        };
        self.arity(lo, 2)?;
        let target = match self.args.len() {
            2 => match self.word(1) {
                Some(w) if delete && w == "auto" => None,
                Some(w) if !delete && w == "all" => None,
                Some(w) => TagTarget::named(w),
                None => None,
            },
            _ => Some(TagTarget::All),
        };
        let Some(target) = target else {
            return self.bad_selector(1, words);
        };
        if target == TagTarget::Vertices {
            self.warn_once(
                "Shapegram keeps no vertex tags: `vertices` tags nothing and finds none".into(),
            );
        }
        self.args.truncate(1);
        let name = self.args.pop();
        Some(if delete {
            Op::DeleteTags {
                query: name,
                target,
            }
        } else {
            Op::Tag {
                name: name?,
                target,
            }
        })
    }
}
