//! Compiling a call into an [`Op`]: the dispatch by name and the argument checks all forms share.

use super::catalogue::{IMPLEMENTED, UNSUPPORTED, VISUAL_ONLY};
use super::*;

/// Compiles `call` as an operation. Returns `None` when no operation has that name,
/// `Some(None)` when it is one but the call has errors (already reported).
pub(crate) fn compile(
    c: &mut Compiler,
    call: &ast::Call,
    params: &[ast::Ident],
) -> Option<Option<Op>> {
    let name = call.name.name.as_str();
    if !is_operation(name) {
        return None;
    }
    if !IMPLEMENTED.contains(&name) {
        // Never evaluated: its arguments may use CGA words we do not know, which is no error.
        let mut ctx = Ctx {
            c,
            call,
            params,
            args: Vec::new(),
            words: Vec::new(),
        };
        return Some(ctx.build(name));
    }
    let args: Vec<CExpr> = call
        .args
        .iter()
        .flatten()
        .enumerate()
        .map(|(i, a)| match (&a.value.kind, name, i) {
            // `set(@name, …)` writes the attribute: no read.
            (ast::ExprKind::GoalAttribute { name, .. }, "set", 0) => {
                c.goal_attr_target(name, a.value.span)
            }
            _ => c.arg(&a.value, params),
        })
        .collect();
    let mut args = args;
    // `set` reads its first argument as a name itself, `setupProjection` its second.
    let own_word = match name {
        "set" => Some(0),
        "setupProjection" => Some(1),
        _ => None,
    };
    for (_, a) in args
        .iter_mut()
        .enumerate()
        .filter(|(i, _)| Some(*i) != own_word)
    {
        if let CKind::Selector(word) = &a.kind
            && crate::builtins::Query::is_known_unsupported(word)
        {
            let word = word.clone();
            a.kind = c.unknown_name(&word, a.span, params);
        }
    }
    let stray: Vec<(usize, String, Span)> = args
        .iter()
        .enumerate()
        .filter_map(|(i, a)| match &a.kind {
            CKind::Selector(word) => Some((i, word.clone(), a.span)),
            _ => None,
        })
        .collect();
    let mut ctx = Ctx {
        c,
        call,
        params,
        args,
        words: Vec::new(),
    };
    let op = ctx.build(name);
    // A bare word where the operation wanted a value is a name that does not exist. A skipped
    // operation reads none of its arguments: its words (`cleanupGeometry(all, 1)`) are its own.
    let errors = ctx.c.error_count();
    let reads_words = op.as_ref().is_some_and(|op| !matches!(op, Op::Ignored));
    for (i, word, span) in stray {
        if reads_words && !ctx.words.contains(&i) {
            ctx.c.unknown_name(&word, span, params);
        }
    }
    let failed = ctx.c.error_count() > errors;
    Some(op.filter(|_| !failed))
}

pub(super) struct Ctx<'a, 'g> {
    pub c: &'a mut Compiler<'g>,
    pub call: &'a ast::Call,
    pub params: &'a [ast::Ident],
    pub args: Vec<CExpr>,
    /// Argument positions read as bare words (selectors).
    pub words: Vec<usize>,
}

impl Ctx<'_, '_> {
    pub(super) fn build(&mut self, name: &str) -> Option<Op> {
        if VISUAL_ONLY.contains(&name) {
            self.warn_once(format!(
                "`{name}` is not supported yet: it is ignored (no effect on geometry)"
            ));
            return Some(Op::Ignored);
        }
        if UNSUPPORTED.contains(&name) {
            self.warn_once(format!(
                "operation `{name}` is not supported yet: it is skipped and the shape goes on unchanged"
            ));
            return Some(Op::Ignored);
        }
        let op = match name {
            "extrude" => self.extrude()?,
            "t" => Op::Translate(self.three()?),
            "r" => self.rotate()?,
            "s" => Op::Size(self.three()?),
            "center" => Op::Center(self.axes_selector()?),
            "mirror" => Op::Mirror(self.three()?),
            "alignScopeToAxes" => self.align()?,
            "alignScopeToGeometry" => self.align_to_geometry()?,
            "alignScopeToGeometryBBox" => self.align_to_bbox()?,
            "rotateScope" => Op::RotateScope(self.three()?),
            "mirrorScope" => Op::MirrorScope(self.three()?),
            "setPivot" => {
                self.arity(2, 2)?;
                let up = match self.word(0) {
                    Some("xyz") => 1,
                    Some("yzx") => 0,
                    Some("zxy") => 2,
                    _ => return self.bad_selector(0, "`xyz`, `yzx` or `zxy`"),
                };
                Op::SetPivot {
                    up,
                    corner: self.args.pop()?,
                }
            }
            "resetGeometry" => {
                self.arity(0, 0)?;
                Op::ResetGeometry
            }
            "i" | "insert" => self.insert()?,
            "primitiveCube" => self.primitive(Primitive::Cube, &[0, 3])?,
            "primitiveQuad" => self.primitive(Primitive::Quad, &[0, 2])?,
            "primitiveDisk" => self.primitive(Primitive::Disk, &[0, 1, 2])?,
            "primitivePyramid" => self.primitive(Primitive::Pyramid, &[0])?,
            "primitiveCylinder" => self.primitive(Primitive::Cylinder, &[0, 1, 3])?,
            "primitiveCone" => self.primitive(Primitive::Cone, &[0, 1])?,
            "primitiveSphere" => self.primitive(Primitive::Sphere, &[0, 1, 2])?,
            "split" => self.split(false)?,
            "splitArea" => self.split(true)?,
            "splitAndSetbackPerimeter" => self.perimeter_split()?,
            "joint" => {
                self.c.kinematic = true;
                Op::Joint(self.three()?)
            }
            "rotationLimits" => self.joint_limits(true)?,
            "translationLimits" => self.joint_limits(false)?,
            "rotateJoint" | "translateJoint" => {
                self.c.kinematic = true;
                let values = self.three()?;
                Op::JointPose {
                    rotation: name == "rotateJoint",
                    values,
                }
            }
            "snap" | "Snap" => self.snap()?,
            "tag" => self.tagging(false)?,
            "deleteTags" => self.tagging(true)?,
            "label" => {
                self.arity(1, 1)?;
                Op::Label(self.args.pop()?)
            }
            "comp" => self.comp()?,
            "setback" => self.setback()?,
            "setbackPerEdge" => {
                self.arity(1, 2)?;
                self.args.truncate(1);
                let blocks = self.setback_block(name, false)?;
                Op::Setback {
                    depths: Depths::PerEdge(self.args.pop()?),
                    entries: blocks.0,
                    shape: None,
                    remainder: blocks.2,
                }
            }
            "setbackToArea" => {
                self.arity(1, 4)?;
                let blocks = self.setback_block(name, false)?;
                Op::Setback {
                    depths: Depths::ToArea(std::mem::take(&mut self.args)),
                    entries: blocks.0,
                    shape: None,
                    remainder: blocks.2,
                }
            }
            "shapeL" => self.shape_luo(&[FaceClass::Front, FaceClass::Left])?,
            "shapeU" => self.shape_luo(&[FaceClass::Front, FaceClass::Right, FaceClass::Left])?,
            "shapeO" => self.shape_luo(&[
                FaceClass::Front,
                FaceClass::Right,
                FaceClass::Back,
                FaceClass::Left,
            ])?,
            "setupProjection" => self.setup_projection()?,
            "projectUV" => {
                self.arity(1, 1)?;
                Op::ProjectUv(self.args.pop()?)
            }
            "texture" => {
                self.arity(1, 1)?;
                Op::Texture(self.args.pop()?)
            }
            "tileUV" => self.edit_uv(UvEdit::Tile, 3)?,
            "scaleUV" => self.edit_uv(UvEdit::Scale, 3)?,
            "translateUV" | "offsetUV" => self.edit_uv(UvEdit::Translate, 3)?,
            "rotateUV" => self.edit_uv(UvEdit::Rotate, 2)?,
            "deleteUV" => self.edit_uv(UvEdit::Delete, 1)?,
            "copyUV" => self.edit_uv(UvEdit::Copy, 2)?,
            "normalizeUV" => self.normalize_uv()?,
            "color" => {
                if !matches!(self.args.len(), 1 | 3 | 4) {
                    return self.wrong_arity();
                }
                let args = std::mem::take(&mut self.args);
                match args.as_slice() {
                    [
                        CExpr {
                            kind: CKind::Value(Value::Str(text)),
                            ..
                        },
                    ] => match Color::from_hex(text) {
                        Some(color) => Op::ColorLiteral(color),
                        None => Op::Color(args),
                    },
                    _ => Op::Color(args),
                }
            }
            "set" => self.set()?,
            "report" => {
                self.arity(2, 2)?;
                let value = self.args.pop()?;
                Op::Report(self.args.pop()?, value)
            }
            "print" => {
                self.arity(1, 1)?;
                Op::Print(self.args.pop()?)
            }
            "reverseNormals" => {
                self.arity(0, 0)?;
                Op::ReverseNormals
            }
            "trim" => {
                self.arity(0, 0)?;
                Op::Trim
            }
            "convexify" => {
                self.arity(0, 1)?;
                Op::Convexify(self.args.pop())
            }
            "translate" | "rotate" => {
                self.arity(5, 5)?;
                let absolute = match self.word(0) {
                    Some("abs") => true,
                    Some("rel") => false,
                    _ => return self.bad_selector(0, "`abs` or `rel`"),
                };
                let system = match self.word(1) {
                    Some("scope" | "pivot") => CoordSystem::Scope,
                    Some("object") => CoordSystem::Object,
                    Some("world") => CoordSystem::World,
                    _ => return self.bad_selector(1, "`scope`, `pivot`, `object` or `world`"),
                };
                self.args.drain(..2);
                Op::Transform {
                    rotate: name == "rotate",
                    absolute,
                    system,
                    values: self.three()?,
                }
            }
            "scatter" => self.scatter()?,
            "footprint" => {
                self.arity(0, 0)?;
                Op::Footprint
            }
            // Shapegram's faces hold no holes: nothing to delete.
            "deleteHoles" => {
                self.arity(0, 0)?;
                Op::Ignored
            }
            "cleanupGeometry" => {
                self.arity(2, 2)?;
                let (vertices, edges, faces) = match self.word(0) {
                    Some("vertices") => (true, false, false),
                    Some("edges") => (false, true, false),
                    Some("faces") => (false, false, true),
                    Some("all") => (true, true, true),
                    _ => return self.bad_selector(0, "`vertices`, `edges`, `faces` or `all`"),
                };
                Op::Cleanup {
                    what: shapegram_geom::cleanup::Cleanup {
                        vertices,
                        faces,
                        edges,
                    },
                    tolerance: self.args.pop()?,
                }
            }
            "envelope" => {
                if !matches!(self.args.len(), 4 | 6 | 8 | 10) {
                    return self.wrong_arity();
                }
                let world_up = match self.word(0) {
                    Some("world.up") => true,
                    Some("normal") => false,
                    _ => return self.bad_selector(0, "`normal` or `world.up`"),
                };
                Op::Envelope {
                    world_up,
                    params: self.args.split_off(1),
                }
            }
            "innerRectangle" => {
                self.arity(1, 1)?;
                let edge = match self.word(0) {
                    Some("scope") => false,
                    Some("edge") => true,
                    _ => return self.bad_selector(0, "`scope` or `edge`"),
                };
                let (_, shape, remainder) = self.setback_block(name, true)?;
                Op::InnerRectangle {
                    edge,
                    shape,
                    remainder,
                    split: true,
                }
            }
            "innerRect" => {
                self.arity(0, 0)?;
                Op::InnerRectangle {
                    edge: false,
                    shape: None,
                    remainder: None,
                    split: false,
                }
            }
            "offset" => self.offset()?,
            "roofGable" => self.roof(RoofKind::Gable)?,
            "roofHip" => self.roof(RoofKind::Hip)?,
            "roofPyramid" => self.roof(RoofKind::Pyramid)?,
            "roofShed" => self.roof(RoofKind::Shed)?,
            "roofRidge" => self.roof(RoofKind::Ridge)?,
            "implicit" => self.implicit()?,
            "csg" => self.csg()?,
            "taper" => self.deform(DeformKind::Taper)?,
            "twist" => self.deform(DeformKind::Twist)?,
            "shear" => self.deform(DeformKind::Shear { toward: 0 })?,
            "sync" => self.sync()?,
            "union" => self.boolean(BooleanOp::Union)?,
            "subtract" => self.boolean(BooleanOp::Subtract)?,
            "intersect" => self.boolean(BooleanOp::Intersect)?,
            "inline" => self.inline()?,
            _ => unreachable!("`{name}` is listed in IMPLEMENTED but not built"),
        };
        // A skipped form (`comp(g) { … }`) keeps the block it was written with.
        let needs_block = matches!(
            op,
            Op::Split { .. }
                | Op::UvSplit { .. }
                | Op::Scatter(_)
                | Op::Comp { .. }
                | Op::Setback { .. }
                | Op::PerimeterSplit(_)
                | Op::InnerRectangle { split: true, .. }
                | Op::Boolean { .. }
                | Op::Inline { .. }
                | Op::Ignored
        );
        if !needs_block && self.call.block.is_some() {
            self.error(format!("`{name}` takes no `{{…}}` block"));
            return None;
        }
        Some(op)
    }

    pub(super) fn error(&mut self, message: String) {
        self.c.report(Diagnostic::error(message, self.call.span));
    }

    pub(super) fn warn_once(&mut self, message: String) {
        self.c.warn_once(
            &self.call.name.name,
            Diagnostic::warning(message, self.call.name.span),
        );
    }

    pub(super) fn wrong_arity(&mut self) -> Option<Op> {
        let signature = signature(&self.call.name.name).unwrap_or("");
        self.c.report(
            Diagnostic::error(
                format!("wrong number of arguments for `{}`", self.call.name.name),
                self.call.span,
            )
            .with_hint(format!("the signature is `{signature}`")),
        );
        None
    }

    pub(super) fn arity(&mut self, lo: usize, hi: usize) -> Option<()> {
        if self.args.len() < lo || self.args.len() > hi {
            self.wrong_arity()?;
        }
        Some(())
    }

    pub(super) fn three(&mut self) -> Option<[CExpr; 3]> {
        self.arity(3, 3)?;
        let z = self.args.pop()?;
        let y = self.args.pop()?;
        Some([self.args.pop()?, y, z])
    }

    /// The bare word (or string literal) of argument `i`.
    pub(super) fn word(&mut self, i: usize) -> Option<&str> {
        self.words.push(i);
        match &self.args.get(i)?.kind {
            CKind::Selector(s) => Some(s),
            CKind::Value(Value::Str(s)) => Some(s),
            _ => None,
        }
    }

    pub(super) fn bad_selector(&mut self, i: usize, expected: &str) -> Option<Op> {
        let span = self.args.get(i).map_or(self.call.span, |a| a.span);
        self.c.report(
            Diagnostic::error(format!("expected {expected}"), span)
                .with_label(format!("in `{}`", self.call.name.name)),
        );
        None
    }
}
