//! Implicit solids in shapes: `implicit(sphere)` fits a solid to the scope, `csg("rock", union)`
//! and friends make it a member of a CSG group, and when the derivation is done each group (per
//! initial shape) is combined into one solid and meshed as one smooth surface.

use std::sync::Arc;

use rayon::prelude::*;
use rustc_hash::FxHashMap;
use shapegram_geom::{Color, DVec3, Part};
use shapegram_implicit::{MeshOptions, Solid};
use shapegram_syntax::Span;

use crate::engine::Leaf;
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

/// One group to mesh: its members in leaf order, and what it is called and coloured.
struct Group<'a> {
    name: Arc<str>,
    color: Option<Color>,
    members: Vec<(&'a Leaf, &'a Implicit)>,
}

/// The implicit leaves meshed: a part per CSG group of each initial shape, named after the group
/// and coloured like its first adding member, then a part per solid meshed alone, named and
/// coloured like its leaf; groups in order of their first member, solids in leaf order. Grid
/// cells have edge `cell` when given, else a size picked per group (see [`cell_size`]).
pub(crate) fn mesh_solids(leaves: &[Leaf], cell: Option<f64>) -> Result<Vec<Part>, DeriveError> {
    let mut groups: Vec<Group> = Vec::new();
    let mut index: FxHashMap<(u32, &str), usize> = FxHashMap::default();
    for leaf in leaves {
        let Geometry::Implicit(implicit) = &leaf.geometry else {
            continue;
        };
        let (name, key) = match &implicit.csg {
            Some(csg) => (csg.group.clone(), Some((leaf.lot, &*csg.group))),
            None => (leaf.name.clone(), None),
        };
        let slot = match key.and_then(|k| index.get(&k)) {
            Some(&i) => i,
            None => {
                groups.push(Group {
                    name,
                    color: None,
                    members: Vec::new(),
                });
                if let Some(k) = key {
                    index.insert(k, groups.len() - 1);
                }
                groups.len() - 1
            }
        };
        let group = &mut groups[slot];
        let adds = !matches!(
            implicit.csg.as_ref().map(|c| c.op),
            Some(CsgOp::Subtract(_) | CsgOp::Intersect(_))
        );
        if adds && group.color.is_none() {
            group.color = Some(leaf.color);
        }
        group.members.push((leaf, implicit));
    }
    groups
        .par_iter()
        .map(|group| mesh_group(group, cell))
        .filter_map(Result::transpose)
        .collect()
}

/// The group's solid meshed, or `None` when nothing of it is left.
fn mesh_group(group: &Group, cell: Option<f64>) -> Result<Option<Part>, DeriveError> {
    let Some((solid, span)) = combine(&group.members)? else {
        return Ok(None);
    };
    let Some(bounds) = solid.bounds() else {
        return Ok(None);
    };
    let smallest = group
        .members
        .iter()
        .map(|(leaf, _)| leaf.scope.size.min_element())
        .fold(f64::INFINITY, f64::min);
    let h = cell.unwrap_or_else(|| cell_size(bounds.size().max_element(), smallest));
    let meshing =
        shapegram_implicit::mesh(&solid, &MeshOptions::with_cell_size(h)).map_err(|e| {
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
        name: group.name.to_string(),
        color: group.color.unwrap_or_default(),
        mesh: meshing.mesh,
        normals,
    }))
}

/// The members combined in world coordinates, with the span of the first member's operation:
/// first what adds (`union`, `morph`) in leaf order, then each `subtract`, then each
/// `intersect`, so carving does not depend on whether the carving shape was derived before or
/// after what it carves. `None` when nothing adds.
fn combine(members: &[(&Leaf, &Implicit)]) -> Result<Option<(Solid, Span)>, DeriveError> {
    let mut base = Solid::empty();
    let mut span = None;
    for pass in 0..3 {
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
            let at = implicit.csg.as_ref().map_or(Span::default(), |c| c.span);
            span.get_or_insert(at);
            let fail = |e: shapegram_implicit::ImplicitError| DeriveError::at(e.message(), at);
            let member = implicit
                .solid
                .transform(&leaf.scope.local_to_world())
                .map_err(fail)?;
            base = match op {
                _ if base.is_empty() && pass == 0 => member,
                CsgOp::Union(k) if k > 0.0 => base.smooth_union(&member, k).map_err(fail)?,
                CsgOp::Union(_) => base.union(&member),
                CsgOp::Morph(a) => base.morph(&base.union(&member), a).map_err(fail)?,
                CsgOp::Subtract(k) if k > 0.0 => {
                    base.smooth_difference(&member, k).map_err(fail)?
                }
                CsgOp::Subtract(_) => base.difference(&member),
                CsgOp::Intersect(k) if k > 0.0 => {
                    base.smooth_intersection(&member, k).map_err(fail)?
                }
                CsgOp::Intersect(_) => base.intersection(&member),
            };
        }
        if pass == 0 && base.is_empty() {
            return Ok(None);
        }
    }
    Ok(span.map(|s| (base, s)))
}
