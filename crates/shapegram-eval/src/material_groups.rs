//! The faces of a shape's geometry grouped by the material they wear, for CGA's `comp(m)` and
//! `geometry.materials`: the materials of an inserted asset in the asset's order (each face of
//! a piece cut from the asset wearing the material of the asset face under it), then the faces
//! that wear the shape's own material, named by `set(material.name, …)` (`""` when unset). A
//! shape without an asset wears one material.

use std::collections::BTreeMap;
use std::sync::Arc;

use shapegram_geom::Mesh;

use crate::asset_look::NO_MATERIAL;
use crate::shape::State;

/// The material groups of `state`'s geometry, whose world mesh is `world`: each material's
/// name and its faces (indices into `world`), in order.
pub(crate) fn material_groups(state: &State, world: &Mesh) -> Vec<(Arc<str>, Vec<usize>)> {
    let own = state.material.clone().unwrap_or_else(|| Arc::from(""));
    let worn = state.texturing.as_ref().and_then(|t| t.asset.as_ref());
    let Some(worn) = worn else {
        let all: Vec<usize> = (0..world.face_count()).collect();
        return if all.is_empty() {
            Vec::new()
        } else {
            vec![(own, all)]
        };
    };
    let local = state.geometry.local_mesh(state.scope.size);
    let dressed = worn.dress(world.clone(), local.as_ref());
    let mut by_material: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (f, &m) in dressed.face_materials.iter().enumerate() {
        by_material.entry(m).or_default().push(f);
    }
    by_material
        .into_iter()
        .map(|(m, faces)| {
            let name = (m != NO_MATERIAL)
                .then(|| worn.look.material_name(m).cloned())
                .flatten()
                .unwrap_or_else(|| own.clone());
            (name, faces)
        })
        .collect()
}
