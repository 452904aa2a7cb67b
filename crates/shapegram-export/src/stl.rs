//! Binary STL writer: 80-byte header, triangle count, then 50 bytes per triangle.

use std::io::{self, Cursor, Seek, SeekFrom, Write};

use shapegram_geom::Model;

use crate::flat::flat_faces;

/// The header text. It must not start with "solid", which readers take for ASCII STL.
const HEADER: &[u8] = b"shapegram";

/// The model as binary STL (all parts merged; STL has no groups or colours, and holds
/// triangles only, so line sets are left out).
pub fn write_stl(model: &Model) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    write_stl_to(model, &mut out).expect("writing to a Vec cannot fail");
    out.into_inner()
}

/// Writes the model as binary STL to `out` (see [`write_stl`]), going back to fill in the
/// triangle count at the end; wrap files in a `BufWriter`.
pub fn write_stl_to(model: &Model, out: &mut (impl Write + Seek)) -> io::Result<()> {
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
