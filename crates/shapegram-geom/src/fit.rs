//! Placing assets into scopes (CGA `i()`).
//!
//! [`fit_into_scope`] stretches an asset's bounding box onto a scope's box, with CGA's rules for
//! scopes that are flat along some axes:
//! - a scope size of zero along an axis (a flat or line-like scope) scales the asset along that
//!   axis by the mean of the scale factors of the other axes, so the asset keeps its proportions
//!   there: a line-like scope scales the asset uniformly to its one length;
//! - a scope of size zero along all three axes keeps the asset as it is, its own coordinates read
//!   as scope-local coordinates (CGA's point-like scope);
//! - an asset that is flat along an axis where the scope is not stays flat there, at the scope's
//!   origin side, instead of dividing by zero.
//!
//! [`fit_proportionally_into_scope`] keeps the asset's proportions instead (planted L-systems):
//! scaled uniformly to fit inside the scope, centred in x and z, standing on the scope's floor.
//!
//! Sizes count as zero below 10⁻⁹ of the largest size, so scopes fitted around flat faces (whose
//! depth is rounding noise) count as flat. Negative scope sizes mirror the asset (CGA `s(-1, …)`),
//! with face loops reversed so normals keep pointing outward.

use crate::{Aabb, DAffine3, DVec3, Mesh, RELATIVE_EPSILON, Scope};

/// CGA `i()`: the asset scaled per axis so its bounding box fills the scope, its bounding box's
/// minimum corner at the scope's origin, in the scope's axes. See the module docs for flat scopes
/// and flat assets. An empty mesh is returned unchanged.
pub fn fit_into_scope(mesh: &Mesh, scope: &Scope) -> Mesh {
    let Some(bounds) = mesh.bounds() else {
        return mesh.clone();
    };
    let target = scope.size;
    let asset = bounds.size();
    let zero = |size: DVec3, k: usize| size[k].abs() <= RELATIVE_EPSILON * size.abs().max_element();
    let scope_zero: [bool; 3] = std::array::from_fn(|k| zero(target, k));
    if scope_zero.iter().all(|&z| z) {
        return mesh_in_scope(mesh, scope);
    }
    let stretched: [Option<f64>; 3] =
        std::array::from_fn(|k| (!scope_zero[k] && !zero(asset, k)).then(|| target[k] / asset[k]));
    let defined: Vec<f64> = stretched.iter().flatten().map(|f| f.abs()).collect();
    let mean = if defined.is_empty() {
        1.0
    } else {
        defined.iter().sum::<f64>() / defined.len() as f64
    };
    let factors = DVec3::from_array(std::array::from_fn(|k| match stretched[k] {
        Some(f) => f,
        None if scope_zero[k] => mean,
        // A flat asset along an axis the scope spans: nothing to stretch.
        None => 1.0,
    }));
    let map = scope.local_to_world()
        * DAffine3::from_scale(factors)
        * DAffine3::from_translation(-bounds.min);
    mesh.transformed(&map)
}

/// A mesh given in a scope's local coordinates, placed in world coordinates (no scaling).
pub fn mesh_in_scope(mesh: &Mesh, scope: &Scope) -> Mesh {
    mesh.transformed(&scope.local_to_world())
}

/// CGA's rules for inserting into a scope with zero sizes: the scope takes sizes (and may move)
/// before the asset is fitted, and keeps them for later operations. With `bounds` the asset's
/// box (size `a`, minimum corner `m`, in its own coordinates):
/// - every size zero: the scope takes the asset's size and moves by `m`, so the asset lands
///   unchanged relative to the scope's origin;
/// - two sizes zero: one factor `f`, the other size over the asset's along it; the zero sizes
///   become `f·a` and the scope moves by `f·m` along them (the asset scales uniformly, keeping
///   its offset from the origin);
/// - one size zero: it becomes the mean of the other two axes' factors times the asset's size
///   along it; the scope stays where it is.
///
/// Axes along which the asset is flat too keep size zero. A scope without zero sizes is left
/// as it is.
pub fn adapt_scope_to_asset(scope: &mut Scope, bounds: &Aabb) {
    let (a, m) = (bounds.size(), bounds.min);
    let zero: [bool; 3] = std::array::from_fn(|k| {
        scope.size[k].abs() <= RELATIVE_EPSILON * scope.size.abs().max_element()
    });
    let factor = |k: usize| (a[k] > 0.0).then(|| scope.size[k] / a[k]);
    let (size, shift) = match zero.iter().filter(|&&z| z).count() {
        0 => return,
        3 => (a, m),
        2 => {
            let k = zero.iter().position(|&z| !z).expect("one size is not zero");
            let f = factor(k).unwrap_or(1.0);
            let flat = |v: DVec3| {
                DVec3::from_array(std::array::from_fn(
                    |i| {
                        if zero[i] { f * v[i] } else { 0.0 }
                    },
                ))
            };
            (
                flat(a) + DVec3::select(zero.map(|z| !z).into(), scope.size, DVec3::ZERO),
                flat(m),
            )
        }
        _ => {
            let k = zero.iter().position(|&z| z).expect("one size is zero");
            let factors: Vec<f64> = (0..3).filter(|&i| i != k).filter_map(factor).collect();
            let mean = if factors.is_empty() {
                1.0
            } else {
                factors.iter().sum::<f64>() / factors.len() as f64
            };
            let mut size = scope.size;
            size[k] = mean * a[k];
            (size, DVec3::ZERO)
        }
    };
    scope.origin = scope.to_world(shift);
    scope.size = size;
}

/// The map that scales a box of `bounds` uniformly (keeping its proportions) to fit the box from
/// the origin to `size`, centred in x and z and standing on y = 0. Axes where either box is flat
/// do not limit the scale; when every axis is flat the scale is 1.
pub fn proportional_map(bounds: &Aabb, size: DVec3) -> DAffine3 {
    let extent = bounds.size();
    let tiny = 1e-12 * extent.max_element().max(size.max_element());
    let scale = (0..3)
        .filter(|&k| size[k] > tiny && extent[k] > tiny)
        .map(|k| size[k] / extent[k])
        .reduce(f64::min)
        .unwrap_or(1.0);
    let offset = DVec3::new(
        (size.x - extent.x * scale) / 2.0,
        0.0,
        (size.z - extent.z * scale) / 2.0,
    );
    DAffine3::from_translation(offset)
        * DAffine3::from_scale(DVec3::splat(scale))
        * DAffine3::from_translation(-bounds.min)
}

/// The asset scaled uniformly to fit inside the scope (see [`proportional_map`]) and placed in
/// world space with the scope's origin and axes. An empty mesh is returned unchanged.
pub fn fit_proportionally_into_scope(mesh: &Mesh, scope: &Scope) -> Mesh {
    let Some(bounds) = mesh.bounds() else {
        return mesh.clone();
    };
    mesh.transformed(&(scope.local_to_world() * proportional_map(&bounds, scope.size)))
}
