//! What a shape carries besides its geometry, and what a derivation tells besides the model:
//! `color`, `set` (attributes, colour channels, material name), `report` and `print`.

use std::rc::Rc;
use std::sync::Arc;

use shapegram_geom::{Color, DAffine3, DVec3};

use super::Fallible;
use super::machine::Engine;
use super::texturing::follow_geometry;
use crate::error::DeriveError;
use crate::ops::SetTarget;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Engine<'_> {
    /// The colour `color("#rrggbb")` or `color(r, g, b [, a])` gives (channels from 0 to 1,
    /// clamped).
    pub(super) fn color(
        &mut self,
        state: &mut State,
        params: &[CExpr],
        args: &[Value],
    ) -> Fallible<Color> {
        if let [one] = params {
            let text = self.ev.string(one, state, args)?;
            return Color::from_hex(&text).ok_or_else(|| {
                DeriveError::at(
                    format!("`{text}` is not a colour like \"#3a6ea5\""),
                    one.span,
                )
            });
        }
        let mut c = [1.0f32; 4];
        for (i, p) in params.iter().enumerate() {
            c[i] = self.ev.number(p, state, args)?.clamp(0.0, 1.0) as f32;
        }
        Ok(Color {
            r: c[0],
            g: c[1],
            b: c[2],
            a: c[3],
        })
    }

    /// CGA `set(target, value)`: an attribute, the colour or a channel of it, the material
    /// name, or the scope's position or size along one axis.
    pub(super) fn set(
        &mut self,
        state: &mut State,
        target: &SetTarget,
        value: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        if let SetTarget::Map(layer) = target {
            return self.texture(state, *layer, false, value, args);
        }
        if let SetTarget::Finish(attr) = target {
            return self.set_finish(state, *attr, value, args);
        }
        let span = value.span;
        let value = self.ev.eval(value, state, args)?;
        let wrong = |what: &str, v: &Value| {
            DeriveError::at(format!("expected {what}, found a {}", v.type_name()), span)
        };
        match target {
            SetTarget::Attr(i) => Rc::make_mut(&mut state.attrs)[*i as usize] = value,
            SetTarget::Goal(attr) => self.set_goal_attr(state, *attr, value),
            SetTarget::Color(None) => match &value {
                Value::Str(s) => {
                    state.color = Color::from_hex(s).ok_or_else(|| {
                        DeriveError::at(format!("`{s}` is not a colour like \"#3a6ea5\""), span)
                    })?;
                    state.painted = true;
                }
                v => return Err(wrong("a colour string", v)),
            },
            SetTarget::Color(Some(channel)) => match value {
                Value::Number(n) => {
                    let c = n.clamp(0.0, 1.0) as f32;
                    // Opacity is told set by being below 1 (see `crate::asset_look`).
                    match channel {
                        0 => state.color.r = c,
                        1 => state.color.g = c,
                        2 => state.color.b = c,
                        _ => state.color.a = c,
                    }
                    state.painted |= *channel < 3;
                }
                v => return Err(wrong("a number", &v)),
            },
            SetTarget::MaterialName => state.material = Some(Arc::from(value.to_string().as_str())),
            SetTarget::Trim(horizontal) => match value {
                Value::Bool(on) if *horizontal => state.trim.horizontal = on,
                Value::Bool(on) => state.trim.set_vertical(on),
                v => return Err(wrong("true or false", &v)),
            },
            SetTarget::ScopeOrigin(axis) => {
                let Value::Number(n) = value else {
                    return Err(wrong("a number", &value));
                };
                let before = state.scope;
                state.scope.origin[*axis] = n;
                follow_geometry(state, &before, DAffine3::IDENTITY);
            }
            SetTarget::ScopeSize(axis) => match value {
                Value::Number(n) if n >= 0.0 => {
                    let mut size = state.scope.size;
                    size[*axis] = n;
                    let before = state.scope;
                    state.resize(size);
                    let old = before.size;
                    let factor = DVec3::select(old.cmpeq(DVec3::ZERO), DVec3::ONE, size / old);
                    follow_geometry(state, &before, DAffine3::from_scale(factor));
                }
                v => return Err(wrong("a size of 0 or more", &v)),
            },
            SetTarget::Ignored | SetTarget::Map(_) | SetTarget::Finish(_) => {}
        }
        Ok(())
    }

    /// `report(key, value)`: a value for the derivation's reports, made on the shape's tree
    /// node when the derivation keeps its tree.
    pub(super) fn report(
        &mut self,
        state: &mut State,
        key: &CExpr,
        value: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let key = self.ev.eval(key, state, args)?.to_string();
        let value = self.ev.eval(value, state, args)?;
        self.ev.reports.push((key, value));
        if self.tree.is_some() {
            self.report_nodes.push(state.node);
        }
        Ok(())
    }

    /// `print(value)`: a line of the derivation's printed output.
    pub(super) fn print(
        &mut self,
        state: &mut State,
        value: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let text = self.ev.eval(value, state, args)?.to_string();
        self.ev.print(text);
        Ok(())
    }
}
