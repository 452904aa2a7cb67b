//! Topological grammars (`.grammar`) as hosts run them: loaded with the images of their
//! materials' textures, read beside the grammar's file as `shapegram topo` reads them, derived
//! generation by generation, and meshed into triangles that reach the buffers with their uvs
//! and textures.

use std::path::Path;
use std::sync::Arc;

use shapegram_export::{Buffers, Corners};
use shapegram_geom::{Model, Texture};
use shapegram_topo::{GrammarMesh, GrammarState};

use crate::error::Error;
use crate::grammar::Settings;

/// Generations of a topological grammar when none are set, as `shapegram topo` has it.
const TOPO_GENERATIONS: u32 = 8;

/// A loaded topological grammar.
pub struct TopoGrammar {
    /// The compiled grammar.
    pub grammar: shapegram_topo::Grammar,
    /// The symbol derivations start from: the grammar's first.
    pub symbol: String,
    /// Per material of the grammar, its texture (`None` for a material without one), the image
    /// read when the grammar was loaded (`None` when it could not be: its faces keep the
    /// material's colour).
    pub textures: Vec<Option<Arc<Texture>>>,
}

impl TopoGrammar {
    /// Parses `text`, named `name` in messages; texture paths are relative to `name`'s folder.
    pub(crate) fn load(name: &str, text: &str) -> Result<TopoGrammar, Error> {
        let grammar = shapegram_topo::Grammar::from_json(text).map_err(|e| {
            let separator = if e.location.starts_with(|c: char| c.is_ascii_digit()) {
                ":"
            } else {
                ": "
            };
            let error = Error::grammar(format!("{name}{separator}{}: {}", e.location, e.message));
            // JSON syntax and type errors are at a line and column; others at a path.
            match e
                .location
                .split_once(':')
                .and_then(|(line, column)| Some((line.parse().ok()?, column.parse().ok()?)))
            {
                Some((line, column)) => error.at(line, column, e.message),
                None => error,
            }
        })?;
        let symbol = grammar
            .symbol_names()
            .first()
            .map(|s| (*s).to_owned())
            .ok_or_else(|| Error::grammar(format!("{name}: the grammar has no symbol")))?;
        let folder = Path::new(name).parent().unwrap_or(Path::new(""));
        let textures = grammar
            .materials
            .iter()
            .map(|m| m.texture_with(|path| read_image(name, folder, path)))
            .collect();
        Ok(TopoGrammar {
            grammar,
            symbol,
            textures,
        })
    }

    /// Runs the grammar from its symbol with the seed and generations of `settings` (8 when
    /// none are set), checking for cancellation before each generation.
    pub(crate) fn derive(&self, settings: &Settings) -> Result<TopoMesh, Error> {
        let generations = settings.generations.unwrap_or(TOPO_GENERATIONS);
        let mut state = GrammarState::new(&self.grammar, &self.symbol)
            .map_err(|e| Error::derive(e.to_string()))?
            .with_seed(settings.seed & shapegram_topo::SEED_MASK)
            .with_generations(generations);
        state.start();
        for _ in 0..generations {
            if state.non_terminals().is_empty() {
                break;
            }
            if settings.control.is_cancelled() {
                return Err(Error::cancelled());
            }
            state
                .next_generation()
                .map_err(|e| Error::derive(e.to_string()))?;
        }
        Ok(TopoMesh {
            mesh: GrammarMesh::new(&state),
            textures: self.textures.clone(),
        })
    }
}

/// The image at `path` relative to `folder`, when it can be read; else a warning naming the
/// grammar `name`, as the command gives, and no image.
fn read_image(name: &str, folder: &Path, path: &str) -> Option<Arc<[u8]>> {
    let file = folder.join(path);
    let problem = match std::fs::read(&file) {
        Ok(bytes) => {
            let texture = Texture {
                path: path.into(),
                image: Some(bytes.into()),
            };
            if texture.mime_type().is_some() {
                return texture.image;
            }
            "it is not a PNG or JPEG image (the formats glTF embeds)".to_owned()
        }
        Err(e) => e.to_string(),
    };
    eprintln!(
        "warning: {name}: cannot read the texture {}: {problem} (its faces are drawn in their \
         colour)",
        file.display()
    );
    None
}

/// A topological grammar's shapes in flat-shaded triangles, with its materials' textures.
pub struct TopoMesh {
    /// The triangles, one part per symbol, face colour and material.
    pub mesh: GrammarMesh,
    /// Per material, its texture, as [`TopoGrammar::textures`] has it.
    pub textures: Vec<Option<Arc<Texture>>>,
}

impl TopoMesh {
    /// The mesh as a model for the exporters, the textures' images in it (a GLB embeds them).
    pub fn to_model(&self) -> Model {
        self.mesh.to_model_with(|path| {
            let texture = self.textures.iter().flatten().find(|t| &*t.path == path)?;
            texture.image.clone()
        })
    }

    /// Replaces the contents of `buffers` with the triangles, textured parts with their uvs.
    pub(crate) fn fill(&self, buffers: &mut Buffers) {
        buffers.clear();
        for (i, part) in self.mesh.parts.iter().enumerate() {
            if part.triangles.is_empty() {
                continue;
            }
            let texture = part
                .material
                .and_then(|m| self.textures[m as usize].as_ref())
                .map(|texture| (texture, part.uvs.as_slice()));
            let corners = Corners {
                positions: &part.positions,
                normals: &part.normals,
                triangles: &part.triangles,
            };
            buffers.push_triangles(i, part.color.to_array(), corners, texture);
        }
    }

    /// The name of the material part `part` is drawn with, if any.
    pub(crate) fn part_material(&self, part: usize) -> Option<&str> {
        let material = self.mesh.parts[part].material?;
        Some(&self.mesh.materials[material as usize].name)
    }
}
