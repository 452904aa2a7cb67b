//! The faces of a shape's geometry in sets, for CGA's `comp(m)`, `comp(g)`,
//! `geometry.materials` and `geometry.groups`.
//!
//! By **material**: the materials of an inserted asset in the asset's order (each face of
//! a piece cut from the asset wearing the material of the asset face under it), then the faces
//! that wear the shape's own material, named by `set(material.name, …)` (`""` when unset). A
//! shape without an asset wears one material.
//!
//! By **group**: the groups of an inserted asset (its OBJ `g`/`o` groups, its glTF nodes), in
//! the order the faces have them, then the faces in none (named `""`), such as the caps of a
//! cut or a shape without an asset. Faces keep their group through cuts (see
//! [`crate::tags::FaceTags`]).

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

/// The asset groups of `state`'s geometry, whose world mesh is `world`: each group's name and
/// its faces (indices into `world`), in order.
pub(crate) fn asset_groups(state: &State, world: &Mesh) -> Vec<(Arc<str>, Vec<usize>)> {
    let tags = state.geometry.tags();
    let mut groups: Vec<(Arc<str>, Vec<usize>)> = Vec::new();
    let mut ungrouped = Vec::new();
    for f in 0..world.face_count() {
        match tags.and_then(|t| t.get(f)).and_then(|t| t.group.as_ref()) {
            Some(name) => match groups.iter_mut().find(|(n, _)| n == name) {
                Some((_, faces)) => faces.push(f),
                None => groups.push((name.clone(), vec![f])),
            },
            None => ungrouped.push(f),
        }
    }
    if !ungrouped.is_empty() {
        groups.push((Arc::from(""), ungrouped));
    }
    groups
}
