//! Implicit solids in shapes: `implicit(sphere)` fits a solid to the scope, `csg("rock", union)`
//! and friends make it a member of a CSG group, and when the derivation is done each group (per
//! initial shape) is combined into one solid and meshed as one smooth surface.

use std::sync::Arc;
use std::time::{Duration, Instant};

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use shapegram_geom::{Aabb, Color, DVec3, Part};
use shapegram_implicit::{MeshOptions, Solid};
use shapegram_syntax::Span;

use crate::engine::{Derivation, Leaf};
use crate::error::DeriveError;
use crate::ops::ImplicitKind;
use crate::shape::{CsgOp, Geometry, Implicit};

/// The solid `kind` filling a box of `size` (all positive) from the origin, in the box's frame:
/// round solids take their radius from x and are stretched along z (and, for spheres and short
/// capsules, along y) to fill the box; exact distances where the box allows (a round section).
pub(crate) fn fitted(kind: ImplicitKind, size: DVec3) -> Result<Solid, String> {
    let (sx, sy, sz) = (size.x, size.y, size.z);
    let r = sx / 2.0;
    let fail = |e: shapegram_implicit::ImplicitError| e.message().to_owned();
    let solid = match kind {
        ImplicitKind::Box => Solid::cuboid(size).map_err(fail)?,
        ImplicitKind::Pyramid => Solid::pyramid(size).map_err(fail)?,
        ImplicitKind::Sphere => Solid::sphere(r)
            .and_then(|s| s.scale(DVec3::new(1.0, sy / sx, sz / sx)))
            .map_err(fail)?,
        ImplicitKind::Cylinder => Solid::cylinder(r, sy)
            .and_then(|s| s.scale(DVec3::new(1.0, 1.0, sz / sx)))
            .map_err(fail)?,
        ImplicitKind::Cone => Solid::cone(r, sy)
            .and_then(|s| s.scale(DVec3::new(1.0, 1.0, sz / sx)))
            .map_err(fail)?,
        ImplicitKind::Capsule => {
            // A box lower than wide holds a ball squashed to its height.
            let (length, squash) = if sy >= sx {
                (sy - sx, 1.0)
            } else {
                (0.0, sy / sx)
            };
            Solid::capsule(r, length)
                .and_then(|s| s.scale(DVec3::new(1.0, squash, sz / sx)))
                .map_err(fail)?
        }
        ImplicitKind::Torus => {
            let minor = sy / 2.0;
            if minor >= r / 2.0 {
                return Err(format!(
                    "a torus needs a scope more than twice as wide (x) as high (y); it is {} by {}",
                    sx, sy
                ));
            }
            Solid::torus(r - minor, minor)
                .and_then(|s| s.scale(DVec3::new(1.0, 1.0, sz / sx)))
                .map_err(fail)?
        }
    };
    solid.translate(size / 2.0).map_err(fail)
}

/// Cells along the longest side of a group's bounds, at least and at most, when the cell size
/// is chosen automatically.
const CELLS_AT_LEAST: f64 = 64.0;
const CELLS_AT_MOST: f64 = 256.0;
/// Cells across the smallest member, when that asks for more than [`CELLS_AT_LEAST`].
const CELLS_PER_MEMBER: f64 = 4.0;

/// The automatic cell size of a group: fine enough for 4 cells across its smallest member and
/// 64 along its longest side, but no finer than 256 along that side (to bound the work).
fn cell_size(longest: f64, smallest_member: f64) -> f64 {
    let wanted = (smallest_member / CELLS_PER_MEMBER).min(longest / CELLS_AT_LEAST);
    wanted.max(longest / CELLS_AT_MOST)
}

/// What members share a group: a named CSG group, or the rule and colour of solids that join
/// none; either way within one initial shape.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum GroupKey<'a> {
    Named(u32, &'a str),
    Rule(u32, &'a str, [u32; 4]),
}

/// One group to mesh: its members in leaf order, and what it is called and coloured.
struct Group<'a> {
    name: Arc<str>,
    color: Option<Color>,
    members: Vec<(&'a Leaf, &'a Implicit)>,
}

/// The span of the operation that made a member what it is.
fn span_of(implicit: &Implicit) -> Span {
    implicit.csg.as_ref().map_or(implicit.span, |c| c.span)
}

/// The implicit leaves meshed: a part per CSG group of each initial shape, named after the group
/// and coloured like its first adding member, and a part per rule and colour of each initial
/// shape for the solids in no group (overlapping ones merge), named after the rule; in order of
/// their first members. Grid cells have edge `cell` when given, else a size picked per group
/// (see [`cell_size`]). Meshing a group may take `time_budget` (like deriving a lot).
pub(crate) fn mesh_solids(
    derivation: &Derivation,
    cell: Option<f64>,
    time_budget: Option<Duration>,
) -> Result<Vec<Part>, DeriveError> {
    let mut groups: Vec<Group> = Vec::new();
    let mut index: FxHashMap<GroupKey, usize> = FxHashMap::default();
    for leaf in &derivation.leaves {
        let Geometry::Implicit(implicit) = &leaf.geometry else {
            continue;
        };
        let (name, key) = match &implicit.csg {
            Some(csg) => (csg.group.clone(), GroupKey::Named(leaf.lot, &csg.group)),
            None => {
                let color = derivation.color(leaf).to_array().map(f32::to_bits);
                let name = &derivation.names[leaf.name.0 as usize];
                (name.clone(), GroupKey::Rule(leaf.lot, name, color))
            }
        };
        let slot = *index.entry(key).or_insert_with(|| {
            groups.push(Group {
                name,
                color: None,
                members: Vec::new(),
            });
            groups.len() - 1
        });
        let group = &mut groups[slot];
        let adds = implicit.csg.as_ref().is_none_or(|c| c.op.adds());
        if adds && group.color.is_none() {
            group.color = Some(derivation.color(leaf));
        }
        group.members.push((leaf, implicit));
    }
    groups
        .par_iter()
        .map(|group| mesh_group(group, cell, time_budget))
        .filter_map(Result::transpose)
        .collect()
}

/// The group's solid meshed, or `None` when nothing of it is left.
fn mesh_group(
    group: &Group,
    cell: Option<f64>,
    time_budget: Option<Duration>,
) -> Result<Option<Part>, DeriveError> {
    let Some((solid, span)) = combine(&group.members)? else {
        return Ok(None);
    };
    let Some(bounds) = solid.bounds() else {
        return Ok(None);
    };
    let h = match cell {
        Some(h) => h,
        None => automatic_cell(group, bounds, span)?,
    };
    let options = MeshOptions {
        deadline: time_budget.map(|t| Instant::now() + t),
        ..MeshOptions::with_cell_size(h)
    };
    let meshing = shapegram_implicit::mesh(&solid, &options).map_err(|e| {
        DeriveError::at(
            format!("cannot mesh `{}`: {}", group.name, e.message()),
            span,
        )
    })?;
    if meshing.mesh.is_empty() {
        return Ok(None);
    }
    let normals = shapegram_implicit::surface_normals(&solid, &meshing.mesh, h);
    Ok(Some(Part {
        texture: None,
        uvs: Vec::new(),
        bone: None,
        metadata: None,
        name: group.name.to_string(),
        color: group.color.unwrap_or_default(),
        mesh: meshing.mesh,
        normals,
        material: None,
        surface: None,
        instance: None,
    }))
}

/// The automatic cell size of a group whose solid has `bounds` (see [`cell_size`]); an error
/// when the solid is less than two cells thick all through, and so would vanish from the mesh.
/// (A thin member among thicker ones is not checked: slabs of one solid are thin, and whole.)
fn automatic_cell(group: &Group, bounds: Aabb, span: Span) -> Result<f64, DeriveError> {
    let thinnest = group
        .members
        .iter()
        .filter_map(|(_, implicit)| implicit.solid.bounds())
        .map(|b| b.size().min_element())
        .fold(f64::INFINITY, f64::min);
    let (longest, thickness) = (bounds.size().max_element(), bounds.size().min_element());
    let h = cell_size(longest, thinnest);
    if thickness < 2.0 * h {
        return Err(DeriveError::at(
            format!(
                "`{}` is {thickness} thin, less than two of the {h} cells it can be meshed with at its size ({longest} long): it would vanish",
                group.name
            ),
            span,
        )
        .with_hint("choose the cell size with --implicit-cell, or make it thicker"));
    }
    Ok(h)
}

/// An error when a fillet is larger than the solids it joins together: it would swell them into
/// a blob (or, past the range of numbers, empty them).
fn check_fillet(op: CsgOp, base: &Solid, member: &Solid, at: Span) -> Result<(), DeriveError> {
    let (CsgOp::Union(k) | CsgOp::Subtract(k) | CsgOp::Intersect(k)) = op else {
        return Ok(());
    };
    let extent = |s: &Solid| s.bounds().map_or(0.0, |b| b.size().max_element());
    let limit = extent(base).max(extent(member));
    if k > limit {
        return Err(DeriveError::at(
            format!("fillet radius {k} is larger than the solids it joins ({limit} across)"),
            at,
        ));
    }
    Ok(())
}

/// The members combined in world coordinates, with the span of the first member's operation:
/// first what adds (`union`, `morph`) in leaf order, then each `subtract`, then each
/// `intersect`, so carving does not depend on whether the carving shape was derived before or
/// after what it carves. `None` when nothing adds.
fn combine(members: &[(&Leaf, &Implicit)]) -> Result<Option<(Solid, Span)>, DeriveError> {
    let mut base = Solid::empty();
    let mut span = None;
    for pass in 0..3 {
        // Sharp members wait to be joined in one balanced tree: maxima and minima are exact, so
        // this changes no value, but a chain of hundreds (the slabs of a split) would make every
        // evaluation walk all of it.
        let mut sharp: Vec<Solid> = Vec::new();
        for (leaf, implicit) in members {
            let op = implicit.csg.as_ref().map_or(CsgOp::Union(0.0), |c| c.op);
            let phase = match op {
                CsgOp::Union(_) | CsgOp::Morph(_) => 0,
                CsgOp::Subtract(_) => 1,
                CsgOp::Intersect(_) => 2,
            };
            if phase != pass {
                continue;
            }
            let at = span_of(implicit);
            span.get_or_insert(at);
            let fail = |e: shapegram_implicit::ImplicitError| DeriveError::at(e.message(), at);
            let member = implicit
                .solid
                .transform(&leaf.scope.local_to_world())
                .map_err(fail)?;
            if let CsgOp::Union(0.0) | CsgOp::Subtract(0.0) | CsgOp::Intersect(0.0) = op {
                sharp.push(member);
                continue;
            }
            base = join_sharp(pass, base, std::mem::take(&mut sharp));
            check_fillet(op, &base, &member, at)?;
            base = match op {
                _ if base.is_empty() && pass == 0 => member,
                CsgOp::Union(k) => base.smooth_union(&member, k).map_err(fail)?,
                CsgOp::Morph(a) => base.morph(&base.union(&member), a).map_err(fail)?,
                CsgOp::Subtract(k) => base.smooth_difference(&member, k).map_err(fail)?,
                CsgOp::Intersect(k) => base.smooth_intersection(&member, k).map_err(fail)?,
            };
        }
        base = join_sharp(pass, base, sharp);
        if pass == 0 && base.is_empty() {
            return Ok(None);
        }
    }
    Ok(span.map(|s| (base, s)))
}

/// `base` with the sharp members of pass `pass` joined in: added (pass 0), carved away (1) or
/// trimmed to (2).
fn join_sharp(pass: usize, base: Solid, sharp: Vec<Solid>) -> Solid {
    let trims = pass == 2;
    let Some(joined) = balanced(sharp, trims) else {
        return base;
    };
    match pass {
        0 if base.is_empty() => joined,
        0 => base.union(&joined),
        1 => base.difference(&joined),
        _ => base.intersection(&joined),
    }
}

/// The union (or, for `intersect`, the intersection) of `solids` as a balanced tree.
fn balanced(mut solids: Vec<Solid>, intersect: bool) -> Option<Solid> {
    while solids.len() > 1 {
        solids = solids
            .chunks(2)
            .map(|pair| match pair {
                [a, b] if intersect => a.intersection(b),
                [a, b] => a.union(b),
                [a] => a.clone(),
                _ => unreachable!("chunks of two"),
            })
            .collect();
    }
    solids.pop()
}
