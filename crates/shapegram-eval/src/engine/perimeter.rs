//! CGA `splitAndSetbackPerimeter(offset [, firstEdge, mask]) { len : depth : … }[*] {
//! remainder : … }`: the perimeter of a flat shape laid out like a split ([`Layout`]), each
//! section set back by its own depth ([`shapegram_geom::perimeter`]), and the rest.
//!
//! The perimeter is the face edges in face-edge order from `firstEdge` (wrapped), those the
//! mask selects, one after the other; the pattern starts `offset` along it and wraps round its
//! end, so a section may span several edges and the perimeter's start.

use shapegram_geom::perimeter::{EdgePiece, Stretch, split_setback_perimeter};
use shapegram_geom::{DMat3, DVec3};
use shapegram_syntax::Span;

use super::Fallible;
use super::footprint::{Piece, flat_faces, set_flat_geometry};
use super::machine::{Engine, Work};
use super::split::Layout;
use crate::error::DeriveError;
use crate::ops::PerimeterSplit;
use crate::program::{CExpr, CKind, CStmt};
use crate::shape::State;
use crate::tags::FaceTags;
use crate::value::Value;

/// A face edge of the shape: its face, its index in the face, and its ends.
struct FaceEdge {
    face: usize,
    index: usize,
    ends: [DVec3; 2],
}

impl FaceEdge {
    fn length(&self) -> f64 {
        self.ends[0].distance(self.ends[1])
    }
}

/// A laid-out section: where it starts along the perimeter, its length, body and depth.
type Section<'p> = (f64, f64, &'p [CStmt], Option<&'p CExpr>);

impl<'p> Engine<'p> {
    /// Derives the sections of a perimeter split (each its setback strip, in a scope along its
    /// first edge like a setback's strips), then the remainder.
    pub(super) fn perimeter_split(
        &mut self,
        state: &mut State,
        spec: &'p PerimeterSplit,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let world = flat_faces(state, "splitAndSetbackPerimeter", span)?;
        let faces: Vec<Vec<DVec3>> = (0..world.face_count())
            .map(|f| world.face_points(f).collect())
            .collect();
        let edges: Vec<FaceEdge> = faces
            .iter()
            .enumerate()
            .flat_map(|(face, points)| {
                (0..points.len()).map(move |index| FaceEdge {
                    face,
                    index,
                    ends: [points[index], points[(index + 1) % points.len()]],
                })
            })
            .collect();
        let chain = self.perimeter_chain(state, spec, &edges, args)?;
        let length: f64 = chain.iter().map(|&e| edges[e].length()).sum();
        let offset = self.pattern_offset(state, &spec.offset, length, args)?;
        let sections = self.sections(state, spec, length, span, args)?;
        // Each section's child, made now so that its depth sees its split.index.
        let total = sections.len() as u32;
        let mut children = Vec::with_capacity(sections.len());
        for (i, &(_, _, _, depth)) in sections.iter().enumerate() {
            let mut child = state.spawn();
            child.split = (i as u32, total);
            let depth = match depth {
                Some(e) => section_depth(self, e, &mut child, args)?,
                None => 0.0,
            };
            children.push((child, depth));
        }
        let mut polygons: Vec<Vec<Vec<DVec3>>> = vec![Vec::new(); sections.len()];
        let mut axes: Vec<Option<DMat3>> = vec![None; sections.len()];
        let mut rest: Vec<Vec<DVec3>> = Vec::new();
        for (f, points) in faces.iter().enumerate() {
            let normal = world.face_normal(f);
            let mut stretches = Vec::with_capacity(sections.len());
            for (i, &(start, size, _, _)) in sections.iter().enumerate() {
                let pieces = pieces_on_face(&edges, &chain, f, (offset + start, size), length);
                if axes[i].is_none()
                    && let Some(first) = pieces.first()
                {
                    axes[i] = strip_axes(&edges, f, first.edge, normal);
                }
                stretches.push(Stretch {
                    depth: children[i].1,
                    pieces,
                });
            }
            let cut = split_setback_perimeter(points, &stretches).ok_or_else(|| {
                DeriveError::at(
                    "splitAndSetbackPerimeter cannot cut this shape: a polygon that is not simple, or a section so deep that its edge runs onto the line of an edge that stays",
                    span,
                )
            })?;
            for (i, cut) in cut.stretches.into_iter().enumerate() {
                polygons[i].extend(cut);
            }
            rest.extend(cut.remainder);
        }
        for (((mut child, _), &(_, _, body, _)), (polygons, axes)) in children
            .into_iter()
            .zip(&sections)
            .zip(polygons.iter().zip(axes))
        {
            let (Some(axes), false) = (axes, polygons.is_empty()) else {
                continue;
            };
            let polygons: Vec<&[DVec3]> = polygons.iter().map(Vec::as_slice).collect();
            set_flat_geometry(&mut child, axes, &polygons, &|_| FaceTags::default());
            self.admit(&mut child, span)?;
            self.run_stmts(body, &mut child, args, out)?;
        }
        if let Some((merge, body)) = &spec.remainder {
            let pieces: Vec<Piece> = rest
                .iter()
                .map(|p| (state.scope.axes, vec![p.as_slice()]))
                .collect();
            self.flat_children(state, pieces, *merge, 0, body, span, args, out)?;
        }
        Ok(())
    }

    /// The face edges of the perimeter, in order: from the first edge (wrapped), those the
    /// mask selects (all without one), edges without length left out.
    fn perimeter_chain(
        &mut self,
        state: &mut State,
        spec: &PerimeterSplit,
        edges: &[FaceEdge],
        args: &[Value],
    ) -> Fallible<Vec<usize>> {
        let count = edges.len();
        let selected: Vec<bool> = match &spec.mask {
            None => vec![true; count],
            Some(e) => match self.ev.eval(e, state, args)? {
                // Missing entries leave their edges out; extra ones are ignored.
                Value::Array(list) => (0..count)
                    .map(|k| match list.get(k) {
                        None => Ok(false),
                        Some(Value::Bool(b)) => Ok(*b),
                        Some(other) => Err(DeriveError::at(
                            format!(
                                "splitAndSetbackPerimeter's edge mask holds booleans, not {}",
                                other.type_name()
                            ),
                            e.span,
                        )),
                    })
                    .collect::<Fallible<_>>()?,
                other => {
                    return Err(DeriveError::at(
                        format!(
                            "splitAndSetbackPerimeter's edge mask is an array of booleans (one per face edge), not {}",
                            other.type_name()
                        ),
                        e.span,
                    ));
                }
            },
        };
        let first = match &spec.first_edge {
            None => 0,
            Some(e) => {
                let index = self.ev.number(e, state, args)?;
                if !index.is_finite() {
                    return Err(DeriveError::at(
                        format!(
                            "splitAndSetbackPerimeter's first edge must be a number, not {index}"
                        ),
                        e.span,
                    ));
                }
                (index.floor() as i64).rem_euclid(count.max(1) as i64) as usize
            }
        };
        Ok((0..count)
            .map(|k| (first + k) % count)
            .filter(|&e| selected[e] && edges[e].length() > 0.0)
            .collect())
    }

    /// Where the pattern starts along a perimeter of `length`: metres, or `'` a fraction of it.
    fn pattern_offset(
        &mut self,
        state: &mut State,
        offset: &CExpr,
        length: f64,
        args: &[Value],
    ) -> Fallible<f64> {
        let value = match &offset.kind {
            CKind::Relative(inner) => self.ev.number(inner, state, args)? * length,
            _ => self.ev.number(offset, state, args)?,
        };
        if !value.is_finite() {
            return Err(DeriveError::at(
                format!("splitAndSetbackPerimeter's offset must be a number, not {value}"),
                offset.span,
            ));
        }
        Ok(value)
    }

    /// The sections laid out along a perimeter of `length`.
    fn sections(
        &mut self,
        state: &mut State,
        spec: &'p PerimeterSplit,
        length: f64,
        span: Span,
        args: &[Value],
    ) -> Fallible<Vec<Section<'p>>> {
        if length <= 0.0 {
            return Ok(Vec::new());
        }
        let mut layout: Layout<'p> = self.layouts.take();
        let laid = layout.lay_out(&spec.sections, length, span, &mut self.ev, state, args);
        let sections = layout
            .parts
            .iter()
            .map(|p| (p.start, p.size, p.body, p.depth))
            .collect();
        self.layouts.put(layout);
        laid.map(|()| sections)
    }
}

/// A section's depth: a number of 0 or more.
fn section_depth(
    engine: &mut Engine<'_>,
    e: &CExpr,
    child: &mut State,
    args: &[Value],
) -> Fallible<f64> {
    let depth = engine.ev.number(e, child, args)?;
    if !(depth.is_finite() && depth >= 0.0) {
        return Err(DeriveError::at(
            format!("a section's setback depth must be 0 or more, not {depth}"),
            e.span,
        ));
    }
    Ok(depth)
}

/// The pieces of face `face`'s edges that the section from `start` (wrapped round the
/// perimeter) over `size` metres covers, in the section's order.
fn pieces_on_face(
    edges: &[FaceEdge],
    chain: &[usize],
    face: usize,
    (start, size): (f64, f64),
    length: f64,
) -> Vec<EdgePiece> {
    let start = start.rem_euclid(length);
    let mut pieces = Vec::new();
    let mut at = 0.0;
    for &e in chain {
        let edge = &edges[e];
        let long = edge.length();
        // The section, and the section past the perimeter's end come round to its start.
        for shift in [0.0, length] {
            let from = start.max(at + shift);
            let to = (start + size).min(at + shift + long);
            if edge.face == face && to > from {
                let piece = EdgePiece {
                    edge: edge.index,
                    from: from - at - shift,
                    to: to - at - shift,
                };
                pieces.push((from, piece));
            }
        }
        at += long;
    }
    pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
    pieces.into_iter().map(|(_, piece)| piece).collect()
}

/// A section's scope axes, as a setback strip's: x along its first edge (against the face's
/// turn), y along the face's normal, z into the face.
fn strip_axes(edges: &[FaceEdge], face: usize, index: usize, normal: DVec3) -> Option<DMat3> {
    let edge = edges.iter().find(|e| e.face == face && e.index == index)?;
    let x = (edge.ends[0] - edge.ends[1]).try_normalize()?;
    let y = normal.try_normalize()?;
    Some(DMat3::from_cols(x, y, x.cross(y)))
}
