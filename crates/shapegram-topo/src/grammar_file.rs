//! The `.grammar` file layout (versioned JSON, see docs/topo.md) and its conversion to and from
//! a [`Grammar`], with the helpers project files share: colours, points and JSON messages.

use serde::{Deserialize, Serialize};
use shapegram_geom::{Color, DVec2, DVec3};

use crate::grammar::{
    GRAMMAR_FORMAT, GRAMMAR_VERSION, GRAMMAR_VERSION_PLAIN, Grammar, GrammarError, GrammarRule,
    GrammarShape, GrammarSymbol, OffsetCut, SubShape, VirtualVertex,
};
use crate::material::Material;
use crate::polyhedron::Index;

/// An optional `#rrggbb` colour from a file; `location` names the field for the error.
fn parse_color(
    hex: Option<&str>,
    location: impl FnOnce() -> String,
) -> Result<Option<Color>, GrammarError> {
    match hex {
        None => Ok(None),
        Some(hex) => Color::from_hex(hex).map(Some).ok_or_else(|| GrammarError {
            location: location(),
            message: format!("'{}' is not a colour like '#3a6ea5'", hex.escape_debug()),
        }),
    }
}

/// A serde error message without serde's own "at line … column …" suffix.
pub(crate) fn json_message(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rfind(" at line ") {
        Some(cut) => text[..cut].to_owned(),
        None => text,
    }
}

/// `[x, y, z]` in files.
pub(crate) type Point = [f64; 3];

pub(crate) fn point(p: DVec3) -> Point {
    p.to_array()
}

/// The file layout of a `.grammar`.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GrammarFile {
    format: String,
    version: u32,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    materials: Vec<MaterialEntry>,
    symbols: Vec<SymbolEntry>,
    shapes: Vec<ShapeEntry>,
    rules: Vec<RuleEntry>,
}

/// A material in grammar and project files.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MaterialEntry {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    color: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    texture: Option<String>,
    /// `[width, height]` in metres.
    tile: [f64; 2],
}

impl From<&Material> for MaterialEntry {
    fn from(m: &Material) -> Self {
        Self {
            name: m.name.clone(),
            color: m.color.map(|c| c.to_hex()),
            texture: m.texture.clone(),
            tile: m.tile.to_array(),
        }
    }
}

impl MaterialEntry {
    /// The material, its colour parsed (`location` names the entry for the error); the rest is
    /// checked by [`Material::check`].
    pub(crate) fn into_material(self, location: &str) -> Result<Material, GrammarError> {
        Ok(Material {
            color: parse_color(self.color.as_deref(), || format!("{location}.color"))?,
            name: self.name,
            texture: self.texture,
            tile: DVec2::from_array(self.tile),
        })
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SymbolEntry {
    name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    color: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    face_colors: Vec<Option<String>>,
    vertex_count: u32,
    faces: Vec<Vec<Index>>,
    rules: Vec<Index>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ShapeEntry {
    symbol: Index,
    vertices: Vec<Point>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RuleEntry {
    symbol: Index,
    name: String,
    weight: f64,
    virtual_vertices: Vec<(Index, Index, f64)>,
    sub_shapes: Vec<SubShapeEntry>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    offset_cuts: Vec<OffsetCutEntry>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SubShapeEntry {
    symbol: Index,
    vertices: Vec<Index>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    materials: Vec<Option<Index>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    from_faces: Vec<Option<Index>>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct OffsetCutEntry {
    step: u32,
    face: [Index; 3],
    distance: f64,
    vertices: Vec<Index>,
}

impl From<&Grammar> for GrammarFile {
    fn from(grammar: &Grammar) -> Self {
        Self {
            format: GRAMMAR_FORMAT.into(),
            version: if grammar.needs_version_2() {
                GRAMMAR_VERSION
            } else {
                GRAMMAR_VERSION_PLAIN
            },
            materials: grammar.materials.iter().map(MaterialEntry::from).collect(),
            symbols: grammar
                .symbols
                .iter()
                .map(|s| SymbolEntry {
                    name: s.name.clone(),
                    color: s.color.map(|c| c.to_hex()),
                    face_colors: s
                        .face_colors
                        .iter()
                        .map(|c| c.map(|c| c.to_hex()))
                        .collect(),
                    vertex_count: s.vertex_count,
                    faces: s.faces.clone(),
                    rules: s.rules.clone(),
                })
                .collect(),
            shapes: grammar
                .shapes
                .iter()
                .map(|s| ShapeEntry {
                    symbol: s.symbol,
                    vertices: s.vertices.iter().map(|&p| point(p)).collect(),
                })
                .collect(),
            rules: grammar
                .rules
                .iter()
                .map(|r| RuleEntry {
                    symbol: r.symbol,
                    name: r.name.clone(),
                    weight: r.weight,
                    virtual_vertices: r
                        .virtual_vertices
                        .iter()
                        .map(|v| (v.from, v.to, v.t))
                        .collect(),
                    sub_shapes: r
                        .sub_shapes
                        .iter()
                        .map(|s| SubShapeEntry {
                            symbol: s.symbol,
                            vertices: s.vertices.clone(),
                            materials: s.materials.clone(),
                            from_faces: s.from_faces.clone(),
                        })
                        .collect(),
                    offset_cuts: r
                        .offset_cuts
                        .iter()
                        .map(|c| OffsetCutEntry {
                            step: c.step,
                            face: c.face,
                            distance: c.distance,
                            vertices: c.vertices.clone(),
                        })
                        .collect(),
                })
                .collect(),
        }
    }
}

impl GrammarFile {
    pub(crate) fn into_grammar(self) -> Result<Grammar, GrammarError> {
        if self.format != GRAMMAR_FORMAT {
            return Err(GrammarError {
                location: "format".into(),
                message: format!(
                    "'{}' is not a topological grammar (expected '{GRAMMAR_FORMAT}')",
                    self.format.escape_debug()
                ),
            });
        }
        if !(1..=GRAMMAR_VERSION).contains(&self.version) {
            return Err(GrammarError {
                location: "version".into(),
                message: format!(
                    "version {} is not supported (this build reads versions 1 to \
                     {GRAMMAR_VERSION})",
                    self.version
                ),
            });
        }
        let materials = self
            .materials
            .into_iter()
            .enumerate()
            .map(|(i, m)| m.into_material(&format!("materials[{i}]")))
            .collect::<Result<_, _>>()?;
        let mut symbols = Vec::with_capacity(self.symbols.len());
        for (i, s) in self.symbols.into_iter().enumerate() {
            let color = parse_color(s.color.as_deref(), || format!("symbols[{i}].color"))?;
            let face_colors = s
                .face_colors
                .iter()
                .enumerate()
                .map(|(f, hex)| {
                    parse_color(hex.as_deref(), || format!("symbols[{i}].face_colors[{f}]"))
                })
                .collect::<Result<_, _>>()?;
            symbols.push(GrammarSymbol {
                name: s.name,
                color,
                face_colors,
                vertex_count: s.vertex_count,
                faces: s.faces,
                rules: s.rules,
            });
        }
        let grammar = Grammar {
            shapes: self
                .shapes
                .into_iter()
                .map(|s| GrammarShape {
                    symbol: s.symbol,
                    vertices: s.vertices.into_iter().map(DVec3::from_array).collect(),
                })
                .collect(),
            symbols,
            rules: self
                .rules
                .into_iter()
                .map(|r| GrammarRule {
                    symbol: r.symbol,
                    name: r.name,
                    weight: r.weight,
                    virtual_vertices: r
                        .virtual_vertices
                        .into_iter()
                        .map(|(from, to, t)| VirtualVertex { from, to, t })
                        .collect(),
                    sub_shapes: r
                        .sub_shapes
                        .into_iter()
                        .map(|s| SubShape {
                            symbol: s.symbol,
                            vertices: s.vertices,
                            materials: s.materials,
                            from_faces: s.from_faces,
                        })
                        .collect(),
                    offset_cuts: r
                        .offset_cuts
                        .into_iter()
                        .map(|c| OffsetCut {
                            step: c.step,
                            face: c.face,
                            distance: c.distance,
                            vertices: c.vertices,
                        })
                        .collect(),
                })
                .collect(),
            materials,
        };
        grammar.validate()?;
        Ok(grammar)
    }
}
