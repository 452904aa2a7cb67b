//! The authoring API (thesis 3.1.7): symbols and rules, and the cutting tools — face cut (with
//! the global option), prism cut with grid snapping, multi-cut, 3-point cut and the symmetric
//! three-part cut of 4.4 — plus assignment of symbols with anchors.
//!
//! Every method either succeeds or returns an error and leaves the project unchanged; wrap calls
//! in [`crate::Editor::apply`] for undo and redo.

use shapegram_geom::{Color, DMat3, DVec3};

use crate::anchor::{Anchor, all_anchors, canonical_order};
use crate::cut::{CutError, CutPlane, cut};
use crate::material::Material;
use crate::polyhedron::{Index, Polyhedron};
use crate::project::{
    Assignment, EditError, FaceOffset, NodeId, NodeKind, Project, Rule, RuleTree, Symbol,
};

/// Faces count as parallel when their normals' dot product is within this of −1.
const PARALLEL_EPSILON: f64 = 1e-9;

impl Project {
    /// An empty project.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a symbol with a prototype shape and reference anchor; returns its index.
    pub fn add_symbol(
        &mut self,
        name: &str,
        shape: Polyhedron,
        anchor: Anchor,
    ) -> Result<Index, EditError> {
        self.check_new_name(name)?;
        if anchor.half_edge(&shape).is_none() {
            return Err(EditError::NotFound(format!(
                "the anchor (face {}, corner {}) is not on the shape",
                anchor.face, anchor.corner
            )));
        }
        self.symbols.push(Symbol {
            name: name.to_owned(),
            color: None,
            face_colors: Vec::new(),
            shape,
            anchor,
        });
        Ok((self.symbols.len() - 1) as Index)
    }

    /// Adds a symbol whose prototype is the box `[0, size]`, anchored on its top face (face 3,
    /// corner 0: from the corner at x = 0, z = 0 towards z = 1, so the symbol stands upright).
    pub fn add_box_symbol(&mut self, name: &str, size: DVec3) -> Result<Index, EditError> {
        let shape = Polyhedron::cuboid(DVec3::ZERO, size).map_err(EditError::Shape)?;
        self.add_symbol(name, shape, Anchor::new(3, 0))
    }

    /// The index of the symbol called `name`.
    pub fn symbol_named(&self, name: &str) -> Option<Index> {
        self.symbols
            .iter()
            .position(|s| s.name == name)
            .map(|i| i as Index)
    }

    /// Renames symbol `symbol`.
    pub fn rename_symbol(&mut self, symbol: Index, name: &str) -> Result<(), EditError> {
        self.symbol(symbol)?;
        if self.symbols[symbol as usize].name != name {
            self.check_new_name(name)?;
        }
        self.symbols[symbol as usize].name = name.to_owned();
        Ok(())
    }

    /// Sets the colour of symbol `symbol` in generated meshes.
    pub fn set_color(&mut self, symbol: Index, color: Option<Color>) -> Result<(), EditError> {
        self.symbol(symbol)?;
        self.symbols[symbol as usize].color = color;
        Ok(())
    }

    /// Sets (or with `None` clears) the colour of one face of symbol `symbol`'s shapes, which
    /// overrides the symbol's colour there (the thesis's per-face materials, 4.4).
    pub fn set_face_color(
        &mut self,
        symbol: Index,
        face: Index,
        color: Option<Color>,
    ) -> Result<(), EditError> {
        let faces = self.symbol(symbol)?.shape.face_count();
        if face >= faces {
            return Err(EditError::NotFound(format!(
                "symbol {symbol} has no face {face} (it has {faces})"
            )));
        }
        let colors = &mut self.symbols[symbol as usize].face_colors;
        colors.retain(|&(f, _)| f != face);
        if let Some(color) = color {
            colors.push((face, color));
            colors.sort_by_key(|&(f, _)| f);
        }
        Ok(())
    }

    /// Adds an empty rule (one uncut sub-shape) to `symbol`; returns its index.
    pub fn add_rule(&mut self, symbol: Index, name: &str, weight: f64) -> Result<Index, EditError> {
        check_weight(weight)?;
        let tree = RuleTree::new(self.symbol(symbol)?);
        self.rules.push(Rule {
            name: name.to_owned(),
            symbol,
            weight,
            tree,
        });
        Ok((self.rules.len() - 1) as Index)
    }

    /// Sets the weight of rule `rule`.
    pub fn set_weight(&mut self, rule: Index, weight: f64) -> Result<(), EditError> {
        check_weight(weight)?;
        self.rule_mut(rule)?.weight = weight;
        Ok(())
    }

    /// Cuts sub-shape `leaf` of `rule` by `plane`; returns the new sub-shapes `[below, above]`.
    pub fn plane_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        plane: CutPlane,
    ) -> Result<[NodeId; 2], EditError> {
        self.rule_mut(rule)?.tree.cut(leaf, plane)
    }

    /// Face cut: a plane parallel to `face` of sub-shape `leaf`, `distance` inside it. Returns
    /// `[slice along the face, rest]`.
    pub fn face_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        face: Index,
        distance: f64,
    ) -> Result<[NodeId; 2], EditError> {
        let plane = self.face_plane(rule, leaf, face, distance)?;
        let [below, above] = self.plane_cut(rule, leaf, plane)?;
        Ok([above, below])
    }

    /// Offset cut: like [`Project::face_cut`], a plane parallel to `face` of sub-shape `leaf`
    /// `distance` inside it, but the distance stays `distance` metres when the rule is applied
    /// to a shape of another size (a wall of constant thickness) instead of scaling with it.
    /// Returns `[slice along the face, rest]`.
    pub fn offset_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        face: Index,
        distance: f64,
    ) -> Result<[NodeId; 2], EditError> {
        if !(distance.is_finite() && distance > 0.0) {
            return Err(EditError::Invalid(format!(
                "the distance {distance} must be a positive number of metres"
            )));
        }
        let plane = self.face_plane(rule, leaf, face, distance)?;
        let offset = FaceOffset { face, distance };
        let [below, above] = self
            .rule_mut(rule)?
            .tree
            .cut_with(leaf, plane, Some(offset))?;
        Ok([above, below])
    }

    /// Face cut with the global option: the plane of [`Project::face_cut`] cuts every uncut,
    /// unassigned sub-shape of the rule it passes through. Returns `[in front of the face's
    /// side, behind]` for each sub-shape cut, in depth-first order.
    pub fn global_face_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        face: Index,
        distance: f64,
    ) -> Result<Vec<[NodeId; 2]>, EditError> {
        let plane = self.face_plane(rule, leaf, face, distance)?;
        let cuts = self.cut_all(rule, plane, |_| true)?;
        Ok(cuts.into_iter().map(|[b, a]| [a, b]).collect())
    }

    /// Prism cut: sub-shape `leaf` must be a prism with `base` as one base; the plane parallel to
    /// the bases cuts at `fraction` of the height from `base`, snapped to a multiple of `grid`
    /// (world units) when given. Returns `[next to the base, rest]`.
    pub fn prism_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        base: Index,
        fraction: f64,
        grid: Option<f64>,
    ) -> Result<[NodeId; 2], EditError> {
        let mut distance = fraction * self.prism_height(rule, leaf, base)?;
        if let Some(step) = grid {
            if !(step.is_finite() && step > 0.0) {
                return Err(EditError::Invalid(format!(
                    "grid step {step} is not a positive number"
                )));
            }
            distance = (distance / step).round() * step;
        }
        let [near, rest] = self.face_cut(rule, leaf, base, distance)?;
        Ok([near, rest])
    }

    /// Multi-cut: `cuts` planes split prism `leaf` into `cuts + 1` equal prisms along the axis
    /// from `base`. Returns the parts in order from the base.
    pub fn multi_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        base: Index,
        cuts: usize,
    ) -> Result<Vec<NodeId>, EditError> {
        if cuts == 0 || cuts > 40 {
            return Err(EditError::Invalid(format!(
                "a multi-cut makes 1 to 40 cuts, not {cuts}"
            )));
        }
        let parts = cuts as f64 + 1.0;
        let fractions: Vec<f64> = (1..=cuts).map(|k| k as f64 / parts).collect();
        self.cut_prism_at(rule, leaf, base, &fractions)
    }

    /// The symmetric three-part cut of thesis 4.4: prism `leaf` is cut at `margin` and
    /// `1 − margin` of its height from `base`, so the two outer parts are equal. Returns
    /// `[margin at the base, middle, far margin]`.
    pub fn symmetric_cut(
        &mut self,
        rule: Index,
        leaf: NodeId,
        base: Index,
        margin: f64,
    ) -> Result<[NodeId; 3], EditError> {
        if !(margin > 0.0 && margin < 0.5) {
            return Err(EditError::Invalid(format!(
                "the margin {margin} must lie strictly between 0 and 0.5 of the height"
            )));
        }
        let parts = self.cut_prism_at(rule, leaf, base, &[margin, 1.0 - margin])?;
        Ok([parts[0], parts[1], parts[2]])
    }

    /// 3-point cut: the plane through `points` cuts every uncut, unassigned sub-shape of the rule
    /// whose section by the plane overlaps the triangle. Returns `[below, above]` per sub-shape
    /// cut (the normal follows the right-hand rule over the points), in depth-first order.
    pub fn three_point_cut(
        &mut self,
        rule: Index,
        points: [DVec3; 3],
    ) -> Result<Vec<[NodeId; 2]>, EditError> {
        let plane = CutPlane::through(points[0], points[1], points[2]).ok_or_else(|| {
            EditError::Invalid("the three points lie on one line: they define no plane".into())
        })?;
        self.cut_all(rule, plane, |section| triangle_overlaps(&points, section))
    }

    /// A point for the 3-point cut on an edge of sub-shape `leaf`: on the directed edge `edge`
    /// (a face and corner, written like an anchor) at `fraction` of its length from its start,
    /// the distance snapped to a multiple of `grid` when given (the editor's Ctrl); fractions 0
    /// and 1 are its vertices (the editor's Shift).
    pub fn edge_point(
        &self,
        rule: Index,
        leaf: NodeId,
        edge: Anchor,
        fraction: f64,
        grid: Option<f64>,
    ) -> Result<DVec3, EditError> {
        let shape = &self.rule(rule)?.tree.node(leaf)?.shape;
        let h = edge.half_edge(shape).ok_or_else(|| {
            EditError::NotFound(format!(
                "sub-shape {leaf} has no edge at face {}, corner {}",
                edge.face, edge.corner
            ))
        })?;
        if !(0.0..=1.0).contains(&fraction) {
            return Err(EditError::Invalid(format!(
                "the fraction {fraction} must lie between 0 and 1"
            )));
        }
        let (a, b) = (
            shape.position(shape.origin(h)),
            shape.position(shape.destination(h)),
        );
        let length = (b - a).length();
        let mut distance = fraction * length;
        if let Some(step) = grid {
            if !(step.is_finite() && step > 0.0) {
                return Err(EditError::Invalid(format!(
                    "grid step {step} is not a positive number"
                )));
            }
            distance = ((distance / step).round() * step).min(length);
        }
        // The far end is the vertex itself: `a + (b − a)` can miss `b` by a rounding, and a
        // point snapped to a vertex must cut exactly through it.
        if distance >= length {
            return Ok(b);
        }
        Ok(a + (b - a) * (distance / length))
    }

    /// Assigns `assignment` to sub-shape `leaf` (a symbol must match the leaf's topology under
    /// the anchor).
    pub fn assign(
        &mut self,
        rule: Index,
        leaf: NodeId,
        assignment: Assignment,
    ) -> Result<(), EditError> {
        let symbols = std::mem::take(&mut self.symbols);
        let result = self
            .rule_mut(rule)
            .and_then(|r| r.tree.assign(leaf, assignment, &symbols));
        self.symbols = symbols;
        result
    }

    /// Assigns `symbol` to sub-shape `leaf` with the anchor that stands the symbol's prototype
    /// up along `up` and faces its front (+z of the prototype) along `front`: the anchor a user
    /// would place by looking at the shape. Returns the anchor.
    pub fn assign_facing(
        &mut self,
        rule: Index,
        leaf: NodeId,
        symbol: Index,
        up: DVec3,
        front: DVec3,
    ) -> Result<Anchor, EditError> {
        let target = self.symbol(symbol)?;
        let node = self.rule(rule)?.tree.node(leaf)?;
        let prototype = canonical_order(&target.shape, target.anchor)
            .map(|o| {
                o.vertices
                    .iter()
                    .map(|&v| target.shape.position(v))
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default();
        let expected = target.topology();
        let mut best: Option<(f64, Anchor)> = None;
        for anchor in all_anchors(&node.shape) {
            let Some(order) = canonical_order(&node.shape, anchor) else {
                continue;
            };
            if order.topology != expected {
                continue;
            }
            let placed: Vec<DVec3> = order
                .vertices
                .iter()
                .map(|&v| node.shape.position(v))
                .collect();
            let map = fit_linear(&prototype, &placed);
            let score = (map * DVec3::Y)
                .normalize_or_zero()
                .dot(up.normalize_or_zero())
                + (map * DVec3::Z)
                    .normalize_or_zero()
                    .dot(front.normalize_or_zero());
            if best.is_none_or(|(s, _)| score > s + 1e-9) {
                best = Some((score, anchor));
            }
        }
        let Some((_, anchor)) = best else {
            return Err(EditError::TopologyMismatch(format!(
                "sub-shape {leaf} ({} vertices, {} faces) does not have the topology of symbol \
                 '{}' ({} vertices, {} faces)",
                node.shape.vertex_count(),
                node.shape.face_count(),
                target.name,
                target.shape.vertex_count(),
                target.shape.face_count()
            )));
        };
        self.assign(rule, leaf, Assignment::Symbol { symbol, anchor })?;
        Ok(anchor)
    }

    /// Makes a new symbol from sub-shape `leaf` (its shape and geometry, `anchor` as the
    /// reference anchor) and assigns it to the leaf, as the tree view's "new symbol" button.
    pub fn symbol_from_leaf(
        &mut self,
        rule: Index,
        leaf: NodeId,
        name: &str,
        anchor: Anchor,
    ) -> Result<Index, EditError> {
        let shape = self.rule(rule)?.tree.node(leaf)?.shape.clone();
        if let NodeKind::Cut { .. } = self.rule(rule)?.tree.node(leaf)?.kind {
            return Err(EditError::NotCuttable(format!(
                "node {leaf} is a cut, not a sub-shape"
            )));
        }
        let symbol = self.add_symbol(name, shape, anchor)?;
        if let Err(e) = self.assign(rule, leaf, Assignment::Symbol { symbol, anchor }) {
            self.symbols.pop();
            return Err(e);
        }
        Ok(symbol)
    }

    /// The face of sub-shape `leaf` whose outward normal points most nearly along `direction`
    /// (what clicking a face selects in the editor).
    pub fn face_towards(
        &self,
        rule: Index,
        leaf: NodeId,
        direction: DVec3,
    ) -> Result<Index, EditError> {
        let shape = &self.rule(rule)?.tree.node(leaf)?.shape;
        let score = |f: Index| shape.face_normal(f).dot(direction);
        Ok((0..shape.face_count())
            .reduce(|best, f| if score(f) > score(best) { f } else { best })
            .unwrap_or(0))
    }

    /// Symbol `symbol`.
    pub fn symbol(&self, symbol: Index) -> Result<&Symbol, EditError> {
        self.symbols
            .get(symbol as usize)
            .ok_or_else(|| EditError::NotFound(format!("there is no symbol {symbol}")))
    }

    /// Adds a material; returns its index.
    pub fn add_material(&mut self, material: Material) -> Result<Index, EditError> {
        self.check_material(&material, None)?;
        self.materials.push(material);
        Ok((self.materials.len() - 1) as Index)
    }

    /// Replaces material `index` (its name, colour, texture or tile size); faces that have it
    /// keep it.
    pub fn set_material(&mut self, index: Index, material: Material) -> Result<(), EditError> {
        self.material(index)?;
        self.check_material(&material, Some(index))?;
        self.materials[index as usize] = material;
        Ok(())
    }

    /// Material `index`.
    pub fn material(&self, index: Index) -> Result<&Material, EditError> {
        self.materials
            .get(index as usize)
            .ok_or_else(|| EditError::NotFound(format!("there is no material {index}")))
    }

    /// The index of the material called `name`.
    pub fn material_named(&self, name: &str) -> Option<Index> {
        self.materials
            .iter()
            .position(|m| m.name == name)
            .map(|i| i as Index)
    }

    /// Gives face `face` of sub-shape `node` of `rule` the material `material` (`None` clears
    /// it). On a cut node, the pieces of the face in every sub-shape cut from it get it too;
    /// sub-shapes cut later keep the material of the face they were cut from, and at
    /// derivation the sub-shapes of a symbol's shapes inherit their faces' materials.
    pub fn assign_face_material(
        &mut self,
        rule: Index,
        node: NodeId,
        face: Index,
        material: Option<Index>,
    ) -> Result<(), EditError> {
        if let Some(m) = material {
            self.material(m)?;
        }
        self.rule_mut(rule)?
            .tree
            .set_face_material(node, face, material)
    }

    fn check_material(&self, material: &Material, index: Option<Index>) -> Result<(), EditError> {
        material.check().map_err(EditError::Invalid)?;
        match self.material_named(&material.name) {
            Some(other) if Some(other) != index => Err(EditError::Invalid(format!(
                "there is already a material '{}'",
                material.name.escape_debug()
            ))),
            _ => Ok(()),
        }
    }

    /// Rule `rule`.
    pub fn rule(&self, rule: Index) -> Result<&Rule, EditError> {
        self.rules
            .get(rule as usize)
            .ok_or_else(|| EditError::NotFound(format!("there is no rule {rule}")))
    }

    fn rule_mut(&mut self, rule: Index) -> Result<&mut Rule, EditError> {
        self.rules
            .get_mut(rule as usize)
            .ok_or_else(|| EditError::NotFound(format!("there is no rule {rule}")))
    }

    fn check_new_name(&self, name: &str) -> Result<(), EditError> {
        if name.trim().is_empty() || name.len() > 200 {
            return Err(EditError::Invalid(
                "a symbol name must be 1 to 200 characters, not blank".into(),
            ));
        }
        if self.symbol_named(name).is_some() {
            return Err(EditError::Invalid(format!(
                "there is already a symbol '{name}'"
            )));
        }
        Ok(())
    }

    /// The plane parallel to `face` of `leaf`, `distance` inside, normal pointing out of the face.
    fn face_plane(
        &self,
        rule: Index,
        leaf: NodeId,
        face: Index,
        distance: f64,
    ) -> Result<CutPlane, EditError> {
        let shape = &self.rule(rule)?.tree.node(leaf)?.shape;
        if face >= shape.face_count() {
            return Err(EditError::NotFound(format!(
                "sub-shape {leaf} has no face {face} (it has {})",
                shape.face_count()
            )));
        }
        if !distance.is_finite() {
            return Err(EditError::Invalid(format!(
                "the distance {distance} is not a number"
            )));
        }
        let normal = shape.face_normal(face);
        Ok(CutPlane::new(
            shape.face_centroid(face) - normal * distance,
            normal,
        ))
    }

    /// The height of sub-shape `leaf` over `base`, after checking that it is a prism on it.
    fn prism_height(&self, rule: Index, leaf: NodeId, base: Index) -> Result<f64, EditError> {
        let shape = &self.rule(rule)?.tree.node(leaf)?.shape;
        if base >= shape.face_count() {
            return Err(EditError::NotFound(format!(
                "sub-shape {leaf} has no face {base} (it has {})",
                shape.face_count()
            )));
        }
        let sides = shape.face_len(base);
        let normal = shape.face_normal(base);
        let opposite = (0..shape.face_count()).find(|&f| {
            f != base
                && shape.face_len(f) == sides
                && shape.face_normal(f).dot(normal) < -1.0 + PARALLEL_EPSILON
        });
        let is_prism = opposite.is_some()
            && shape.vertex_count() == 2 * sides
            && shape.face_count() as usize == sides + 2;
        let (true, Some(opposite)) = (is_prism, opposite) else {
            return Err(EditError::NotCuttable(format!(
                "sub-shape {leaf} is not a prism with face {base} as a base"
            )));
        };
        Ok((shape.face_centroid(base) - shape.face_centroid(opposite)).dot(normal))
    }

    /// Cuts prism `leaf` at each of the increasing `fractions` of its height from `base`;
    /// returns the parts from the base outward.
    fn cut_prism_at(
        &mut self,
        rule: Index,
        leaf: NodeId,
        base: Index,
        fractions: &[f64],
    ) -> Result<Vec<NodeId>, EditError> {
        let height = self.prism_height(rule, leaf, base)?;
        let first = self.face_plane(rule, leaf, base, 0.0)?;
        let snapshot = self.rules[rule as usize].tree.clone();
        let mut parts = Vec::with_capacity(fractions.len() + 1);
        let mut rest = leaf;
        for &fraction in fractions {
            let plane = CutPlane::new(
                first.point - first.normal * (fraction * height),
                first.normal,
            );
            match self.plane_cut(rule, rest, plane) {
                Ok([below, above]) => {
                    parts.push(above);
                    rest = below;
                }
                Err(e) => {
                    self.rules[rule as usize].tree = snapshot;
                    return Err(e);
                }
            }
        }
        parts.push(rest);
        Ok(parts)
    }

    /// Cuts every cuttable leaf of `rule` that `plane` passes through and whose section
    /// satisfies `accept`; nothing is cut (and an error returned) when no leaf qualifies.
    fn cut_all(
        &mut self,
        rule: Index,
        plane: CutPlane,
        accept: impl Fn(&[DVec3]) -> bool,
    ) -> Result<Vec<[NodeId; 2]>, EditError> {
        let tree = &self.rule(rule)?.tree;
        let mut targets = Vec::new();
        for leaf in tree.cuttable_leaves() {
            let shape = &tree.node(leaf)?.shape;
            match cut(shape, &plane) {
                Ok(parts) => {
                    let cap = &parts.below;
                    let section: Vec<DVec3> = cap
                        .shape
                        .face_loop(cap.cap)
                        .map(|v| cap.shape.position(v))
                        .collect();
                    if accept(&section) {
                        targets.push(leaf);
                    }
                }
                Err(CutError::Miss) => {}
                Err(e) => return Err(e.into()),
            }
        }
        if targets.is_empty() {
            return Err(EditError::Cut(CutError::Miss));
        }
        let tree = &mut self.rule_mut(rule)?.tree;
        let snapshot = tree.clone();
        let mut out = Vec::with_capacity(targets.len());
        for leaf in targets {
            match tree.cut(leaf, plane) {
                Ok(children) => out.push(children),
                Err(e) => {
                    *tree = snapshot;
                    return Err(e);
                }
            }
        }
        Ok(out)
    }
}

fn check_weight(weight: f64) -> Result<(), EditError> {
    if weight.is_finite() && weight > 0.0 {
        Ok(())
    } else {
        Err(EditError::Invalid(format!(
            "a rule weight must be a positive number, not {weight}"
        )))
    }
}

/// The linear part of the least-squares affine map taking `from` onto `to` (paired points).
fn fit_linear(from: &[DVec3], to: &[DVec3]) -> DMat3 {
    let n = from.len().max(1) as f64;
    let (cf, ct) = (from.iter().sum::<DVec3>() / n, to.iter().sum::<DVec3>() / n);
    let mut cross = DMat3::ZERO;
    let mut spread = DMat3::ZERO;
    for (&p, &q) in from.iter().zip(to) {
        let (p, q) = (p - cf, q - ct);
        cross += DMat3::from_cols(q * p.x, q * p.y, q * p.z);
        spread += DMat3::from_cols(p * p.x, p * p.y, p * p.z);
    }
    cross * spread.inverse()
}

/// Whether the triangle and a convex polygon in the same plane overlap with positive area.
fn triangle_overlaps(triangle: &[DVec3; 3], polygon: &[DVec3]) -> bool {
    let normal = (triangle[1] - triangle[0]).cross(triangle[2] - triangle[0]);
    let polygon_normal = polygon_normal_of(polygon);
    // Walk the polygon so that it winds like the triangle.
    let ordered: Vec<DVec3> = if polygon_normal.dot(normal) < 0.0 {
        polygon.iter().rev().copied().collect()
    } else {
        polygon.to_vec()
    };
    let mut clipped = triangle.to_vec();
    for (k, &a) in ordered.iter().enumerate() {
        let b = ordered[(k + 1) % ordered.len()];
        let inward = normal.cross(b - a);
        let side = |p: DVec3| inward.dot(p - a);
        let mut next = Vec::with_capacity(clipped.len() + 1);
        for (i, &p) in clipped.iter().enumerate() {
            let q = clipped[(i + 1) % clipped.len()];
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                next.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                next.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        clipped = next;
        if clipped.len() < 3 {
            return false;
        }
    }
    let area = polygon_normal_of(&clipped).length();
    area > 1e-9 * normal.length()
}

/// Twice the vector area of a polygon.
fn polygon_normal_of(points: &[DVec3]) -> DVec3 {
    let Some(&first) = points.first() else {
        return DVec3::ZERO;
    };
    points
        .windows(2)
        .map(|w| (w[0] - first).cross(w[1] - first))
        .sum()
}
