//! `GrammarMesh`: an `ArrayMesh` that follows a `GrammarState`, a surface per part.

use godot::classes::base_material_3d::{TextureParam, Transparency};
use godot::classes::mesh::{ArrayType, PrimitiveType};
use godot::classes::{ArrayMesh, Image, ImageTexture, StandardMaterial3D};
use godot::global::Error as GodotError;
use godot::prelude::*;
use shapegram_geom::Texture;

use crate::job::Output;
use crate::state::GrammarState;

/// The mesh of a `GrammarState`'s last derivation: one surface per part, named after it, with
/// the part's colour as vertex colour and as the albedo of the surface's material (a resource
/// named as the grammar names the material, `set(material.name, …)`); a textured
/// part has its uvs and its image as the albedo texture (which the colour multiplies). It is
/// built again whenever the state emits `changed`.
#[derive(GodotClass)]
#[class(tool, init, base = ArrayMesh)]
pub struct GrammarMesh {
    /// The state this mesh follows.
    #[export]
    #[var(set)]
    state: Option<Gd<GrammarState>>,
    base: Base<ArrayMesh>,
}

#[godot_api]
impl GrammarMesh {
    /// Follows `state` from now on (and no longer the state before), and builds its mesh.
    #[func]
    pub fn set_state(&mut self, state: Option<Gd<GrammarState>>) {
        let callable = Callable::from_object_method(&self.to_gd(), "rebuild");
        if let Some(old) = self.state.take() {
            let mut old = old.upcast::<Object>();
            if old.is_connected("changed", &callable) {
                old.disconnect("changed", &callable);
            }
        }
        if let Some(new) = &state {
            new.clone().upcast::<Object>().connect("changed", &callable);
        }
        self.state = state;
        self.rebuild();
    }

    /// Builds the surfaces again from the state's last derivation.
    #[func]
    pub fn rebuild(&mut self) {
        self.base_mut().clear_surfaces();
        let Some(state) = self.state.clone() else {
            return;
        };
        let state = state.bind();
        let output = state.output();
        // Each image once, however many parts use it.
        let textures: Vec<Option<Gd<ImageTexture>>> =
            output.buffers.textures.iter().map(|t| texture(t)).collect();
        for (i, range) in output.buffers.parts.iter().enumerate() {
            let texture = range.texture.and_then(|t| textures[t as usize].clone());
            self.add_part(output, i, texture);
        }
    }

    /// How many vertices the surfaces hold together (what Godot draws).
    #[func]
    pub fn vertex_count(&self) -> i64 {
        let mesh = self.base();
        (0..mesh.get_surface_count())
            .map(|surface| i64::from(mesh.surface_get_array_len(surface)))
            .sum()
    }

    /// Adds part range `index` of `output` as a surface, drawn with `texture` when it has one.
    fn add_part(&mut self, output: &Output, index: usize, texture: Option<Gd<ImageTexture>>) {
        let buffers = &output.buffers;
        let range = &buffers.parts[index];
        let vertices =
            range.first_vertex as usize..(range.first_vertex + range.vertex_count) as usize;
        let vector = |v: &[f32; 3]| Vector3::new(v[0], v[1], v[2]);
        let positions: PackedVector3Array = buffers.positions[vertices.clone()]
            .iter()
            .map(vector)
            .collect();
        let normals: PackedVector3Array = buffers.normals[vertices.clone()]
            .iter()
            .map(vector)
            .collect();
        let [r, g, b, a] = range.color;
        let color = Color::from_rgba(r, g, b, a);
        let colors: PackedColorArray = std::iter::repeat_n(color, positions.len()).collect();
        let first = range.first_index as usize;
        let triangles = buffers.indices[first..first + range.index_count as usize].chunks_exact(3);
        // Godot's front faces wind clockwise, the buffers' (glTF's) counter-clockwise.
        let indices: PackedInt32Array = triangles
            .flat_map(|t| [t[0], t[2], t[1]])
            .map(|index| (index - range.first_vertex) as i32)
            .collect();
        let mut arrays = VarArray::new();
        arrays.resize(ArrayType::MAX.ord() as usize, &Variant::nil());
        arrays.set(ArrayType::VERTEX.ord() as usize, &positions.to_variant());
        arrays.set(ArrayType::NORMAL.ord() as usize, &normals.to_variant());
        arrays.set(ArrayType::COLOR.ord() as usize, &colors.to_variant());
        arrays.set(ArrayType::INDEX.ord() as usize, &indices.to_variant());
        if texture.is_some() {
            // Godot's v points down, as the buffers' (glTF's) does.
            let uvs: PackedVector2Array = buffers.uvs[vertices]
                .iter()
                .map(|&[u, v]| Vector2::new(u, v))
                .collect();
            arrays.set(ArrayType::TEX_UV.ord() as usize, &uvs.to_variant());
        }
        let mut mesh = self.base_mut();
        mesh.add_surface_from_arrays(PrimitiveType::TRIANGLES, &arrays);
        let surface = mesh.get_surface_count() - 1;
        mesh.surface_set_name(surface, &output.part_names[index]);
        let mut material = material(color, texture);
        if let Some(name) = &output.part_materials[index] {
            material.set_name(name);
        }
        mesh.surface_set_material(surface, &material);
    }
}

/// A material in the part's colour (sRGB, as Godot's albedo is), see-through when it is, with
/// `texture` as its albedo texture.
fn material(color: Color, texture: Option<Gd<ImageTexture>>) -> Gd<StandardMaterial3D> {
    let mut material = StandardMaterial3D::new_gd();
    material.set_albedo(color);
    if color.a < 1.0 {
        material.set_transparency(Transparency::ALPHA);
    }
    if let Some(texture) = texture {
        material.set_texture(TextureParam::ALBEDO, &texture);
    }
    material
}

/// The image of `texture` as a Godot texture; `None` (the part keeps its colour) when Godot
/// cannot decode it, as a GLB viewer would show it.
fn texture(texture: &Texture) -> Option<Gd<ImageTexture>> {
    let bytes = PackedByteArray::from(texture.image.as_deref()?);
    let mut image = Image::new_gd();
    let loaded = match texture.mime_type()? {
        "image/png" => image.load_png_from_buffer(&bytes),
        _ => image.load_jpg_from_buffer(&bytes),
    };
    if loaded != GodotError::OK {
        godot_warn!("{}: Godot cannot decode the image", texture.path);
        return None;
    }
    ImageTexture::create_from_image(&image)
}
