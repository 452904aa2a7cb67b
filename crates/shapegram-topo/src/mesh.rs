//! Triangle meshes of a grammar state (thesis 3.2.3): faces fan-triangulated (they are convex),
//! flat normals from the face corners, one coloured part per symbol and per material of its
//! faces, with tiled planar texture coordinates on faces that have a material.

use std::sync::Arc;

use shapegram_geom::{Color, DVec2, DVec3, Mesh, Model, Part, Texture};

use crate::grammar::Grammar;
use crate::interpret::{GrammarState, ShapeList};
use crate::material::{Material, planar_uv};
use crate::polyhedron::Index;

/// Faces whose area is below this times the square of their longest corner distance are skipped,
/// so no degenerate triangle reaches an exporter.
const MIN_RELATIVE_AREA: f64 = 1e-12;

/// The triangles of every shape of one symbol (of one colour).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshPart {
    /// The symbol.
    pub symbol: Index,
    /// Its name (`terminal` for anonymous terminals).
    pub name: String,
    /// Its colour.
    pub color: Color,
    /// Corner positions, three or more per face (faces share no vertex, for flat shading).
    pub positions: Vec<DVec3>,
    /// The face normal at each corner.
    pub normals: Vec<DVec3>,
    /// Triangles as corner indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// The material of its faces (an index into [`GrammarMesh::materials`]); `None` for faces
    /// coloured by their symbol.
    pub material: Option<Index>,
    /// Texture coordinates, one per corner, in tiles of the material (see
    /// [`crate::planar_uv`]); empty without a material.
    pub uvs: Vec<DVec2>,
}

/// The triangle mesh of a grammar state: one part per symbol with shapes (and per face colour
/// of it), in symbol order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GrammarMesh {
    /// The parts.
    pub parts: Vec<MeshPart>,
    /// The grammar's materials, which parts name by index.
    pub materials: Vec<Material>,
}

impl GrammarMesh {
    /// Meshes the terminal and the non-terminal shapes of `state`.
    pub fn new(state: &GrammarState<'_>) -> Self {
        Self::from_lists(state.grammar(), [state.terminals(), state.non_terminals()])
    }

    /// Meshes the shapes of `lists`, which must come from `grammar`. Faces with a colour of
    /// their own go to a part of that colour (named after the symbol too).
    pub fn from_lists<'a>(
        grammar: &Grammar,
        lists: impl IntoIterator<Item = &'a ShapeList>,
    ) -> Self {
        // Per symbol, its parts: the symbol's colour first, then face colours as met.
        let mut by_symbol: Vec<Vec<MeshPart>> = vec![Vec::new(); grammar.symbols.len()];
        for list in lists {
            for i in 0..list.len() {
                let symbol = list.symbol(i);
                let entry = &grammar.symbols[symbol as usize];
                let parts = &mut by_symbol[symbol as usize];
                let vertices = list.vertices(i);
                let materials = list.face_materials(i);
                for (f, face) in entry.faces.iter().enumerate() {
                    let material = materials.get(f).copied().flatten();
                    let color = match material {
                        Some(m) => grammar.materials[m as usize].surface_color(),
                        None => entry
                            .face_colors
                            .get(f)
                            .copied()
                            .flatten()
                            .or(entry.color)
                            .unwrap_or_default(),
                    };
                    let found = parts
                        .iter()
                        .position(|p| p.color == color && p.material == material);
                    let k = match found {
                        Some(k) => k,
                        None => {
                            parts.push(MeshPart {
                                symbol,
                                name: grammar.display_name(symbol).to_owned(),
                                color,
                                material,
                                ..MeshPart::default()
                            });
                            parts.len() - 1
                        }
                    };
                    let tile = material.map(|m| grammar.materials[m as usize].tile);
                    parts[k].add_face(face.iter().map(|&v| vertices[v as usize]), tile);
                }
            }
        }
        Self {
            parts: by_symbol.into_iter().flatten().collect(),
            materials: grammar.materials.clone(),
        }
    }

    /// Number of triangles over all parts.
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.triangles.len()).sum()
    }

    /// The mesh as a model for the exporters (GLB, OBJ, STL): one part per symbol and
    /// material, textures without their images (see [`GrammarMesh::to_model_with`]).
    pub fn to_model(&self) -> Model {
        self.to_model_with(|_| None)
    }

    /// The mesh as a model, each texture's image read by `image` from its path (as the
    /// material names it); a texture without an image is drawn in its material's colour.
    pub fn to_model_with(&self, mut image: impl FnMut(&str) -> Option<Arc<[u8]>>) -> Model {
        let textures: Vec<Option<Arc<Texture>>> = self
            .materials
            .iter()
            .map(|m| m.texture_with(&mut image))
            .collect();
        let names: Vec<Arc<str>> = self
            .materials
            .iter()
            .map(|m| m.name.as_str().into())
            .collect();
        Model {
            skeletons: Vec::new(),
            parts: self
                .parts
                .iter()
                .filter(|p| !p.triangles.is_empty())
                .map(|p| {
                    let material = p.material.map(|m| m as usize);
                    Part {
                        texture: material.and_then(|m| textures[m].clone()),
                        uvs: p.uvs.clone(),
                        bone: None,
                        metadata: None,
                        name: p.name.clone(),
                        color: p.color,
                        mesh: Mesh::from_faces(p.positions.clone(), &p.triangles),
                        normals: Vec::new(),
                        material: material.map(|m| names[m].clone()),
                        surface: None,
                        instance: None,
                    }
                })
                .collect(),
            lines: Vec::new(),
        }
    }
}

impl MeshPart {
    /// Appends one convex face as a triangle fan, unless it has no area; with a material's
    /// `tile`, its corners get planar texture coordinates.
    fn add_face(&mut self, corners: impl Iterator<Item = DVec3> + Clone, tile: Option<DVec2>) {
        let mut points = corners.clone();
        let Some(first) = points.next() else {
            return;
        };
        let mut area = DVec3::ZERO;
        let mut reach: f64 = 0.0;
        let mut previous = DVec3::ZERO;
        for p in points {
            let p = p - first;
            area += previous.cross(p);
            reach = reach.max(p.length_squared());
            previous = p;
        }
        // Written so that NaN and infinity (from overflowing coordinates) also skip the face.
        let has_area = area.is_finite() && area.length() > MIN_RELATIVE_AREA * reach;
        if !has_area {
            return;
        }
        let normal = area.normalize();
        let base = self.positions.len() as u32;
        for p in corners {
            self.positions.push(p);
            self.normals.push(normal);
            if let Some(tile) = tile {
                self.uvs.push(planar_uv(p, normal, tile));
            }
        }
        let end = self.positions.len() as u32;
        for k in base + 1..end - 1 {
            let (a, b, c) = (
                self.positions[base as usize],
                self.positions[k as usize],
                self.positions[k as usize + 1],
            );
            if (b - a).cross(c - a).length() > MIN_RELATIVE_AREA * reach {
                self.triangles.push([base, k, k + 1]);
            }
        }
    }
}
