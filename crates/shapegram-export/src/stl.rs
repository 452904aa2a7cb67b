//! Binary STL writer: 80-byte header, triangle count, then 50 bytes per triangle.

use shapegram_geom::Model;

use crate::flat::flat_faces;

/// The header text. It must not start with "solid", which readers take for ASCII STL.
const HEADER: &[u8] = b"shapegram";

/// The model as binary STL (all parts merged; STL has no groups or colours).
pub fn write_stl(model: &Model) -> Vec<u8> {
    let mut out = Vec::with_capacity(84);
    out.extend_from_slice(HEADER);
    out.resize(80, 0);
    out.extend_from_slice(&[0; 4]);
    let mut count: u32 = 0;
    for part in &model.parts {
        flat_faces(&part.mesh, |face| {
            for triangle in face.triangles {
                for v in face
                    .normal
                    .iter()
                    .chain(triangle.iter().flat_map(|&c| &face.corners[c as usize]))
                {
                    out.extend_from_slice(&v.to_le_bytes());
                }
                out.extend_from_slice(&0u16.to_le_bytes());
                count += 1;
            }
        });
    }
    out[80..84].copy_from_slice(&count.to_le_bytes());
    out
}
