//! Which face of an inserted asset a piece of geometry lies on, after an operation cut the
//! asset (a split, a component split, a trim plane): each face of the piece takes the material
//! of the asset face under it, and its corners the asset's uvs there, as CityEngine carries
//! them through cuts.

use shapegram_geom::{DAffine3, DVec2, DVec3, Mesh};

use crate::asset_look::NO_MATERIAL;

/// A mesh dressed from an asset: every face with its own corners (so that a face keeps its
/// uvs where faces meet at a seam), the asset material of each face ([`NO_MATERIAL`] for a
/// face on none of the asset's), and uv set 0 per corner when the asset has uvs.
pub(crate) struct Dressed {
    /// World-space geometry.
    pub mesh: Mesh,
    /// The asset material of each face.
    pub face_materials: Vec<u32>,
    /// uv set 0, one per vertex.
    pub uvs: Option<Vec<DVec2>>,
}

/// `mesh` (world space) dressed from the asset `faces` (in the asset's coordinates, placed in
/// the world by `placed`), whose faces wear `face_materials` and whose vertices carry `uvs`.
pub(crate) fn dress(
    mesh: &Mesh,
    faces: &Mesh,
    placed: &DAffine3,
    face_materials: &[u32],
    uvs: Option<&[DVec2]>,
) -> Dressed {
    let to_asset = placed.inverse();
    let size = faces
        .bounds()
        .map_or(1.0, |b| b.size().max_element())
        .max(f64::MIN_POSITIVE);
    let tolerance = 1e-6 * size;
    let mut out = Dressed {
        mesh: Mesh::new(),
        face_materials: Vec::with_capacity(mesh.face_count()),
        uvs: uvs.map(|_| Vec::new()),
    };
    let mut corners = Vec::new();
    for f in 0..mesh.face_count() {
        let points: Vec<DVec3> = mesh
            .face_points(f)
            .map(|p| to_asset.transform_point3(p))
            .collect();
        let centre = points.iter().sum::<DVec3>() / points.len() as f64;
        let normal = shapegram_geom::mesh::newell(points.iter().copied()).normalize_or_zero();
        let under = (0..faces.face_count()).find(|&g| {
            faces.face_normal(g).dot(normal) > 0.999
                && (centre - faces.position(faces.face(g)[0]))
                    .dot(faces.face_normal(g))
                    .abs()
                    <= tolerance
                && inside(faces, g, centre, tolerance).is_some()
        });
        corners.clear();
        for (&p, world) in points.iter().zip(mesh.face_points(f)) {
            corners.push(out.mesh.add_vertex(world));
            if let (Some(out_uvs), Some(uvs)) = (&mut out.uvs, uvs) {
                let uv = under.map_or(DVec2::ZERO, |g| uv_at(faces, uvs, g, p));
                out_uvs.push(uv);
            }
        }
        out.mesh.add_face(&corners);
        out.face_materials
            .push(under.map_or(NO_MATERIAL, |g| face_materials[g]));
    }
    out
}

/// The fan triangle of face `g` that holds `p` (within `tolerance` of its plane), with `p`'s
/// barycentric weights in it.
fn inside(faces: &Mesh, g: usize, p: DVec3, tolerance: f64) -> Option<([u32; 3], DVec3)> {
    let face = faces.face(g);
    let slack = tolerance / faces.face_area(g).sqrt().max(f64::MIN_POSITIVE);
    (1..face.len().saturating_sub(1)).find_map(|i| {
        let corners = [face[0], face[i], face[i + 1]];
        let weights = barycentric(faces, corners, p)?;
        (weights.min_element() >= -slack).then_some((corners, weights))
    })
}

/// The uv of the asset at `p` on its face `g`: interpolated in the fan triangle that holds it,
/// else extrapolated from the face's first triangle.
fn uv_at(faces: &Mesh, uvs: &[DVec2], g: usize, p: DVec3) -> DVec2 {
    let face = faces.face(g);
    let found = inside(faces, g, p, 0.0).or_else(|| {
        let corners = [face[0], face[1], face[2]];
        barycentric(faces, corners, p).map(|w| (corners, w))
    });
    found.map_or(DVec2::ZERO, |(corners, w)| {
        uvs[corners[0] as usize] * w.x
            + uvs[corners[1] as usize] * w.y
            + uvs[corners[2] as usize] * w.z
    })
}

/// The barycentric weights of `p` (projected onto the plane) in triangle `corners` of `mesh`;
/// `None` for a degenerate triangle.
fn barycentric(mesh: &Mesh, corners: [u32; 3], p: DVec3) -> Option<DVec3> {
    let [a, b, c] = corners.map(|v| mesh.position(v));
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if det.abs() <= f64::EPSILON * g11 * g22 || det == 0.0 {
        return None;
    }
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let y = (d1 * g22 - d2 * g12) / det;
    let z = (d2 * g11 - d1 * g12) / det;
    Some(DVec3::new(1.0 - y - z, y, z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_piece_of_an_asset_face_takes_its_material_and_interpolated_uvs() {
        // A 2 × 1 asset quad with the whole texture on it, placed 3 m along x.
        let faces = Mesh::from_faces(
            vec![
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.0),
            ],
            [[0u32, 1, 2, 3]],
        );
        let uvs = [DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y];
        let placed = DAffine3::from_translation(DVec3::new(3.0, 0.0, 0.0));
        // Its right half, and a face standing across it (on no asset face).
        let piece = Mesh::from_faces(
            vec![
                DVec3::new(4.0, 0.0, 0.0),
                DVec3::new(5.0, 0.0, 0.0),
                DVec3::new(5.0, 1.0, 0.0),
                DVec3::new(4.0, 1.0, 0.0),
                DVec3::new(4.0, 0.0, 1.0),
            ],
            [vec![0u32, 1, 2, 3], vec![0, 3, 4]],
        );
        let dressed = dress(&piece, &faces, &placed, &[7], Some(&uvs));
        assert_eq!(dressed.face_materials, [7, NO_MATERIAL]);
        assert_eq!(dressed.mesh.vertex_count(), 7);
        let uvs = dressed.uvs.unwrap();
        let expected = [
            DVec2::new(0.5, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.5, 1.0),
        ];
        for (uv, want) in uvs.iter().zip(expected) {
            assert!((*uv - want).length() < 1e-12, "{uv} != {want}");
        }
    }
}
