//! CGA's tag functions: `geometry.tags([query [, components]])`, the sorted tags of the
//! shape's geometry the query matches, and `geometry.hasTags([query [, components]])`, whether
//! there are any; `components` is `all` (faces and edges), `faces`, `edges` or `vertices`
//! (Shapegram keeps no vertex tags: none). Also `geometry.materials()`, the names of the
//! materials the geometry wears, in the order of `comp(m)` (see [`crate::material_groups`]).

use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::material_groups::material_groups;
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
}

impl TagFn {
    /// The function called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "geometry.tags" => Some(Self::Tags),
            "geometry.hasTags" => Some(Self::HasTags),
            "geometry.materials" => Some(Self::Materials),
            _ => None,
        }
    }

    /// Every function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        ["geometry.tags", "geometry.hasTags", "geometry.materials"].into_iter()
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Self::Materials => (0, 0),
            _ => (0, 2),
        }
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        match self {
            Self::Tags => "geometry.tags([tagQuery [, all | faces | edges | vertices]])",
            Self::HasTags => "geometry.hasTags([tagQuery [, all | faces | edges | vertices]])",
            Self::Materials => "geometry.materials()",
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
        if function == TagFn::Materials {
            let groups = shape
                .geometry
                .world_mesh(&shape.scope)
                .map(|world| material_groups(shape, &world))
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
            TagFn::Materials => unreachable!("answered above"),
        })
    }
}
