//! An MTL material as a part wears it: colour and opacity (`Kd`, `d`), name, colour map
//! (`map_Kd`) and the other layers and attributes CGA has (`map_Ks`, `map_d`, `bump`, `norm`,
//! `Ks`, `Ka`, `Ke`, `Ns`), with the images read by the caller.

use std::sync::Arc;

use shapegram_geom::{Color, Finish, Maps, Surface, Texture};

/// What a part of an OBJ wears.
pub(crate) struct Look {
    /// `Kd` and `d` (the default colour without `Kd`).
    pub color: Color,
    /// The material's name.
    pub name: Arc<str>,
    /// `map_Kd`.
    pub texture: Option<Arc<Texture>>,
    /// The other attributes and layers, when the material has any.
    pub surface: Option<Arc<Surface>>,
}

/// The look of `material`, whose texture files `image` reads by the names the MTL gives.
pub(crate) fn look(material: &tobj::Material, image: &dyn Fn(&str) -> Arc<Texture>) -> Look {
    let color = match material.diffuse {
        Some([r, g, b]) => Color::rgb(r as f32, g as f32, b as f32),
        None => Color::default(),
    };
    let color = Color {
        a: material.dissolve.map_or(1.0, |d| d.clamp(0.0, 1.0) as f32),
        ..color
    };
    let map = |name: &Option<String>| name.as_deref().and_then(file_name).map(|f| image(&f));
    let unknown = |key: &str| material.unknown_param.get(key).cloned();
    let maps = Maps {
        specular: map(&material.specular_texture),
        opacity: map(&material.dissolve_texture),
        // tobj reads `bump` and `map_Bump` as its normal texture; CGA's bump map is the one.
        bump: map(&material.normal_texture),
        normal: map(&unknown("norm")),
        emissive: map(&unknown("map_Ke")),
        ..Maps::default()
    };
    let channels = |c: Option<[f64; 3]>| c.map(|c| c.map(|x| x.clamp(0.0, 1.0) as f32));
    let finish = Finish {
        specular: channels(material.specular),
        ambient: channels(material.ambient),
        emissive: channels(material.emissive),
        shininess: material.shininess.map(|s| s.clamp(0.0, 128.0) as f32),
        ..Finish::default()
    };
    let surface = (!finish.is_unset() || !maps.is_empty()).then(|| {
        Arc::new(Surface {
            finish,
            maps,
            ..Surface::default()
        })
    });
    Look {
        color,
        name: Arc::from(material.name.as_str()),
        texture: map(&material.diffuse_texture),
        surface,
    }
}

/// The file a texture statement names: its last word when options (`-s 1 1 1 …`) come first,
/// with Windows separators turned to `/`.
fn file_name(statement: &str) -> Option<String> {
    let statement = statement.trim();
    let file = if statement.starts_with('-') {
        statement.split_whitespace().next_back()?
    } else {
        statement
    };
    (!file.is_empty()).then(|| file.replace('\\', "/"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_statements_name_their_last_word_after_options() {
        assert_eq!(file_name("brick.png").as_deref(), Some("brick.png"));
        assert_eq!(
            file_name("-s 2 2 1 maps\\brick.png").as_deref(),
            Some("maps/brick.png")
        );
        assert_eq!(file_name("  "), None);
    }
}
