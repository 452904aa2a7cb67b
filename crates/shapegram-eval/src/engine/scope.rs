//! Scope operations: `t`, `r`, `s`, `center`, `mirror`, `alignScopeToAxes`,
//! `alignScopeToGeometry`, `alignScopeToGeometryBBox` and `rotateScope`. `t`, `r` and `center`
//! move the scope and the geometry with it, `s` and `mirror` stretch and flip the geometry in
//! it; the `align…` operations and `rotateScope` turn the scope while the geometry stays where
//! it is, and fit the scope around it again.

use std::sync::Arc;

use shapegram_geom::{DAffine3, DMat3, DVec3, Pivot, Scope};
use shapegram_syntax::Span;

use super::Fallible;
use super::implicit::no_solid;
use super::machine::Engine;
use super::texturing::follow_geometry;
use crate::error::DeriveError;
use crate::ops::{EdgeChoice, FaceChoice};
use crate::program::{CExpr, CKind};
use crate::shape::{Geometry, State, moved};
use crate::value::Value;

impl Engine<'_> {
    /// `t(x, y, z)`: the scope moves along its own axes.
    pub(super) fn translate(
        &mut self,
        state: &mut State,
        v: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let v = self.vector(v, state, args)?;
        let before = state.scope;
        state.scope.translate(v);
        follow_geometry(state, &before, DAffine3::IDENTITY);
        Ok(())
    }

    /// `r([scopeCenter,] x, y, z)`: the scope turns by angles in degrees about its own axes,
    /// around its origin or its centre.
    pub(super) fn rotate(
        &mut self,
        state: &mut State,
        about_center: bool,
        degrees: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let v = self.vector(degrees, state, args)?;
        let pivot = if about_center {
            Pivot::Center
        } else {
            Pivot::Origin
        };
        let before = state.scope;
        state.scope.rotate_euler_degrees(v, pivot);
        follow_geometry(state, &before, DAffine3::IDENTITY);
        Ok(())
    }

    /// `s(x, y, z)`: the scope's size, the geometry stretched with it.
    pub(super) fn size(
        &mut self,
        state: &mut State,
        v: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let v = self.vector(v, state, args)?;
        let before = state.scope;
        state.resize(v.abs());
        // A negative size mirrors: the axis turns around the scope's origin, and the
        // geometry with it.
        for i in 0..3 {
            if v[i] < 0.0 {
                state.mirror_axis(i);
            }
        }
        let old = before.size;
        let factor = DVec3::select(old.cmpeq(DVec3::ZERO), DVec3::ONE, v.abs() / old);
        follow_geometry(state, &before, DAffine3::from_scale(factor));
        Ok(())
    }

    /// `mirror(x, y, z)`: the geometry flipped within its scope along the axes whose argument
    /// is true (or a number other than 0).
    pub(super) fn mirror(
        &mut self,
        state: &mut State,
        flags: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let mut f = [false; 3];
        for (i, e) in flags.iter().enumerate() {
            f[i] = match self.ev.eval(e, state, args)? {
                Value::Bool(b) => b,
                Value::Number(n) => n != 0.0,
                other => {
                    return Err(DeriveError::at(
                        format!("expected a boolean, found a {}", other.type_name()),
                        e.span,
                    ));
                }
            };
        }
        mirror_in_scope(state, f);
        Ok(())
    }

    /// CGA `alignScopeToGeometry(yUp | zUp, face, edge)`: the scope turned to an edge of a face
    /// (see [`geometry_axes`]) and fitted around the geometry.
    pub(super) fn align_to_geometry(
        &mut self,
        state: &mut State,
        z_up: bool,
        face: &FaceChoice,
        edge: &EdgeChoice,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        no_solid(state, "alignScopeToGeometry", span)?;
        let face = match face {
            FaceChoice::Index(e) => FacePick::Index(self.index(e, state, args)?),
            FaceChoice::Lowest => FacePick::Lowest,
            FaceChoice::Largest => FacePick::Largest,
            FaceChoice::Any => FacePick::Any,
        };
        let edge = match edge {
            EdgeChoice::Index(e) => EdgePick::Index(self.index(e, state, args)?),
            EdgeChoice::Lowest => EdgePick::Lowest,
            EdgeChoice::Longest => EdgePick::Longest,
        };
        if let Some(axes) = geometry_axes(state, z_up, face, edge) {
            refit(state, axes);
        }
        Ok(())
    }

    /// CGA `rotateScope(x, y, z)`: the scope turns about its origin while the geometry stays,
    /// and is fitted around it.
    pub(super) fn rotate_scope(
        &mut self,
        state: &mut State,
        v: &[CExpr; 3],
        args: &[Value],
    ) -> Fallible<()> {
        let v = self.vector(v, state, args)?;
        let mut turned = state.scope;
        turned.rotate_euler_degrees(v, Pivot::Origin);
        refit(state, turned.axes);
        Ok(())
    }

    /// Evaluates three operation arguments, resolving relative ones against the scope size.
    pub(super) fn vector(
        &mut self,
        exprs: &[CExpr; 3],
        state: &mut State,
        args: &[Value],
    ) -> Fallible<DVec3> {
        let mut v = DVec3::ZERO;
        for (i, e) in exprs.iter().enumerate() {
            v[i] = match &e.kind {
                CKind::Relative(inner) => self.ev.number(inner, state, args)? * state.scope.size[i],
                _ => self.ev.number(e, state, args)?,
            };
        }
        Ok(v)
    }

    /// Evaluates a face or edge index: a whole number, negative ones counting from the end.
    fn index(&mut self, e: &CExpr, state: &mut State, args: &[Value]) -> Fallible<i64> {
        let n = self.ev.number(e, state, args)?;
        if n.fract() != 0.0 || n.abs() > 1e15 {
            return Err(DeriveError::at(
                format!("index {n}: expected a whole number"),
                e.span,
            ));
        }
        Ok(n as i64)
    }
}

/// `center(xyz)`: the scope centred, along the given axes, on the centre of `anchor` (the
/// scope the rule's statements started with, or the last one pushed).
pub(super) fn center(state: &mut State, anchor: &Scope, axes: [bool; 3]) {
    let target = anchor.center();
    let before = state.scope;
    state.scope.center_on(target, axes);
    follow_geometry(state, &before, DAffine3::IDENTITY);
}

/// CGA `alignScopeToGeometryBBox`: the scope turned as [`bbox_axes`] says and fitted around
/// the geometry.
pub(super) fn align_to_bbox(state: &mut State, first: usize, second: usize) {
    if let Some(axes) = bbox_axes(state, first, second) {
        refit(state, axes);
    }
}

/// Moves the scope to new axes, fitted around the geometry, which stays where it is.
pub(super) fn refit(state: &mut State, axes: DMat3) {
    // A solid is fitted by a coarse mesh of it (to within a cell), not by its bounds, which
    // would grow with every turn.
    let scope = match state.geometry.world_mesh(&state.scope) {
        Some(mesh) => Scope::fit(axes, mesh.positions().iter().copied()),
        None => Scope::new(state.scope.origin, axes, state.scope.size),
    };
    state.rescope(scope);
}

/// The face `alignScopeToGeometry` takes, evaluated.
enum FacePick {
    Index(i64),
    Lowest,
    Largest,
    Any,
}

/// The edge `alignScopeToGeometry` takes, evaluated.
enum EdgePick {
    Index(i64),
    Lowest,
    Longest,
}

/// CGA `alignScopeToGeometry`: x along the picked edge of the picked face, the face's normal as
/// y (`yUp`) or z (`zUp`); `None` for shapes without faces or a degenerate edge.
fn geometry_axes(state: &State, z_up: bool, face: FacePick, edge: EdgePick) -> Option<DMat3> {
    let world = state.geometry.world_mesh(&state.scope)?;
    let n = world.face_count();
    if n == 0 {
        return None;
    }
    let wrap = |i: i64, len: usize| i.rem_euclid(len as i64) as usize;
    // Edges of face `f` as (start, end).
    let edges = |f: usize| {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let k = points.len();
        (0..k).map(move |j| (points[j], points[(j + 1) % k]))
    };
    // How an edge selector ranks edges: smaller is better.
    let rank = |(a, b): (DVec3, DVec3)| match edge {
        EdgePick::Lowest => (a.y + b.y) / 2.0,
        EdgePick::Longest => -a.distance(b),
        EdgePick::Index(_) => 0.0,
    };
    let best = |scores: &mut dyn Iterator<Item = (f64, usize)>| {
        scores
            .fold(None, |best: Option<(f64, usize)>, (v, i)| match best {
                Some((w, _)) if w <= v => best,
                _ => Some((v, i)),
            })
            .map(|(_, i)| i)
    };
    let f = match face {
        FacePick::Index(i) => wrap(i, n),
        // The lowest by its centre: a box's walls reach down as far as its bottom does.
        FacePick::Lowest => best(&mut (0..n).map(|f| (world.face_centroid(f).y, f)))?,
        FacePick::Largest => best(&mut (0..n).map(|f| (-world.face_area(f), f)))?,
        FacePick::Any => best(&mut (0..n).map(|f| {
            let score = edges(f).map(rank).fold(f64::INFINITY, f64::min);
            (score, f)
        }))?,
    };
    let (a, b) = match edge {
        EdgePick::Index(j) => edges(f).nth(wrap(j, world.face(f).len()))?,
        _ => {
            let all: Vec<(DVec3, DVec3)> = edges(f).collect();
            all[best(&mut all.iter().enumerate().map(|(j, &e)| (rank(e), j)))?]
        }
    };
    let normal = world.face_normal(f).try_normalize()?;
    let x = (b - a).reject_from(normal).try_normalize()?;
    Some(if z_up {
        DMat3::from_cols(x, normal.cross(x), normal)
    } else {
        DMat3::from_cols(x, normal, x.cross(normal))
    })
}

/// CGA `alignScopeToGeometryBBox`: the scope's axes `first` and `second` turned about the third
/// so that they span the minimum-area rectangle around the geometry seen along it, `first` along
/// its longer side (pointing the way the old `first` axis did, as far as it can).
fn bbox_axes(state: &State, first: usize, second: usize) -> Option<DMat3> {
    let world = state.geometry.world_mesh(&state.scope)?;
    let fixed = 3 - first - second;
    let axes = state.scope.axes;
    let (u, v) = (axes.col(first), axes.col(second));
    let flat: Vec<shapegram_geom::DVec2> = world
        .positions()
        .iter()
        .map(|p| shapegram_geom::DVec2::new(p.dot(u), p.dot(v)))
        .collect();
    let rectangle = shapegram_geom::rectangle::min_area_rectangle(&flat)?;
    let mut along = rectangle.long_axis;
    if along.x < 0.0 {
        along = -along;
    }
    let mut cols = [DVec3::ZERO; 3];
    cols[fixed] = axes.col(fixed);
    cols[first] = u * along.x + v * along.y;
    // The remaining axis completes a right-handed frame (x = y × z, y = z × x, z = x × y).
    cols[second] = cols[(second + 1) % 3].cross(cols[(second + 2) % 3]);
    Some(DMat3::from_cols(cols[0], cols[1], cols[2]))
}

/// CGA `alignScopeToAxes`: all axes to the world's, or one axis to the world's with a second
/// axis kept, projected onto the plane across it, as CityEngine keeps it: for `x` the scope's z
/// axis, for `y` and `z` its x axis; the third completes a right-handed frame.
pub(super) fn align_to_axes(state: &mut State, axis: Option<usize>) {
    let axes = match axis {
        None => DMat3::IDENTITY,
        Some(k) => {
            let target = DVec3::AXES[k];
            let kept = if k == 0 { 2 } else { 0 };
            let keep = state
                .scope
                .axes
                .col(kept)
                .reject_from(target)
                .try_normalize()
                .unwrap_or(DVec3::AXES[kept]);
            let mut cols = [DVec3::ZERO; 3];
            cols[k] = target;
            cols[kept] = keep;
            let third = 3 - k - kept;
            // x = y × z, y = z × x, z = x × y.
            cols[third] = cols[(third + 1) % 3].cross(cols[(third + 2) % 3]);
            DMat3::from_cols(cols[0], cols[1], cols[2])
        }
    };
    refit(state, axes);
}

/// The geometry flipped within its scope along the flagged axes, each about the scope's middle;
/// the scope stays as it is.
fn mirror_in_scope(state: &mut State, flags: [bool; 3]) {
    if !flags.contains(&true) {
        return;
    }
    let size = state.scope.size;
    let mut scale = DVec3::ONE;
    let mut shift = DVec3::ZERO;
    for i in 0..3 {
        if flags[i] {
            scale[i] = -1.0;
            shift[i] = size[i];
        }
    }
    let map = DAffine3::from_translation(shift) * DAffine3::from_scale(scale);
    let scope = state.scope;
    follow_geometry(state, &scope, map);
    if let Geometry::Implicit(implicit) = &state.geometry {
        state.geometry = state.geometry.with_solid(moved(&implicit.solid, map));
        return;
    }
    let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
        return;
    };
    let tags = state.geometry.shared_tags();
    state.geometry = Geometry::Mesh(Arc::new(mesh.transformed(&map)), tags);
}
