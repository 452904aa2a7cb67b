//! Shapegram's file formats: GLB (binary glTF 2.0), OBJ + MTL and binary STL, written from and
//! read into [`shapegram_geom::Model`]; GeoJSON polygons read as footprints.
//!
//! Writers are deterministic: the same model gives the same bytes (materials are ordered by the
//! first part that uses their colour, nothing depends on hash order, floats are printed with
//! Rust's shortest round-trip formatting). Every writer drops faces without area or with
//! non-finite corners, and GLB/STL also drop triangles that lose their area in f32; parts left
//! without faces are not written. Parts with one normal per vertex are written smooth (shared
//! vertices with their normals) to GLB and OBJ; line sets become GLB LINES primitives and OBJ
//! `l` elements (STL holds triangles only and leaves them out). Segments between points that
//! are not finite or coincide in f32 are dropped, as are points no segment uses.
//!
//! Kinematic skeletons ([`Model::skeletons`]) go into GLB as glTF skins: rest-pose vertices
//! bound rigidly to one joint each, joint nodes posed, limits and pose in the joints' extras
//! (`docs/kinematics.md`). OBJ and STL have no skins and write the posed model
//! ([`Model::posed`]) instead. A model without bound parts is written exactly as it would be
//! without skeletons.
//!
//! Readers treat their input as untrusted and return [`Error`] rather than panic.

mod buffers;
mod error;
mod flat;
mod geojson;
mod glb;
mod mtl;
mod obj;
mod read;
mod stl;
mod svg;
pub mod tiles;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use std::sync::Arc;

use shapegram_geom::{Model, Texture};

pub use buffers::{BufferJoint, Buffers, Corners, NO_JOINT, PartRange};
pub use error::Error;
pub use geojson::{Footprints, read_geojson};
pub use glb::{
    Features, GlbLayout, Instancing, face_triangles, write_glb, write_glb_to,
    write_glb_with_features_to, write_glb_with_layout,
};
pub use obj::{write_obj, write_obj_to};
pub use read::{read_glb, read_obj, read_stl};
pub use stl::{write_stl, write_stl_to};
pub use svg::{SvgDrawing, SvgPolygon, SvgPolyline, write_svg};

/// A file format, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Binary glTF 2.0.
    Glb,
    /// Wavefront OBJ with an MTL beside it.
    Obj,
    /// Binary STL (ASCII STL is read too).
    Stl,
}

impl Format {
    /// By file extension (case-insensitive): .glb, .obj, .stl; otherwise `Error::UnknownFormat`.
    pub fn from_path(path: &Path) -> Result<Format, Error> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("glb") => Ok(Self::Glb),
            Some("obj") => Ok(Self::Obj),
            Some("stl") => Ok(Self::Stl),
            _ => Err(Error::UnknownFormat(path.to_path_buf())),
        }
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Glb => "glb",
            Self::Obj => "obj",
            Self::Stl => "stl",
        }
    }

    /// The name used in messages.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Glb => "GLB",
            Self::Obj => "OBJ",
            Self::Stl => "STL",
        }
    }
}

/// Choices that change what the writers produce.
#[derive(Clone, Debug, Default)]
pub struct ExportOptions {
    /// One glTF node (and one OBJ `o`) per part, named after the part; otherwise parts with the
    /// same colour are merged into one mesh per material.
    pub group_by_part: bool,
    /// How GLB writes parts that repeat a prototype ([`shapegram_geom::Part::instance`]); OBJ
    /// and STL write every part's own geometry.
    pub instancing: Instancing,
    /// How GLB stores vertex data (OBJ and STL are always text or floats).
    pub encoding: GlbEncoding,
    /// Whether GLB writes the normals of flat-shaded parts (OBJ always does).
    pub flat_normals: FlatNormals,
}

/// Whether a GLB's flat-shaded primitives carry a NORMAL attribute. glTF requires readers to
/// shade a primitive without normals flat, with each triangle's own normal, so leaving them out
/// loses nothing and lets faces of one material share the vertices where they meet (a box:
/// 8 vertices, not 24). Smooth and normal-mapped parts keep their normals either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FlatNormals {
    /// No NORMAL on flat-shaded primitives: readers compute the faces' normals.
    #[default]
    Computed,
    /// Each face's normal on its own four (or more) corners, for readers that do not follow
    /// the specification's rule (`--normals`).
    Written,
}

/// How a GLB stores its vertex data. Vertices are shared and (outside
/// [`write_glb_with_layout`]) coplanar rectangles merged and triangles put in vertex-cache
/// order in every encoding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GlbEncoding {
    /// 32-bit floats, readable by every glTF reader.
    #[default]
    Float,
    /// KHR_mesh_quantization: positions as i16 (the mesh's node scales them back), normals
    /// as i8, uvs within `0..=1` as u16 (`--quantize`).
    Quantized,
    /// Quantised, then compressed with EXT_meshopt_compression (`--meshopt`).
    Compressed,
}

/// Writes to `path` in the format of its extension; OBJ also writes the .mtl beside it (same
/// stem) and the images of textured parts (named after their files; an existing file of that
/// name is replaced). Parent directories must exist. Files are streamed through a buffer rather than built
/// in memory first. STL holds triangles only: line sets are left out. GLB keeps skeletons as
/// skins; OBJ and STL write the model in its current pose.
pub fn save(model: &Model, path: &Path, options: &ExportOptions) -> Result<(), Error> {
    let failed = |file: &Path| {
        let file = file.to_path_buf();
        move |source| Error::Write { path: file, source }
    };
    match Format::from_path(path)? {
        Format::Glb => stream(path, |out| write_glb_to(model, options, out)).map_err(failed(path)),
        Format::Stl => stream(path, |out| write_stl_to(model, out)).map_err(failed(path)),
        Format::Obj => {
            let mtl_path = path.with_extension("mtl");
            let mtl_name = mtl_path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let mut mtl = String::new();
            stream(path, |out| {
                mtl = write_obj_to(model, options, &mtl_name, out)?;
                Ok(())
            })
            .map_err(failed(path))?;
            std::fs::write(&mtl_path, mtl).map_err(failed(&mtl_path))?;
            let dir = path.parent().unwrap_or(Path::new(""));
            for (_, name, image) in flat::texture_files(model) {
                let image_path = dir.join(name);
                std::fs::write(&image_path, image).map_err(failed(&image_path))?;
            }
            Ok(())
        }
    }
}

/// Creates `path` and hands `write` a buffered writer on it, flushing at the end.
pub(crate) fn stream(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut out = BufWriter::with_capacity(1 << 20, File::create(path)?);
    write(&mut out)?;
    out.flush()
}

/// Reads a file by extension; for OBJ, an MTL named by `mtllib` beside it gives the materials
/// (name, `Kd`, `d`, texture maps read beside it, …) when it exists.
pub fn load(path: &Path) -> Result<Model, Error> {
    load_with(path, |file| std::fs::read(file))
}

/// [`load`] with the bytes of the file and of the MTL and texture files it names read by
/// `read`: the
/// assets of a rule package are entries of an archive, not files. `path` names the file in
/// messages and its extension picks the format.
pub fn load_with(
    path: &Path,
    read: impl Fn(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Model, Error> {
    let format = Format::from_path(path)?;
    let bytes = read(path).map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let model = match format {
        // Embedded images are named within their file: under the file's path, they stay apart
        // from another asset's and keep their own name as the last part.
        Format::Glb => read_glb(&bytes).map(|mut model| {
            for part in &mut model.parts {
                if let Some(texture) = &mut part.texture {
                    let path = format!("{}/{}", path.display(), texture.path);
                    Arc::make_mut(texture).path = Arc::from(path);
                }
            }
            model
        }),
        Format::Stl => read_stl(&bytes),
        Format::Obj => {
            let text = std::str::from_utf8(&bytes)
                .map_err(|e| Error::broken(Format::Obj, format!("not UTF-8 text ({e})")))
                .map_err(|e| e.at(path))?;
            let dir = path.parent().unwrap_or(Path::new(""));
            // A texture that cannot be read leaves its part in its colour, as CityEngine
            // draws an asset whose texture is missing.
            let texture = |name: &str| {
                let file = dir.join(name);
                Arc::new(Texture {
                    path: Arc::from(file.to_string_lossy().as_ref()),
                    image: read(&file).ok().map(Arc::from),
                })
            };
            read::read_obj_with(
                text,
                |mtl| match read(&dir.join(mtl)) {
                    Ok(bytes) => tobj::load_mtl_buf(&mut bytes.as_slice()),
                    Err(_) => Err(tobj::LoadError::OpenFileFailed),
                },
                &texture,
            )
        }
    };
    model.map_err(|e| e.at(path))
}
