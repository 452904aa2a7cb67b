//! Tangents for normal-mapped primitives (glTF `TANGENT`: unit xyz along increasing u, and w,
//! ±1, the handedness that turns `normal × tangent` into the direction of increasing v).
//!
//! glTF viewers generate tangents themselves when a normal-mapped primitive has none, but how is
//! not portable (the validator warns), so they are written, computed from the uvs as written
//! (v down, as glTF has them).

/// The tangent of a flat face (every corner has the face's normal), from its first triangle
/// whose uvs span an area.
pub(super) fn face_tangent(
    normal: [f32; 3],
    corners: &[[f32; 3]],
    uvs: &[[f32; 2]],
    triangles: &[[u32; 3]],
) -> [f32; 4] {
    let along = triangles.iter().find_map(|t| {
        triangle_directions(t.map(|c| corners[c as usize]), t.map(|c| uvs[c as usize]))
    });
    oriented(normal, along)
}

/// One tangent per vertex of a smooth mesh: the uv directions of the triangles around each
/// vertex, summed, made perpendicular to its normal.
pub(super) fn vertex_tangents(
    positions: &[[f32; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    indices: &[u32],
) -> Vec<[f32; 4]> {
    let mut sums = vec![([0.0f32; 3], [0.0f32; 3]); positions.len()];
    for t in indices.chunks_exact(3) {
        let t = [t[0], t[1], t[2]];
        let Some((u, v)) =
            triangle_directions(t.map(|i| positions[i as usize]), t.map(|i| uvs[i as usize]))
        else {
            continue;
        };
        for i in t {
            let (su, sv) = &mut sums[i as usize];
            *su = add(*su, u);
            *sv = add(*sv, v);
        }
    }
    sums.iter()
        .zip(normals)
        .map(|(&(u, v), &n)| oriented(n, (length(u) > 0.0).then_some((u, v))))
        .collect()
}

/// The directions in which u and v grow across a triangle, unnormalised; `None` when its uvs
/// span no area.
fn triangle_directions(p: [[f32; 3]; 3], uv: [[f32; 2]; 3]) -> Option<([f32; 3], [f32; 3])> {
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let (du1, dv1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
    let (du2, dv2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
    let det = du1 * dv2 - du2 * dv1;
    if det.abs() <= f32::EPSILON * (du1.abs() + du2.abs()) * (dv1.abs() + dv2.abs())
        || !det.is_finite()
    {
        return None;
    }
    let r = 1.0 / det;
    let u = scale(sub(scale(e1, dv2), scale(e2, dv1)), r);
    let v = scale(sub(scale(e2, du1), scale(e1, du2)), r);
    Some((u, v))
}

/// A unit tangent perpendicular to `normal` along `u`, with the handedness of `v`; without
/// directions (uvs that span nothing), any unit vector perpendicular to the normal.
fn oriented(normal: [f32; 3], along: Option<([f32; 3], [f32; 3])>) -> [f32; 4] {
    let along = along.and_then(|(u, v)| {
        let t = sub(u, scale(normal, dot(normal, u)));
        (length(t) > 0.0).then_some((t, v))
    });
    let (t, w) = match along {
        Some((t, v)) => (
            t,
            if dot(cross(normal, t), v) < 0.0 {
                -1.0
            } else {
                1.0
            },
        ),
        None => {
            // The world axis least along the normal, made perpendicular to it.
            let axis = if normal[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            (sub(axis, scale(normal, dot(normal, axis))), 1.0)
        }
    };
    let t = scale(t, 1.0 / length(t));
    [t[0], t[1], t[2], w]
}

fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn length(a: [f32; 3]) -> f32 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floor_with_u_along_x_and_v_growing_towards_plus_z() {
        // glTF's v grows down the image: here towards +z on a floor seen from above.
        let corners = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 0.0, -1.0]];
        let uvs = [[0.0, 1.0], [2.0, 1.0], [2.0, 0.0]];
        let t = face_tangent([0.0, 1.0, 0.0], &corners, &uvs, &[[0, 1, 2]]);
        // normal × tangent = +y × +x = −z, the way v shrinks: left-handed, w = −1.
        assert_eq!(t, [1.0, 0.0, 0.0, -1.0]);
        let mirrored = [[2.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
        let t = face_tangent([0.0, 1.0, 0.0], &corners, &mirrored, &[[0, 1, 2]]);
        assert_eq!(t, [-1.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn uvs_that_span_nothing_still_give_a_unit_tangent_across_the_normal() {
        let corners = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let t = face_tangent([0.0, 0.0, 1.0], &corners, &[[0.5, 0.5]; 3], &[[0, 1, 2]]);
        assert_eq!(t, [1.0, 0.0, 0.0, 1.0]);
        let t = vertex_tangents(
            &corners,
            &[[1.0, 0.0, 0.0]; 3],
            &[[0.0, 0.0]; 3],
            &[0, 1, 2],
        );
        assert_eq!(t, [[0.0, 1.0, 0.0, 1.0]; 3]);
    }
}
