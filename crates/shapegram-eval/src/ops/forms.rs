//! The arguments of each family of operations, read into their [`Op`]s.

use super::build::Ctx;
use super::*;

impl Ctx<'_, '_> {
    pub(super) fn setup_projection(&mut self) -> Option<Op> {
        self.arity(4, 7)?;
        let word = self.word(1).map(str::to_owned);
        let parsed = word.as_deref().and_then(|w| {
            let (world, letters) = match w.split_once('.')? {
                ("scope", letters) => (false, letters),
                ("world", letters) => (true, letters),
                _ => return None,
            };
            let axis = |c: char| "xyz".find(c);
            let mut chars = letters.chars();
            let (a, b) = (axis(chars.next()?)?, axis(chars.next()?)?);
            (chars.next().is_none() && a != b).then_some((world, [a, b]))
        });
        let Some((world, axes)) = parsed else {
            return self.bad_selector(1, "projection axes such as `scope.xy` or `world.xz`");
        };
        let mut args = std::mem::take(&mut self.args).into_iter();
        let set = args.next()?;
        let sizes = [args.nth(1)?, args.next()?];
        let rest: Vec<CExpr> = args.collect();
        let (offsets, uw_factor) = match <[CExpr; 3]>::try_from(rest) {
            Ok([a, b, k]) => (Some([a, b]), Some(k)),
            Err(mut rest) if rest.len() == 2 => {
                let b = rest.pop()?;
                (Some([rest.pop()?, b]), None)
            }
            Err(mut rest) => (None, rest.pop()),
        };
        Some(Op::SetupProjection(Box::new(ProjectionSetup {
            set,
            world,
            axes,
            sizes,
            offsets,
            uw_factor,
        })))
    }

    pub(super) fn normalize_uv(&mut self) -> Option<Op> {
        self.arity(3, 3)?;
        let mode = match self.word(1) {
            Some("uv") => UvNormalization::Each,
            Some("uvUniform") => UvNormalization::Uniform,
            Some("u") => UvNormalization::U,
            Some("v") => UvNormalization::V,
            _ => return self.bad_selector(1, "`uv`, `uvUniform`, `u` or `v`"),
        };
        match self.word(2) {
            Some("collectiveAllFaces") => {}
            Some("separatePerFace") => self.warn_once(
                "`normalizeUV(…, separatePerFace)` normalizes the faces of a shape together (as `collectiveAllFaces`): exact for shapes of one face"
                    .into(),
            ),
            _ => return self.bad_selector(2, "`separatePerFace` or `collectiveAllFaces`"),
        }
        self.args.truncate(1);
        Some(Op::EditUv(
            UvEdit::Normalize(mode),
            std::mem::take(&mut self.args),
        ))
    }

    pub(super) fn edit_uv(&mut self, edit: UvEdit, count: usize) -> Option<Op> {
        self.arity(count, count)?;
        Some(Op::EditUv(edit, std::mem::take(&mut self.args)))
    }

    pub(super) fn extrude(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let world_up = if self.args.len() == 2 {
            match self.word(0) {
                Some("world.up" | "world.up.flatTop" | "world.y") => true,
                Some("face.normal" | "vertex.normal") => false,
                _ => {
                    return self.bad_selector(0, "`world.up`, `world.up.flatTop` or `face.normal`");
                }
            }
        } else {
            false
        };
        Some(Op::Extrude {
            world_up,
            distance: self.args.pop()?,
        })
    }

    pub(super) fn rotate(&mut self) -> Option<Op> {
        let about_center = match self.args.len() {
            3 => false,
            4 => match self.word(0) {
                Some("scopeCenter") => true,
                Some("scopeOrigin") => false,
                _ => return self.bad_selector(0, "`scopeCenter` or `scopeOrigin`"),
            },
            _ => return self.wrong_arity(),
        };
        let z = self.args.pop()?;
        let y = self.args.pop()?;
        let x = self.args.pop()?;
        Some(Op::Rotate {
            about_center,
            degrees: [x, y, z],
        })
    }

    pub(super) fn axes_selector(&mut self) -> Option<[bool; 3]> {
        self.arity(1, 1)?;
        let word = self.word(0).map(str::to_owned);
        match word.as_deref() {
            Some(w) if !w.is_empty() && w.chars().all(|ch| "xyz".contains(ch)) => {
                Some([w.contains('x'), w.contains('y'), w.contains('z')])
            }
            _ => {
                self.bad_selector(0, "axes such as `x`, `xz` or `xyz`");
                None
            }
        }
    }

    pub(super) fn align(&mut self) -> Option<Op> {
        self.arity(0, 1)?;
        if self.args.is_empty() {
            return Some(Op::AlignScopeToAxes(None));
        }
        match self.word(0) {
            Some("x" | "world.x") => Some(Op::AlignScopeToAxes(Some(0))),
            Some("y" | "world.y") => Some(Op::AlignScopeToAxes(Some(1))),
            Some("z" | "world.z") => Some(Op::AlignScopeToAxes(Some(2))),
            Some("world.xyz" | "xyz") => Some(Op::AlignScopeToAxes(None)),
            _ => self.bad_selector(0, "`x`, `y`, `z` or `world.xyz`"),
        }
    }

    pub(super) fn insert(&mut self) -> Option<Op> {
        self.arity(1, 4)?;
        let mut placement = Placement::default();
        if self.args.len() > 1 {
            placement.z_up = match self.word(1) {
                Some("yUp") => false,
                Some("zUp") => true,
                _ => return self.bad_selector(1, "the asset's up axis, `yUp` or `zUp`"),
            };
        }
        if self.args.len() > 2 {
            placement.fit = match self.word(2) {
                Some("alignSizeAndPosition") => InsertFit::Align,
                Some("keepSizeAndPosition") => InsertFit::Keep,
                Some("keepSizeAlignPosition") => InsertFit::KeepSize,
                _ => {
                    return self.bad_selector(
                        2,
                        "`alignSizeAndPosition`, `keepSizeAndPosition` or `keepSizeAlignPosition`",
                    );
                }
            };
        }
        // Shapegram's meshes need no numerical cleanup, so both choices insert alike.
        if self.args.len() > 3 && !matches!(self.word(3), Some("numericalCleanup" | "noCleanup")) {
            return self.bad_selector(3, "`numericalCleanup` or `noCleanup`");
        }
        Some(Op::Insert(self.args.swap_remove(0), placement))
    }

    /// A `primitive…(…)` call with one of the argument counts its forms take.
    pub(super) fn primitive(&mut self, kind: Primitive, forms: &[usize]) -> Option<Op> {
        if !forms.contains(&self.args.len()) {
            return self.wrong_arity();
        }
        Some(Op::Primitive(kind, std::mem::take(&mut self.args)))
    }

    pub(super) fn split(&mut self, by_area: bool) -> Option<Op> {
        self.arity(1, 5)?;
        let axis = match self.word(0) {
            Some("x") => 0,
            Some("y") => 1,
            Some("z") => 2,
            Some("u") if !by_area => return self.uv_split(0),
            Some("v") if !by_area => return self.uv_split(1),
            _ => return self.bad_selector(0, "the split axis `x`, `y` or `z`"),
        };
        let mut adjust = true;
        let mut snap = None;
        let mut joints = SplitJoints::Auto;
        let mut i = 1;
        while i < self.args.len() {
            match self.word(i) {
                Some("adjust") if snap.is_none() => adjust = true,
                Some("noAdjust") if snap.is_none() => adjust = false,
                Some("sequential") if snap.is_none() => {
                    joints = SplitJoints::Sequential;
                    self.c.kinematic = true;
                }
                Some("parallel") if snap.is_none() => {
                    joints = SplitJoints::Parallel;
                    self.c.kinematic = true;
                }
                Some("snap") if snap.is_none() => {
                    let tag = self.args.get(i + 1).cloned();
                    i += usize::from(tag.is_some());
                    snap = Some(tag);
                    self.c.uses.context = true;
                }
                _ => {
                    return self.bad_selector(
                        i,
                        "`adjust`, `noAdjust`, `sequential`, `parallel` or `snap`",
                    );
                }
            }
            i += 1;
        }
        if by_area && (snap.is_some() || joints != SplitJoints::Auto) {
            self.error("`splitArea` takes `adjust` or `noAdjust` only".into());
            return None;
        }
        let Some(block) = &self.call.block else {
            let name = &self.call.name.name;
            self.error(format!("`{name}` needs a `{{ size : … }}` block"));
            return None;
        };
        let block = split_block(self.c, block, self.params, false)?;
        Some(Op::Split {
            axis,
            by_area,
            adjust,
            snap,
            joints,
            block,
        })
    }

    /// `splitAndSetbackPerimeter(offset [, firstEdge, mask]) { len : depth : … }[*] {
    /// remainder : … }`, its blocks joined by the parser (see `ast::Call`).
    pub(super) fn perimeter_split(&mut self) -> Option<Op> {
        if !matches!(self.args.len(), 1 | 3) {
            return self.wrong_arity();
        }
        let Some(block) = &self.call.block else {
            self.error("`splitAndSetbackPerimeter` needs a `{ length : depth : … }` block".into());
            return None;
        };
        let mut entries = block.entries.iter();
        let Some(BlockEntry::Group(sections)) = entries.next() else {
            self.error("`splitAndSetbackPerimeter` needs a `{ length : depth : … }` block".into());
            return None;
        };
        let sections = split_block(self.c, sections, self.params, true)?;
        let mut remainder = None;
        for entry in entries {
            match entry {
                BlockEntry::Part {
                    key:
                        ast::Expr {
                            kind: ast::ExprKind::Name(name),
                            ..
                        },
                    merge,
                    body,
                    ..
                } if name == "remainder" && remainder.is_none() => {
                    remainder = Some((*merge, self.c.stmts(body, self.params)));
                }
                BlockEntry::Part { span, .. } => {
                    self.c.report(Diagnostic::error(
                        "the second block of `splitAndSetbackPerimeter` holds one `remainder : …` entry",
                        *span,
                    ));
                    return None;
                }
                BlockEntry::Group(group) => {
                    self.c.report(Diagnostic::error(
                        "the second block of `splitAndSetbackPerimeter` holds one `remainder : …` entry",
                        group.span,
                    ));
                    return None;
                }
            }
        }
        let mut args = std::mem::take(&mut self.args).into_iter();
        let offset = args.next()?;
        Some(Op::PerimeterSplit(Box::new(PerimeterSplit {
            offset,
            first_edge: args.next(),
            mask: args.next(),
            sections,
            remainder,
        })))
    }

    /// `scatter(domain, n, uniform | gaussian [, mean [, stddev]]) { … }`.
    pub(super) fn scatter(&mut self) -> Option<Op> {
        self.arity(3, 5)?;
        let domain = match self.word(0) {
            Some("surface") => ScatterDomain::Surface,
            Some("volume") => ScatterDomain::Volume,
            Some("scope") => ScatterDomain::Scope,
            _ => return self.bad_selector(0, "`surface`, `volume` or `scope`"),
        };
        let count = self.args.len();
        let gaussian = match self.word(2) {
            Some("uniform") if count == 3 => false,
            Some("gaussian") => true,
            Some("uniform") => return self.bad_selector(3, "nothing after `uniform`"),
            _ => return self.bad_selector(2, "`uniform` or `gaussian`"),
        };
        let mean = if self.args.len() > 3 {
            let at = match self.word(3) {
                Some("center") => [0.5, 0.5, 0.5],
                Some("front") => [0.5, 0.5, 1.0],
                Some("back") => [0.5, 0.5, 0.0],
                Some("left") => [0.0, 0.5, 0.5],
                Some("right") => [1.0, 0.5, 0.5],
                Some("top") => [0.5, 1.0, 0.5],
                Some("bottom") => [0.5, 0.0, 0.5],
                _ => {
                    return self.bad_selector(
                        3,
                        "`center`, `front`, `back`, `left`, `right`, `top` or `bottom`",
                    );
                }
            };
            Some(at)
        } else {
            None
        };
        let stddev = (self.args.len() == 5).then(|| self.args.pop()).flatten();
        let Some(block) = &self.call.block else {
            self.error("`scatter` needs a `{ … }` block with what to do at each point".into());
            return None;
        };
        let [BlockEntry::Part { body, .. }] = block.entries.as_slice() else {
            self.error("`scatter` takes one body in its block: `{ operations }`".into());
            return None;
        };
        let body = self.c.stmts(body, self.params);
        Some(Op::Scatter(Box::new(ScatterSpec {
            domain,
            count: self.args.swap_remove(1),
            gaussian: gaussian.then(|| (mean.unwrap_or([0.5; 3]), stddev)),
            body,
        })))
    }

    /// `split(u | v, uvSpace | unitSpace, uvSet) { … }`.
    pub(super) fn uv_split(&mut self, coordinate: usize) -> Option<Op> {
        if self.args.len() != 3 {
            return self.wrong_arity();
        }
        let metres = match self.word(1) {
            Some("uvSpace") => false,
            Some("unitSpace") => true,
            _ => return self.bad_selector(1, "`uvSpace` or `unitSpace`"),
        };
        let Some(block) = &self.call.block else {
            self.error("`split` needs a `{ size : … }` block".into());
            return None;
        };
        let block = split_block(self.c, block, self.params, false)?;
        Some(Op::UvSplit {
            coordinate,
            metres,
            set: self.args.pop()?,
            block,
        })
    }

    /// `rotationLimits(axis, min, max)` and `translationLimits(axis, min, max)`.
    pub(super) fn joint_limits(&mut self, rotation: bool) -> Option<Op> {
        self.c.kinematic = true;
        self.arity(3, 3)?;
        let axis = match self.word(0) {
            Some("x") => 0,
            Some("y") => 1,
            Some("z") => 2,
            _ => return self.bad_selector(0, "the joint axis `x`, `y` or `z`"),
        };
        let max = self.args.pop()?;
        let min = self.args.pop()?;
        Some(Op::JointLimits {
            rotation,
            axis,
            min,
            max,
        })
    }

    /// `snap(x)`, `snap(xy, "tag")`, Müller's `Snap("X")`.
    pub(super) fn snap(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let word = self.word(0).map(str::to_ascii_lowercase);
        let mut axes = [false; 3];
        let valid = word.as_deref().is_some_and(|w| {
            !w.is_empty()
                && w.chars().all(|c| match c {
                    'x' | 'y' | 'z' => {
                        axes[c as usize - 'x' as usize] = true;
                        true
                    }
                    _ => false,
                })
        });
        if !valid {
            return self.bad_selector(0, "the axes to snap to: `x`, `y`, `z` or a mix like `xz`");
        }
        Some(Op::Snap {
            axes,
            tag: self.args.get(1).cloned(),
        })
    }

    pub(super) fn comp(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let kind = match self.word(0) {
            Some("f") => CompKind::Faces,
            Some("e") => CompKind::Edges,
            Some("fe") => CompKind::FaceEdges,
            Some("v") => CompKind::Vertices,
            Some("fv") => CompKind::FaceVertices,
            Some("h") => CompKind::Holes,
            Some("m") => CompKind::Materials,
            Some("g") => {
                // The groups are recorded at the insert only for grammars that ask for them.
                self.c.tagged = true;
                CompKind::Groups
            }
            Some(other) => {
                let other = other.to_owned();
                self.warn_once(format!("`comp({other})` is not supported yet: skipped"));
                return Some(Op::Ignored);
            }
            None => return self.bad_selector(0, "`f`, `e`, `fe`, `v`, `fv`, `m`, `g` or `h`"),
        };
        let Some(block) = &self.call.block else {
            self.error("`comp` needs a `{ selector : … }` block".into());
            return None;
        };
        let mut entries = Vec::new();
        for entry in &block.entries {
            match entry {
                BlockEntry::Part {
                    key,
                    merge,
                    body,
                    span,
                } => {
                    let selector = comp_selector(self.c, key, self.params, *span);
                    entries.push(CompEntry {
                        selector,
                        merge: *merge,
                        body: self.c.stmts(body, self.params),
                    });
                }
                BlockEntry::Group(group) => {
                    self.c.report(Diagnostic::error(
                        "component splits take `selector : …` entries, not groups",
                        group.span,
                    ));
                    return None;
                }
            }
        }
        Some(Op::Comp { kind, entries })
    }

    pub(super) fn setback(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let blocks = self.setback_block("setback", false)?;
        Some(Op::Setback {
            depths: Depths::Selected(self.args.pop()?),
            entries: blocks.0,
            shape: None,
            remainder: blocks.2,
        })
    }

    pub(super) fn shape_luo(&mut self, classes: &[FaceClass]) -> Option<Op> {
        self.arity(classes.len(), classes.len())?;
        let name = self.call.name.name.clone();
        let (_, shape, remainder) = self.setback_block(&name, true)?;
        let depths = classes.iter().copied().zip(self.args.drain(..)).collect();
        Some(Op::Setback {
            depths: Depths::ByClass(depths),
            entries: Vec::new(),
            shape,
            remainder,
        })
    }

    /// The block of a setback operation: edge entries (setback), or `shape` (shapeL/U/O), and
    /// `remainder`.
    #[allow(clippy::type_complexity)]
    pub(super) fn setback_block(
        &mut self,
        name: &str,
        luo: bool,
    ) -> Option<(
        Vec<CompEntry>,
        Option<(bool, Vec<CStmt>)>,
        Option<(bool, Vec<CStmt>)>,
    )> {
        let Some(block) = &self.call.block else {
            let first = if luo { "shape" } else { "selector" };
            self.error(format!(
                "`{name}` needs a `{{ {first} : … | remainder : … }}` block"
            ));
            return None;
        };
        let (mut entries, mut shape, mut remainder) = (Vec::new(), None, None);
        for entry in &block.entries {
            let BlockEntry::Part {
                key,
                merge,
                body,
                span,
            } = entry
            else {
                self.error(format!("`{name}` takes `selector : …` entries, not groups"));
                return None;
            };
            let body = self.c.stmts(body, self.params);
            match &key.kind {
                ast::ExprKind::Name(n) if n == "remainder" => remainder = Some((*merge, body)),
                ast::ExprKind::Name(n) if luo && n == "shape" => shape = Some((*merge, body)),
                _ if luo => {
                    self.c.report(Diagnostic::error(
                        format!("`{name}` selects `shape` or `remainder`"),
                        *span,
                    ));
                    return None;
                }
                _ => entries.push(CompEntry {
                    selector: edge_selector(self.c, key, *span),
                    merge: *merge,
                    body,
                }),
            }
        }
        Some((entries, shape, remainder))
    }

    pub(super) fn set(&mut self) -> Option<Op> {
        self.arity(2, 2)?;
        let value = self.args.pop()?;
        let target = self.args.pop()?;
        self.words.push(0);
        let name = match &target.kind {
            CKind::Attr(i) => return Some(Op::Set(SetTarget::Attr(*i), value)),
            CKind::GoalAttr(i, _) => return Some(Op::Set(SetTarget::Goal(*i), value)),
            CKind::Selector(name) => name.clone(),
            // `set(sel("material.color.r"), v)`: the name must be known before the derivation.
            CKind::Builtin(crate::builtins::Builtin::Sel, word) => match &word[0].kind {
                CKind::Value(Value::Str(name)) => name.to_string(),
                _ => {
                    self.c.report(Diagnostic::error(
                        "`set(sel(…), …)` needs the name as a string literal: a name computed \
                         during the derivation is not supported",
                        word[0].span,
                    ));
                    return None;
                }
            },
            CKind::Query(crate::builtins::Query::ScopeOrigin(i)) => {
                return Some(Op::Set(SetTarget::ScopeOrigin(*i), value));
            }
            CKind::Query(crate::builtins::Query::ScopeSize(i)) => {
                return Some(Op::Set(SetTarget::ScopeSize(*i), value));
            }
            CKind::Query(_) => {
                self.c.report(
                    Diagnostic::error("`set` cannot write this shape attribute", target.span)
                        .with_hint(
                            "`set` writes attributes, `scope.tx`…`scope.sz`, `material.*` and `trim.*`",
                        ),
                );
                return None;
            }
            _ => {
                self.c.report(
                    Diagnostic::error("`set` needs an attribute name", target.span)
                        .with_hint("declare it with `attr name = …`"),
                );
                return None;
            }
        };
        let target = match name.as_str() {
            "material.color" => SetTarget::Color(None),
            "material.color.r" => SetTarget::Color(Some(0)),
            "material.color.g" => SetTarget::Color(Some(1)),
            "material.color.b" => SetTarget::Color(Some(2)),
            "material.opacity" | "material.color.a" => SetTarget::Color(Some(3)),
            "material.color.rgb" => SetTarget::Color(None),
            "material.name" => SetTarget::MaterialName,
            // Every material is written as a PBR material, whichever shader CityEngine would
            // draw it with.
            "material.shader" => SetTarget::Ignored,
            n if n
                .strip_prefix("material.")
                .and_then(texturing::FinishAttr::from_name)
                .is_some() =>
            {
                SetTarget::Finish(
                    n.strip_prefix("material.")
                        .and_then(texturing::FinishAttr::from_name)?,
                )
            }
            n if n
                .strip_prefix("material.")
                .and_then(texturing::layer)
                .is_some() =>
            {
                SetTarget::Map(n.strip_prefix("material.").and_then(texturing::layer)?)
            }
            "trim.horizontal" => SetTarget::Trim(true),
            "trim.vertical" => SetTarget::Trim(false),
            n if n.starts_with("material.") || n.starts_with("trim.") => {
                self.warn_once(format!("`set({n}, …)` is not supported yet: ignored"));
                SetTarget::Ignored
            }
            n if n.contains('.') => {
                // `style.attr` and `import.attr` name attributes of imported rule files.
                self.warn_once(format!(
                    "`set({n}, …)` sets an attribute of an imported file: imports are not supported yet, ignored"
                ));
                SetTarget::Ignored
            }
            n => {
                let mut d = Diagnostic::error(format!("unknown attribute `{n}`"), target.span)
                    .with_hint("declare it with `attr name = …` before setting it");
                if let Some(close) = shapegram_syntax::suggest(n, self.c.attr_names()) {
                    d = d.with_hint(format!("did you mean `{close}`?"));
                }
                self.c.report(d);
                return None;
            }
        };
        Some(Op::Set(target, value))
    }

    pub(super) fn sync(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let Some(word) = self.word(0).map(str::to_owned) else {
            return self.bad_selector(0, "the name of a synchronization");
        };
        let span = self.args[0].span;
        let Some(scope) = &self.c.goal else {
            self.c.report(
                Diagnostic::error(
                    "`sync` synchronizes shapes of goal grammars",
                    self.call.span,
                )
                .with_hint("in the main syntax, shapes made by one rule derive alike already"),
            );
            return None;
        };
        if let Some(id) = scope.sync(&word) {
            return Some(Op::Sync(id));
        }
        let mut d = Diagnostic::error(format!("unknown synchronization `{word}`"), span).with_hint(
            format!("declare it: `sync {word}` (`var {word} = new Synchronize();`)"),
        );
        if let Some(close) = shapegram_syntax::suggest(&word, scope.sync_names()) {
            d = d.with_hint(format!("did you mean `{close}`?"));
        }
        self.c.report(d);
        None
    }

    pub(super) fn offset(&mut self) -> Option<Op> {
        self.arity(1, 2)?;
        let keep = if self.args.len() == 2 {
            match self.word(1) {
                Some("inside") => OffsetKeep::Inside,
                Some("border") => OffsetKeep::Border,
                Some("all") => OffsetKeep::All,
                _ => return self.bad_selector(1, "`inside`, `border` or `all`"),
            }
        } else {
            OffsetKeep::All
        };
        self.args.truncate(1);
        Some(Op::Offset {
            distance: self.args.pop()?,
            keep,
        })
    }

    pub(super) fn align_to_geometry(&mut self) -> Option<Op> {
        self.arity(2, 3)?;
        if self.args.len() == 2 {
            // The older two-argument form `(upAxis, edgeIndex)` real files still use: an edge of face 0.
            let span = self.args[1].span;
            let first_face = CExpr {
                kind: CKind::Value(Value::Number(0.0)),
                span,
            };
            self.args.insert(1, first_face);
        }
        let z_up = match self.word(0) {
            Some("yUp") => false,
            Some("zUp") => true,
            _ => return self.bad_selector(0, "`yUp` or `zUp` (`xUp` is not supported)"),
        };
        let is_word = |a: &CExpr| matches!(a.kind, CKind::Selector(_));
        let (face_word, edge_word) = (
            self.word(1).map(str::to_owned),
            self.word(2).map(str::to_owned),
        );
        let edge = match edge_word.as_deref() {
            Some("world.lowest") => EdgeChoice::Lowest,
            Some("longest") => EdgeChoice::Longest,
            _ if is_word(&self.args[2]) => {
                return self.bad_selector(2, "an edge index, `world.lowest` or `longest`");
            }
            _ => EdgeChoice::Index(self.args.pop()?),
        };
        let face = match face_word.as_deref() {
            Some("world.lowest") => FaceChoice::Lowest,
            Some("largest") => FaceChoice::Largest,
            Some("any") if !matches!(edge, EdgeChoice::Index(_)) => FaceChoice::Any,
            Some("any") => {
                return self.bad_selector(
                    1,
                    "a face index, `world.lowest` or `largest` (`any` needs an edge selector)",
                );
            }
            _ if is_word(&self.args[1]) => {
                return self.bad_selector(1, "a face index, `world.lowest`, `largest` or `any`");
            }
            _ => FaceChoice::Index(self.args.swap_remove(1)),
        };
        Some(Op::AlignScopeToGeometry { z_up, face, edge })
    }

    pub(super) fn align_to_bbox(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        let axes: Vec<usize> = self
            .word(0)
            .map(|w| w.chars().filter_map(|c| "xyz".find(c)).collect())
            .unwrap_or_default();
        match axes[..] {
            [first, second] if first != second && self.word(0).is_some_and(|w| w.len() == 2) => {
                Some(Op::AlignScopeToGeometryBBox { first, second })
            }
            _ => self.bad_selector(0, "two axes: `xy`, `yx`, `xz`, `zx`, `yz` or `zy`"),
        }
    }

    pub(super) fn implicit(&mut self) -> Option<Op> {
        self.arity(1, 1)?;
        self.c.solids = true;
        if let Some(kind) = self.word(0).and_then(ImplicitKind::from_name) {
            return Some(Op::Implicit(kind));
        }
        // Anything else but a bare word is the path of an implicit grammar.
        if matches!(self.args[0].kind, CKind::Selector(_)) {
            return self.bad_selector(
                0,
                "a solid: `box`, `sphere`, `cylinder`, `cone`, `pyramid`, `torus` or `capsule`, or the path of a .cave file",
            );
        }
        Some(Op::ImplicitFile(self.args.pop()?))
    }

    pub(super) fn csg(&mut self) -> Option<Op> {
        self.arity(2, 3)?;
        let kinds = [
            CsgKind::Union,
            CsgKind::Subtract,
            CsgKind::Intersect,
            CsgKind::Morph,
        ];
        let word = self.word(1);
        let Some(kind) = kinds.into_iter().find(|k| word == Some(k.name())) else {
            return self.bad_selector(1, "`union`, `subtract`, `intersect` or `morph`");
        };
        if kind == CsgKind::Morph && self.args.len() < 3 {
            return self.wrong_arity();
        }
        let amount = (self.args.len() == 3).then(|| self.args.pop()).flatten();
        Some(Op::Csg {
            kind,
            group: self.args.swap_remove(0),
            amount,
        })
    }

    /// `taper(axis, factor)`, `twist(axis, degrees)`, `shear(axis, toward, amount)`; CGA's own
    /// `taper(height)`, which takes one number, is the pyramid over the first face.
    pub(super) fn deform(&mut self, kind: DeformKind) -> Option<Op> {
        let name = kind.name();
        if kind == DeformKind::Taper
            && self.args.len() == 1
            && !matches!(self.args[0].kind, CKind::Selector(_))
        {
            return Some(Op::Pyramid(self.args.pop()?));
        }
        let count = if matches!(kind, DeformKind::Shear { .. }) {
            3
        } else {
            2
        };
        self.arity(count, count)?;
        let axis = self.axis_word(0, name)?;
        let kind = match kind {
            DeformKind::Shear { .. } => {
                let toward = self.axis_word(1, name)?;
                if toward == axis {
                    let span = self.args[1].span;
                    let word = ["x", "y", "z"][axis];
                    self.c.report(
                        Diagnostic::error(
                            format!(
                                "`shear` needs two different axes, not `{word}` twice: points move \
                                 along the second by their position along the first"
                            ),
                            span,
                        )
                        .with_label("in `shear`"),
                    );
                    return None;
                }
                DeformKind::Shear { toward }
            }
            other => other,
        };
        Some(Op::Deform {
            kind,
            axis,
            amount: self.args.pop()?,
        })
    }

    /// Argument `i` as a scope axis, `x`, `y` or `z`; an error in `op` for anything else.
    pub(super) fn axis_word(&mut self, i: usize, op: &str) -> Option<usize> {
        let axis = match self.word(i) {
            Some("x") => Some(0),
            Some("y") => Some(1),
            Some("z") => Some(2),
            _ => None,
        };
        if axis.is_none() {
            let span = self.args.get(i).map_or(self.call.span, |a| a.span);
            self.c.report(
                Diagnostic::error("expected the axis `x`, `y` or `z`", span)
                    .with_label(format!("in `{op}`")),
            );
        }
        axis
    }

    pub(super) fn roof(&mut self, kind: RoofKind) -> Option<Op> {
        let by_height = match self.args.first().map(|a| &a.kind) {
            Some(CKind::Selector(w)) if w == "byAngle" => Some(false),
            Some(CKind::Selector(w)) if w == "byHeight" => Some(true),
            _ => None,
        };
        if by_height.is_some() {
            self.words.push(0);
            self.args.remove(0);
        }
        // The angle or height, then: overhangX, overhangY, even, index (gable); overhang, even
        // (hip); index (shed). CGA's byHeight gable takes no index.
        let max = match kind {
            RoofKind::Gable if by_height.is_some() => 4,
            RoofKind::Gable => 5,
            RoofKind::Hip => 3,
            RoofKind::Pyramid | RoofKind::Ridge => 1,
            RoofKind::Shed => 2,
        };
        self.arity(1, max)?;
        Some(Op::Roof {
            kind,
            by_height: by_height == Some(true),
            params: std::mem::take(&mut self.args),
        })
    }
}

/// A split block compiled; in a perimeter split (`sections`) its keys are `[length, depth]`.
fn split_block(
    c: &mut Compiler,
    block: &ast::Block,
    params: &[ast::Ident],
    sections: bool,
) -> Option<SplitBlock> {
    let mut entries = Vec::with_capacity(block.entries.len());
    for entry in &block.entries {
        entries.push(match entry {
            BlockEntry::Part { key, body, .. } => {
                // A perimeter split's key is the pair `[length, depth]` (see `ast::Call`).
                let (size, depth) = match &key.kind {
                    ast::ExprKind::Array(pair) if sections && pair.len() == 2 => {
                        (c.expr(&pair[0], params), Some(c.expr(&pair[1], params)))
                    }
                    _ => (c.expr(key, params), None),
                };
                SplitEntry::Part {
                    size,
                    depth,
                    body: c.stmts(body, params),
                }
            }
            BlockEntry::Group(group) => SplitEntry::Group(split_block(c, group, params, sections)?),
        });
    }
    Some(SplitBlock {
        entries,
        repeat: block.repeat,
    })
}

impl Ctx<'_, '_> {
    /// `union Rule`, `union(swap) { ops }`, `union { opsA | opsB }` and the same of `subtract`
    /// and `intersect`: the target operand first.
    pub(super) fn boolean(&mut self, kind: BooleanOp) -> Option<Op> {
        self.arity(0, 1)?;
        let swap = match self.args.is_empty() {
            true => false,
            false => match self.word(0) {
                Some("swap") => true,
                Some("noSwap") => false,
                _ => return self.bad_selector(0, "`swap` or `noSwap`"),
            },
        };
        let bodies = self.operand_bodies(1, 2)?;
        let mut operands = match <[_; 2]>::try_from(bodies) {
            Ok([a, b]) => [Some(a), Some(b)],
            Err(mut one) => [None, one.pop()],
        };
        if swap {
            operands.swap(0, 1);
        }
        Some(Op::Boolean { kind, operands })
    }

    /// `inline Rule`, `inline(append | unify | recompose) { ops }`.
    pub(super) fn inline(&mut self) -> Option<Op> {
        self.arity(0, 1)?;
        let mode = match self.args.is_empty() {
            true => InlineMode::Append,
            false => match self.word(0) {
                Some("append") => InlineMode::Append,
                Some("unify") => InlineMode::Unify,
                Some("recompose") => InlineMode::Recompose,
                _ => return self.bad_selector(0, "`append`, `unify` or `recompose`"),
            },
        };
        let mut bodies = self.operand_bodies(1, 1)?;
        Some(Op::Inline {
            mode,
            body: bodies.pop()?,
        })
    }

    /// The compiled bodies of an operand block, between `lo` and `hi` of them.
    fn operand_bodies(&mut self, lo: usize, hi: usize) -> Option<Vec<Vec<CStmt>>> {
        self.c.derives_now = true;
        let call = self.call;
        let name = &call.name.name;
        let Some(block) = &call.block else {
            self.error(format!(
                "`{name}` needs what to derive: a rule (`{name} Rule`) or operations in a block (`{name} {{ … }}`)"
            ));
            return None;
        };
        let bodies: Vec<_> = block
            .entries
            .iter()
            .filter_map(|entry| match entry {
                BlockEntry::Part { body, .. } => Some(body),
                BlockEntry::Group(_) => None,
            })
            .collect();
        if bodies.len() != block.entries.len() || bodies.len() < lo || bodies.len() > hi {
            let wanted = match hi {
                1 => format!("`{name}` takes one operand: `{name} {{ ops }}`"),
                _ => format!(
                    "`{name}` takes one operand (`{name} {{ ops }}`) or two (`{name} {{ opsA | opsB }}`)"
                ),
            };
            self.c.report(
                Diagnostic::error(wanted, block.span)
                    .with_label(format!("{} operands here", block.entries.len())),
            );
            return None;
        }
        Some(
            bodies
                .into_iter()
                .map(|body| self.c.stmts(body, self.params))
                .collect(),
        )
    }
}
