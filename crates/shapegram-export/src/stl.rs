//! Binary STL writer: 80-byte header, triangle count, then 50 bytes per triangle.
//!
//! STL has no skins, so parts that hang from a skeleton are written in the current pose
//! ([`Model::posed`]).

use std::io::{self, Cursor, Seek, SeekFrom, Write};

use shapegram_geom::Model;

use crate::flat::{flat_faces, posed};

/// The header text. It must not start with "solid", which readers take for ASCII STL.
const HEADER: &[u8] = b"shapegram";

/// The model as binary STL (all parts merged; STL has no groups or colours, and holds
/// triangles only, so line sets are left out).
///
/// # Panics
/// If a part's bone names a section the model does not have (see [`write_stl_to`]).
pub fn write_stl(model: &Model) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    write_stl_to(model, &mut out).unwrap_or_else(|e| panic!("{e}"));
    out.into_inner()
}

/// Writes the model as binary STL to `out` (see [`write_stl`]), going back to fill in the
/// triangle count at the end; wrap files in a `BufWriter`. A part whose bone names a section
/// the model does not have is an `InvalidInput` error, found before anything is written.
pub fn write_stl_to(model: &Model, out: &mut (impl Write + Seek)) -> io::Result<()> {
    let model = posed(model)?;
    let start = out.stream_position()?;
    let mut header = [0u8; 84];
    header[..HEADER.len()].copy_from_slice(HEADER);
    out.write_all(&header)?;
    let mut count: u32 = 0;
    let mut result = Ok(());
    let mut record = [0u8; 50];
    for part in &model.parts {
        flat_faces(&part.mesh, |face| {
            for triangle in face.triangles {
                let values = face
                    .normal
                    .iter()
                    .chain(triangle.iter().flat_map(|&c| &face.corners[c as usize]));
                for (slot, v) in record.chunks_exact_mut(4).zip(values) {
                    slot.copy_from_slice(&v.to_le_bytes());
                }
                if result.is_ok() {
                    result = out.write_all(&record);
                }
                count += 1;
            }
        });
    }
    result?;
    let end = out.stream_position()?;
    out.seek(SeekFrom::Start(start + 80))?;
    out.write_all(&count.to_le_bytes())?;
    out.seek(SeekFrom::Start(end))?;
    Ok(())
}
