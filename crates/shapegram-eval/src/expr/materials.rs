//! `getMaterial(source, mode)` and `readMaterial(path)`: a shape's material, or a material
//! file's, as CGA's attribute names and their values, a table of rows `[name, value]` that
//! CGA's `setMaterial` takes.

use std::sync::Arc;

use shapegram_geom::{AlphaMode, Color, Finish};

use super::{Evaluator, Result};
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::texturing::{COLORMAP, LAYERS, UV_SETS};
use crate::value::Value;

/// A material as far as it is set: `None` and empty layers leave CGA's defaults.
#[derive(Default)]
struct Material {
    name: Option<Arc<str>>,
    color: Option<Color>,
    finish: Finish,
    /// The texture of each layer, in the order of [`LAYERS`], by the path it was named by.
    layers: [Option<Arc<str>>; UV_SETS],
}

impl Material {
    /// What the grammar set on the shape itself.
    fn of_shape(shape: &State) -> Self {
        let mut material = Self {
            name: shape.material.clone(),
            color: shape.painted.then_some(shape.color),
            ..Self::default()
        };
        if let Some(texturing) = &shape.texturing {
            material.finish = texturing.finish;
            for (layer, map) in material.layers.iter_mut().zip(&texturing.maps) {
                *layer = map.as_ref().map(|t| Arc::clone(&t.path));
            }
        }
        material
    }

    /// The material of the shape's geometry: an inserted asset's first material, else none.
    fn of_geometry(shape: &State) -> Self {
        let worn = shape.texturing.as_ref().and_then(|t| t.asset.as_ref());
        let Some(part) = worn.and_then(|a| a.look.first_material()) else {
            return Self::default();
        };
        let mut material = Self {
            name: part.name.clone(),
            color: Some(part.color),
            ..Self::default()
        };
        material.layers[COLORMAP] = part.texture.as_ref().map(|t| Arc::clone(&t.path));
        if let Some(surface) = &part.surface {
            material.finish = surface.finish;
            for (name, map) in surface.maps.layers() {
                if let Some(i) = LAYERS.iter().position(|l| *l == name) {
                    material.layers[i] = map.map(|t| Arc::clone(&t.path));
                }
            }
        }
        material
    }

    /// The first material of an MTL file, its textures named by their paths from the folder
    /// `folder` the file is in, as the statements map to CGA's attributes (`Kd` colour, `d`
    /// opacity, `Ns` shininess, `Ks`, `Ka` and `Ke` the specular, ambient and emissive colours;
    /// `map_Kd`, `map_d`, `map_Ks`, `bump` and `norm` the colour, opacity, specular, bump and
    /// normal maps).
    fn from_mtl(text: &str, folder: &str) -> std::result::Result<Self, String> {
        let (materials, _) = tobj::load_mtl_buf(&mut text.as_bytes())
            .map_err(|e| format!("not a material file ({e})"))?;
        let first = materials
            .first()
            .ok_or_else(|| "the file defines no material (`newmtl`)".to_owned())?;
        let unit = |v: f64| v as f32;
        let colour = |c: Option<[f64; 3]>| c.map(|c| c.map(unit));
        let mut material = Self {
            name: Some(Arc::from(first.name.as_str())),
            color: first.diffuse.map(|[r, g, b]| Color {
                r: unit(r),
                g: unit(g),
                b: unit(b),
                a: unit(first.dissolve.unwrap_or(1.0)),
            }),
            ..Self::default()
        };
        material.finish.shininess = first.shininess.map(unit);
        material.finish.specular = colour(first.specular);
        material.finish.ambient = colour(first.ambient);
        material.finish.emissive = colour(first.emissive);
        let path = |file: &String| -> Arc<str> {
            match folder {
                "" => Arc::from(file.as_str()),
                _ => Arc::from(format!("{folder}/{file}")),
            }
        };
        let layer = |name: &str| LAYERS.iter().position(|l| *l == name).unwrap_or(0);
        for (name, file) in [
            ("colormap", first.diffuse_texture.as_ref()),
            ("opacitymap", first.dissolve_texture.as_ref()),
            ("specularmap", first.specular_texture.as_ref()),
            ("bumpmap", first.normal_texture.as_ref()),
            ("normalmap", first.unknown_param.get("norm")),
        ] {
            material.layers[layer(name)] = file.map(path);
        }
        Ok(material)
    }

    /// `self` over `under`, attribute by attribute, as a shape's material overrides its
    /// geometry's.
    fn over(self, under: Self) -> Self {
        let surface = |finish: Finish| shapegram_geom::Surface {
            finish,
            maps: shapegram_geom::Maps::default(),
            transforms: Default::default(),
        };
        let finish = surface(self.finish).over(&surface(under.finish)).finish;
        let mut layers = under.layers;
        for (mine, theirs) in self.layers.into_iter().zip(layers.iter_mut()) {
            if mine.is_some() {
                *theirs = mine;
            }
        }
        Self {
            name: self.name.or(under.name),
            color: self.color.or(under.color),
            finish,
            layers,
        }
    }

    /// The rows `[name, value]`: of every attribute (`all`, defaults where not set) or only
    /// of those set (`changed`).
    fn rows(&self, all: bool) -> Vec<Value> {
        let number = |v: f32| v.to_string();
        let mut rows: Vec<(String, Option<String>, String)> = Vec::new();
        let mut add = |name: &str, value: Option<String>, default: &str| {
            rows.push((name.to_owned(), value, default.to_owned()));
        };
        add("name", self.name.as_deref().map(str::to_owned), "");
        for (i, channel) in ["color.r", "color.g", "color.b"].iter().enumerate() {
            let value = self.color.map(|c| number([c.r, c.g, c.b][i]));
            add(channel, value, "1");
        }
        // `color(r, g, b)` leaves opacity as it was: only an opacity below 1 was set.
        let opacity = self.color.filter(|c| c.a != 1.0).map(|c| number(c.a));
        add("opacity", opacity, "1");
        let f = &self.finish;
        add("metallic", f.metallic.map(number), "0");
        add("roughness", f.roughness.map(number), "1");
        for (colour, value) in [
            ("emissive", f.emissive),
            ("specular", f.specular),
            ("ambient", f.ambient),
        ] {
            for (i, c) in ["r", "g", "b"].iter().enumerate() {
                add(&format!("{colour}.{c}"), value.map(|v| number(v[i])), "0");
            }
        }
        add("shininess", f.shininess.map(number), "1");
        add("reflectivity", f.reflectivity.map(number), "0");
        add("bumpValue", f.bump_value.map(number), "1");
        let mode = |m: AlphaMode| match m {
            AlphaMode::Blend => "blend",
            AlphaMode::Mask => "mask",
            AlphaMode::Opaque => "opaque",
        };
        add(
            "opacitymap.mode",
            f.alpha_mode.map(|m| mode(m).to_owned()),
            "blend",
        );
        add("opacitymap.cutoff", f.alpha_cutoff.map(number), "0.5");
        add("doubleSided", f.double_sided.map(|d| d.to_string()), "true");
        for (name, layer) in LAYERS.iter().zip(&self.layers) {
            add(name, layer.as_deref().map(str::to_owned), "");
        }
        rows.into_iter()
            .filter_map(|(name, value, default)| match value {
                Some(value) => Some((name, value)),
                None => all.then_some((name, default)),
            })
            .map(|(name, value)| {
                Value::Array(Arc::from([Value::string(&name), Value::string(&value)]))
            })
            .collect()
    }
}

impl Evaluator<'_> {
    /// `getMaterial(used | shape | geometry, changed | all)`.
    pub(super) fn material_table(
        &mut self,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let source = self.word(&params[0], shape, args)?;
        let mode = self.word(&params[1], shape, args)?;
        let material = match &*source {
            "shape" => Material::of_shape(shape),
            "geometry" => Material::of_geometry(shape),
            "used" => Material::of_shape(shape).over(Material::of_geometry(shape)),
            other => {
                return Err(DeriveError::at(
                    format!("expected `used`, `shape` or `geometry`, found `{other}`"),
                    params[0].span,
                ));
            }
        };
        let all = match &*mode {
            "all" => true,
            "changed" => false,
            other => {
                return Err(DeriveError::at(
                    format!("expected `changed` or `all`, found `{other}`"),
                    params[1].span,
                ));
            }
        };
        Ok(Value::Array(material.rows(all).into()))
    }

    /// `readMaterial(path)`: the attributes an MTL file's first material sets, read as assets
    /// are; a `.cgamat` file, whose format CityEngine does not publish, is an error.
    pub(super) fn read_material(
        &mut self,
        path: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = self.string(path, shape, args)?;
        let lower = name.to_ascii_lowercase();
        if lower.ends_with(".cgamat") {
            return Err(DeriveError::at(
                format!("cannot read `{name}`: CityEngine's .cgamat format is not supported"),
                path.span,
            )
            .with_hint("export the material as an .mtl file and read that"));
        }
        if !lower.ends_with(".mtl") {
            return Err(DeriveError::at(
                format!("`{name}` is no material file: expected a .mtl (or .cgamat) file"),
                path.span,
            ));
        }
        let loader = self.loader(&format!("read `{name}`"), path.span)?;
        let text = loader
            .text(&name)
            .map_err(|why| DeriveError::at(why, path.span))?;
        let folder = name.rfind('/').map_or("", |i| &name[..i]);
        let material = Material::from_mtl(&text, folder)
            .map_err(|why| DeriveError::at(format!("`{name}`: {why}"), path.span))?;
        Ok(Value::Array(material.rows(false).into()))
    }
}
