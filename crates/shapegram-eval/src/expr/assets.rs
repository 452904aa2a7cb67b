//! CGA's asset and image functions (see [`crate::asset_queries`]): what an asset's bounding
//! box, names and metadata are, an image's pixel size, and which files of a list or a search
//! fit the scope best. Files are found and read by the derivation's [`AssetLoader`].

use std::sync::Arc;

use shapegram_geom::{Aabb, DVec3};

use super::{Evaluator, Result};
use crate::asset_queries::{
    AssetFn, image_axes, ranked, ratio_misfit, ratio_pairs, size_axes, size_misfit,
};
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

/// Files given to a sorting function, and whether they came as an array (the result is one
/// too) or as a string list.
struct FileList {
    files: Vec<Arc<str>>,
    array: bool,
}

impl FileList {
    /// `files` in the form the list came in.
    fn value(&self, files: impl IntoIterator<Item = Arc<str>>) -> Value {
        listed(files, self.array)
    }
}

/// `names` as an array, or as a string list with each entry ended by `;`.
fn listed(names: impl IntoIterator<Item = Arc<str>>, array: bool) -> Value {
    if array {
        Value::Array(names.into_iter().map(Value::Str).collect())
    } else {
        Value::string(
            &names
                .into_iter()
                .map(|n| format!("{n};"))
                .collect::<String>(),
        )
    }
}

impl Evaluator<'_> {
    /// Evaluates the asset or image function `f` on its arguments `params`.
    pub(super) fn asset_function(
        &mut self,
        f: AssetFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        match f {
            AssetFn::Info => self.asset_info(params, shape, args),
            AssetFn::ImageInfo => self.image_info(params, shape, args),
            AssetFn::NamingInfo | AssetFn::NamingInfos => {
                let names = self.naming_info(params, shape, args)?;
                Ok(listed(names, f == AssetFn::NamingInfos))
            }
            AssetFn::Metadata => {
                let path = self.string(&params[0], shape, args)?;
                self.string(&params[1], shape, args)?;
                let default = self.eval(&params[2], shape, args)?;
                // The asset must be there as for `assetInfo`; the formats Shapegram reads
                // carry no metadata it reads, so every key has the default.
                self.asset_bounds(&path, &params[0])?;
                Ok(default)
            }
            AssetFn::SortSize | AssetFn::SortRatio | AssetFn::ImagesSortRatio => {
                self.sort_files(f, params, shape, args)
            }
            AssetFn::BestSize | AssetFn::ApproxSize | AssetFn::FitSize => {
                let chosen = self.choose_by_size(f, params, shape, args)?;
                Ok(Value::Str(chosen.unwrap_or_else(|| Arc::from(""))))
            }
            AssetFn::BestRatio
            | AssetFn::ApproxRatio
            | AssetFn::ImageBestRatio
            | AssetFn::ImageApproxRatio => {
                let chosen = self.choose_by_ratio(f, params, shape, args)?;
                Ok(Value::Str(chosen.unwrap_or_else(|| Arc::from(""))))
            }
        }
    }

    /// `assetNamingInfo(s)(path, g | m)`: the asset's group or material names.
    fn naming_info(
        &mut self,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Vec<Arc<str>>> {
        let path = self.string(&params[0], shape, args)?;
        let which = self.word(&params[1], shape, args)?;
        let naming = match crate::engine::builtin_asset(&path) {
            Some(_) => Arc::default(),
            None => self
                .loader(&format!("read the asset `{path}`"), params[0].span)?
                .naming(&path)
                .map_err(|why| {
                    DeriveError::at(
                        format!("cannot read the asset `{path}`: {why}"),
                        params[0].span,
                    )
                })?,
        };
        match &*which {
            "g" => Ok(naming.groups.clone()),
            "m" => Ok(naming.materials.clone()),
            _ => Err(DeriveError::at(
                format!("`{which}`: expected g (group names) or m (material names)"),
                params[1].span,
            )),
        }
    }

    /// `assetsSortSize`, `assetsSortRatio` and `imagesSortRatio` on a list or array of files.
    fn sort_files(
        &mut self,
        f: AssetFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let list = self.file_list(&params[0], shape, args)?;
        let scope = shape.scope.size;
        let sorted = match f {
            AssetFn::SortSize => {
                let axes = self.size_selector(&params[1], shape, args)?;
                let max_error = self.number(&params[2], shape, args)?;
                self.by_size(&list.files, axes, scope, max_error)
            }
            AssetFn::SortRatio => {
                let pairs = self.ratio_selector(&params[1], shape, args)?;
                files_of(self.by_ratio(&list.files, pairs, scope))
            }
            _ => {
                let axes = self.image_selector(&params[1], shape, args)?;
                files_of(self.images_by_ratio(&list.files, axes, scope))
            }
        };
        Ok(list.value(sorted))
    }

    /// `assetBestSize`, `assetApproxSize` and `assetFitSize`: an asset of a search by size.
    fn choose_by_size(
        &mut self,
        f: AssetFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Option<Arc<str>>> {
        let found = self.searched(&params[0], shape, args)?;
        let axes = self.size_selector(&params[1], shape, args)?;
        let scope = shape.scope.size;
        Ok(match f {
            AssetFn::ApproxSize => {
                let n = self.number(&params[2], shape, args)?;
                draw(first(self.by_size(&found, axes, scope, 0.0), n), shape)
            }
            AssetFn::FitSize => {
                let max_error = self.number(&params[2], shape, args)?;
                draw(self.by_size(&found, axes, scope, max_error), shape)
            }
            _ => self.by_size(&found, axes, scope, 0.0).into_iter().next(),
        })
    }

    /// `assetBestRatio`, `assetApproxRatio`, `imageBestRatio` and `imageApproxRatio`: an asset
    /// or image of a search by proportions.
    fn choose_by_ratio(
        &mut self,
        f: AssetFn,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Option<Arc<str>>> {
        let found = self.searched(&params[0], shape, args)?;
        let scope = shape.scope.size;
        let sorted = if matches!(f, AssetFn::BestRatio | AssetFn::ApproxRatio) {
            let pairs = self.ratio_selector(&params[1], shape, args)?;
            self.by_ratio(&found, pairs, scope)
        } else {
            let axes = self.image_selector(&params[1], shape, args)?;
            self.images_by_ratio(&found, axes, scope)
        };
        Ok(match f {
            AssetFn::BestRatio => sorted.into_iter().next().map(|(_, file)| file),
            AssetFn::ImageBestRatio => {
                // The reference: among images that share the best ratio, a random one.
                let best = sorted.first().map(|(m, _)| *m);
                let ties: Vec<Arc<str>> = sorted
                    .into_iter()
                    .take_while(|(m, _)| Some(*m) == best)
                    .map(|(_, file)| file)
                    .collect();
                match ties.len() {
                    0 | 1 => ties.into_iter().next(),
                    _ => draw(ties, shape),
                }
            }
            _ => {
                let n = self.number(&params[2], shape, args)?;
                let files = files_of(sorted);
                // CityEngine's library draws among all the images for an `n` of 0 or less,
                // and among the first `n` (none below 1) otherwise.
                let drawn = if f == AssetFn::ImageApproxRatio && n <= 0.0 {
                    files
                } else {
                    first(files, n)
                };
                draw(drawn, shape)
            }
        })
    }

    /// `imageInfo(path, sx | sy)`: the image's width or height in pixels.
    fn image_info(&mut self, params: &[CExpr], shape: &mut State, args: &[Value]) -> Result<Value> {
        let path = self.string(&params[0], shape, args)?;
        let which = self.word(&params[1], shape, args)?;
        let pick_width = match &*which {
            "sx" => true,
            "sy" => false,
            _ => {
                return Err(DeriveError::at(
                    format!("`{which}`: expected sx (the width) or sy (the height)"),
                    params[1].span,
                ));
            }
        };
        let (width, height) = self
            .loader(&format!("read the image `{path}`"), params[0].span)?
            .image_size(&path)
            .map_err(|why| DeriveError::at(why, params[0].span))?;
        Ok(Value::Number(f64::from(if pick_width {
            width
        } else {
            height
        })))
    }

    /// `assetInfo(path, sx | sy | sz | tx | ty | tz)`: a size or the minimum of the asset's
    /// bounding box along one axis.
    fn asset_info(&mut self, params: &[CExpr], shape: &mut State, args: &[Value]) -> Result<Value> {
        let path = self.string(&params[0], shape, args)?;
        let which = self.word(&params[1], shape, args)?;
        let (axis, size) = match which.as_bytes() {
            [b's', a @ (b'x' | b'y' | b'z')] => (a - b'x', true),
            [b't', a @ (b'x' | b'y' | b'z')] => (a - b'x', false),
            _ => {
                return Err(DeriveError::at(
                    format!("`{which}`: expected sx, sy, sz, tx, ty or tz"),
                    params[1].span,
                ));
            }
        };
        let bounds = self.asset_bounds(&path, &params[0])?;
        let v = if size { bounds.size() } else { bounds.min };
        Ok(Value::Number(v[usize::from(axis)]))
    }

    /// A string list (`"a.obj;b.obj;"`) or an array of strings.
    fn file_list(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<FileList> {
        match self.eval(e, shape, args)? {
            Value::Str(list) => Ok(FileList {
                files: list
                    .split(';')
                    .filter(|f| !f.is_empty())
                    .map(Arc::from)
                    .collect(),
                array: false,
            }),
            Value::Array(items) => Ok(FileList {
                files: items
                    .iter()
                    .map(|item| match item {
                        Value::Str(s) => Ok(Arc::clone(s)),
                        other => Err(DeriveError::at(
                            format!(
                                "expected an array of file paths, found a {} in it",
                                other.type_name()
                            ),
                            e.span,
                        )),
                    })
                    .collect::<Result<_>>()?,
                array: true,
            }),
            other => Err(DeriveError::at(
                format!(
                    "expected a list of files (a string list or a string array), found a {}",
                    other.type_name()
                ),
                e.span,
            )),
        }
    }

    fn size_selector(
        &mut self,
        e: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<&'static [usize]> {
        let word = self.word(e, shape, args)?;
        size_axes(&word).ok_or_else(|| {
            DeriveError::at(
                format!("`{word}`: expected the scope axes x, y, z, xy, xz, yz or xyz"),
                e.span,
            )
        })
    }

    fn ratio_selector(
        &mut self,
        e: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<&'static [(usize, usize)]> {
        let word = self.word(e, shape, args)?;
        ratio_pairs(&word).ok_or_else(|| {
            DeriveError::at(
                format!("`{word}`: expected the scope axes xy, xz, yz or xyz"),
                e.span,
            )
        })
    }

    fn image_selector(
        &mut self,
        e: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<(usize, usize)> {
        let word = self.word(e, shape, args)?;
        image_axes(&word).ok_or_else(|| {
            DeriveError::at(
                format!("`{word}`: expected the scope axes xy, xz, yx, yz, zx or zy"),
                e.span,
            )
        })
    }

    /// The size of the asset `i(path)` would insert, or `None` for a file that is not a mesh
    /// (a texture found by a broad search): such files take no part in the sorting functions.
    fn mesh_size(&self, path: &str) -> Option<DVec3> {
        let bounds = match crate::engine::builtin_asset(path) {
            Some(mesh) => mesh.bounds(),
            None => self.assets?.load(path).ok()?.bounds(),
        };
        Some(bounds?.size())
    }

    /// `assetsSortSize`: the meshes among `files` by how much `i()` would scale them along
    /// `axes` (best first), those needing more than `max_error` left out when it is above 0.
    fn by_size(
        &self,
        files: &[Arc<str>],
        axes: &[usize],
        scope: DVec3,
        max_error: f64,
    ) -> Vec<Arc<str>> {
        let scored = files
            .iter()
            .filter_map(|f| Some((size_misfit(self.mesh_size(f)?, scope, axes), Arc::clone(f))))
            .filter(|(misfit, _)| max_error <= 0.0 || *misfit <= max_error)
            .collect();
        ranked(scored).into_iter().map(|(_, f)| f).collect()
    }

    /// `assetsSortRatio`: the meshes among `files` by how far their proportions are from the
    /// scope's over the axis `pairs`, best first, with that distance.
    fn by_ratio(
        &self,
        files: &[Arc<str>],
        pairs: &[(usize, usize)],
        scope: DVec3,
    ) -> Vec<(f64, Arc<str>)> {
        let scored = files
            .iter()
            .filter_map(|f| {
                Some((
                    ratio_misfit(self.mesh_size(f)?, scope, pairs),
                    Arc::clone(f),
                ))
            })
            .collect();
        ranked(scored)
    }

    /// `imagesSortRatio`: the images among `files` by how far their width to height is from
    /// the scope's along `axes`, best first, with that distance. Files that are not images
    /// whose size can be read take no part.
    fn images_by_ratio(
        &self,
        files: &[Arc<str>],
        (a, b): (usize, usize),
        scope: DVec3,
    ) -> Vec<(f64, Arc<str>)> {
        let Some(loader) = self.assets else {
            return Vec::new();
        };
        let scored = files
            .iter()
            .filter_map(|f| {
                let (width, height) = loader.image_size(f).ok()?;
                let mut size = DVec3::ZERO;
                size[a] = f64::from(width);
                size[b] = f64::from(height);
                Some((ratio_misfit(size, scope, &[(a, b)]), Arc::clone(f)))
            })
            .collect();
        ranked(scored)
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

/// The files of a ranking, in its order.
fn files_of(ranked: Vec<(f64, Arc<str>)>) -> Vec<Arc<str>> {
    ranked.into_iter().map(|(_, file)| file).collect()
}

/// The first `n` of `files` (none when `n` is below 1), as CGA's `listRange(list, 0, n)`.
fn first(mut files: Vec<Arc<str>>, n: f64) -> Vec<Arc<str>> {
    files.truncate(n.max(0.0).floor().min(files.len() as f64) as usize);
    files
}

/// One of `files` drawn from the shape's random stream as CGA's `listRandom` draws (a number
/// is drawn even from no files); `None` when there are none.
fn draw(files: Vec<Arc<str>>, shape: &mut State) -> Option<Arc<str>> {
    let at = (shape.rng.next_f64() * (files.len() as f64 - 1e-7)).floor();
    (at >= 0.0)
        .then(|| files.into_iter().nth(at as usize))
        .flatten()
}
