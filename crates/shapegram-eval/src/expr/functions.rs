//! The built-in functions of coordinates, colours and the inputs Shapegram has no source for:
//! `convert`, `getGeoCoord`, the colour conversions and ramps, and the street graph's edge
//! attributes.

use std::sync::Arc;

use shapegram_geom::DVec3;
use shapegram_syntax::Span;

use super::{Evaluator, Result};
use crate::builtins::Builtin;
use crate::colors::ColorFn;
use crate::convert::CoordinateSystem;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Evaluator<'_> {
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

    /// `colorRamp(gradient, value)`: the colour of a named ramp at a value in [0, 1], as
    /// `#RRGGBB` (see [`crate::color_ramps`]).
    pub(super) fn color_ramp(
        &mut self,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = self.string(&params[0], shape, args)?;
        let value = self.number(&params[1], shape, args)?;
        crate::color_ramps::color_at(&name, value)
            .map(|hex| Value::string(&hex))
            .ok_or_else(|| {
                let names: Vec<String> = crate::color_ramps::names()
                    .map(|n| format!("`{n}`"))
                    .collect();
                DeriveError::at(
                    format!("`{name}` is no colour ramp: expected {}", names.join(", ")),
                    params[0].span,
                )
            })
    }

    /// `getGeoCoord(x | y | lon | lat)`: where the shape's scope origin lies on the map. Lots
    /// are in a local metric frame without georeference, so the scene's coordinates are that
    /// frame's: `x` east (+x) and `y` north (−z), in metres; `lon` and `lat` need a
    /// georeference and are 0.
    pub(super) fn geo_coord(
        &mut self,
        which: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let origin = shape.scope.origin;
        Ok(Value::Number(match &*self.word(which, shape, args)? {
            "x" => origin.x,
            "y" => -origin.z,
            "lon" | "lat" => 0.0,
            other => {
                return Err(DeriveError::at(
                    format!("expected `x`, `y`, `lon` or `lat`, found `{other}`"),
                    which.span,
                ));
            }
        }))
    }

    /// `edgeAttr.getFloat/getString/getBool(name)`: the street graph's attribute of the edge
    /// nearest the shape. Shapegram's lots come without a street graph, so every attribute is
    /// missing and each getter gives its default, as CityEngine does for a missing attribute:
    /// 0, `""` and false.
    pub(super) fn edge_attr(
        &mut self,
        b: Builtin,
        name: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        self.string(name, shape, args)?;
        Ok(match b {
            Builtin::EdgeAttrFloat => Value::Number(0.0),
            Builtin::EdgeAttrString => Value::string(""),
            _ => Value::Bool(false),
        })
    }
}
