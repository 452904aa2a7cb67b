//! A model as the flat arrays a game engine uploads: the triangles the GLB writer writes, with
//! their normals, part after part, and the skeletons' joints with each vertex's joint, so that
//! a host can pose the model as the GLB's skin does.

use std::sync::Arc;

use shapegram_geom::kinematics::{Frame, Skeleton};
use shapegram_geom::{DVec2, DVec3, Model, Texture};

use crate::flat::{drawable, texture_uvs, unit};
use crate::glb::{Chunk, gltf_uv};

/// Where one part of the model is in [`Buffers`], and its colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartRange {
    /// The part's index in the model it came from ([`Model::parts`]; parts without triangles
    /// have no range).
    pub part: usize,
    /// The part's colour: sRGB with straight alpha, each channel in `0..=1`.
    pub color: [f32; 4],
    /// Its first vertex in [`Buffers::positions`] and [`Buffers::normals`].
    pub first_vertex: u32,
    /// How many vertices it has.
    pub vertex_count: u32,
    /// Its first index in [`Buffers::indices`].
    pub first_index: u32,
    /// How many indices it has (three per triangle).
    pub index_count: u32,
    /// Its colour map, as an index into [`Buffers::textures`]; its vertices' uvs are in
    /// [`Buffers::uvs`].
    pub texture: Option<u32>,
}

/// Triangles of a model's parts, as the GLB writer makes them: a flat part gives every face its
/// own vertices with the face normal, a smooth part keeps its shared vertices and their normals.
/// Indices count from the first vertex of the whole buffer, so one draw call can draw it all.
/// Parts without a triangle and line sets are left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Buffers {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Triangles, three indices each.
    pub indices: Vec<u32>,
    /// The parts in model order.
    pub parts: Vec<PartRange>,
    /// Texture coordinates as glTF has them (v down, the image's top row at v = 0), one per
    /// position when some part is textured (0, 0 for the vertices of the others); empty when
    /// none is.
    pub uvs: Vec<[f32; 2]>,
    /// The distinct images the textured parts name, in order of first use.
    pub textures: Vec<Arc<Texture>>,
    /// The joints of the model's skeletons, skeleton after skeleton, each skeleton's parents
    /// before their children; empty for a model without a skeleton.
    pub joints: Vec<BufferJoint>,
    /// Per vertex when some part hangs from a joint: the index in [`Buffers::joints`] of the
    /// joint that moves it rigidly, [`NO_JOINT`] for a vertex of a part that hangs from none;
    /// empty when no part hangs from a joint.
    pub vertex_joints: Vec<u32>,
}

/// In [`Buffers::vertex_joints`]: the vertex hangs from no joint.
pub const NO_JOINT: u32 = u32::MAX;

/// A joint of a skeleton as a host's skeleton takes it: a glTF joint node's transformation with
/// the section's limits and pose (`docs/kinematics.md`). The vertices are in the derived pose,
/// so a host that poses joint `j` anew moves the vertices hanging from it by
/// `world_new(j) · world(j)⁻¹`, where `world` multiplies the `translation`/`rotation` frames
/// from the root down.
#[derive(Clone, Debug, PartialEq)]
pub struct BufferJoint {
    /// The section's name, which stays the same when the grammar is derived again: its rule
    /// and a hash of its place in the derivation (`Boom_5d7b45`).
    pub name: String,
    /// The skeleton it belongs to (one per initial shape that has one).
    pub skeleton: u32,
    /// Its parent's index in [`Buffers::joints`]; `None` for a skeleton's root.
    pub parent: Option<u32>,
    /// Its transformation relative to its parent in the derived pose: the translation, in
    /// metres.
    pub translation: [f32; 3],
    /// … and the rotation, a unit quaternion in x, y, z, w order.
    pub rotation: [f32; 4],
    /// The same in the rest pose (every joint at rest): translation in metres.
    pub rest_translation: [f32; 3],
    /// … and rotation, x, y, z, w.
    pub rest_rotation: [f32; 4],
    /// The pose the derivation left it in: rotation about the joint's x, then y, then z axis
    /// (fixed axes), in degrees; the posed transformation is `rest · T(translation) · R`.
    pub pose_rotation_deg: [f32; 3],
    /// … and translation along the joint's axes, in metres.
    pub pose_translation_m: [f32; 3],
    /// Per axis x, y, z: the least and greatest rotation, in degrees.
    pub rotation_limits_deg: [[f32; 2]; 3],
    /// Per axis x, y, z: the least and greatest translation, in metres.
    pub translation_limits_m: [[f32; 2]; 3],
}

impl BufferJoint {
    /// Section `id`'s joint in `skeleton` (model skeleton `index`), with its parent at `parent`.
    fn of_section(
        skeleton: &Skeleton,
        index: usize,
        id: shapegram_geom::kinematics::SectionId,
        parent: Option<u32>,
    ) -> Self {
        let section = skeleton.section(id);
        let (translation, rotation) = trs(&skeleton.local(id));
        let (rest_translation, rest_rotation) = trs(&skeleton.joint(id));
        let limits = section.limits();
        let ranges =
            |r: &[shapegram_geom::kinematics::Range; 3]| r.map(|r| [r.min as f32, r.max as f32]);
        Self {
            name: section.name().to_string(),
            skeleton: index as u32,
            parent,
            translation,
            rotation,
            rest_translation,
            rest_rotation,
            pose_rotation_deg: section.pose().rotation.as_vec3().to_array(),
            pose_translation_m: section.pose().translation.as_vec3().to_array(),
            rotation_limits_deg: ranges(&limits.rotation),
            translation_limits_m: ranges(&limits.translation),
        }
    }
}

/// A frame as single-precision translation and xyzw rotation.
fn trs(frame: &Frame) -> ([f32; 3], [f32; 4]) {
    (
        frame.translation.as_vec3().to_array(),
        frame.rotation.as_quat().to_array(),
    )
}

impl Buffers {
    /// The buffers of `model`.
    pub fn of_model(model: &Model) -> Self {
        let mut buffers = Self::default();
        buffers.fill(model);
        buffers
    }

    /// Empties the buffers, keeping their memory for the next [`Buffers::fill`].
    pub fn clear(&mut self) {
        self.positions.clear();
        self.normals.clear();
        self.indices.clear();
        self.parts.clear();
        self.uvs.clear();
        self.textures.clear();
        self.joints.clear();
        self.vertex_joints.clear();
    }

    /// Replaces the contents with the buffers of `model`, reusing the memory already held.
    /// Parts hanging from a joint come in the pose the derivation left them in.
    pub fn fill(&mut self, model: &Model) {
        self.clear();
        // Each skeleton's first joint in `joints`, and each section's joint index.
        let mut joint_of: Vec<Vec<u32>> = Vec::with_capacity(model.skeletons.len());
        for (index, skeleton) in model.skeletons.iter().enumerate() {
            let mut of_section = vec![0; skeleton.len()];
            for id in skeleton.order() {
                let parent = skeleton.section(id).parent().map(|p| of_section[p.index()]);
                of_section[id.index()] = self.joints.len() as u32;
                self.joints
                    .push(BufferJoint::of_section(skeleton, index, id, parent));
            }
            joint_of.push(of_section);
        }
        let bound = model.parts.iter().any(|p| p.bone.is_some());
        let posed;
        let shown = if bound {
            posed = model.posed();
            &posed
        } else {
            model
        };
        let textured = model.parts.iter().any(|p| texture_uvs(p).is_some());
        for (index, (part, bone)) in shown
            .parts
            .iter()
            .zip(model.parts.iter().map(|p| p.bone))
            .enumerate()
        {
            let Some(chunk) = Chunk::of_part(part) else {
                continue;
            };
            let first_vertex = self.positions.len() as u32;
            let first_index = self.indices.len() as u32;
            chunk.positions(|p| self.positions.push(p));
            chunk.normals(|n| self.normals.push(n));
            let texture = texture_uvs(part)
                .and(part.texture.as_ref())
                .map(|texture| self.texture_index(texture));
            if texture.is_some() {
                chunk.uvs(|uv| self.uvs.push(uv));
            } else if textured {
                self.uvs.resize(self.positions.len(), [0.0; 2]);
            }
            if bound {
                let joint = bone.map_or(NO_JOINT, |b| {
                    joint_of[b.skeleton as usize][b.section.index()]
                });
                self.vertex_joints.resize(self.positions.len(), joint);
            }
            self.indices
                .extend(chunk.indices().iter().map(|&i| first_vertex + i));
            self.parts.push(PartRange {
                part: index,
                color: part.color.to_array(),
                first_vertex,
                vertex_count: chunk.vertex_count() as u32,
                first_index,
                index_count: chunk.indices().len() as u32,
                texture,
            });
        }
    }

    /// Appends a part already in triangles with a normal per corner (a topological grammar's
    /// `GrammarMesh` part), as part `part` of its model; triangles index `positions`. A part
    /// drawn with a `texture` brings one uv per corner (v up, as grammars measure it); without
    /// an image glTF can carry, the part is left untextured, as [`Buffers::fill`] leaves it.
    pub fn push_triangles(
        &mut self,
        part: usize,
        color: [f32; 4],
        corners: Corners<'_>,
        texture: Option<(&Arc<Texture>, &[DVec2])>,
    ) {
        let first_vertex = self.positions.len() as u32;
        let first_index = self.indices.len() as u32;
        let texture =
            texture.filter(|(t, uvs)| drawable(t) && uvs.len() == corners.positions.len());
        let texture = texture.map(|(texture, uvs)| {
            if self.uvs.is_empty() {
                self.uvs.resize(self.positions.len(), [0.0; 2]);
            }
            self.uvs.extend(uvs.iter().map(|&uv| gltf_uv(uv)));
            self.texture_index(texture)
        });
        self.positions
            .extend(corners.positions.iter().map(|p| p.as_vec3().to_array()));
        self.normals
            .extend(corners.normals.iter().map(|&n| unit(n)));
        if texture.is_none() && !self.uvs.is_empty() {
            self.uvs.resize(self.positions.len(), [0.0; 2]);
        }
        self.indices.extend(
            corners
                .triangles
                .iter()
                .flatten()
                .map(|&i| first_vertex + i),
        );
        self.parts.push(PartRange {
            part,
            color,
            first_vertex,
            vertex_count: corners.positions.len() as u32,
            first_index,
            index_count: 3 * corners.triangles.len() as u32,
            texture,
        });
    }

    /// The index of `texture` in [`Buffers::textures`], added when it is not there yet (images
    /// are told apart by their paths).
    fn texture_index(&mut self, texture: &Arc<Texture>) -> u32 {
        let known = self.textures.iter().position(|t| t.path == texture.path);
        known.unwrap_or_else(|| {
            self.textures.push(Arc::clone(texture));
            self.textures.len() - 1
        }) as u32
    }
}

/// Triangles with a normal per corner, as [`Buffers::push_triangles`] takes them.
#[derive(Clone, Copy, Debug)]
pub struct Corners<'a> {
    /// Corner positions.
    pub positions: &'a [DVec3],
    /// The normal at each corner (scaled as it comes: the buffers make it unit).
    pub normals: &'a [DVec3],
    /// Triangles as indices into `positions`.
    pub triangles: &'a [[u32; 3]],
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapegram_geom::{Color, DVec2, DVec3, Part, primitives};

    #[test]
    fn a_flat_box_and_a_smooth_sphere_share_one_index_space() {
        let flat = Part {
            name: "box".into(),
            color: Color::from_hex("#ff0000").unwrap(),
            mesh: primitives::cuboid(DVec3::ONE),
            ..Part::default()
        };
        let sphere = primitives::sphere(DVec3::ONE, 8, 4);
        let smooth = Part {
            name: "ball".into(),
            color: Color::from_hex("#0000ff80").unwrap(),
            normals: sphere.vertex_normals(),
            mesh: sphere.clone(),
            ..Part::default()
        };
        let model = Model {
            parts: vec![flat, smooth],
            ..Model::default()
        };
        let buffers = Buffers::of_model(&model);
        // Six quads of four corners each, two triangles each.
        assert_eq!((buffers.parts[0].part, buffers.parts[1].part), (0, 1));
        assert_eq!(buffers.parts[0].vertex_count, 24);
        assert_eq!(buffers.parts[0].index_count, 36);
        assert_eq!(buffers.parts[1].first_vertex, 24);
        assert_eq!(buffers.parts[1].first_index, 36);
        assert_eq!(buffers.parts[1].color, [0.0, 0.0, 1.0, 128.0 / 255.0]);
        assert_eq!(buffers.positions.len(), buffers.normals.len());
        let smooth_indices = &buffers.indices[36..];
        assert!(
            smooth_indices
                .iter()
                .all(|&i| (24..buffers.positions.len() as u32).contains(&i))
        );
        assert_eq!(
            buffers.positions.len() as u32,
            24 + buffers.parts[1].vertex_count
        );
        let mut again = Buffers::of_model(&Model::default());
        again.fill(&model);
        assert_eq!(again, buffers);
        // A triangle after them, already split: indices move past the vertices before it.
        let corners = [DVec3::ZERO, DVec3::X, DVec3::Z];
        let triangle = Corners {
            positions: &corners,
            normals: &[DVec3::Y * 2.0; 3],
            triangles: &[[0, 2, 1]],
        };
        again.push_triangles(2, [1.0; 4], triangle, None);
        let n = buffers.positions.len() as u32;
        assert_eq!(again.indices[buffers.indices.len()..], [n, n + 2, n + 1]);
        assert_eq!(again.normals[n as usize], [0.0, 1.0, 0.0]);
        assert_eq!(again.parts[2].part, 2);
        assert!(again.uvs.is_empty());
    }

    #[test]
    fn textured_triangles_bring_gltf_uvs_and_zeros_stand_for_the_others() {
        let image = |path: &str, bytes: &[u8]| {
            Arc::new(Texture {
                path: path.into(),
                image: Some(bytes.into()),
            })
        };
        let brick = image("textures/brick.png", b"\x89PNG\r\n\x1a\n");
        let text = image("notes.txt", b"not an image");
        let corners = [DVec3::ZERO, DVec3::X, DVec3::Z];
        let triangle = Corners {
            positions: &corners,
            normals: &[DVec3::Y; 3],
            triangles: &[[0, 2, 1]],
        };
        let uvs = [
            DVec2::new(0.0, 0.0),
            DVec2::new(1.5, 0.25),
            DVec2::new(0.0, 2.0),
        ];
        let mut buffers = Buffers::default();
        buffers.push_triangles(0, [1.0; 4], triangle, None);
        buffers.push_triangles(1, [1.0; 4], triangle, Some((&brick, &uvs)));
        // Not an image glTF carries: drawn in its colour, like a model's part.
        buffers.push_triangles(2, [1.0; 4], triangle, Some((&text, &uvs)));
        buffers.push_triangles(3, [1.0; 4], triangle, Some((&brick, &uvs)));
        assert_eq!(
            buffers.parts.iter().map(|p| p.texture).collect::<Vec<_>>(),
            [None, Some(0), None, Some(0)]
        );
        assert_eq!(buffers.textures, [brick]);
        let textured = [[0.0, 1.0], [1.5, 0.75], [0.0, -1.0]];
        assert_eq!(buffers.uvs[..3], [[0.0; 2]; 3]);
        assert_eq!(buffers.uvs[3..6], textured);
        assert_eq!(buffers.uvs[6..9], [[0.0; 2]; 3]);
        assert_eq!(buffers.uvs[9..], textured);
    }
}
