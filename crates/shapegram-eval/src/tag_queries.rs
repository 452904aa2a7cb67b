//! CGA's tag functions: `geometry.tags([query [, components]])`, the sorted tags of the
//! shape's geometry the query matches, and `geometry.hasTags([query [, components]])`, whether
//! there are any; `components` is `all` (faces and edges), `faces`, `edges` or `vertices`
//! (Shapegram keeps no vertex tags: none). Also `geometry.materials()` and
//! `geometry.groups()`, the names of the materials the geometry wears and of the asset groups
//! it holds, in the order of `comp(m)` and `comp(g)` (see [`crate::face_sets`]).

use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::face_sets::{asset_groups, material_groups};
use crate::program::{CExpr, CKind};
use crate::shape::State;
use crate::tags::{TagQuery, TagTarget, collect};
use crate::value::Value;

/// A tag function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TagFn {
    /// `geometry.tags`.
    Tags,
    /// `geometry.hasTags`.
    HasTags,
    /// `geometry.materials`.
    Materials,
    /// `geometry.groups`.
    Groups,
}

impl TagFn {
    /// The function called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "geometry.tags" => Some(Self::Tags),
            "geometry.hasTags" => Some(Self::HasTags),
            "geometry.materials" => Some(Self::Materials),
            "geometry.groups" => Some(Self::Groups),
            _ => None,
        }
    }

    /// Every function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        [
            "geometry.tags",
            "geometry.hasTags",
            "geometry.materials",
            "geometry.groups",
        ]
        .into_iter()
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Self::Materials | Self::Groups => (0, 0),
            _ => (0, 2),
        }
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        match self {
            Self::Tags => "geometry.tags([tagQuery [, all | faces | edges | vertices]])",
            Self::HasTags => "geometry.hasTags([tagQuery [, all | faces | edges | vertices]])",
            Self::Materials => "geometry.materials()",
            Self::Groups => "geometry.groups()",
        }
    }
}

impl Evaluator<'_> {
    /// The value of a tag function for the shape.
    pub(crate) fn tag_function(
        &mut self,
        function: TagFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value, DeriveError> {
        if let TagFn::Materials | TagFn::Groups = function {
            let sets = if function == TagFn::Materials {
                material_groups
            } else {
                asset_groups
            };
            let groups = shape
                .geometry
                .world_mesh(&shape.scope)
                .map(|world| sets(shape, &world))
                .unwrap_or_default();
            return Ok(Value::Array(
                groups.iter().map(|(name, _)| Value::string(name)).collect(),
            ));
        }
        let query = match params.first() {
            Some(p) => TagQuery::parse(&self.string(p, shape, args)?),
            None => TagQuery::parse(""),
        };
        let target = match params.get(1) {
            None => TagTarget::All,
            Some(p) => match &p.kind {
                CKind::Selector(w) if w != "auto" => TagTarget::named(w),
                _ => None,
            }
            .ok_or_else(|| {
                DeriveError::at("expected `all`, `faces`, `edges` or `vertices`", p.span)
            })?,
        };
        let names = collect(shape.geometry.tags(), &query, target);
        Ok(match function {
            TagFn::Tags => Value::Array(names.iter().map(|n| Value::string(n)).collect()),
            TagFn::HasTags => Value::Bool(!names.is_empty()),
            TagFn::Materials | TagFn::Groups => unreachable!("answered above"),
        })
    }
}
