//! What a shape is given to hold: `i("path")` with an asset from a file (through the
//! [`AssetLoader`]) or a built-in one, and the `primitive…()` shapes.

use std::sync::Arc;

use shapegram_geom::fit::adapt_scope_to_asset;
use shapegram_geom::{Aabb, DAffine3, DVec2, DVec3, Mesh, Part, Scope, primitives};
use shapegram_implicit::Solid;
use shapegram_syntax::Span;

use super::Fallible;
use super::machine::Engine;
use super::texturing::{drop_uvs, texturing_mut, wear};
use crate::asset_look::AssetLook;
use crate::error::DeriveError;
use crate::ops::{InsertFit, Placement, Primitive};
use crate::program::CExpr;
use crate::rng::child_seed;
use crate::shape::{Geometry, State, box_mesh};
use crate::tags::FaceTags;
use crate::texturing::{ProjectionFrame, UvMap};
use crate::value::Value;

/// Loads the assets that `i("path")` inserts (built-in assets are handled by the engine) and
/// the implicit grammars that `implicit("path")` runs.
pub trait AssetLoader: Send + Sync {
    /// The mesh stored at `path`, or a one-line reason why it cannot be had.
    fn load(&self, path: &str) -> Result<Arc<Mesh>, String>;

    /// What `i("path")` inserts in a shape that asks for variant `variant` (below
    /// [`ASSET_VARIANTS`]) of assets grown from a seed, such as stochastic L-systems; fixed
    /// files ignore it. By default [`load`](Self::load)'s mesh, stretched to the scope.
    fn asset(&self, path: &str, _variant: u32) -> Result<Asset, String> {
        Ok(Asset {
            mesh: self.load(path)?,
            proportional: false,
            look: None,
            groups: None,
        })
    }

    /// The implicit solid that the grammar at `path` makes, or a one-line reason why it cannot
    /// be had.
    fn solid(&self, path: &str) -> Result<Solid, String> {
        Err(format!("cannot read `{path}` as an implicit grammar here"))
    }

    /// The text of the file at `path` (tables for `readStringTable`), or a one-line reason why
    /// it cannot be had.
    fn text(&self, path: &str) -> Result<Arc<str>, String> {
        Err(format!("cannot read `{path}` here"))
    }

    /// The files a `fileSearch` query finds, sorted, as paths `i()` and the other file
    /// functions take; or a one-line reason why the query cannot be answered.
    fn search(&self, query: &str) -> Result<Vec<Arc<str>>, String> {
        Err(format!("cannot search for `{query}` here"))
    }

    /// How a rule of an imported file whose folder is `folder` (relative to the grammar's,
    /// `/`-separated) names `path` to the other methods, when CityEngine finds it next to that
    /// file, which it looks at first; `None` to look `path` up as from the grammar. By default
    /// `None`.
    fn beside(&self, _folder: &str, _path: &str) -> Option<String> {
        None
    }

    /// Whether there is a file at `path` (CGA's `fileExists`): by default, whether it can be
    /// read as text, an image or a mesh.
    fn exists(&self, path: &str) -> bool {
        self.text(path).is_ok()
            || matches!(self.image(path), Ok(Some(_)))
            || self.load(path).is_ok()
    }

    /// The bytes of the image at `path` (a PNG or JPEG texture); `Ok(None)` when it cannot be
    /// had but the derivation goes on without it; or a one-line reason why it cannot be had.
    fn image(&self, path: &str) -> Result<Option<Arc<[u8]>>, String> {
        Err(format!("cannot read the image `{path}` here"))
    }

    /// The width and height in pixels of the image at `path` (CGA's `imageInfo`), or a
    /// one-line reason why they cannot be had.
    fn image_size(&self, path: &str) -> Result<(u32, u32), String> {
        Err(format!("cannot read the image `{path}` here"))
    }

    /// The group and material names of the asset at `path` (CGA's `assetNamingInfo`), or a
    /// one-line reason why they cannot be had.
    fn naming(&self, path: &str) -> Result<Arc<AssetNaming>, String> {
        Err(format!("cannot read the asset `{path}` here"))
    }
}

/// The names an asset file gives its parts, each once, in the order the file first uses them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AssetNaming {
    /// Group names (OBJ `o` and `g`, glTF node names).
    pub groups: Vec<Arc<str>>,
    /// Material names (OBJ `usemtl`, glTF material names); parts without a material name none.
    pub materials: Vec<Arc<str>>,
}

/// How many variants of a seeded asset (see [`AssetLoader::asset`]) the shapes of a derivation
/// choose among, each by its own random stream: enough for a varied park, few enough that a
/// city of trees grows each variant once.
pub const ASSET_VARIANTS: u32 = 8;

/// An asset for `i()` and how it is placed.
#[derive(Clone, Debug)]
pub struct Asset {
    /// The geometry, in the asset's own coordinates.
    pub mesh: Arc<Mesh>,
    /// Scaled uniformly to fit inside the scope, centred in x and z and standing on the scope's
    /// floor (a planted tree keeps its shape), instead of stretched to the scope as CGA's `i()`.
    pub proportional: bool,
    /// Its materials and uvs, when it has any (see [`AssetLook::from_parts`]).
    pub look: Option<Arc<AssetLook>>,
    /// The group (an OBJ `g`/`o` group, a glTF node) of each face, when the asset has groups
    /// (see [`crate::tags::face_groups`]), for `comp(g)` and `geometry.groups`.
    pub groups: Option<Arc<[Arc<str>]>>,
}

impl Engine<'_> {
    /// CGA `i("path" [, upAxis [, mode]])`: the asset at the path, turned up if it is `zUp`,
    /// placed as the mode says (see [`place`]); a seeded asset in the variant the shape's seed
    /// picks.
    pub(super) fn insert(
        &mut self,
        state: &mut State,
        path: &CExpr,
        placement: Placement,
        args: &[Value],
    ) -> Fallible<()> {
        let file = self.ev.string(path, state, args)?;
        let file = self.rule_path(&file);
        // From the shape's seed, not its stream, so asking for a variant draws nothing
        // that later random choices of the shape would miss.
        let variant = (child_seed(state.seed, u64::MAX) % u64::from(ASSET_VARIANTS)) as u32;
        let mut asset = self.asset(&file, variant, path.span)?;
        let up = if placement.z_up {
            DAffine3::from_rotation_x(-std::f64::consts::FRAC_PI_2)
        } else {
            DAffine3::IDENTITY
        };
        if placement.z_up {
            asset.mesh = Arc::new(asset.mesh.transformed(&up));
        }
        drop_uvs(state);
        place(state, &asset, placement.fit);
        if asset.look.is_some() {
            wear(state, asset.look.as_ref(), placed(state, &asset.mesh) * up);
        }
        if let (true, Some(groups), Geometry::Mesh(mesh, _)) =
            (self.program.tagged, &asset.groups, &state.geometry)
        {
            // The faces are the asset's, in its order: each wears its group.
            let tags = (0..mesh.face_count())
                .map(|f| FaceTags {
                    group: groups.get(f).cloned(),
                    ..FaceTags::default()
                })
                .collect();
            state.geometry = Geometry::tagged_mesh((**mesh).clone(), tags);
        }
        // Recorded before the trim, which makes a new mesh when it cuts (then the shape is no
        // instance any more, as in CityEngine).
        state.instance = match &state.geometry {
            Geometry::Mesh(mesh, _) => Some(Arc::downgrade(mesh)),
            _ => None,
        };
        trim(state);
        Ok(())
    }

    /// `primitiveCube()` and friends: the shape becomes the primitive filling its scope, with
    /// as many subdivisions as its arguments ask for.
    pub(super) fn primitive(
        &mut self,
        state: &mut State,
        kind: Primitive,
        params: &[CExpr],
        span: Span,
        args: &[Value],
    ) -> Fallible<()> {
        let numbers = self.numbers(params, state, args)?;
        drop_uvs(state);
        let (counts, size) = match (kind, numbers.as_slice()) {
            (Primitive::Cube, &[w, h, d]) => (&[][..], Some((DVec3::new(w, h, d), 1))),
            (Primitive::Quad, &[w, l]) => (&[][..], Some(quad_size(&state.scope, w, l))),
            (Primitive::Disk, &[_, r]) => (
                &numbers[..1],
                Some(quad_size(&state.scope, 2.0 * r, 2.0 * r)),
            ),
            (Primitive::Cylinder, &[_, r, h]) => {
                (&numbers[..1], Some((DVec3::new(2.0 * r, h, 2.0 * r), 1)))
            }
            _ => (&numbers[..], None),
        };
        match size {
            Some((size, up)) => {
                place_sized(&mut state.scope, size.abs(), up, span)?;
                // A negative dimension mirrors, as a negative size of `s()` does: the
                // primitive stays centred across, and a negative height hangs below y = 0.
                for i in (0..3).filter(|&i| size[i] < 0.0) {
                    if i != up {
                        state.scope.origin += state.scope.axes.col(i) * size[i].abs();
                    }
                    state.mirror_axis(i);
                }
            }
            // A disk fills the scope's flat face as it is.
            None if kind == Primitive::Disk => {}
            None => {
                // A primitive is a unit asset: a flat scope takes sizes by `i()`'s rules (a
                // cube on a 20 × 30 lot is 25 high, the mean of the other two).
                let unit = match kind {
                    Primitive::Quad => DVec3::new(1.0, 1.0, 0.0),
                    _ => DVec3::ONE,
                };
                adapt_scope_to_asset(&mut state.scope, &Aabb::new(DVec3::ZERO, unit));
            }
        }
        let size = state.scope.size;
        let count = |i: usize, default: u32| -> Fallible<u32> {
            match counts.get(i) {
                None => Ok(default),
                Some(&n) if (3.0..=100_000.0).contains(&n) => Ok(n as u32),
                Some(&n) => Err(DeriveError::at(
                    format!("{n} subdivisions: expected 3 to 100000"),
                    span,
                )),
            }
        };
        if kind == Primitive::Quad {
            quad_uvs(state);
        }
        if kind == Primitive::Cube && size.cmpgt(DVec3::ZERO).all() {
            let placed = state.scope.local_to_world() * DAffine3::from_scale(size);
            wear(state, Some(cube_look()), placed);
        }
        state.geometry = match kind {
            Primitive::Cube | Primitive::Quad => Geometry::Box,
            Primitive::Disk => {
                let flat = quad_size(&state.scope, 1.0, 1.0).1;
                let across = (0..3).filter(|&i| i != flat);
                if across.clone().any(|i| size[i] == 0.0) {
                    Geometry::Empty
                } else {
                    Geometry::mesh(primitives::disk(size, flat, count(0, 16)?))
                }
            }
            Primitive::Pyramid => Geometry::mesh(primitives::pyramid(size)),
            Primitive::Cylinder => Geometry::mesh(primitives::cylinder(size, count(0, 16)?)),
            Primitive::Cone => Geometry::mesh(primitives::cone(size, count(0, 16)?)),
            Primitive::Sphere => {
                let rings = count(0, 16)?;
                Geometry::mesh(primitives::sphere(size, count(1, 2 * rings)?, rings))
            }
        };
        trim(state);
        Ok(())
    }

    /// The path by which the loader finds the file the rule being applied names `path`: as
    /// CityEngine looks first next to the rule's own file, an imported file's rule names a
    /// file beside it by its place from the grammar (see [`AssetLoader::beside`]).
    pub(super) fn rule_path(&self, path: &str) -> String {
        let relative = !path.starts_with('/') && !path.starts_with("builtin:");
        let beside = self
            .program
            .rule_folder(self.rule)
            .filter(|_| relative && !path.is_empty())
            .zip(self.options.assets.as_ref())
            .and_then(|(folder, loader)| loader.beside(folder, path));
        beside.unwrap_or_else(|| path.to_owned())
    }

    /// The asset `i("path")` inserts: a built-in one, or variant `variant` of what the
    /// loader finds at `path`.
    fn asset(&self, path: &str, variant: u32, span: Span) -> Fallible<Asset> {
        if let Some(mesh) = builtin_asset(path) {
            return Ok(Asset {
                mesh: Arc::new(mesh),
                proportional: false,
                look: (path == "builtin:cube").then(|| Arc::clone(cube_look())),
                groups: None,
            });
        }
        let Some(loader) = &self.options.assets else {
            return Err(DeriveError::at(
                format!("cannot insert `{path}`: no asset folder is set"),
                span,
            )
            .with_hint("use a built-in asset such as \"builtin:cube\""));
        };
        loader
            .asset(path, variant)
            .map_err(|why| DeriveError::at(format!("cannot insert `{path}`: {why}"), span))
    }
}

/// The sizes along the scope's axes of `primitiveQuad(width, length)` and the axis it lies
/// across: in the plane of the two scope sizes that are not zero when one is, else in the
/// scope's xz-plane.
fn quad_size(scope: &Scope, width: f64, length: f64) -> (DVec3, usize) {
    let zero: Vec<usize> = (0..3).filter(|&i| scope.size[i] == 0.0).collect();
    match zero.as_slice() {
        [0] => (DVec3::new(0.0, width, length), 0),
        [2] => (DVec3::new(width, length, 0.0), 2),
        _ => (DVec3::new(width, 0.0, length), 1),
    }
}

/// A primitive given its dimensions, as CityEngine places it: `size` centred in the scope
/// across the two other axes, lying on the scope's plane `up` = 0 (y for all but a quad
/// standing in the yz- or xy-plane).
fn place_sized(scope: &mut Scope, size: DVec3, up: usize, span: Span) -> Fallible<()> {
    if !size.is_finite() {
        return Err(DeriveError::at(
            format!(
                "primitive dimensions {} × {} × {}: expected finite sizes",
                size.x, size.y, size.z
            ),
            span,
        ));
    }
    for i in (0..3).filter(|&i| i != up) {
        scope.origin += scope.axes.col(i) * ((scope.size[i] - size[i]) / 2.0);
    }
    scope.size = size;
    Ok(())
}

/// The uvs `primitiveQuad()` brings: uv set 0 running from 0 to 1 across the quad, u along
/// scope x and v along scope y, as CityEngine gives its primitives. (The cube brings its
/// faces' uvs as an asset's, see [`cube_look`]; the round primitives, whose every face shows
/// the whole texture in CityEngine, bring none yet.)
fn quad_uvs(state: &mut State) {
    let scope = &state.scope;
    if scope.size.x == 0.0 || scope.size.y == 0.0 {
        return;
    }
    let (u, v) = (scope.axes.col(0), scope.axes.col(1));
    let frame = ProjectionFrame {
        origin: scope.origin,
        u,
        v,
        w: u.cross(v),
        uw_factor: 0.0,
    };
    let map = UvMap::projection(&frame, scope.size.x, scope.size.y, DVec2::ZERO);
    texturing_mut(state).uvs[0] = Some(map);
}

/// The look of CityEngine's built-in cube (`primitiveCube()`, `i("builtin:cube")`): uv set 0
/// covering every face from 0 to 1, u along the face's first edge (its bottom edge on the
/// sides) and v across it, so each face shows the whole texture upright; no material of its
/// own. `builtin:cube:notex` has none.
fn cube_look() -> &'static Arc<AssetLook> {
    static LOOK: std::sync::OnceLock<Arc<AssetLook>> = std::sync::OnceLock::new();
    LOOK.get_or_init(|| {
        let cube = primitives::cuboid(DVec3::ONE);
        let corners = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let faces: Vec<Part> = (0..cube.face_count())
            .map(|f| {
                let points: Vec<DVec3> = cube.face_points(f).collect();
                let face = Mesh::from_faces(points, [[0u32, 1, 2, 3]]);
                Part {
                    uvs: corners.to_vec(),
                    ..Part::new(String::new(), Default::default(), face, Vec::new())
                }
            })
            .collect();
        AssetLook::from_parts(&faces)
            .1
            .expect("the cube's faces have uvs")
    })
}

/// Cuts the shape's geometry at its trim planes (see [`crate::trim`]), as inserts do and CGA's
/// `trim()`; what nothing is left of keeps no geometry. A plane cuts what lies along its edge,
/// give or take the shape's largest size.
pub(super) fn trim(state: &mut State) {
    if !state.trim.cuts() {
        return;
    }
    let Some(world) = state.geometry.world_mesh(&state.scope) else {
        return;
    };
    let reach = state.scope.size.abs().max_element();
    if let Some(mut cut) = state.trim.cut(&world, reach) {
        // What is left of a face keeps its tags (inserts drop them anyway).
        let tags = state
            .geometry
            .tags()
            .and_then(|tags| crate::tags::carry(&world, tags, &cut));
        state.geometry = if cut.is_empty() {
            Geometry::Empty
        } else {
            cut.transform(&state.scope.world_to_local());
            Geometry::Mesh(Arc::new(cut), tags)
        };
    }
}

/// Where the coordinates of `asset` are in the world once placed: its box onto the box of the
/// shape's geometry, axis by axis (every placement stretches, scales or keeps it along the
/// scope's axes).
fn placed(state: &State, asset: &Mesh) -> DAffine3 {
    let (Some(from), Geometry::Mesh(local, _)) = (asset.bounds(), &state.geometry) else {
        return state.scope.local_to_world();
    };
    let Some(to) = local.bounds() else {
        return state.scope.local_to_world();
    };
    let (from_size, to_size) = (from.size(), to.size());
    let scale = DVec3::from_array(std::array::from_fn(|i| {
        if from_size[i] > 0.0 {
            to_size[i] / from_size[i]
        } else {
            1.0
        }
    }));
    let fit = DAffine3::from_scale(scale);
    let fit = DAffine3::from_translation(to.min - fit.transform_point3(from.min)) * fit;
    state.scope.local_to_world() * fit
}

/// CGA's built-in assets, each filling the unit box.
pub(crate) fn builtin_asset(path: &str) -> Option<Mesh> {
    let name = path.strip_prefix("builtin:")?;
    let name = name.split(':').next().unwrap_or(name);
    Some(match name {
        "cube" => primitives::cuboid(DVec3::ONE),
        "cylinder" => primitives::cylinder(DVec3::ONE, 32),
        "cone" => primitives::cone(DVec3::ONE, 32),
        "sphere" => primitives::sphere(DVec3::ONE, 32, 16),
        "pyramid" => primitives::pyramid(DVec3::ONE),
        "quad" => box_mesh(DVec3::new(1.0, 1.0, 0.0))?,
        _ => return None,
    })
}

/// Places an asset as `i()`'s mode says: `alignSizeAndPosition` fits it to the scope
/// ([`fit_asset`]); `keepSizeAndPosition` fits it to a scope of size zero, so it keeps its size
/// and its place relative to the scope's origin; `keepSizeAlignPosition` gives the scope the
/// asset's size, centred where the scope was in x and z, on its floor. The scope keeps the
/// asset's box in both keeping modes.
fn place(state: &mut State, asset: &Asset, fit: InsertFit) {
    let bounds = asset.mesh.bounds().filter(|_| !asset.mesh.is_empty());
    match (fit, bounds) {
        (InsertFit::Align, _) | (_, None) => {}
        (InsertFit::Keep, Some(_)) => state.scope.size = DVec3::ZERO,
        (InsertFit::KeepSize, Some(bounds)) => {
            let size = bounds.size();
            let scope = &mut state.scope;
            let centred = DVec3::new(
                (scope.size.x - size.x) / 2.0,
                0.0,
                (scope.size.z - size.z) / 2.0,
            );
            scope.origin = scope.to_world(centred);
            scope.size = size;
        }
    }
    let asset = match fit {
        InsertFit::Align => asset,
        // The keeping modes place the asset as it is, seeded or not.
        _ => &Asset {
            proportional: false,
            ..asset.clone()
        },
    };
    fit_asset(state, asset);
}

/// Fits an asset into the scope (CGA `i`, see `shapegram_geom::fit`): stretched, after a scope
/// with zero sizes took sizes by CGA's rules ([`adapt_scope_to_asset`]); or keeping its
/// proportions, the scope then taking the asset's fitted extent along axes where it has none.
fn fit_asset(state: &mut State, asset: &Asset) {
    let Some(bounds) = asset.mesh.bounds().filter(|_| !asset.mesh.is_empty()) else {
        state.geometry = Geometry::Empty;
        return;
    };
    let mut local = if asset.proportional {
        shapegram_geom::fit::fit_proportionally_into_scope(&asset.mesh, &state.scope)
    } else {
        adapt_scope_to_asset(&mut state.scope, &bounds);
        shapegram_geom::fit::fit_into_scope(&asset.mesh, &state.scope)
    };
    local.transform(&state.scope.world_to_local());
    if let Some(bounds) = local.bounds() {
        let size = &mut state.scope.size;
        for i in 0..3 {
            if size[i] == 0.0 {
                size[i] = bounds.max[i];
            }
        }
    }
    state.geometry = Geometry::mesh(local);
}
