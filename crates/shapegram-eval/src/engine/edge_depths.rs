//! How far each edge of a setback moves: one distance for the selected edges (`setback(d)`),
//! an array in face-edge order (`setback(comp(fe){ … })`), a distance per side class (shapeL/U/O),
//! an expression evaluated on every face edge (`setbackPerEdge`) or the distance that leaves
//! the remainder a given area (`setbackToArea`).

use shapegram_geom::{DVec3, FaceClass, Mesh, component, mesh::newell, offset};
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::Engine;
use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::ops::{CompEntry, CompSelector, Depths};
use crate::program::CExpr;
use crate::shape::{Geometry, State};
use crate::value::Value;

/// How far the edges of a setback move, evaluated.
pub(super) enum EdgeDepths {
    /// The edges that entries select, by this distance.
    Selected(f64),
    /// Each face edge by its own distance, in face-edge order (face after face, edge after
    /// edge); missing ones stay.
    PerEdge(Vec<f64>),
    /// Edges by the class of their outward direction.
    ByClass(Vec<(FaceClass, f64)>),
}

/// Bisection steps of `setbackToArea`: enough to pin the distance down to the last bits of an
/// f64 on any lot.
const AREA_STEPS: usize = 100;

impl Engine<'_> {
    /// How far the edges of a setback of the faces of `world` move: the distances evaluated,
    /// none below 0.
    pub(super) fn edge_depths(
        &mut self,
        state: &mut State,
        depths: &Depths,
        world: &Mesh,
        entries: &[CompEntry],
        span: Span,
        args: &[Value],
    ) -> Fallible<EdgeDepths> {
        Ok(match depths {
            Depths::Selected(e) => match self.ev.eval(e, state, args)? {
                Value::Array(list) => EdgeDepths::PerEdge(distances(&list, e.span)?),
                _ => EdgeDepths::Selected(depth(&mut self.ev, e, state, args)?),
            },
            Depths::ByClass(list) => EdgeDepths::ByClass(
                list.iter()
                    .map(|(class, e)| Ok((*class, depth(&mut self.ev, e, state, args)?)))
                    .collect::<Fallible<Vec<_>>>()?,
            ),
            Depths::PerEdge(e) => {
                // The expression sees each face edge as the current shape, as comp(fe) makes it.
                let edges = component::face_edges(world);
                let total = edges.len() as u32;
                let mut list = Vec::with_capacity(edges.len());
                for (i, edge) in edges.iter().enumerate() {
                    let mut shape = state.spawn();
                    shape.scope = edge.scope;
                    shape.geometry = Geometry::Empty;
                    shape.comp = (i as u32, total);
                    shape.comp_sel = CompSelector::All.code();
                    list.push(depth(&mut self.ev, e, &mut shape, args)?);
                }
                EdgeDepths::PerEdge(list)
            }
            Depths::ToArea(exprs) => {
                let selected = self.selected_edges(state, world, entries);
                let bounds = self.area_bounds(state, exprs, args)?;
                EdgeDepths::PerEdge(to_area(world, &selected, &bounds, span)?)
            }
        })
    }

    /// Whether each face edge of `world` (in face-edge order) is taken by one of `entries`.
    fn selected_edges(&self, state: &State, world: &Mesh, entries: &[CompEntry]) -> Vec<bool> {
        let frames = self.ev.frames(&state.scope);
        let mut selected = Vec::new();
        for f in 0..world.face_count() {
            let normal = world.face_normal(f);
            let points: Vec<DVec3> = world.face_points(f).collect();
            for (i, &a) in points.iter().enumerate() {
                let outward = (points[(i + 1) % points.len()] - a).cross(normal);
                selected.push(
                    entries
                        .iter()
                        .any(|e| e.selector.takes_edge(outward, i, &frames)),
                );
            }
        }
        selected
    }

    /// The arguments of `setbackToArea(area [, minDists [, maxDists]] [, uvSet])` evaluated.
    fn area_bounds(
        &mut self,
        state: &mut State,
        exprs: &[CExpr],
        args: &[Value],
    ) -> Fallible<AreaBounds> {
        let area = self.ev.number(&exprs[0], state, args)?;
        let mut lists = Vec::new();
        for (k, e) in exprs.iter().enumerate().skip(1) {
            match self.ev.eval(e, state, args)? {
                Value::Array(list) if lists.len() < 2 => lists.push(distances(&list, e.span)?),
                // The uv set, last: only texturing would read it.
                Value::Number(_) if k == exprs.len() - 1 => {}
                other => {
                    return Err(DeriveError::at(
                        format!(
                            "setbackToArea: expected arrays of minimum and maximum distances (and a uv set last), found {}",
                            other.type_name()
                        ),
                        e.span,
                    ));
                }
            }
        }
        let mut lists = lists.into_iter();
        Ok(AreaBounds {
            area,
            min: lists.next().unwrap_or_default(),
            max: lists.next(),
        })
    }
}

/// What `setbackToArea` aims at: the remainder's area, and each face edge's least and greatest
/// distance (in face-edge order; missing minima are 0, missing maxima unbounded).
struct AreaBounds {
    area: f64,
    min: Vec<f64>,
    max: Option<Vec<f64>>,
}

/// The per-edge distances of `setbackToArea`: the selected edges move by their minimum plus a
/// common distance, capped at their maximum, found by bisection so that the remainder has the
/// target area. A target the setback cannot reach (not below the shape's area, above what the
/// minima leave, below what the maxima allow) leaves every edge where it is.
fn to_area(world: &Mesh, selected: &[bool], bounds: &AreaBounds, span: Span) -> Fallible<Vec<f64>> {
    if !(bounds.area.is_finite() && bounds.area > 0.0) {
        return Err(DeriveError::at(
            format!(
                "setbackToArea's area must be more than 0, not {}",
                bounds.area
            ),
            span,
        ));
    }
    let distances = |common: f64| -> Vec<f64> {
        selected
            .iter()
            .enumerate()
            .map(|(k, &taken)| match taken {
                false => 0.0,
                true => {
                    let least = bounds.min.get(k).copied().unwrap_or(0.0);
                    let most = bounds
                        .max
                        .as_ref()
                        .and_then(|m| m.get(k).copied())
                        .unwrap_or(f64::INFINITY);
                    (least + common).min(most)
                }
            })
            .collect()
    };
    let stay = vec![0.0; selected.len()];
    let reach = world
        .positions()
        .iter()
        .fold((DVec3::MAX, DVec3::MIN), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let (mut near, mut far) = (0.0, (reach.1 - reach.0).length());
    let fits = |common: f64| remainder_area(world, &distances(common));
    let reachable =
        fits(near).is_some_and(|a| a >= bounds.area) && fits(far).is_none_or(|a| a <= bounds.area);
    if !reachable {
        return Ok(stay);
    }
    for _ in 0..AREA_STEPS {
        let mid = 0.5 * (near + far);
        match fits(mid) {
            Some(a) if a > bounds.area => near = mid,
            _ => far = mid,
        }
    }
    match fits(near) {
        Some(_) => Ok(distances(near)),
        None => Ok(stay),
    }
}

/// The area left by a setback of every face of `world` with these per-edge distances (in
/// face-edge order), `None` when a face cannot be cut so.
fn remainder_area(world: &Mesh, distances: &[f64]) -> Option<f64> {
    let mut first = 0;
    let mut total = 0.0;
    for f in 0..world.face_count() {
        let points: Vec<DVec3> = world.face_points(f).collect();
        let cut = offset::setback(&points, |i, _, _| {
            distances.get(first + i).copied().unwrap_or(0.0)
        })?;
        total += cut
            .remainder
            .iter()
            .map(|l| newell(l.iter().copied()).length() * 0.5)
            .sum::<f64>();
        first += points.len();
    }
    Some(total)
}

/// A setback distance evaluated: an error below 0.
fn depth(ev: &mut Evaluator, e: &CExpr, state: &mut State, args: &[Value]) -> Fallible<f64> {
    let d = ev.number(e, state, args)?;
    if d < 0.0 {
        return Err(DeriveError::at(
            format!("setback distance {d}: expected 0 or more"),
            e.span,
        ));
    }
    Ok(d)
}

/// An array of setback distances: numbers of 0 or more.
fn distances(list: &[Value], span: Span) -> Fallible<Vec<f64>> {
    list.iter()
        .map(|v| match v {
            Value::Number(d) if *d >= 0.0 => Ok(*d),
            other => Err(DeriveError::at(
                format!("setback distances: expected numbers of 0 or more, found {other}"),
                span,
            )),
        })
        .collect()
}
