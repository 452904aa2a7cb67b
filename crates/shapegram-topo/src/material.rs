//! Tiled materials of faces: a name, a colour and/or a texture image, and the size in metres of
//! one tile of the image, with the planar texture coordinates that keep the tile size constant
//! in the world whatever the size of the face.

use std::sync::Arc;

use shapegram_geom::{Color, DVec2, DVec3, Texture};

/// Longest material name or texture path accepted.
const MAX_TEXT: usize = 1000;

/// A material that faces of sub-shapes can be given.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Unique, non-blank name; it names the material in exported files.
    pub name: String,
    /// The surface colour (multiplied with the texture when both are given); `None` with a
    /// texture draws the texture as it is.
    pub color: Option<Color>,
    /// The image, as a path relative to the grammar or project file.
    pub texture: Option<String>,
    /// Width and height in metres that one copy of the image covers.
    pub tile: DVec2,
}

impl Material {
    /// Its texture, if it names one, with the image `image` reads from the named path (`None`:
    /// drawn in the material's colour).
    pub fn texture_with(
        &self,
        image: impl FnOnce(&str) -> Option<Arc<[u8]>>,
    ) -> Option<Arc<Texture>> {
        let path = self.texture.as_deref()?;
        Some(Arc::new(Texture {
            path: path.into(),
            image: image(path),
        }))
    }

    /// A material of one colour, tiles of one metre.
    pub fn colored(name: &str, color: Color) -> Self {
        Self {
            name: name.to_owned(),
            color: Some(color),
            texture: None,
            tile: DVec2::ONE,
        }
    }

    /// A textured material whose image covers `tile` metres (width, height).
    pub fn textured(name: &str, texture: &str, tile: DVec2) -> Self {
        Self {
            name: name.to_owned(),
            color: None,
            texture: Some(texture.to_owned()),
            tile,
        }
    }

    /// The colour meshes get: the material's, else white so that the texture shows unaltered.
    pub fn surface_color(&self) -> Color {
        self.color.unwrap_or(Color::rgb(1.0, 1.0, 1.0))
    }

    /// Why the material cannot be used, if it cannot.
    pub fn check(&self) -> Result<(), String> {
        if self.name.trim().is_empty() || self.name.len() > MAX_TEXT {
            return Err(format!(
                "a material name must be 1 to {MAX_TEXT} characters, not blank"
            ));
        }
        if self.color.is_none() && self.texture.is_none() {
            return Err(format!(
                "material '{}' needs a colour or a texture",
                self.name.escape_debug()
            ));
        }
        if let Some(texture) = &self.texture
            && (texture.trim().is_empty() || texture.len() > MAX_TEXT)
        {
            return Err(format!(
                "material '{}': a texture path must be 1 to {MAX_TEXT} characters, not blank",
                self.name.escape_debug()
            ));
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(self.tile.x) && positive(self.tile.y)) {
            return Err(format!(
                "material '{}': the tile size {} × {} must be two positive numbers of metres",
                self.name.escape_debug(),
                self.tile.x,
                self.tile.y
            ));
        }
        Ok(())
    }
}

/// The face axes texture coordinates run along: `u` horizontal in the face (to the right seen
/// from outside), `v` up the face; for a horizontal face, `u` is world x and `v` completes a
/// right-handed frame with the normal. They depend on the face's plane only, not on where its
/// loop starts, so a face reads the same whatever anchor its symbol has.
pub fn face_axes(normal: DVec3) -> (DVec3, DVec3) {
    let across = DVec3::Y.cross(normal);
    let u = if across.length() > 1e-6 {
        across.normalize()
    } else {
        DVec3::X
    };
    (u, normal.cross(u).normalize())
}

/// The texture coordinates of `point` on a face with unit `normal` under `tile`: world metres
/// along the face axes divided by the tile size, measured from the world origin, so that
/// neighbouring faces in one plane (a wall cut into pieces) continue each other's pattern.
pub fn planar_uv(point: DVec3, normal: DVec3, tile: DVec2) -> DVec2 {
    let (u, v) = face_axes(normal);
    DVec2::new(point.dot(u) / tile.x, point.dot(v) / tile.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_front_face_reads_right_and_up_in_tiles() {
        let tile = DVec2::new(2.0, 0.5);
        assert_eq!(
            planar_uv(DVec3::new(4.0, 3.0, 7.0), DVec3::Z, tile),
            DVec2::new(2.0, 6.0)
        );
        // Seen from behind, right is −x.
        assert_eq!(
            planar_uv(DVec3::new(4.0, 3.0, 7.0), -DVec3::Z, tile),
            DVec2::new(-2.0, 6.0)
        );
        let (u, v) = face_axes(DVec3::Y);
        assert_eq!((u, v), (DVec3::X, -DVec3::Z));
    }

    #[test]
    fn materials_need_a_name_a_look_and_a_positive_tile() {
        let red = Color::rgb(1.0, 0.0, 0.0);
        assert_eq!(Material::colored("Red", red).check(), Ok(()));
        let mut bad = Material::colored(" ", red);
        assert!(bad.check().unwrap_err().contains("not blank"));
        bad = Material::colored("Red", red);
        bad.color = None;
        assert_eq!(
            bad.check().unwrap_err(),
            "material 'Red' needs a colour or a texture"
        );
        let flat = Material::textured("Brick", "brick.png", DVec2::new(1.0, 0.0));
        assert_eq!(
            flat.check().unwrap_err(),
            "material 'Brick': the tile size 1 × 0 must be two positive numbers of metres"
        );
    }
}
