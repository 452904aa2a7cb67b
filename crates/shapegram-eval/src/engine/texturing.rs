//! Texturing operations: `setupProjection`, `projectUV`, `texture`, the uv edits (`tileUV`,
//! `scaleUV`, `translateUV`, `rotateUV`, `deleteUV`, `copyUV`, `normalizeUV`), texture layers
//! and the other material attributes set with `set(material.…)`, and uv sets following the
//! geometry when `t`, `r`, `s`, `center` or `mirror` move it (see [`crate::texturing`]).

use std::sync::Arc;

use shapegram_geom::{AlphaMode, DAffine3, DMat3, DVec2, DVec3, Scope, Texture};

use super::Fallible;
use super::machine::Engine;
use crate::asset_look::{AssetLook, UvAffine, WornAsset};
use crate::error::DeriveError;
use crate::ops::{ProjectionSetup, UvEdit, UvNormalization};
use crate::program::{CExpr, CKind};
use crate::shape::State;
use crate::texturing::{FinishAttr, OPACITYMAP, ProjectionFrame, Texturing, UV_SETS, UvMap};
use crate::value::Value;

impl Engine<'_> {
    /// `setupProjection`: the projection of a uv set, frozen in world space.
    pub(super) fn setup_projection(
        &mut self,
        state: &mut State,
        setup: &ProjectionSetup,
        args: &[Value],
    ) -> Fallible<()> {
        let ProjectionSetup {
            set,
            world,
            axes,
            sizes,
            offsets,
            uw_factor,
        } = setup;
        let (world, axes) = (*world, *axes);
        let set = self.uv_set(set, state, args)?;
        let (origin, frame) = if world {
            (DVec3::ZERO, DMat3::IDENTITY)
        } else {
            (state.scope.origin, state.scope.axes)
        };
        // Relative and floating sizes measure the scope along the axis of the same letter.
        let lengths = axes.map(|a| state.scope.size[a]);
        let mut tile = [0.0; 2];
        for i in 0..2 {
            tile[i] = self.texture_length(&sizes[i], state, args, lengths[i])?;
            if tile[i] == 0.0 || !tile[i].is_finite() {
                return Err(DeriveError::at(
                    format!(
                        "a texture {} of {}: expected a length other than 0",
                        ["width", "height"][i],
                        tile[i]
                    ),
                    sizes[i].span,
                ));
            }
        }
        let offset = match offsets {
            Some([a, b]) => DVec2::new(
                self.texture_length(a, state, args, lengths[0])?,
                self.texture_length(b, state, args, lengths[1])?,
            ),
            None => DVec2::ZERO,
        };
        let uw_factor = match uw_factor {
            Some(k) => self.ev.number(k, state, args)?,
            None => 0.0,
        };
        let (u, v) = (frame.col(axes[0]), frame.col(axes[1]));
        let frame = ProjectionFrame {
            origin,
            u,
            v,
            w: u.cross(v),
            uw_factor,
        };
        let map = UvMap::projection(&frame, tile[0], tile[1], offset);
        texturing_mut(state).projections[set] = Some(map);
        Ok(())
    }

    /// `projectUV(uvSet)`: the uv set from its projection; without a projection the uvs stay
    /// as they are.
    pub(super) fn project_uv(
        &mut self,
        state: &mut State,
        set: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let set = self.uv_set(set, state, args)?;
        let Some(projection) = state.texturing.as_ref().and_then(|t| t.projections[set]) else {
            return Ok(());
        };
        texturing_mut(state).uvs[set] = Some(projection);
        Ok(())
    }

    /// `texture(path)` (`texture_op`: also the opacity map, to the same image when it has
    /// alpha and to none otherwise) and `set(material.<layer>, path)`: a texture layer; `""` is
    /// none. The image is read through the asset loader (without one, the texture is kept by
    /// its path alone).
    pub(super) fn texture(
        &mut self,
        state: &mut State,
        layer: usize,
        texture_op: bool,
        path: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let span = path.span;
        let path = self.ev.string(path, state, args)?;
        let path = Arc::<str>::from(self.rule_path(&path));
        let texture = if path.is_empty() {
            None
        } else {
            let image = match &self.options.assets {
                Some(loader) => loader
                    .image(&path)
                    .map_err(|e| DeriveError::at(format!("cannot read the texture: {e}"), span))?,
                None => None,
            };
            Some(Arc::new(Texture { path, image }))
        };
        let alpha = texture.as_ref().is_some_and(|t| t.has_alpha());
        let texturing = texturing_mut(state);
        if texture_op {
            texturing.maps[OPACITYMAP] = texture.clone().filter(|_| alpha);
        }
        texturing.maps[layer] = texture;
        Ok(())
    }

    /// `set(material.<attribute>, value)` for the attributes of [`FinishAttr`]: numbers
    /// (clamped to their ranges), `"blend"`, `"mask"` or `"opaque"` for the opacity map's mode,
    /// true or false for `doubleSided`.
    pub(super) fn set_finish(
        &mut self,
        state: &mut State,
        attr: FinishAttr,
        value: &CExpr,
        args: &[Value],
    ) -> Fallible<()> {
        let span = value.span;
        let value = self.ev.eval(value, state, args)?;
        if let FinishAttr::Transform(layer, part) = attr {
            let Value::Number(n) = value else {
                return Err(DeriveError::at(
                    format!("expected a number, found a {}", value.type_name()),
                    span,
                ));
            };
            if !n.is_finite() {
                return Err(DeriveError::at(
                    format!("{n}: expected a finite number"),
                    span,
                ));
            }
            part.set(&mut texturing_mut(state).transforms[layer], n);
            return Ok(());
        }
        let finish = &mut texturing_mut(state).finish;
        let wrong = |what: &str| {
            DeriveError::at(
                format!("expected {what}, found a {}", value.type_name()),
                span,
            )
        };
        match (attr, &value) {
            (FinishAttr::AlphaMode, Value::Str(mode)) => {
                finish.alpha_mode = Some(AlphaMode::from_cga(mode).ok_or_else(|| {
                    DeriveError::at(format!("unknown opacity map mode `{mode}`"), span)
                        .with_hint("the modes are \"blend\", \"mask\" and \"opaque\"")
                })?);
            }
            (FinishAttr::AlphaMode, _) => return Err(wrong("\"blend\", \"mask\" or \"opaque\"")),
            (FinishAttr::DoubleSided, Value::Bool(on)) => finish.double_sided = Some(*on),
            (FinishAttr::DoubleSided, _) => return Err(wrong("true or false")),
            (_, Value::Number(n)) => {
                attr.set_number(finish, *n);
            }
            _ => return Err(wrong("a number")),
        }
        Ok(())
    }

    /// A uv edit (see [`UvEdit`]); a set the geometry does not have is left alone. uv set 0
    /// of an inserted asset (its own uvs, per vertex) is edited as a projected set is.
    pub(super) fn edit_uv(
        &mut self,
        state: &mut State,
        edit: UvEdit,
        params: &[CExpr],
        args: &[Value],
    ) -> Fallible<()> {
        let set = self.uv_set(&params[0], state, args)?;
        if edit == UvEdit::Copy {
            let to = self.uv_set(&params[1], state, args)?;
            if let Some(t) = state.texturing.as_ref().filter(|t| t.uvs[set] != t.uvs[to]) {
                let map = t.uvs[set];
                texturing_mut(state).uvs[to] = map;
            }
            return Ok(());
        }
        let texturing = state.texturing.as_ref();
        if let Some(map) = texturing.and_then(|t| t.uvs[set]) {
            let extent = uv_bounds(state, &map).map(|bounds| (bounds, map.rates()));
            let change = self.uv_change(state, edit, extent, params, args)?;
            texturing_mut(state).uvs[set] = change.map(|c| map.then(c.m, c.t));
            return Ok(());
        }
        let Some(worn) = texturing
            .and_then(|t| t.asset.as_ref())
            .filter(|_| set == 0)
        else {
            return Ok(());
        };
        let Some(extent) = crate::uv_queries::asset_uv_extent(state, worn) else {
            return Ok(());
        };
        let change = self.uv_change(state, edit, Some(extent), params, args)?;
        if let Some(worn) = &mut texturing_mut(state).asset {
            worn.uv_edit = worn.uv_edit.zip(change).map(|(old, new)| old.then(&new));
        }
        Ok(())
    }

    /// What a uv edit does to uvs whose smallest and largest values and growth per metre are
    /// `extent` (`None` when there is no geometry): `None` removes the set.
    fn uv_change(
        &mut self,
        state: &mut State,
        edit: UvEdit,
        extent: Option<((DVec2, DVec2), DVec2)>,
        params: &[CExpr],
        args: &[Value],
    ) -> Fallible<Option<UvAffine>> {
        let linear = |m: [[f64; 2]; 2]| UvAffine { m, t: DVec2::ZERO };
        Ok(match edit {
            UvEdit::Delete => None,
            UvEdit::Scale => {
                let s = self.two(&params[1..], state, args)?;
                Some(linear([[s.x, 0.0], [0.0, s.y]]))
            }
            UvEdit::Translate => {
                let t = self.two(&params[1..], state, args)?;
                Some(UvAffine {
                    t,
                    ..UvAffine::IDENTITY
                })
            }
            UvEdit::Rotate => {
                let (sin, cos) = self
                    .ev
                    .number(&params[1], state, args)?
                    .to_radians()
                    .sin_cos();
                Some(linear([[cos, -sin], [sin, cos]]))
            }
            UvEdit::Tile => Some(match extent {
                Some((bounds, rates)) => self.tile(state, bounds, rates, &params[1..], args)?,
                None => UvAffine::IDENTITY,
            }),
            UvEdit::Normalize(mode) => Some(match extent {
                Some((bounds, _)) => normalized(bounds, mode),
                None => UvAffine::IDENTITY,
            }),
            UvEdit::Copy => Some(UvAffine::IDENTITY),
        })
    }

    /// `tileUV`: the uvs (from `low` to `high`, growing `rates` per metre) start at 0 over the
    /// geometry and one tile spans the given size along each axis (metres on the surface, `'r`
    /// of the current extent, `~f` whole tiles of about `f`; 0 leaves the axis alone).
    fn tile(
        &mut self,
        state: &mut State,
        (low, high): (DVec2, DVec2),
        rates: DVec2,
        sizes: &[CExpr],
        args: &[Value],
    ) -> Fallible<UvAffine> {
        let extent = high - low;
        let (mut scale, mut shift) = (DVec2::ONE, DVec2::ZERO);
        for i in 0..2 {
            if extent[i] <= 0.0 || rates[i] <= 0.0 {
                continue;
            }
            // Metres on the surface per uv unit, and the surface's length along the axis.
            let metres = 1.0 / rates[i];
            let e = &sizes[i];
            let factor = match &e.kind {
                CKind::Relative(inner) => {
                    let r = self.ev.number(inner, state, args)?;
                    (r != 0.0).then(|| 1.0 / (extent[i] * r))
                }
                _ => {
                    let tile = self.texture_length(e, state, args, extent[i] * metres)?;
                    (tile != 0.0).then(|| metres / tile)
                }
            };
            if let Some(factor) = factor {
                scale[i] = factor;
                shift[i] = -low[i] * factor;
            }
        }
        Ok(UvAffine {
            m: [[scale.x, 0.0], [0.0, scale.y]],
            t: shift,
        })
    }

    /// A uv set's number, 0 to 9.
    fn uv_set(&mut self, e: &CExpr, state: &mut State, args: &[Value]) -> Fallible<usize> {
        let n = self.ev.number(e, state, args)?;
        if n.fract() != 0.0 || !(0.0..UV_SETS as f64).contains(&n) {
            return Err(DeriveError::at(
                format!("uv set {n}: expected a whole number from 0 to 9"),
                e.span,
            ));
        }
        Ok(n as usize)
    }

    /// A length of texture space: metres, `'r` (r times `length`) or `~f` (`length` divided
    /// into whole parts of about `f`).
    fn texture_length(
        &mut self,
        e: &CExpr,
        state: &mut State,
        args: &[Value],
        length: f64,
    ) -> Fallible<f64> {
        Ok(match &e.kind {
            CKind::Relative(inner) => self.ev.number(inner, state, args)? * length,
            CKind::Floating(inner) => {
                let about = self.ev.number(inner, state, args)?;
                length / (length / about).round().max(1.0)
            }
            _ => self.ev.number(e, state, args)?,
        })
    }

    fn two(&mut self, e: &[CExpr], state: &mut State, args: &[Value]) -> Fallible<DVec2> {
        Ok(DVec2::new(
            self.ev.number(&e[0], state, args)?,
            self.ev.number(&e[1], state, args)?,
        ))
    }
}

/// The smallest and largest uv a map gives the shape's geometry; `None` without geometry.
fn uv_bounds(state: &State, map: &UvMap) -> Option<(DVec2, DVec2)> {
    let mesh = state.geometry.world_mesh(&state.scope)?;
    let (mut low, mut high) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &p in mesh.positions() {
        let uv = map.at(p);
        low = low.min(uv);
        high = high.max(uv);
    }
    low.is_finite().then_some((low, high))
}

/// `normalizeUV`: uvs from `low` to `high` mapped onto `[0, 1]` along the mode's axes (the
/// smallest becoming 0); an axis along which they do not change is left alone.
fn normalized((low, high): (DVec2, DVec2), mode: UvNormalization) -> UvAffine {
    let extent = high - low;
    let axes = match mode {
        UvNormalization::Each | UvNormalization::Uniform => [true, true],
        UvNormalization::U => [true, false],
        UvNormalization::V => [false, true],
    };
    let (mut scale, mut shift) = (DVec2::ONE, DVec2::ZERO);
    for i in 0..2 {
        let length = match mode {
            UvNormalization::Uniform => extent.max_element(),
            _ => extent[i],
        };
        if axes[i] && length > 0.0 {
            scale[i] = 1.0 / length;
            shift[i] = -low[i] / length;
        }
    }
    UvAffine {
        m: [[scale.x, 0.0], [0.0, scale.y]],
        t: shift,
    }
}

/// The shape's texturing, made its own to change.
pub(super) fn texturing_mut(state: &mut State) -> &mut Texturing {
    Arc::make_mut(state.texturing.get_or_insert_with(Default::default))
}

/// Carries the shape's uv sets, and where the asset it wears is, along after its geometry moved
/// with its scope from `before`,
/// where `local` is how the geometry's scope-local coordinates changed (identity when they
/// did not).
pub(super) fn follow_geometry(state: &mut State, before: &Scope, local: DAffine3) {
    if !state
        .texturing
        .as_ref()
        .is_some_and(|t| t.has_uvs() || t.asset.is_some())
    {
        return;
    }
    let motion = state.scope.local_to_world() * local * before.world_to_local();
    let texturing = texturing_mut(state);
    for map in texturing.uvs.iter_mut().flatten() {
        *map = map.moved(&motion);
    }
    if let Some(worn) = &mut texturing.asset {
        worn.placed = motion * worn.placed;
    }
}

/// Drops the shape's uv sets and the look of an asset it held when its geometry is replaced
/// (an inserted asset or a primitive brings its own).
pub(super) fn drop_uvs(state: &mut State) {
    if state
        .texturing
        .as_ref()
        .is_some_and(|t| t.has_uvs() || t.asset.is_some())
    {
        let texturing = texturing_mut(state);
        texturing.uvs = Default::default();
        texturing.asset = None;
    }
}

/// Gives the shape the look of the asset it now holds (see [`crate::asset_look`]); nothing
/// for an asset without one.
pub(super) fn wear(state: &mut State, look: Option<&Arc<AssetLook>>, placed: DAffine3) {
    if let Some(look) = look {
        texturing_mut(state).asset = Some(WornAsset::new(Arc::clone(look), placed));
    }
}
