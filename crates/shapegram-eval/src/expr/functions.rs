//! The built-in functions CGA's reference lists beyond arithmetic and text: file reading,
//! colours, `convert`, the context functions and `geometry.angle`, and the element-wise
//! operators on arrays.

use std::sync::Arc;

use shapegram_geom::DVec3;
use shapegram_syntax::Span;
use shapegram_syntax::ast::{BinaryOp, UnaryOp};

use super::{Evaluator, Result, apply_binary, binary_symbol, unary_symbol};
use crate::builtins::Builtin;
use crate::colors::ColorFn;
use crate::context::{Extreme, Target};
use crate::convert::CoordinateSystem;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Evaluator<'_> {
    /// `fileExists(path)`: whether the derivation's assets have the file (false when it reads
    /// no files); `readTextFile(path)`: the file's text.
    pub(super) fn read_file(
        &mut self,
        b: Builtin,
        path: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = self.string(path, shape, args)?;
        let assets = self.assets;
        if b == Builtin::FileExists {
            return Ok(Value::Bool(assets.is_some_and(|a| a.exists(&name))));
        }
        let Some(assets) = assets else {
            return Err(DeriveError::at(
                format!("cannot read `{name}`: this derivation reads no files"),
                path.span,
            ));
        };
        let text = assets
            .text(&name)
            .map_err(|why| DeriveError::at(why, path.span))?;
        Ok(Value::Str(text))
    }

    /// `convert(x, from, to, pos, x, y, z)` (one coordinate) and `convert(from, to, pos, [x,
    /// y, z])` (all three): see [`crate::convert`].
    pub(super) fn convert(
        &mut self,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        let (component, rest) = match params.len() {
            7 => {
                let word = self.word(&params[0], shape, args)?;
                let i = match &*word {
                    "x" => 0,
                    "y" => 1,
                    "z" => 2,
                    other => {
                        return Err(DeriveError::at(
                            format!("expected the coordinate `x`, `y` or `z`, found `{other}`"),
                            params[0].span,
                        ));
                    }
                };
                (Some(i), &params[1..])
            }
            4 => (None, params),
            n => {
                return Err(DeriveError::at(
                    format!("`convert` takes 4 or 7 arguments, not {n}"),
                    span,
                ));
            }
        };
        let mut frames = [CoordinateSystem::World; 2];
        for (frame, p) in frames.iter_mut().zip(rest) {
            let word = self.word(p, shape, args)?;
            *frame = CoordinateSystem::from_name(&word).ok_or_else(|| {
                DeriveError::at(
                    format!(
                        "expected the coordinate system `scope`, `pivot`, `object` or `world`, found `{word}`"
                    ),
                    p.span,
                )
            })?;
        }
        let orient = match &*self.word(&rest[2], shape, args)? {
            "pos" => false,
            "orient" => true,
            other => {
                return Err(DeriveError::at(
                    format!("expected `pos` or `orient`, found `{other}`"),
                    rest[2].span,
                ));
            }
        };
        let v = if component.is_some() {
            DVec3::new(
                self.number(&rest[3], shape, args)?,
                self.number(&rest[4], shape, args)?,
                self.number(&rest[5], shape, args)?,
            )
        } else {
            match self.eval(&rest[3], shape, args)? {
                Value::Array(items) if items.len() == 3 => {
                    let n = |v: &Value| match v {
                        Value::Number(n) => Ok(*n),
                        other => Err(DeriveError::at(
                            format!("expected a number, found a {}", other.type_name()),
                            rest[3].span,
                        )),
                    };
                    DVec3::new(n(&items[0])?, n(&items[1])?, n(&items[2])?)
                }
                other => {
                    return Err(DeriveError::at(
                        format!("expected three coordinates `[x, y, z]`, found {other}"),
                        rest[3].span,
                    ));
                }
            }
        };
        let out = crate::convert::convert(&shape.scope, frames[0], frames[1], orient, v);
        Ok(match component {
            Some(i) => Value::Number(out[i]),
            None => Value::Array(Arc::from([
                Value::Number(out.x),
                Value::Number(out.y),
                Value::Number(out.z),
            ])),
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
        let Some(context) = self.context else {
            return Err(DeriveError::at(
                "context functions can only be asked in rules (not in attributes or in rules \
                 made before the derivation starts)",
                span,
            ));
        };
        let word = self.word(&params[0], shape, args)?;
        let target = Target::from_name(&word).ok_or_else(|| {
            DeriveError::at(
                format!("expected the target `all`, `intra` or `inter`, found `{word}`"),
                params[0].span,
            )
        })?;
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

    /// A colour function: a hexadecimal string in, a component out, or numbers in, a string out.
    pub(super) fn color(
        &mut self,
        f: ColorFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        if f.reads_hex() {
            let hex = self.string(&params[0], shape, args)?;
            return Ok(Value::Number(f.component(&hex)));
        }
        let numbers = params
            .iter()
            .map(|p| self.number(p, shape, args))
            .collect::<Result<Vec<_>>>()?;
        Ok(Value::string(&f.hex(&numbers)))
    }
}

/// An element-wise operator: arrays element by element (of the same size), a single value with
/// every element of an array.
pub(super) fn each_binary(
    op: BinaryOp,
    a: &Value,
    b: &Value,
    span: Span,
    rhs_span: Span,
) -> Result<Value> {
    let items = match (a, b) {
        (Value::Array(x), Value::Array(y)) if x.len() != y.len() => {
            return Err(DeriveError::at(
                format!(
                    "`.{}` needs arrays of the same size, not {} and {} elements",
                    binary_symbol(op),
                    x.len(),
                    y.len()
                ),
                span,
            ));
        }
        (Value::Array(x), Value::Array(y)) => x
            .iter()
            .zip(y.iter())
            .map(|(x, y)| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (Value::Array(x), y) => x
            .iter()
            .map(|x| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (x, Value::Array(y)) => y
            .iter()
            .map(|y| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (x, y) => return apply_binary(op, x, y, span, rhs_span),
    };
    Ok(Value::Array(items.into()))
}

/// `.-` and `.!` on every element.
pub(super) fn each_unary(op: UnaryOp, v: &Value, span: Span) -> Result<Value> {
    Ok(match (op, v) {
        (_, Value::Array(items)) => Value::Array(
            items
                .iter()
                .map(|x| each_unary(op, x, span))
                .collect::<Result<Vec<_>>>()?
                .into(),
        ),
        (UnaryOp::Neg, Value::Number(n)) => Value::Number(-n),
        (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
        (op, v) => {
            return Err(DeriveError::at(
                format!(
                    "cannot apply `.{}` to a {}",
                    unary_symbol(op),
                    v.type_name()
                ),
                span,
            ));
        }
    })
}

/// `geometry.angle(…)`: of the shape's steepest face, its slope against the ground (degrees,
/// 0 flat, 90 upright), the compass direction it faces (degrees clockwise from north, −z; 0 for
/// a flat face), or 90 − the slope; 0 for a shape without faces.
pub(super) fn slope_angle(which: &str, shape: &State) -> std::result::Result<Value, String> {
    let steepest = shape.geometry.world_mesh(&shape.scope).and_then(|mesh| {
        (0..mesh.face_count())
            .map(|i| mesh.face_normal(i))
            .filter(|n| *n != DVec3::ZERO)
            .min_by(|a, b| a.y.abs().total_cmp(&b.y.abs()))
    });
    let slope = steepest.map_or(0.0, |n| n.y.abs().min(1.0).acos().to_degrees());
    Ok(Value::Number(match which {
        "maxSlope" => slope,
        "zenith" => 90.0 - slope,
        "azimuth" => steepest.map_or(0.0, |n| {
            if n.x.hypot(n.z) < 1e-12 {
                0.0
            } else {
                n.x.atan2(-n.z).to_degrees().rem_euclid(360.0)
            }
        }),
        other => {
            return Err(format!(
                "expected `maxSlope`, `azimuth` or `zenith`, found `{other}`"
            ));
        }
    }))
}
