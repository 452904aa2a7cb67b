//! Where a grammar's `i("file")`, `texture("file")`, `implicit("file")`, tables and file
//! searches find their files: beside the grammar, in its CityEngine project, in the workspace;
//! on disk or in a rule package.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use shapegram_eval::asset_look::AssetLook;
use shapegram_eval::{ASSET_VARIANTS, Asset, AssetLoader, AssetNaming};
use shapegram_geom::{DVec3, Mesh};
use shapegram_implicit::Solid;

use crate::files::Files;
use crate::package::RulePackage;

/// What to insert in place of an asset file that cannot be read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MissingAssets {
    /// Stop the derivation with an error naming the file and the grammar line.
    #[default]
    Error,
    /// Insert a cube filling the scope, so the model keeps its massing.
    Cube,
    /// Insert nothing.
    Skip,
}

/// Assets for `i("path")`: files relative to the grammar's folder (absolute paths as they are),
/// read once each with `shapegram_export::load`, all parts merged into one mesh that keeps
/// their materials and uvs (see [`AssetLook`]); L-system files
/// are grown once per variant. Files that cannot be read are an error, or stand-ins as
/// `--missing-assets` says. Every file the derivation reads (assets, textures, tables, file
/// searches) is found by [`FileAssets::find`]'s one search.
pub struct FileAssets {
    /// Where the files are: on disk or in a rule package.
    files: Files,
    folder: PathBuf,
    /// The CityEngine project the grammar is in: the nearest folder at or above the grammar's
    /// that has an `assets` folder.
    project: Option<PathBuf>,
    /// Where each path asked for was found.
    found: Mutex<HashMap<String, PathBuf>>,
    missing: MissingAssets,
    cache: Mutex<HashMap<PathBuf, Loaded>>,
    plants: Mutex<HashMap<(PathBuf, u32), Arc<Mesh>>>,
    solids: Mutex<HashMap<PathBuf, Solid>>,
    texts: Mutex<HashMap<PathBuf, Arc<str>>>,
    images: Mutex<HashMap<PathBuf, Option<Arc<[u8]>>>>,
    image_sizes: Mutex<HashMap<PathBuf, Result<ImageSize, String>>>,
    searches: Mutex<HashMap<String, Vec<Arc<str>>>>,
}

impl FileAssets {
    /// Assets for a grammar in `folder` (the current folder when empty); `missing` says what
    /// stands in for a file that cannot be read.
    pub fn new(folder: PathBuf, missing: MissingAssets) -> Self {
        // Workspace paths (`/Project/…`) need to know the folder above the project.
        let folder = if folder.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            folder
        };
        let folder = std::fs::canonicalize(&folder).unwrap_or(folder);
        let project = folder
            .ancestors()
            .find(|a| a.join("assets").is_dir())
            .map(Path::to_path_buf);
        Self::with_files(Files::Disk, folder, project, missing)
    }

    /// Assets for the rule file `rule_file` (an entry such as `rules/a.cga`) of a rule package:
    /// the package is the project.
    pub fn in_package(package: Arc<RulePackage>, rule_file: &str, missing: MissingAssets) -> Self {
        let folder = Path::new(rule_file)
            .parent()
            .map_or_else(PathBuf::new, Path::to_path_buf);
        Self::with_files(
            Files::Package(package),
            folder,
            Some(PathBuf::new()),
            missing,
        )
    }

    fn with_files(
        files: Files,
        folder: PathBuf,
        project: Option<PathBuf>,
        missing: MissingAssets,
    ) -> Self {
        Self {
            files,
            folder,
            project,
            found: Mutex::new(HashMap::new()),
            missing,
            cache: Mutex::new(HashMap::new()),
            plants: Mutex::new(HashMap::new()),
            solids: Mutex::new(HashMap::new()),
            texts: Mutex::new(HashMap::new()),
            images: Mutex::new(HashMap::new()),
            image_sizes: Mutex::new(HashMap::new()),
            searches: Mutex::new(HashMap::new()),
        }
    }

    /// Where `path` is, searched as CityEngine does: next to the grammar, then in the project's
    /// `assets` folder, then in the project; a path starting with `/` is in the workspace (the
    /// folder holding the project, or the `.ws` folder of the grammar's folder or one above it).
    /// In a rule package, the package's resolve map comes first, and workspace paths name the
    /// package itself (`/Project/…`) or the workspace files it brings (`.ws/`). The first place
    /// that has the file, or else the first place. Each path is looked for once: every insert
    /// asks.
    pub fn find(&self, path: &str) -> PathBuf {
        let mut found = self.found.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(place) = found.get(path) {
            return place.clone();
        }
        let place = self.search(path);
        found.insert(path.to_owned(), place.clone());
        place
    }

    /// The search behind [`FileAssets::find`].
    fn search(&self, path: &str) -> PathBuf {
        let mut places = Vec::new();
        if let Files::Package(package) = &self.files {
            places.extend(package.resolve(path).map(PathBuf::from));
        }
        match path.strip_prefix('/') {
            Some(in_workspace) if let Files::Package(package) = &self.files => {
                let own = in_workspace
                    .strip_prefix(package.project())
                    .and_then(|p| p.strip_prefix('/'));
                places.extend(own.map(PathBuf::from));
                places.push(Path::new(".ws").join(in_workspace));
            }
            Some(in_workspace) => {
                // Without a project, the grammar's folder stands for it (as `fileSearch` takes it).
                let project = self.project.as_deref().unwrap_or(&self.folder);
                if let Some(workspace) = project.parent() {
                    places.push(workspace.join(in_workspace));
                }
                // An extracted rule package keeps the workspace files it brings in `.ws/` at
                // its root, which need not have an `assets` folder.
                places.extend(
                    self.folder
                        .ancestors()
                        .map(|folder| folder.join(".ws").join(in_workspace)),
                );
                places.push(self.folder.join(in_workspace));
            }
            None => {
                places.push(self.folder.join(path));
                if let Some(project) = &self.project {
                    places.push(project.join("assets").join(path));
                    places.push(project.join(path));
                }
            }
        }
        places
            .iter()
            .find(|p| self.files.is_file(p))
            .unwrap_or(&places[0])
            .clone()
    }

    /// How messages name the file at `full`.
    fn display(&self, full: &Path) -> String {
        self.files.display(full)
    }

    /// A text file (an L-system or implicit grammar) and its name for messages.
    fn read_text(&self, full: &Path) -> Result<NamedText, String> {
        let name = self.display(full);
        let bytes = self.files.read(full)?;
        let text = String::from_utf8(bytes).map_err(|_| format!("{name} is not UTF-8 text"))?;
        Ok(NamedText { name, text })
    }

    /// The asset at `path` with its look (for files that have materials or uvs), read once
    /// per file.
    fn load_worn(&self, path: &str) -> Result<Loaded, String> {
        let full = self.find(path);
        // Loading under the lock means each file is read once even when lots derived in
        // parallel ask for it together.
        let mut cache = self.cache.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(loaded) = cache.get(&full) {
            return Ok(loaded.clone());
        }
        let mut look = None;
        let mut naming = AssetNaming::default();
        let mut groups = None;
        let read = match full.extension().and_then(|e| e.to_str()) {
            Some("lsys") => self
                .read_text(&full)
                .and_then(|t| plant(&t, 0))
                .map(|(m, _)| m),
            Some("cave") => self.read_text(&full).and_then(|t| carve(&t)),
            _ => {
                let shown = PathBuf::from(self.display(&full));
                shapegram_export::load_with(&shown, |file| {
                    self.files.read_io(&self.files.undisplay(file))
                })
                .map(|model| {
                    let (mesh, worn) = AssetLook::from_parts(&model.parts);
                    look = worn;
                    naming = names(&model.parts);
                    groups = shapegram_eval::tags::face_groups(&model.parts);
                    mesh
                })
                .map_err(|e| e.to_string())
            }
        };
        let loaded = Loaded {
            mesh: self.or_stand_in(read)?,
            look,
            naming: Arc::new(naming),
            groups,
        };
        cache.insert(full, loaded.clone());
        Ok(loaded)
    }

    /// What stands in for a file that cannot be read, if anything does.
    fn stand_in(&self) -> Option<Mesh> {
        match self.missing {
            MissingAssets::Error => None,
            MissingAssets::Cube => Some(shapegram_geom::primitives::cuboid(DVec3::ONE)),
            MissingAssets::Skip => Some(Mesh::new()),
        }
    }

    /// The mesh loaded, or the stand-in for a file that cannot be read (reported once per
    /// file, since callers cache what they get).
    fn or_stand_in(&self, loaded: Result<Mesh, String>) -> Result<Arc<Mesh>, String> {
        let mesh = match loaded {
            Ok(mesh) => mesh,
            Err(e) => {
                let Some(stand_in) = self.stand_in() else {
                    return Err(e);
                };
                eprintln!(
                    "warning: {e}: inserting {}",
                    match self.missing {
                        MissingAssets::Cube => "a cube instead",
                        _ => "nothing",
                    }
                );
                stand_in
            }
        };
        Ok(Arc::new(mesh))
    }
}

/// An image's width and height in pixels.
type ImageSize = (u32, u32);

/// An asset file as read: its parts merged, and their materials and uvs.
#[derive(Clone)]
struct Loaded {
    mesh: Arc<Mesh>,
    look: Option<Arc<AssetLook>>,
    groups: Option<Arc<[Arc<str>]>>,
    naming: Arc<AssetNaming>,
}

/// The group and material names of an asset's parts, each once, in the order of the parts.
fn names(parts: &[shapegram_geom::Part]) -> AssetNaming {
    let mut naming = AssetNaming::default();
    for part in parts {
        if !naming.groups.iter().any(|g| **g == *part.name) {
            naming.groups.push(Arc::from(part.name.as_str()));
        }
        if let Some(material) = &part.material
            && !naming.materials.contains(material)
        {
            naming.materials.push(Arc::clone(material));
        }
    }
    naming
}

/// A text file's contents and its name for messages.
struct NamedText {
    name: String,
    text: String,
}

impl AssetLoader for FileAssets {
    /// Files under the project (the grammar's folder when it is in none); each query is
    /// answered once.
    fn search(&self, query: &str) -> Result<Vec<Arc<str>>, String> {
        let mut searches = self.searches.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(found) = searches.get(query) {
            return Ok(found.clone());
        }
        let root = self.project.as_deref().unwrap_or(&self.folder);
        let name = match &self.files {
            Files::Disk => root
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
            Files::Package(package) => package.project().to_owned(),
        };
        let found: Vec<Arc<str>> = crate::search::search_in(&self.files, root, &name, query)?
            .into_iter()
            .map(Arc::from)
            .collect();
        searches.insert(query.to_owned(), found.clone());
        Ok(found)
    }

    /// Text files (tables) as UTF-8 or, with a byte-order mark, UTF-16; read once each. A
    /// file that cannot be read is a warning (once per file) and an empty table, whatever
    /// `--missing-assets` says: CityEngine's `readStringTable` reports the file and goes on
    /// with an empty table.
    fn text(&self, path: &str) -> Result<Arc<str>, String> {
        let full = self.find(path);
        let mut texts = self.texts.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(text) = texts.get(&full) {
            return Ok(Arc::clone(text));
        }
        let read = self.files.read(&full).and_then(|bytes| {
            let (text, _, malformed) = encoding_rs::Encoding::for_bom(&bytes)
                .map_or(encoding_rs::UTF_8, |(encoding, _)| encoding)
                .decode(&bytes);
            if malformed {
                return Err(format!(
                    "{} is not UTF-8 or UTF-16 text",
                    self.display(&full)
                ));
            }
            Ok(Arc::from(text.as_ref()))
        });
        let text = read.unwrap_or_else(|e| {
            eprintln!("warning: {e}: reading an empty table instead");
            Arc::from("")
        });
        texts.insert(full, Arc::clone(&text));
        Ok(text)
    }

    /// PNG and JPEG images (what glTF embeds), read once each and found as assets are. A file
    /// that cannot be read, or is of another format, is a warning (once per file) and no image:
    /// the shapes keep their colour, as CityEngine draws its placeholder and goes on, since a
    /// texture changes no geometry.
    fn image(&self, path: &str) -> Result<Option<Arc<[u8]>>, String> {
        let full = self.find(path);
        let mut images = self.images.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(image) = images.get(&full) {
            return Ok(image.clone());
        }
        let read = self.files.read(&full).and_then(|bytes| {
            let texture = shapegram_geom::Texture {
                path: Arc::from(path),
                image: Some(Arc::from(bytes)),
            };
            match texture.mime_type() {
                Some(_) => Ok(texture.image),
                None => Err(format!(
                    "{} is not a PNG or JPEG image (the formats glTF embeds)",
                    self.display(&full)
                )),
            }
        });
        let image = read.unwrap_or_else(|e| {
            eprintln!("warning: {e}: the shapes keep their colour instead");
            None
        });
        images.insert(full, image.clone());
        Ok(image)
    }

    /// Read from the image's header (PNG, JPEG, TIFF, BMP, GIF, WebP), once per file.
    fn image_size(&self, path: &str) -> Result<(u32, u32), String> {
        let full = self.find(path);
        let mut sizes = self
            .image_sizes
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if let Some(size) = sizes.get(&full) {
            return size.clone();
        }
        let size = self.files.read(&full).and_then(|bytes| {
            let size = imagesize::blob_size(&bytes).map_err(|e| {
                format!(
                    "cannot read the size of the image {}: {e} (PNG, JPEG, TIFF, BMP, GIF and WebP are read)",
                    self.display(&full)
                )
            })?;
            let pixels = |n: usize| u32::try_from(n).map_err(|_| format!("{}: {n} pixels is too many", self.display(&full)));
            Ok((pixels(size.width)?, pixels(size.height)?))
        });
        sizes.insert(full, size.clone());
        size
    }

    /// The names of the file's parts; none for grown assets (L-systems, caves) and
    /// stand-ins.
    fn naming(&self, path: &str) -> Result<Arc<AssetNaming>, String> {
        self.load_worn(path).map(|loaded| loaded.naming)
    }

    fn beside(&self, folder: &str, path: &str) -> Option<String> {
        // Beside the rule's file, then in the project's assets (not beside the grammar, which
        // CityEngine does not search for an imported file's names), each named from the
        // grammar's folder, where the search starts.
        let assets = self.project.as_ref().map(|project| {
            match crate::files::relative(&self.folder, &project.join("assets")) {
                assets if assets.is_empty() => path.to_owned(),
                assets => format!("{assets}/{path}"),
            }
        });
        std::iter::once(format!("{folder}/{path}"))
            .chain(assets)
            .find(|named| self.files.is_file(&self.folder.join(named)))
    }

    fn load(&self, path: &str) -> Result<Arc<Mesh>, String> {
        self.load_worn(path).map(|loaded| loaded.mesh)
    }

    /// L-systems keep their proportions, and stochastic ones grow one tree per variant.
    fn asset(&self, path: &str, variant: u32) -> Result<Asset, String> {
        let full = self.find(path);
        if full.extension().and_then(|e| e.to_str()) != Some("lsys") {
            let Loaded {
                mesh, look, groups, ..
            } = self.load_worn(path)?;
            return Ok(Asset {
                mesh,
                proportional: false,
                look,
                groups,
            });
        }
        let mut plants = self.plants.lock().unwrap_or_else(PoisonError::into_inner);
        let key = (full, variant);
        let mesh = match plants.get(&key) {
            Some(mesh) => Arc::clone(mesh),
            None => {
                let grown = self.read_text(&key.0).and_then(|t| plant(&t, variant));
                // A system without random choices grows the same tree for every variant.
                let variants = match &grown {
                    Ok((_, true)) => variant..variant + 1,
                    _ => 0..ASSET_VARIANTS,
                };
                let mesh = self.or_stand_in(grown.map(|(mesh, _)| mesh))?;
                for v in variants {
                    plants.insert((key.0.clone(), v), Arc::clone(&mesh));
                }
                mesh
            }
        };
        Ok(Asset {
            mesh,
            proportional: true,
            look: None,
            groups: None,
        })
    }

    /// `implicit("grotto.cave")`: the grammar's solid, run once per file. Files that cannot be
    /// read are always an error (`--missing-assets` is about `i()`).
    fn solid(&self, path: &str) -> Result<Solid, String> {
        let full = self.find(path);
        let mut solids = self.solids.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(solid) = solids.get(&full) {
            return Ok(solid.clone());
        }
        if full.extension().and_then(|e| e.to_str()) != Some("cave") {
            return Err("only implicit grammars (.cave files) make implicit solids".to_owned());
        }
        let (solid, _) = cave_solid(&self.read_text(&full)?)?;
        solids.insert(full, solid.clone());
        Ok(solid)
    }
}

/// The geometry of an L-system file (`i("tree.lsys")`): derived with the settings of the file,
/// interpreted by its homomorphism rules and drawn with the turtle, as one mesh. A stochastic
/// system's variant `k` derives with the file's seed plus `k`, so variant 0 is the tree that
/// `shapegram lsystem` draws; other systems ignore the variant. Also says whether the system is
/// stochastic.
fn plant(file: &NamedText, variant: u32) -> Result<(Mesh, bool), String> {
    let NamedText { name, text } = file;
    let system = shapegram_lsystem::LSystem::parse(text).map_err(|e| e.render(name, text))?;
    let options = shapegram_lsystem::DeriveOptions {
        seed: system
            .is_stochastic()
            .then(|| system.settings.seed.wrapping_add(u64::from(variant))),
        ..shapegram_lsystem::DeriveOptions::default()
    };
    let model = shapegram_lsystem::model(&system, &options).map_err(|e| e.render(name, text))?;
    Ok((model.merged_mesh(), system.is_stochastic()))
}

/// The geometry of an implicit grammar (`i("grotto.cave")`): its productions run with the seed
/// of the file and meshed at its level of detail, as one closed mesh that `i` stretches to the
/// scope like any asset.
fn carve(file: &NamedText) -> Result<Mesh, String> {
    let (solid, lod) = cave_solid(file)?;
    let options = shapegram_implicit::MeshOptions::with_cell_size(1.0 / f64::from(lod));
    shapegram_implicit::mesh(&solid, &options)
        .map(|meshing| meshing.mesh)
        .map_err(|e| format!("{}: {e}", file.name))
}

/// The solid an implicit grammar makes with the seed of its file, and its level of detail.
fn cave_solid(file: &NamedText) -> Result<(Solid, u32), String> {
    let NamedText { name, text } = file;
    let located = |e: shapegram_implicit::TextError| format!("{name}:{e}");
    let program = shapegram_implicit::text::parse(text).map_err(located)?;
    let run = program.run(None).map_err(located)?;
    let lod = program
        .lod
        .unwrap_or(shapegram_implicit::CaveParams::default().lod);
    Ok((run.builder.solid().clone(), lod))
}
