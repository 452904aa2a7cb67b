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
//! Sizes count as zero below 10⁻⁹ of the largest size, so scopes fitted around flat faces (whose
//! depth is rounding noise) count as flat. Negative scope sizes mirror the asset (CGA `s(-1, …)`),
//! with face loops reversed so normals keep pointing outward.

use crate::{DAffine3, DVec3, Mesh, RELATIVE_EPSILON, Scope};

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
