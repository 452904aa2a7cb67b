//! `GrammarInstance3D`: the node that shows a `GrammarState` in a scene.

use godot::classes::{IMeshInstance3D, Mesh, MeshInstance3D};
use godot::obj::EngineBitfield;
use godot::prelude::*;
use godot::register::info::{PropertyInfo, PropertyUsageFlags};

use crate::mesh::GrammarMesh;
use crate::state::GrammarState;

/// A mesh instance showing a `GrammarState`: setting the state gives the node a `GrammarMesh`
/// that follows it. It can be moved, turned and scaled like any `MeshInstance3D`.
#[derive(GodotClass)]
#[class(tool, init, base = MeshInstance3D)]
pub struct GrammarInstance3D {
    /// The state whose derivations the node shows.
    #[export]
    #[var(set)]
    grammar_state: Option<Gd<GrammarState>>,
    base: Base<MeshInstance3D>,
}

#[godot_api]
impl IMeshInstance3D for GrammarInstance3D {
    /// The mesh is made from the state: a saved scene keeps the state, not its triangles.
    fn on_validate_property(&self, property: &mut PropertyInfo) {
        if property.property_name == "mesh" {
            let usage = property.usage.ord() & !PropertyUsageFlags::STORAGE.ord();
            property.usage = PropertyUsageFlags::from_ord(usage);
        }
    }
}

#[godot_api]
impl GrammarInstance3D {
    /// Shows `state` through a new `GrammarMesh` (no mesh without a state).
    #[func]
    pub fn set_grammar_state(&mut self, state: Option<Gd<GrammarState>>) {
        self.grammar_state = state.clone();
        let mesh = state.map(|state| {
            let mut mesh = GrammarMesh::new_gd();
            mesh.bind_mut().set_state(Some(state));
            mesh.upcast::<Mesh>()
        });
        self.base_mut().set_mesh(mesh.as_ref());
    }

    /// The `GrammarMesh` the node shows, if it shows one.
    #[func]
    pub fn grammar_mesh(&self) -> Option<Gd<GrammarMesh>> {
        self.base()
            .get_mesh()
            .and_then(|mesh| mesh.try_cast::<GrammarMesh>().ok())
    }
}
