//! The asset functions of CGA's reference that real rule files use: `assetInfo` (an asset's
//! bounding box) and `assetBestSize` (the asset of a file search that fits the scope best).

use shapegram_geom::{Aabb, DVec3};

use super::{Evaluator, Result};
use crate::builtins::Builtin;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Evaluator<'_> {
    /// `assetInfo(path, sx | sy | sz | tx | ty | tz)` and `assetBestSize(query, axes)`.
    pub(super) fn asset_function(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let first = self.string(&params[0], shape, args)?;
        let second = self.word(&params[1], shape, args)?;
        if b == Builtin::AssetInfo {
            let (axis, size) = match second.as_bytes() {
                [b's', a @ (b'x' | b'y' | b'z')] => (a - b'x', true),
                [b't', a @ (b'x' | b'y' | b'z')] => (a - b'x', false),
                _ => {
                    return Err(DeriveError::at(
                        format!("`{second}`: expected sx, sy, sz, tx, ty or tz"),
                        params[1].span,
                    ));
                }
            };
            let bounds = self.asset_bounds(&first, &params[0])?;
            let v = if size { bounds.size() } else { bounds.min };
            return Ok(Value::Number(v[usize::from(axis)]));
        }
        let axes: Vec<usize> = second
            .chars()
            .map(|c| match c {
                'x' => Some(0),
                'y' => Some(1),
                'z' => Some(2),
                _ => None,
            })
            .collect::<Option<_>>()
            .filter(|a: &Vec<usize>| !a.is_empty() && a.len() <= 3)
            .ok_or_else(|| {
                DeriveError::at(
                    format!(
                        "`{second}`: expected the scope axes to fit, such as \"xz\" or \"xyz\""
                    ),
                    params[1].span,
                )
            })?;
        let loader = self.loader(&format!("search for `{first}`"), params[0].span)?;
        let found = loader
            .search(&first)
            .map_err(|why| DeriveError::at(why, params[0].span))?;
        // The misfit is the sum, over the axes asked for, of how far the asset's size is from
        // the scope's; files that are not meshes (textures found by a broad query) take no part.
        let scope = shape.scope.size;
        let mut best: Option<(f64, &str)> = None;
        for file in &found {
            let Some(bounds) = loader.load(file).ok().and_then(|m| m.bounds()) else {
                continue;
            };
            let misfit: f64 = axes
                .iter()
                .map(|&a| (bounds.size()[a] - scope[a]).abs())
                .sum();
            if best.is_none_or(|(m, _)| misfit < m) {
                best = Some((misfit, file));
            }
        }
        Ok(Value::string(best.map_or("", |(_, file)| file)))
    }

    /// The bounding box of the asset `i(path)` would insert, in the asset's own coordinates.
    fn asset_bounds(&self, path: &str, at: &CExpr) -> Result<Aabb> {
        let bounds = match crate::engine::builtin_asset(path) {
            Some(mesh) => mesh.bounds(),
            None => {
                let loader = self.loader(&format!("read the asset `{path}`"), at.span)?;
                let mesh = loader.load(path).map_err(|why| {
                    DeriveError::at(format!("cannot read the asset `{path}`: {why}"), at.span)
                })?;
                mesh.bounds()
            }
        };
        Ok(bounds.unwrap_or_else(|| Aabb::new(DVec3::ZERO, DVec3::ZERO)))
    }
}
