//! What an inserted asset wears: its materials (CGA's *geometry* material) and its own uv set 0,
//! and how a shape's material attributes override them, as CityEngine has it.
//!
//! An asset's parts keep their materials (name, colour, opacity, colour map and the other layers
//! and attributes) per face, and its uvs per vertex. When the model is made, each material of an
//! asset a leaf holds becomes a piece of its own, wearing, attribute by attribute, what the
//! grammar set on the shape (before or after `i()`), else the asset's: the colour when the
//! grammar set one (`color()`, `set(material.color…)`), the opacity when the grammar made it
//! less than 1, the name, the colour map and each other layer and attribute when set. uv set 0
//! is the asset's until `projectUV(0)` replaces it.
//!
//! The look follows the asset through moves, scales and turns of the shape, and through cuts
//! (splits, component splits, trim planes): a cut piece's faces wear the material of the asset
//! face under them and its uvs there (see [`crate::asset_faces`]); faces on none of the asset's
//! (the caps of an extrusion, say) wear the shape's material.

use std::sync::Arc;

use shapegram_geom::{Color, DAffine3, DVec2, Mesh, Part, Surface, Texture};

use crate::asset_faces::Dressed;

use crate::texturing::COLORMAP;

/// The material index of a face on none of the asset's faces: it wears the shape's material.
pub const NO_MATERIAL: u32 = u32::MAX;

/// The materials and uvs an inserted asset brings.
#[derive(Clone, Debug, PartialEq)]
pub struct AssetLook {
    /// The asset's mesh as loaded: a shape keeps the look while its geometry has these faces.
    faces: Arc<Mesh>,
    /// The material of each face, as an index into `materials`.
    face_materials: Vec<u32>,
    /// The materials of the asset's parts.
    materials: Vec<AssetMaterial>,
    /// uv set 0, one per vertex; empty unless every part has uvs.
    uvs: Vec<DVec2>,
}

/// The material of a part of an asset.
#[derive(Clone, Debug, PartialEq)]
pub struct AssetMaterial {
    /// The material's name; `None` for a part without a material, which wears the shape's.
    pub name: Option<Arc<str>>,
    /// Colour and opacity.
    pub color: Color,
    /// The colour map.
    pub texture: Option<Arc<Texture>>,
    /// The other attributes and layers.
    pub surface: Option<Arc<Surface>>,
}

/// An asset's look as a shape wears it: the look, and what uv edits (`tileUV(0, …)` and the
/// others) made of the asset's uv set 0 since the insert.
#[derive(Clone, Debug, PartialEq)]
pub struct WornAsset {
    /// The asset's look.
    pub look: Arc<AssetLook>,
    /// uv set 0 as `m · uv + t` of the asset's own uvs; `None` once `deleteUV(0)` removed it.
    pub uv_edit: Option<UvAffine>,
    /// Where the asset's coordinates are in the world, following the shape's geometry as it
    /// moves: what cut pieces of the asset are looked up by.
    pub placed: DAffine3,
}

/// An affine change of uvs: `(u, v) → (m00 u + m01 v + t0, m10 u + m11 v + t1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvAffine {
    /// The linear part.
    pub m: [[f64; 2]; 2],
    /// The shift.
    pub t: DVec2,
}

impl UvAffine {
    /// No change.
    pub const IDENTITY: Self = Self {
        m: [[1.0, 0.0], [0.0, 1.0]],
        t: DVec2::ZERO,
    };

    /// The uv changed.
    pub fn at(&self, uv: DVec2) -> DVec2 {
        DVec2::new(
            self.m[0][0] * uv.x + self.m[0][1] * uv.y + self.t.x,
            self.m[1][0] * uv.x + self.m[1][1] * uv.y + self.t.y,
        )
    }

    /// `self` followed by `next`.
    pub fn then(&self, next: &UvAffine) -> UvAffine {
        let (a, b) = (next.m, self.m);
        let m =
            std::array::from_fn(|i| std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j]));
        UvAffine {
            m,
            t: next.at(self.t),
        }
    }
}

impl WornAsset {
    /// A freshly inserted asset's look, the asset placed in the world by `placed`.
    pub fn new(look: Arc<AssetLook>, placed: DAffine3) -> Self {
        Self {
            look,
            uv_edit: Some(UvAffine::IDENTITY),
            placed,
        }
    }

    /// The world-space `mesh` of a shape wearing the asset dressed in it: as the asset's own
    /// faces when it still has them (`local`, its scope-local geometry, tells), else each face
    /// as the asset face under it.
    pub(crate) fn dress(&self, mesh: Mesh, local: Option<&Mesh>) -> Dressed {
        let uvs = self.uvs();
        if local.is_some_and(|local| self.look.fits(local)) {
            return Dressed {
                mesh,
                face_materials: self.look.face_materials.clone(),
                uvs,
            };
        }
        crate::asset_faces::dress(
            &mesh,
            &self.look.faces,
            &self.placed,
            &self.look.face_materials,
            uvs.as_deref(),
        )
    }

    /// uv set 0 at each vertex of the asset, when it has one.
    pub fn uvs(&self) -> Option<Vec<DVec2>> {
        let edit = self.uv_edit.filter(|_| !self.look.uvs.is_empty())?;
        Some(self.look.uvs.iter().map(|&uv| edit.at(uv)).collect())
    }

    /// The smallest and largest of uv set 0 over `mesh` (the shape's geometry in world space,
    /// `local` its scope-local mesh when it has one), dressed from the asset as the model draws
    /// it, and how fast u and v grow per metre on its largest face that lies on the asset;
    /// `None` without uvs or without a face on the asset.
    pub(crate) fn uv_extent(
        &self,
        mesh: Mesh,
        local: Option<&Mesh>,
    ) -> Option<((DVec2, DVec2), DVec2)> {
        let Dressed {
            mesh,
            face_materials,
            uvs,
        } = self.dress(mesh, local);
        let uvs = uvs?;
        // Faces on none of the asset's faces have no uvs of the asset.
        let on_asset: Vec<usize> = (0..mesh.face_count())
            .filter(|&f| face_materials[f] != NO_MATERIAL)
            .collect();
        let corners = on_asset.iter().flat_map(|&f| mesh.face(f).iter());
        let (low, high) = corners.fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(low, high), &v| (low.min(uvs[v as usize]), high.max(uvs[v as usize])),
        );
        let largest = on_asset
            .iter()
            .copied()
            .max_by(|&a, &b| mesh.face_area(a).total_cmp(&mesh.face_area(b)))?;
        let face = mesh.face(largest);
        let rates = (face.len() >= 3)
            .then(|| surface_rates(&mesh, &uvs, [face[0], face[1], face[2]]))
            .flatten()
            .unwrap_or(DVec2::ZERO);
        low.is_finite().then_some(((low, high), rates))
    }
}

/// How fast u and v grow per metre on triangle `corners` of `mesh` (the lengths of their
/// gradients in its plane); `None` for a degenerate triangle.
fn surface_rates(mesh: &Mesh, uvs: &[DVec2], corners: [u32; 3]) -> Option<DVec2> {
    let [a, b, c] = corners.map(|v| (mesh.position(v), uvs[v as usize]));
    let (e1, e2) = (b.0 - a.0, c.0 - a.0);
    let (d1, d2) = (b.1 - a.1, c.1 - a.1);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if det.abs() <= f64::EPSILON * g11 * g22 {
        return None;
    }
    // The gradient x e1 + y e2 whose dot products with the edges are the uv differences.
    let gradient = |d1: f64, d2: f64| {
        let x = (d1 * g22 - d2 * g12) / det;
        let y = (d2 * g11 - d1 * g12) / det;
        (e1 * x + e2 * y).length()
    };
    Some(DVec2::new(gradient(d1.x, d2.x), gradient(d1.y, d2.y)))
}

impl AssetLook {
    /// The material of the asset's first part that has one (`getMaterial(geometry, …)`).
    pub fn first_material(&self) -> Option<&AssetMaterial> {
        self.materials.iter().find(|m| m.name.is_some())
    }

    /// An asset's parts merged into one mesh (the geometry `i()` places), and their look when
    /// some part has a material or uvs: without, the asset wears the shape's material alone.
    pub fn from_parts(parts: &[Part]) -> (Mesh, Option<Arc<AssetLook>>) {
        let mut mesh = Mesh::new();
        let mut face_materials = Vec::new();
        let mut materials: Vec<AssetMaterial> = Vec::new();
        let all_uvs = parts.iter().all(|p| p.uvs.len() == p.mesh.vertex_count());
        let mut uvs = Vec::new();
        for part in parts {
            let material = AssetMaterial {
                name: part.material.clone(),
                color: part.color,
                texture: part.texture.clone(),
                surface: part.surface.clone(),
            };
            let index = match materials.iter().position(|m| *m == material) {
                Some(i) => i,
                None => {
                    materials.push(material);
                    materials.len() - 1
                }
            };
            mesh.append(&part.mesh);
            face_materials.resize(mesh.face_count(), index as u32);
            if all_uvs {
                uvs.extend_from_slice(&part.uvs);
            }
        }
        let worn = materials.iter().any(|m| m.name.is_some()) || !uvs.is_empty();
        let look = worn.then(|| {
            Arc::new(AssetLook {
                faces: Arc::new(mesh.clone()),
                face_materials,
                materials,
                uvs,
            })
        });
        (mesh, look)
    }

    /// Whether some part of the asset has a material of its own.
    pub fn has_materials(&self) -> bool {
        self.materials.iter().any(|m| m.name.is_some())
    }

    /// A look for `faces` made by the engine rather than loaded: each face wears the material
    /// `face_materials` gives it, an index into `materials` or [`NO_MATERIAL`]; no uvs.
    pub(crate) fn of_faces(
        faces: Mesh,
        face_materials: Vec<u32>,
        materials: Vec<AssetMaterial>,
    ) -> Self {
        Self {
            faces: Arc::new(faces),
            face_materials,
            materials,
            uvs: Vec::new(),
        }
    }

    /// The name of material `i` of the asset (`None` for a part without a material).
    pub fn material_name(&self, i: u32) -> Option<&Arc<str>> {
        self.materials.get(i as usize)?.name.as_ref()
    }

    /// Whether `mesh` still has the asset's faces (however placed), so the look applies.
    pub fn fits(&self, mesh: &Mesh) -> bool {
        mesh.vertex_count() == self.faces.vertex_count()
            && mesh.face_count() == self.faces.face_count()
            && mesh.faces().eq(self.faces.faces())
    }
}

/// A piece of a leaf as the model draws it: geometry and what it wears.
pub(crate) struct Piece {
    /// World-space geometry.
    pub mesh: Mesh,
    /// Colour and opacity.
    pub color: Color,
    /// The colour map (only with `uvs`).
    pub colormap: Option<Arc<Texture>>,
    /// The material's name.
    pub material: Option<Arc<str>>,
    /// The other attributes and layers (boxed: most pieces have none, and pieces are moved
    /// about once per leaf).
    pub surface: Option<Box<Surface>>,
    /// uv set 0, one per vertex of `mesh`, when something is drawn through it.
    pub uvs: Option<Vec<DVec2>>,
}

/// The shape's own material, as a leaf wears it without an asset's look.
pub(crate) struct ShapeMaterial<'a> {
    /// Colour and opacity.
    pub color: Color,
    /// Whether the grammar set the colour.
    pub painted: bool,
    /// The material name the grammar set.
    pub material: Option<&'a Arc<str>>,
    /// The shape's texturing state.
    pub texturing: Option<&'a crate::texturing::Texturing>,
}

impl ShapeMaterial<'_> {
    /// The leaf's world mesh `mesh` as one piece in the shape's material.
    pub fn piece(&self, mesh: Mesh) -> Piece {
        // Texture layers count only with uvs to place them, as in CityEngine.
        let uv_map = self.texturing.and_then(|t| t.drawn_uvs());
        let colormap = uv_map
            .and(self.texturing)
            .and_then(|t| t.maps[COLORMAP].clone());
        let surface = self
            .texturing
            .and_then(|t| t.surface(uv_map.is_some()))
            .map(Box::new);
        let uvs = uv_map.map(|map| mesh.positions().iter().map(|&p| map.at(p)).collect());
        Piece {
            mesh,
            color: self.color,
            colormap,
            material: self.material.cloned(),
            surface,
            uvs,
        }
    }

    /// The leaf's world mesh `mesh`, which has the faces of `look`'s asset, as one piece per
    /// material of the asset (in the asset's order, those with faces), each wearing the
    /// shape's attributes over the asset's.
    pub fn pieces(&self, dressed: Dressed, look: &AssetLook) -> Vec<Piece> {
        let Dressed {
            mesh,
            face_materials,
            uvs,
        } = dressed;
        let projected = self.texturing.and_then(|t| t.uvs[0].as_ref());
        let uvs: Option<Vec<DVec2>> = match projected {
            Some(map) => Some(mesh.positions().iter().map(|&p| map.at(p)).collect()),
            None => uvs,
        };
        let mesh = &mesh;
        let drawn = uvs.is_some();
        let shape_surface = self.texturing.and_then(|t| t.surface(drawn));
        let shape_map = self.texturing.and_then(|t| t.maps[COLORMAP].clone());
        let mut pieces = Vec::new();
        let none = AssetMaterial {
            name: None,
            color: self.color,
            texture: None,
            surface: None,
        };
        let materials = look.materials.iter().chain(std::iter::once(&none));
        for (index, asset) in materials.enumerate() {
            let index = if asset == &none && index == look.materials.len() {
                NO_MATERIAL
            } else {
                index as u32
            };
            let faces = (0..mesh.face_count()).filter(|&f| face_materials[f] == index);
            let Some((piece_mesh, piece_uvs)) = submesh(mesh, faces, uvs.as_deref()) else {
                continue;
            };
            if asset.name.is_none() {
                pieces.push(Piece {
                    mesh: piece_mesh,
                    color: self.color,
                    colormap: shape_map.clone().filter(|_| drawn),
                    material: self.material.cloned(),
                    surface: shape_surface.clone().map(Box::new),
                    uvs: piece_uvs,
                });
                continue;
            }
            let rgb = if self.painted {
                self.color
            } else {
                asset.color
            };
            let color = Color {
                a: if self.color.a < 1.0 {
                    self.color.a
                } else {
                    asset.color.a
                },
                ..rgb
            };
            let asset_surface = asset.surface.as_deref().map(|s| Surface {
                finish: s.finish,
                maps: if drawn {
                    s.maps.clone()
                } else {
                    Default::default()
                },
                transforms: if drawn {
                    s.transforms
                } else {
                    Default::default()
                },
            });
            let surface = match (&shape_surface, asset_surface) {
                (Some(shape), Some(asset)) => Some(shape.over(&asset)),
                (shape, asset) => shape.clone().or(asset),
            };
            pieces.push(Piece {
                mesh: piece_mesh,
                color,
                colormap: shape_map
                    .clone()
                    .or_else(|| asset.texture.clone())
                    .filter(|_| drawn),
                material: self.material.cloned().or_else(|| asset.name.clone()),
                surface: surface.map(Box::new),
                uvs: piece_uvs,
            });
        }
        pieces
    }
}

/// The faces `faces` of `mesh` as a mesh of their own, with the uvs of their vertices; `None`
/// when there are none.
fn submesh(
    mesh: &Mesh,
    faces: impl Iterator<Item = usize>,
    uvs: Option<&[DVec2]>,
) -> Option<(Mesh, Option<Vec<DVec2>>)> {
    let mut out = Mesh::new();
    let mut out_uvs = uvs.map(|_| Vec::new());
    let mut slot = vec![u32::MAX; mesh.vertex_count()];
    let mut face = Vec::new();
    for f in faces {
        face.clear();
        for &v in mesh.face(f) {
            let s = &mut slot[v as usize];
            if *s == u32::MAX {
                *s = out.add_vertex(mesh.position(v));
                if let (Some(out_uvs), Some(uvs)) = (&mut out_uvs, uvs) {
                    out_uvs.push(uvs[v as usize]);
                }
            }
            face.push(*s);
        }
        out.add_face(&face);
    }
    (!out.is_empty()).then_some((out, out_uvs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::DVec3;

    #[test]
    fn uv_changes_compose_in_order() {
        let scale = UvAffine {
            m: [[2.0, 0.0], [0.0, 3.0]],
            t: DVec2::ZERO,
        };
        let shift = UvAffine {
            t: DVec2::new(0.5, -1.0),
            ..UvAffine::IDENTITY
        };
        let uv = DVec2::new(1.0, 2.0);
        assert_eq!(scale.then(&shift).at(uv), DVec2::new(2.5, 5.0));
        assert_eq!(shift.then(&scale).at(uv), DVec2::new(3.0, 3.0));
    }

    #[test]
    fn parts_merge_with_a_material_per_face_and_uvs_only_when_all_have_them() {
        let quad = |z: f64| {
            Mesh::from_faces(
                vec![
                    DVec3::new(0.0, 0.0, z),
                    DVec3::new(1.0, 0.0, z),
                    DVec3::new(1.0, 1.0, z),
                    DVec3::new(0.0, 1.0, z),
                ],
                [[0u32, 1, 2, 3]],
            )
        };
        let part = |name: &str, z: f64, uvs: bool| Part {
            material: Some(Arc::from(name)),
            uvs: if uvs {
                vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y]
            } else {
                Vec::new()
            },
            ..Part::new(name.to_owned(), Color::default(), quad(z), Vec::new())
        };
        let parts = [
            part("a", 0.0, true),
            part("b", 1.0, true),
            part("a", 2.0, true),
        ];
        let (mesh, look) = AssetLook::from_parts(&parts);
        let look = look.unwrap();
        assert_eq!(mesh.face_count(), 3);
        assert_eq!(look.face_materials, [0, 1, 0]);
        assert_eq!(look.materials.len(), 2);
        assert_eq!(look.uvs.len(), 12);
        assert!(look.fits(&mesh));
        assert!(!look.fits(&quad(0.0)));
        let (_, look) = AssetLook::from_parts(&[part("a", 0.0, true), part("b", 1.0, false)]);
        assert!(look.unwrap().uvs.is_empty());
        // Neither materials nor uvs: nothing to wear.
        let plain = Part::new("p".to_owned(), Color::default(), quad(0.0), Vec::new());
        assert!(AssetLook::from_parts(&[plain]).1.is_none());
    }
}
