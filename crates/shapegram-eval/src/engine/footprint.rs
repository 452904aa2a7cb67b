//! Operations on the faces of flat shapes (lots, and the faces `comp` makes): `extrude`,
//! `offset`, `setback` with `shapeL`, `shapeU` and `shapeO`, and `reverseNormals`. Roofs, which
//! also build on faces, have [`super::roof`].

use std::sync::Arc;

use shapegram_geom::{
    DMat3, DVec3, FaceClass, Mesh, Scope,
    cleanup::{Cleanup, cleanup_classes},
    convex::convex_pieces,
    extrude::{extrude_along, extrude_polygon},
    mesh::newell,
};
use shapegram_syntax::Span;

use super::Fallible;
use super::auto_tags;
use super::edge_depths::EdgeDepths;
use super::implicit::no_solid;
use super::machine::{Engine, Work};
use super::setback_tags::SetbackEdges;
use crate::error::DeriveError;
use crate::ops::{CompEntry, Depths, OffsetKeep};
use crate::program::{CExpr, CStmt};
use crate::shape::{Geometry, State, fills_box, flat_axis};
use crate::tags::{FaceTags, OffsetPart};
use crate::value::Value;

impl<'p> Engine<'p> {
    /// CGA `extrude`: every face pushed along its normal (or world up); the new scope keeps x as
    /// far as it can, takes y along the extrusion and is fitted around the result.
    pub(super) fn extrude(
        &mut self,
        state: &mut State,
        world_up: bool,
        distance: &CExpr,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let distance = self.ev.number(distance, state, args)?;
        if distance == 0.0 {
            return Ok(());
        }
        let scope = state.scope;
        let flat = flat_axis(scope.size);
        let world = flat_faces(state, "extrude", span)?;
        let mut solid = Mesh::new();
        let mut direction = DVec3::ZERO;
        let tagged = self.program.tagged;
        let mut tags = Vec::new();
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let normal = world.face_normal(f);
            let offset = if world_up { DVec3::Y } else { normal } * distance;
            let prism = if world_up {
                extrude_along(&points, offset)
            } else {
                extrude_polygon(&points, distance)
            };
            if let Some(prism) = prism {
                if direction == DVec3::ZERO {
                    direction = if world_up { DVec3::Y } else { normal };
                }
                if tagged {
                    let source = face_tags(state, f);
                    tags.extend(auto_tags::extruded(
                        &prism,
                        &source,
                        offset.dot(normal) < 0.0,
                    ));
                }
                solid.append(&prism);
            }
        }
        if solid.is_empty() {
            return Ok(());
        }
        let fitted = Scope::fit(
            grown_axes(&scope, direction),
            solid.positions().iter().copied(),
        );
        // A flat box extruded along its own axis stays a box.
        let stays_box = state.geometry == Geometry::Box
            && !tagged
            && flat.is_some_and(|k| scope.axes.col(k).abs_diff_eq(direction, 1e-12));
        state.geometry = if stays_box {
            Geometry::Box
        } else {
            solid.transform(&fitted.world_to_local());
            Geometry::tagged_mesh(solid, tags)
        };
        state.scope = fitted;
        Ok(())
    }

    /// CGA `offset(d)`: every face (of a polygon or a volume) shrunk (negative `d`) or grown
    /// (positive) by `d`, the ring between old and new outline kept as border faces; `inside`
    /// or `border` keeps only those.
    pub(super) fn offset(
        &mut self,
        state: &mut State,
        distance: &CExpr,
        keep: OffsetKeep,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let distance = self.ev.number(distance, state, args)?;
        // Each face by itself, a volume's as well (as CityEngine does): the result is faces.
        let Some(world) = state.geometry.world_mesh(&state.scope) else {
            return Err(DeriveError::at(
                "offset needs faces, but the shape has no geometry",
                span,
            ));
        };
        let mut mesh = Mesh::new();
        let mut tags = Vec::new();
        let old = state.geometry.tags();
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let (inside, border) = shapegram_geom::offset::inset_border(&points, distance);
            // The pieces keep their face's tags (not its edges': they move).
            let names = old
                .and_then(|t| t.get(f))
                .map(|t| t.names.clone())
                .unwrap_or_default();
            for (loops, part, wanted) in [
                (inside, OffsetPart::Inside, keep != OffsetKeep::Border),
                (border, OffsetPart::Border, keep != OffsetKeep::Inside),
            ] {
                for points in loops.iter().filter(|_| wanted) {
                    mesh.append(&Mesh::from_polygon(points));
                    tags.push(FaceTags {
                        part,
                        names: names.clone(),
                        ..FaceTags::default()
                    });
                }
            }
        }
        if mesh.is_empty() {
            state.geometry = Geometry::Empty;
            return Ok(());
        }
        let scope = Scope::fit(state.scope.axes, mesh.positions().iter().copied());
        mesh.transform(&scope.world_to_local());
        state.scope = scope;
        state.geometry = Geometry::Mesh(Arc::new(mesh), Some(tags.into()));
        Ok(())
    }

    /// CGA `setback` and `shapeL/U/O`: each face of a flat shape is cut into strips along the
    /// edges that move, their outline and the remainder. A strip goes to the first entry that
    /// selects its edge, with its scope's x along the edge, y along the face's normal and z into
    /// the strip; the outline (`shape`) and the remainder keep the shape's axes.
    pub(super) fn setback(
        &mut self,
        state: &mut State,
        depths: &Depths,
        outputs: SetbackOutputs<'p>,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let entries = outputs.entries;
        let world = flat_faces(state, "setback", span)?;
        let depths = &self.edge_depths(state, depths, &world, entries, span, args)?;
        let scope = state.scope;
        let frames = self.ev.frames(&scope);
        // Strips by entry, the outline's pieces (each its polygons) and remainder loops.
        let mut strips: Vec<Vec<(DVec3, Vec<DVec3>)>> = vec![Vec::new(); entries.len()];
        let (mut outline, mut rest): (Vec<Vec<Vec<DVec3>>>, Vec<Vec<DVec3>>) =
            (Vec::new(), Vec::new());
        let mut first_edge = 0;
        let mut moved: Vec<Vec<bool>> = Vec::new();
        for f in 0..world.face_count() {
            let points: Vec<DVec3> = world.face_points(f).collect();
            let normal = world.face_normal(f);
            let outward = |a: DVec3, b: DVec3| (b - a).cross(normal);
            let taker = |i: usize, a: DVec3, b: DVec3| {
                entries
                    .iter()
                    .position(|e| e.selector.takes_edge(outward(a, b), i, &frames))
            };
            let distance = |i: usize, a: DVec3, b: DVec3| match depths {
                EdgeDepths::Selected(d) => taker(i, a, b).map_or(0.0, |_| *d),
                // One distance per face edge, face after face; missing ones are 0.
                EdgeDepths::PerEdge(list) => list.get(first_edge + i).copied().unwrap_or(0.0),
                EdgeDepths::ByClass(list) => {
                    let class = FaceClass::of(outward(a, b), &scope);
                    list.iter()
                        .find(|(c, _)| *c == class)
                        .map_or(0.0, |(_, d)| *d)
                }
            };
            moved.push(
                (0..points.len())
                    .map(|i| distance(i, points[i], points[(i + 1) % points.len()]) > 0.0)
                    .collect(),
            );
            let cut = shapegram_geom::offset::setback(&points, distance).ok_or_else(|| {
                DeriveError::at(
                    "setback cannot cut this shape: a polygon that is not simple, or a setback so deep that an edge that moves runs onto one that moves slower",
                    span,
                )
            })?;
            // Faces hold no holes: an outline around a hole (shapeO's ring) stays as its strips.
            let holed = cut
                .outline
                .iter()
                .any(|l| newell(l.iter().copied()).dot(normal) < 0.0);
            if holed {
                outline.push(cut.strips.iter().map(|s| s.polygon.clone()).collect());
            } else {
                outline.extend(cut.outline.into_iter().map(|l| vec![l]));
            }
            for strip in cut.strips {
                let [a, b] = strip.ends;
                if let Some(e) = taker(strip.edge, a, b) {
                    strips[e].push((normal, strip.polygon));
                }
            }
            rest.extend(cut.remainder);
            first_edge += points.len();
        }
        let edges = self
            .program
            .tagged
            .then(|| SetbackEdges::new(&world, moved, |f| face_tags(state, f), &rest));
        let edges = edges.as_ref();
        let tags = |remainder: bool| {
            move |polygon: &[DVec3]| {
                edges.map_or_else(FaceTags::default, |e| e.tags(polygon, remainder))
            }
        };
        for (entry, chosen) in entries.iter().zip(&strips) {
            let pieces: Vec<Piece> = chosen
                .iter()
                .filter_map(|(normal, polygon)| {
                    // Like a lot along its front edge: x along the edge, z into the strip.
                    let x = (polygon[0] - polygon[1]).try_normalize()?;
                    let y = normal.try_normalize()?;
                    Some((DMat3::from_cols(x, y, x.cross(y)), vec![polygon.as_slice()]))
                })
                .collect();
            let how = (entry.merge, entry.selector.code(), &tags(false) as &Tagger);
            self.tagged_flat_children(state, pieces, how, &entry.body, span, args, out)?;
        }
        if let Some((merge, body)) = outputs.shape {
            let pieces = outline
                .iter()
                .map(|polygons| (scope.axes, polygons.iter().map(Vec::as_slice).collect()))
                .collect();
            let how = (*merge, 0, &tags(false) as &Tagger);
            self.tagged_flat_children(state, pieces, how, body, span, args, out)?;
        }
        if let Some((merge, body)) = outputs.remainder {
            let pieces = rest
                .iter()
                .map(|p| (scope.axes, vec![p.as_slice()]))
                .collect();
            let how = (*merge, 0, &tags(true) as &Tagger);
            self.tagged_flat_children(state, pieces, how, body, span, args, out)?;
        }
        Ok(())
    }

    /// Derives a child per piece (or one for all when `merge`), each a set of polygons with a
    /// scope of the given axes fitted around them.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn flat_children(
        &mut self,
        state: &mut State,
        pieces: Vec<Piece>,
        merge: bool,
        selector: u8,
        body: &'p [CStmt],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let how = (
            merge,
            selector,
            &(|_: &[DVec3]| FaceTags::default()) as &Tagger,
        );
        self.tagged_flat_children(state, pieces, how, body, span, args, out)
    }

    /// [`Engine::flat_children`], each polygon carrying the tags `tagger` gives it (with
    /// whether to merge and the selector's code).
    #[allow(clippy::too_many_arguments)]
    fn tagged_flat_children(
        &mut self,
        state: &mut State,
        pieces: Vec<Piece>,
        (merge, selector, tagger): (bool, u8, &Tagger),
        body: &'p [CStmt],
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let pieces = match pieces.first() {
            Some(&(axes, _)) if merge => {
                vec![(axes, pieces.into_iter().flat_map(|p| p.1).collect())]
            }
            _ => pieces,
        };
        let total = pieces.len() as u32;
        for (i, (axes, polygons)) in pieces.into_iter().enumerate() {
            let mut child = state.spawn();
            child.comp = (i as u32, total);
            child.comp_sel = selector;
            set_flat_geometry(&mut child, axes, &polygons, tagger);
            self.admit(&mut child, span)?;
            self.run_stmts(body, &mut child, args, out)?;
        }
        Ok(())
    }
}

/// Gives a shape these polygons (world coordinates) as its geometry, in a scope of the given
/// axes fitted around them; a single polygon that fills its scope is a box.
pub(super) fn set_flat_geometry(
    shape: &mut State,
    axes: DMat3,
    polygons: &[&[DVec3]],
    tagger: &Tagger,
) {
    let mut mesh = Mesh::new();
    let mut tags = Vec::new();
    for polygon in polygons {
        mesh.append(&Mesh::from_polygon(polygon));
        tags.push(tagger(polygon));
    }
    shape.scope = Scope::fit(axes, mesh.positions().iter().copied());
    mesh.transform(&shape.scope.world_to_local());
    let plain = tags.iter().all(FaceTags::is_plain);
    shape.geometry =
        if polygons.len() == 1 && plain && fills_box(mesh.positions(), shape.scope.size) {
            Geometry::Box
        } else {
            Geometry::tagged_mesh(mesh, tags)
        };
}

/// Polygons that become one shape, with the axes of its scope.
pub(super) type Piece<'a> = (DMat3, Vec<&'a [DVec3]>);

/// The tags a polygon of a piece carries (world coordinates).
pub(super) type Tagger<'a> = dyn Fn(&[DVec3]) -> FaceTags + 'a;

/// Where the pieces of a setback go.
pub(super) struct SetbackOutputs<'p> {
    /// Entries selecting the edges that move, each taking their strips (setback).
    pub(super) entries: &'p [CompEntry],
    /// The outline's entry, whether it merges and its body (shapeL/U/O).
    pub(super) shape: Option<&'p (bool, Vec<CStmt>)>,
    /// The remainder's entry, likewise.
    pub(super) remainder: Option<&'p (bool, Vec<CStmt>)>,
}

impl Engine<'_> {
    /// CGA `cleanupGeometry(vertices | faces | all, tolerance)`: the geometry cleaned (see
    /// [`shapegram_geom::cleanup`]); the scope stays.
    pub(super) fn cleanup(
        &mut self,
        state: &mut State,
        what: Cleanup,
        tolerance: &CExpr,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        no_solid(state, "cleanupGeometry", span)?;
        let t = self.ev.number(tolerance, state, args)?;
        if !(0.0..=1.0).contains(&t) {
            return Err(DeriveError::at(
                format!("cleanupGeometry's tolerance must be between 0 and 1, not {t}"),
                tolerance.span,
            ));
        }
        if state.geometry == Geometry::Box {
            return Ok(());
        }
        let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
            return Ok(());
        };
        // Faces of different tags stay apart, and each face keeps its tags; a face whose
        // corners changed loses its edges' tags, which named the old edges.
        let old_tags = state.geometry.tags();
        let classes: Vec<u32> = old_tags.map(tag_classes).unwrap_or_default();
        let (cleaned, sources) = cleanup_classes(&mesh, what, t, &classes);
        let tags = old_tags.map(|tags| {
            let kept: Vec<FaceTags> = sources
                .iter()
                .enumerate()
                .map(|(i, &f)| {
                    let mut kept = tags.get(f).cloned().unwrap_or_default();
                    if f >= mesh.face_count() || cleaned.face(i).len() != mesh.face(f).len() {
                        kept.edges = None;
                    }
                    kept
                })
                .collect();
            Arc::from(kept)
        });
        state.geometry = if cleaned.is_empty() {
            Geometry::Empty
        } else {
            Geometry::Mesh(Arc::new(cleaned), tags)
        };
        Ok(())
    }

    /// CGA `convexify([maxCut])`: every concave face of the geometry cut into convex faces
    /// (only along cuts shorter than `maxCut`, when given) that share the face's corners; the
    /// scope stays. Geometry without concave faces is left as it is.
    pub(super) fn convexify(
        &mut self,
        state: &mut State,
        max: Option<&CExpr>,
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        no_solid(state, "convexify", span)?;
        let max = match max {
            Some(e) => {
                let m = self.ev.number(e, state, args)?;
                if m <= 0.0 {
                    return Err(DeriveError::at(
                        format!("convexify's longest cut must be more than 0, not {m}"),
                        e.span,
                    ));
                }
                Some(m)
            }
            None => None,
        };
        let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
            return Ok(());
        };
        let tags = state.geometry.tags();
        let mut faces: Vec<Vec<u32>> = Vec::with_capacity(mesh.face_count());
        let mut kept_tags = Vec::with_capacity(mesh.face_count());
        for (f, face) in mesh.faces().enumerate() {
            let points: Vec<DVec3> = mesh.face_points(f).collect();
            for piece in convex_pieces(&points, max) {
                // The pieces' corners are the face's own: they keep their vertices.
                let piece: Option<Vec<u32>> = piece
                    .iter()
                    .map(|p| points.iter().position(|q| q == p).map(|k| face[k]))
                    .collect();
                faces.push(piece.unwrap_or_else(|| face.to_vec()));
                // Edge tags do not follow: the pieces' edges are not the face's.
                let kept = tags
                    .and_then(|t| t.get(f))
                    .map_or_else(FaceTags::default, |t| FaceTags {
                        edges: None,
                        ..t.clone()
                    });
                kept_tags.push(kept);
            }
        }
        if faces.len() == mesh.face_count() {
            return Ok(());
        }
        let cut = Mesh::from_faces(mesh.positions().to_vec(), faces);
        state.geometry = Geometry::Mesh(Arc::new(cut), tags.map(|_| kept_tags.into()));
        Ok(())
    }
}

/// CGA `footprint()`: the geometry projected onto the scope's xz-plane (its downward faces, or
/// for geometry without any, its upward ones), a flat shape facing the scope's y; the scope
/// keeps its axes and loses its height.
pub(super) fn footprint(state: &mut State, span: Span) -> Fallible<()> {
    no_solid(state, "footprint", span)?;
    let Some(mesh) = state.geometry.local_mesh(state.scope.size) else {
        return Ok(());
    };
    let flat = shapegram_geom::footprint::footprint(&mesh, DVec3::Y);
    if flat.is_empty() {
        state.geometry = Geometry::Empty;
        return Ok(());
    }
    let world: Vec<DVec3> = flat
        .positions()
        .iter()
        .map(|&p| state.scope.to_world(p))
        .collect();
    let fitted = Scope::fit(state.scope.axes, world.iter().copied());
    state.geometry = Geometry::mesh(flat);
    state.rescope(fitted);
    Ok(())
}

/// CGA `reverseNormals`: every face of the geometry turned the other way.
pub(super) fn reverse_normals(state: &mut State, span: Span) -> Fallible<()> {
    no_solid(state, "reverseNormals", span)?;
    if let Some(mut mesh) = state.geometry.local_mesh(state.scope.size) {
        mesh.flip();
        let tags = state.geometry.tags().map(|tags| {
            tags.iter()
                .enumerate()
                .map(|(f, t)| t.reversed(mesh.face(f).len()))
                .collect::<Vec<_>>()
                .into()
        });
        state.geometry = Geometry::Mesh(Arc::new(mesh), tags);
    }
    Ok(())
}

/// What face `f` of a shape's geometry carries.
pub(super) fn face_tags(state: &State, f: usize) -> FaceTags {
    state
        .geometry
        .tags()
        .and_then(|t| t.get(f))
        .cloned()
        .unwrap_or_default()
}

/// The faces of a flat shape in world coordinates, for the operations that build on polygons
/// (`extrude`, `offset`, roofs); an error for shapes without geometry and for volumes.
pub(super) fn flat_faces(state: &State, op: &str, span: Span) -> Fallible<Mesh> {
    let Some(world) = state.geometry.world_mesh(&state.scope) else {
        return Err(DeriveError::at(
            format!("{op} needs a polygon, but the shape has no geometry"),
            span,
        ));
    };
    let volume = flat_axis(state.scope.size).is_none() && state.geometry == Geometry::Box;
    if volume || world.is_watertight() {
        return Err(DeriveError::at(
            format!("{op} needs a flat shape (a polygon), but this shape is a volume"),
            span,
        )
        .with_hint(format!(
            "apply it to a face: `comp(f) {{ top : {op}(…) X }}`"
        )));
    }
    Ok(world)
}

/// The scope axes for a solid grown from faces along `up`: x kept as far as it can be, y up.
pub(super) fn grown_axes(scope: &Scope, up: DVec3) -> DMat3 {
    let x = scope
        .x_axis()
        .reject_from(up)
        .try_normalize()
        .unwrap_or_else(|| up.any_orthonormal_vector());
    DMat3::from_cols(x, up, x.cross(up))
}

/// A class number per face, the same for faces of equal tags: what cleanup keeps apart.
fn tag_classes(tags: &[FaceTags]) -> Vec<u32> {
    let mut distinct: Vec<&FaceTags> = Vec::new();
    tags.iter()
        .map(|face| {
            let class = distinct.iter().position(|d| *d == face).unwrap_or_else(|| {
                distinct.push(face);
                distinct.len() - 1
            });
            class as u32
        })
        .collect()
}
