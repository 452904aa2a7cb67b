//! Calling a built-in function: each family to its evaluator, the functions of numbers here.

use shapegram_syntax::Span;

use super::queries::slope_angle;
use super::{Evaluator, Result};
use crate::builtins::Builtin;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::text::{Out, Text};
use crate::value::Value;

impl Evaluator<'_> {
    pub(super) fn builtin(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        match b {
            Builtin::Inside | Builtin::Overlaps | Builtin::Touches | Builtin::Occ => {
                return self.occlusion(b, params, shape, args, span);
            }
            Builtin::ContextCount | Builtin::ContextCompare | Builtin::MinimumDistance => {
                return self.context_function(b, params, shape, args, span);
            }
            Builtin::Convert => return self.convert(params, shape, args, span),
            Builtin::Print => {
                // As a function, `print` gives its value on.
                let value = self.eval(&params[0], shape, args)?;
                self.print(value.to_string());
                return Ok(value);
            }
            Builtin::Text(t) => return self.text(t, params, shape, args, span),
            Builtin::Uv(q) => return self.uv_query(q, params, shape, args),
            Builtin::Tags(f) => return self.tag_function(f, params, shape, args),
            Builtin::Array(f) => {
                let values = params
                    .iter()
                    .map(|p| self.eval(p, shape, args))
                    .collect::<Result<Vec<_>>>()?;
                return f.apply(&values).map_err(|e| DeriveError::at(e, span));
            }
            Builtin::Color(f) => return self.color(f, params, shape, args),
            Builtin::ColorRamp => return self.color_ramp(params, shape, args),
            Builtin::Sel => return self.string(&params[0], shape, args).map(Value::Str),
            Builtin::GeoCoord => return self.geo_coord(&params[0], shape, args),
            Builtin::EdgeAttrFloat | Builtin::EdgeAttrString | Builtin::EdgeAttrBool => {
                return self.edge_attr(b, &params[0], shape, args);
            }
            Builtin::GetMaterial => return self.material_table(params, shape, args),
            Builtin::ReadMaterial => return self.read_material(&params[0], shape, args),
            Builtin::IsInstanced => return Ok(Value::Bool(shape.is_instanced())),
            Builtin::IsOriented | Builtin::AreaOf => {
                return self.oriented(b, &params[0], shape, args);
            }
            Builtin::IsRectangular
            | Builtin::IsConcave
            | Builtin::IsPlanar
            | Builtin::IsClosedSurface
            | Builtin::EdgeCount
            | Builtin::BoundaryLength
            | Builtin::Height => return self.measure(b, params, shape, args),
            Builtin::Str => {
                return Ok(Value::string(
                    &self.eval(&params[0], shape, args)?.to_string(),
                ));
            }
            Builtin::Bool => {
                return Ok(Value::Bool(match self.eval(&params[0], shape, args)? {
                    Value::Bool(b) => b,
                    Value::Number(n) => n != 0.0,
                    Value::Str(s) => !s.is_empty() && &*s != "false",
                    Value::Array(a) => !a.is_empty(),
                }));
            }
            Builtin::Float => {
                return match self.eval(&params[0], shape, args)? {
                    Value::Number(n) => Ok(Value::Number(n)),
                    Value::Bool(b) => Ok(Value::Number(f64::from(u8::from(b)))),
                    Value::Str(s) => s.trim().parse::<f64>().map(Value::Number).map_err(|_| {
                        DeriveError::at(format!("`{s}` is not a number"), params[0].span)
                    }),
                    Value::Array(_) => Err(DeriveError::at(
                        "cannot convert an array to a number",
                        params[0].span,
                    )),
                };
            }
            Builtin::ReadStringTable | Builtin::ReadFloatTable => {
                return self.read_table(b, &params[0], shape, args);
            }
            Builtin::FileSearch | Builtin::FilesSearch | Builtin::FileRandom => {
                return self.search_files(b, &params[0], shape, args);
            }
            Builtin::Asset(f) => return self.asset_function(f, params, shape, args),
            Builtin::FileExists | Builtin::ReadTextFile => {
                return self.read_file(b, &params[0], shape, args);
            }
            Builtin::Angle => {
                let which = self.word(&params[0], shape, args)?;
                return slope_angle(&which, shape).map_err(|e| DeriveError::at(e, params[0].span));
            }
            Builtin::Rows | Builtin::Columns => {
                let table = self.eval(&params[0], shape, args)?;
                let Value::Array(rows) = &table else {
                    return Err(DeriveError::at(
                        format!(
                            "expected a table (an array of rows), found a {}",
                            table.type_name()
                        ),
                        params[0].span,
                    ));
                };
                let n = match (b, rows.first()) {
                    (Builtin::Rows, _) => rows.len(),
                    (_, Some(Value::Array(row))) => row.len(),
                    (_, Some(_)) => 1,
                    (_, None) => 0,
                };
                return Ok(Value::Number(n as f64));
            }
            Builtin::Len => {
                return match self.eval(&params[0], shape, args)? {
                    Value::Array(a) => Ok(Value::Number(a.len() as f64)),
                    Value::Str(s) => Ok(Value::Number(s.chars().count() as f64)),
                    other => Err(DeriveError::at(
                        format!(
                            "`size` needs an array or a string, not a {}",
                            other.type_name()
                        ),
                        params[0].span,
                    )),
                };
            }
            _ => {}
        }
        let mut n = Vec::with_capacity(params.len());
        for p in params {
            n.push(self.number(p, shape, args)?);
        }
        let deg = std::f64::consts::PI / 180.0;
        let value = match b {
            Builtin::Rand => match n.as_slice() {
                [] => shape.rng.next_f64(),
                [hi] => shape.rng.range(0.0, *hi),
                [lo, hi, ..] => shape.rng.range(*lo, *hi),
            },
            Builtin::P => return Ok(Value::Bool(shape.rng.next_f64() < n[0])),
            Builtin::Floor => n[0].floor(),
            Builtin::Ceil => n[0].ceil(),
            Builtin::Round => n[0].round(),
            // CGA's rint is C's: to the nearest integer, halves to the even one.
            Builtin::Rint => n[0].round_ties_even(),
            // Kept for CGA files that test their numbers: an expression that is not a finite
            // number is an error here, so these are false for every number that gets this far.
            Builtin::IsNan => return Ok(Value::Bool(n[0].is_nan())),
            Builtin::IsInf => return Ok(Value::Bool(n[0].is_infinite())),
            Builtin::Abs => n[0].abs(),
            Builtin::Min => n[0].min(n[1]),
            Builtin::Max => n[0].max(n[1]),
            Builtin::Sqrt => n[0].sqrt(),
            Builtin::Pow => n[0].powf(n[1]),
            Builtin::Exp => n[0].exp(),
            Builtin::Ln => n[0].ln(),
            Builtin::Log10 => n[0].log10(),
            // CGA's trigonometry works in degrees.
            Builtin::Sin => (n[0] * deg).sin(),
            Builtin::Cos => (n[0] * deg).cos(),
            Builtin::Tan => (n[0] * deg).tan(),
            Builtin::Asin => n[0].asin() / deg,
            Builtin::Acos => n[0].acos() / deg,
            Builtin::Atan => n[0].atan() / deg,
            Builtin::Atan2 => n[0].atan2(n[1]) / deg,
            Builtin::Clamp => n[0].max(n[1]).min(n[2]),
            Builtin::Str
            | Builtin::Bool
            | Builtin::Float
            | Builtin::Len
            | Builtin::Inside
            | Builtin::Overlaps
            | Builtin::Touches
            | Builtin::Occ
            | Builtin::IsRectangular
            | Builtin::IsConcave
            | Builtin::IsPlanar
            | Builtin::IsClosedSurface
            | Builtin::EdgeCount
            | Builtin::BoundaryLength
            | Builtin::Height
            | Builtin::ReadStringTable
            | Builtin::ReadFloatTable
            | Builtin::Rows
            | Builtin::Columns
            | Builtin::FileSearch
            | Builtin::FilesSearch
            | Builtin::FileRandom
            | Builtin::FileExists
            | Builtin::ReadTextFile
            | Builtin::Angle
            | Builtin::ContextCount
            | Builtin::ContextCompare
            | Builtin::MinimumDistance
            | Builtin::Print
            | Builtin::Convert
            | Builtin::Asset(_)
            | Builtin::ColorRamp
            | Builtin::Sel
            | Builtin::GeoCoord
            | Builtin::EdgeAttrFloat
            | Builtin::EdgeAttrString
            | Builtin::EdgeAttrBool
            | Builtin::IsOriented
            | Builtin::IsInstanced
            | Builtin::AreaOf
            | Builtin::GetMaterial
            | Builtin::ReadMaterial
            | Builtin::Text(_)
            | Builtin::Array(_)
            | Builtin::Color(_)
            | Builtin::Uv(_)
            | Builtin::Tags(_) => unreachable!("handled above"),
        };
        if !value.is_finite() {
            return Err(DeriveError::at(
                format!(
                    "`{}` gives no finite number for these arguments",
                    b.signature()
                ),
                span,
            ));
        }
        Ok(Value::Number(value))
    }

    /// A string or string-list function: its numeric arguments as numbers, the others as
    /// strings (`listFromArray` takes an array of strings).
    fn text(
        &mut self,
        t: Text,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        if t == Text::ListFromArray {
            return match self.eval(&params[0], shape, args)? {
                Value::Array(items) => Ok(Value::string(
                    &items.iter().map(|i| format!("{i};")).collect::<String>(),
                )),
                other => Err(DeriveError::at(
                    format!("expected an array, found a {}", other.type_name()),
                    params[0].span,
                )),
            };
        }
        let values = params
            .iter()
            .map(|p| self.eval(p, shape, args))
            .collect::<Result<Vec<_>>>()?;
        // `findFirst(array, value)`: the index of the first element equal to the value.
        if let (Text::FindFirst, [Value::Array(items), value]) = (t, values.as_slice()) {
            let at = items.iter().position(|i| i == value);
            return Ok(Value::Number(at.map_or(-1.0, |i| i as f64)));
        }
        let mut strings = Vec::new();
        let mut numbers = Vec::new();
        for (i, (value, p)) in values.iter().zip(params).enumerate() {
            let wrong = |what: &str| {
                DeriveError::at(
                    format!("expected {what}, found a {}", value.type_name()),
                    p.span,
                )
            };
            match value {
                Value::Number(n) if t.numeric(i) => numbers.push(*n),
                Value::Str(s) if !t.numeric(i) => strings.push(s.clone()),
                _ if t.numeric(i) => return Err(wrong("a number")),
                _ => return Err(wrong("a string")),
            }
        }
        let texts: Vec<&str> = strings.iter().map(|s| &**s).collect();
        let out = t
            .apply(&texts, &numbers, || shape.rng.next_f64())
            .map_err(|e| DeriveError::at(e, span))?;
        Ok(match out {
            Out::Number(n) => Value::Number(n),
            Out::Str(s) => Value::string(&s),
            Out::Strings(parts) => Value::Array(parts.iter().map(|p| Value::string(p)).collect()),
        })
    }
}
