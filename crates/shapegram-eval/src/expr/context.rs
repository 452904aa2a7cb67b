//! Questions about other shapes: occlusion and the context functions.

use shapegram_syntax::Span;

use super::{Evaluator, Result};
use crate::builtins::Builtin;
use crate::context::{Context, Extreme, Target};
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl<'p> Evaluator<'p> {
    /// What the labelled shapes of phase 1 are, for `asking` ("occlusion queries"), which
    /// only rules of phase 2 may ask.
    fn phase_one(&self, asking: &str, span: Span) -> Result<&'p Context> {
        self.context.ok_or_else(|| {
            DeriveError::at(
                format!(
                    "{asking} can only be asked in rules (not in attributes or in rules made \
                     before the derivation starts)"
                ),
                span,
            )
        })
    }

    /// The first argument of a context question: `all`, `intra` or `inter`.
    fn target(&mut self, p: &CExpr, shape: &mut State, args: &[Value]) -> Result<Target> {
        let word = self.word(p, shape, args)?;
        Target::from_name(&word).ok_or_else(|| {
            DeriveError::at(
                format!("expected the target `all`, `intra` or `inter`, found `{word}`"),
                p.span,
            )
        })
    }

    /// `inside(target, label)` and friends, and Müller's `occ(label)`.
    pub(super) fn occlusion(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        let context = self.phase_one("occlusion queries", span)?;
        let mut target = Target::All;
        let mut label = None;
        if b == Builtin::Occ {
            // `occ("noparent")`: ancestors never count, so "noparent" is every occluder.
            if let Some(p) = params.first() {
                let text = self.word(p, shape, args)?;
                if !matches!(&*text, "noparent" | "all" | "") {
                    label = Some(text);
                }
            }
        } else {
            if let Some(p) = params.first() {
                target = self.target(p, shape, args)?;
            }
            if let Some(p) = params.get(1) {
                let text = self.string(p, shape, args)?;
                label = (!text.is_empty()).then_some(text);
            }
        }
        let motion = self.motions.get(shape.section as usize);
        let found = context.query(shape, motion, self.lot, target, label.as_deref());
        Ok(match b {
            Builtin::Inside => Value::Bool(found.inside),
            Builtin::Overlaps => Value::Bool(found.overlaps),
            Builtin::Touches => Value::Bool(found.touches),
            _ => Value::string(if found.inside {
                "full"
            } else if found.touches {
                "part"
            } else {
                "none"
            }),
        })
    }

    /// `contextCount(target, label)`, `contextCompare(target, label, key)` and
    /// `minimumDistance(target, label)` over the labelled shapes of phase 1.
    pub(super) fn context_function(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        let context = self.phase_one("context functions", span)?;
        let target = self.target(&params[0], shape, args)?;
        let label = self.string(&params[1], shape, args)?;
        if label.is_empty() {
            return Ok(Value::Number(match b {
                Builtin::MinimumDistance => f64::INFINITY,
                _ => 0.0,
            }));
        }
        Ok(Value::Number(match b {
            Builtin::ContextCount => context.count(shape, self.lot, target, &label) as f64,
            Builtin::MinimumDistance => context.nearest(shape, self.lot, target, &label),
            _ => {
                let key = self.word(&params[2], shape, args)?;
                let extreme = Extreme::from_name(&key).ok_or_else(|| {
                    DeriveError::at(
                        format!(
                            "expected `world.northernmost`, `world.southernmost`, `world.easternmost`, `world.westernmost`, `world.highest` or `world.lowest`, found `{key}`"
                        ),
                        params[2].span,
                    )
                })?;
                context.rank(shape, self.lot, target, &label, extreme) as f64
            }
        }))
    }
}
