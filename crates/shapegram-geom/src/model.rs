//! A model ready for export: named, coloured meshes.

use std::sync::Arc;

use glam::{DAffine3, DVec2, DVec3};

use shapegram_kinematics::{Frame, SectionId, Skeleton};

use crate::{Aabb, Mesh, Surface, SurfaceKey};

/// An sRGB colour (as in `#rrggbb` notation) with straight alpha, each channel in `0..=1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Color {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Alpha (1 is opaque).
    pub a: f32,
}

impl Default for Color {
    /// A light neutral grey, the colour of shapes nobody coloured.
    fn default() -> Self {
        Self::rgb(0.8, 0.8, 0.8)
    }
}

impl Color {
    /// An opaque colour.
    pub const fn rgb(r: f32, g: f32, b: f32) -> Self {
        Self { r, g, b, a: 1.0 }
    }

    /// Parses `#rgb`, `#rrggbb` or `#rrggbbaa` (the `#` is optional).
    pub fn from_hex(text: &str) -> Option<Self> {
        let hex = text.strip_prefix('#').unwrap_or(text);
        if !hex.is_ascii() {
            return None;
        }
        let channel = |s: &str| u8::from_str_radix(s, 16).ok().map(|v| f32::from(v) / 255.0);
        let short = |i: usize| channel(&hex[i..i + 1].repeat(2));
        match hex.len() {
            3 => Some(Self::rgb(short(0)?, short(1)?, short(2)?)),
            6 | 8 => Some(Self {
                r: channel(&hex[0..2])?,
                g: channel(&hex[2..4])?,
                b: channel(&hex[4..6])?,
                a: if hex.len() == 8 {
                    channel(&hex[6..8])?
                } else {
                    1.0
                },
            }),
            _ => None,
        }
    }

    /// The colour as `#rrggbb` (or `#rrggbbaa` when not opaque).
    pub fn to_hex(&self) -> String {
        let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        let rgb = format!(
            "#{:02x}{:02x}{:02x}",
            byte(self.r),
            byte(self.g),
            byte(self.b)
        );
        if self.a >= 1.0 {
            rgb
        } else {
            format!("{rgb}{:02x}", byte(self.a))
        }
    }

    /// The channels converted to linear light, in RGBA order (alpha unchanged): what glTF's
    /// `baseColorFactor` holds, so that a model looks the colour its grammar names.
    pub fn to_linear(&self) -> [f32; 4] {
        let linear = |c: f32| {
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        [linear(self.r), linear(self.g), linear(self.b), self.a]
    }

    /// A colour from linear-light channels in RGBA order: the inverse of [`Color::to_linear`].
    pub fn from_linear(rgba: [f32; 4]) -> Self {
        let encode = |c: f32| {
            if c <= 0.003_130_8 {
                c * 12.92
            } else {
                1.055 * c.powf(1.0 / 2.4) - 0.055
            }
        };
        Self {
            r: encode(rgba[0]),
            g: encode(rgba[1]),
            b: encode(rgba[2]),
            a: rgba[3],
        }
    }

    /// The channels as an array, in RGBA order.
    pub fn to_array(&self) -> [f32; 4] {
        [self.r, self.g, self.b, self.a]
    }

    /// The channels as writers write them, in RGBA order: clamped to `0..=1`, NaN replaced
    /// (by 0, alpha by 1), and -0 made +0 so that equal colours compare equal bit for bit.
    pub fn sanitized(&self) -> [f32; 4] {
        let channel = |c: f32, fallback: f32| {
            if c.is_nan() {
                fallback
            } else {
                c.clamp(0.0, 1.0) + 0.0
            }
        };
        [
            channel(self.r, 0.0),
            channel(self.g, 0.0),
            channel(self.b, 0.0),
            channel(self.a, 1.0),
        ]
    }
}

/// One piece of a model: a mesh with a group name (usually the rule that made it) and a colour.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Part {
    /// Group name, e.g. the symbol of the leaf shape; used for OBJ groups and glTF nodes.
    pub name: String,
    /// Surface colour.
    pub color: Color,
    /// Geometry in world coordinates.
    pub mesh: Mesh,
    /// Smooth shading: one unit normal per mesh vertex, shared by the faces around it. Empty
    /// for flat shading, where each face is lit by its own normal.
    pub normals: Vec<DVec3>,
    /// The skeleton section the part is rigidly attached to, if the model has skeletons; the
    /// mesh is then in the rest pose.
    pub bone: Option<Bone>,
    /// What the part is, for readers of the written file (glTF node extras); a part with
    /// metadata keeps a node of its own.
    pub metadata: Option<Arc<Metadata>>,
    /// The colour map, when the part is textured; then `uvs` has one uv per mesh vertex.
    pub texture: Option<Arc<Texture>>,
    /// Texture coordinates, one per mesh vertex (v up, as CGA has them); empty when the part
    /// has none. Writers write them only for a textured part.
    pub uvs: Vec<DVec2>,
    /// The material's name the grammar set (`set(material.name, …)`), which names the
    /// written material; `None`: the material is named after the colour.
    pub material: Option<Arc<str>>,
    /// The material's other attributes and texture layers, when the grammar set any (the
    /// layers are drawn through `uvs`).
    pub surface: Option<Arc<Surface>>,
    /// When the part is a copy of a shape that repeats in the model: which one, and where it
    /// is. `mesh` still holds the world geometry, for writers that do not instance.
    pub instance: Option<Instance>,
}

/// A part that repeats a prototype: writers that instance write the prototype's geometry once
/// and place it by `transform` wherever it is used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// The prototype, numbered from 0 in order of first use. Parts with the same number have
    /// the same faces and uvs in the prototype's coordinates (up to rounding far below f32's).
    pub prototype: u32,
    /// From the prototype's coordinates to the world: the part's mesh is the prototype's
    /// geometry moved, turned and scaled (per axis) by it; its determinant is positive.
    pub transform: DAffine3,
}

/// What the copies of one prototype share when they are drawn from one mesh: the prototype
/// and the whole material (colour, colour map, material name, other attributes). The engine
/// counts a prototype's uses by it when it decides what to instance, and the GLB writer gathers
/// instanced parts into meshes by it, so both agree on what is one set.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct InstanceSetKey {
    prototype: u32,
    color: [u32; 4],
    texture: Option<Arc<str>>,
    material: Option<Arc<str>>,
    surface: Option<SurfaceKey>,
}

impl InstanceSetKey {
    /// The set of a copy of `prototype` in `color` (as written: [`Color::sanitized`]) with
    /// the colour map `texture`, the material name `material` and `surface`.
    pub fn new(
        prototype: u32,
        color: Color,
        texture: Option<&Texture>,
        material: Option<&Arc<str>>,
        surface: Option<&Surface>,
    ) -> Self {
        Self {
            prototype,
            color: color.sanitized().map(f32::to_bits),
            texture: texture.map(|t| t.path.clone()),
            material: material.cloned(),
            surface: surface.map(Surface::key),
        }
    }

    /// The set of an instanced part; `None` for a part that is no instance.
    pub fn of_part(part: &Part) -> Option<Self> {
        let instance = part.instance?;
        Some(Self::new(
            instance.prototype,
            part.color,
            part.texture.as_deref(),
            part.material.as_ref(),
            part.surface.as_deref(),
        ))
    }
}

impl Part {
    /// An untextured part with the default material of its colour, attached to no bone and
    /// without metadata.
    pub fn new(name: String, color: Color, mesh: Mesh, normals: Vec<DVec3>) -> Self {
        Self {
            name,
            color,
            mesh,
            normals,
            ..Self::default()
        }
    }
}

/// An image a part is textured with.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Texture {
    /// The path the grammar named it by.
    pub path: Arc<str>,
    /// The file's bytes (PNG or JPEG); `None` when it could not be had, and the part is drawn
    /// in its colour alone.
    pub image: Option<Arc<[u8]>>,
}

impl Texture {
    /// The image's media type from its first bytes: `image/png` or `image/jpeg`.
    pub fn mime_type(&self) -> Option<&'static str> {
        let bytes = self.image.as_deref()?;
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some("image/png")
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            Some("image/jpeg")
        } else {
            None
        }
    }

    /// Whether the image has an alpha channel: a PNG of colour type 4 or 6 (grey or RGB with
    /// alpha) or with a transparency chunk; JPEG has none.
    pub fn has_alpha(&self) -> bool {
        let Some(bytes) = self.image.as_deref() else {
            return false;
        };
        if self.mime_type() != Some("image/png") || bytes.len() < 26 {
            return false;
        }
        // The IHDR chunk comes first: its colour type is byte 25 of the file.
        if matches!(bytes[25], 4 | 6) {
            return true;
        }
        // A transparency chunk comes before the image data.
        let mut at = 8;
        while let Some(header) = bytes.get(at..at + 8) {
            let length = u32::from_be_bytes([header[0], header[1], header[2], header[3]]) as usize;
            match &header[4..8] {
                b"tRNS" => return true,
                b"IDAT" | b"IEND" => return false,
                _ => at = at.saturating_add(12).saturating_add(length),
            }
        }
        false
    }
}

/// What a part of the model is, for readers of the written file: the rule and derivation path
/// of its leaf (when asked for), and for goal grammars the goals left open on its shapes, the
/// goals they fulfilled (tags) and their named attributes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metadata {
    /// The rule (symbol) of the leaf.
    pub rule: Option<String>,
    /// The leaf's derivation path (`Lot[0]/Mass[0]/Facade[2]`, see `docs/export.md`).
    pub path: Option<String>,
    /// How many leaves the part holds, when it describes a part of many rather than a leaf.
    pub leaves: Option<u32>,
    /// Goals no rule fulfilled.
    pub goals: Vec<String>,
    /// Goals fulfilled.
    pub tags: Vec<String>,
    /// Named attributes, in name order.
    pub attributes: Vec<(String, MetaValue)>,
    /// The `report()` values made on the shapes it describes, summarised as CityEngine's PRT
    /// summarises them (`key_n`, `key_sum`, `key_avg`, `key_min`, `key_max`); `None` when
    /// reports were not asked for.
    pub reports: Option<Vec<(String, MetaValue)>>,
    /// The metadata of the initial shape (lot) a leaf was derived from, shared by the lot's
    /// leaves: writers give the lot a node of its own above theirs.
    pub lot: Option<Arc<Metadata>>,
}

/// The value of a named attribute in [`Metadata`].
#[derive(Clone, Debug, PartialEq)]
pub enum MetaValue {
    /// A number.
    Number(f64),
    /// Text.
    Text(String),
    /// True or false.
    Bool(bool),
}

impl Eq for Metadata {}

impl std::hash::Hash for Metadata {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.rule.hash(state);
        self.path.hash(state);
        self.leaves.hash(state);
        self.goals.hash(state);
        self.tags.hash(state);
        let entries = |list: &[(String, MetaValue)], state: &mut H| {
            for (name, value) in list {
                name.hash(state);
                match value {
                    MetaValue::Number(n) => n.to_bits().hash(state),
                    MetaValue::Text(t) => t.hash(state),
                    MetaValue::Bool(b) => b.hash(state),
                }
            }
        };
        entries(&self.attributes, state);
        if let Some(reports) = &self.reports {
            entries(reports, state);
        }
        // Equal lots have equal paths: hashing the path alone keeps a lot's reports from being
        // hashed once per leaf.
        self.lot.as_ref().map(|lot| &lot.path).hash(state);
    }
}

/// Where a part hangs in the model's skeletons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Bone {
    /// Index into [`Model::skeletons`].
    pub skeleton: u32,
    /// The section within that skeleton.
    pub section: SectionId,
}

/// Line segments drawn without thickness, such as turtle strokes shown as a viewer's lines.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lines {
    /// Group name; used for OBJ groups and glTF nodes.
    pub name: String,
    /// Line colour.
    pub color: Color,
    /// Points in world coordinates.
    pub points: Vec<DVec3>,
    /// Segments as pairs of indices into `points`.
    pub segments: Vec<[u32; 2]>,
}

impl Lines {
    /// Bounds of the points, `None` for a line set without points.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(self.points.iter().copied())
    }
}

/// A whole model: the parts and line sets in a stable order, and the skeletons that pose them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    /// Parts in output order.
    pub parts: Vec<Part>,
    /// Line sets in output order, after the parts.
    pub lines: Vec<Lines>,
    /// Kinematic skeletons (one per initial shape that has one); parts name theirs in
    /// [`Part::bone`].
    pub skeletons: Vec<Skeleton>,
}

impl Model {
    /// A model of one part.
    pub fn single(name: impl Into<String>, color: Color, mesh: Mesh) -> Self {
        Self {
            parts: vec![Part {
                name: name.into(),
                color,
                mesh,
                ..Part::default()
            }],
            ..Model::default()
        }
    }

    /// The model with each skeleton reduced to its free joints (see
    /// [`Skeleton::without_locked`]): parts hang from the nearest section that may move, and
    /// the model poses exactly as before.
    pub fn with_free_joints_only(&self) -> Model {
        let reduced: Vec<(Skeleton, Vec<SectionId>)> = self
            .skeletons
            .iter()
            .map(Skeleton::without_locked)
            .collect();
        let parts = self
            .parts
            .iter()
            .map(|part| {
                let mut part = part.clone();
                if let Some(bone) = &mut part.bone {
                    bone.section = reduced[bone.skeleton as usize].1[bone.section.index()];
                }
                part
            })
            .collect();
        Model {
            parts,
            lines: self.lines.clone(),
            skeletons: reduced.into_iter().map(|(s, _)| s).collect(),
        }
    }

    /// The model in its current pose: every part attached to a skeleton moved rigidly from the
    /// rest pose by its section's pose (normals turned with it), the skeletons dropped. What
    /// formats without skins (OBJ, STL) write.
    pub fn posed(&self) -> Model {
        let motions: Vec<Vec<Frame>> = self.skeletons.iter().map(Skeleton::skinning).collect();
        let parts = self
            .parts
            .iter()
            .map(|part| {
                let mut part = part.clone();
                if let Some(bone) = part.bone.take() {
                    let motion = motions[bone.skeleton as usize][bone.section.index()];
                    if motion != Frame::IDENTITY {
                        part.mesh.transform(&motion.to_affine());
                        for n in &mut part.normals {
                            *n = motion.transform_vector(*n);
                        }
                    }
                }
                part
            })
            .collect();
        Model {
            parts,
            lines: self.lines.clone(),
            skeletons: Vec::new(),
        }
    }

    /// All parts merged into one mesh (group names and colours dropped).
    pub fn merged_mesh(&self) -> Mesh {
        let mut all = Mesh::new();
        for part in &self.parts {
            all.append(&part.mesh);
        }
        all
    }

    /// Bounds of all parts and line sets, `None` when the model has no vertices or points.
    pub fn bounds(&self) -> Option<Aabb> {
        let parts = self.parts.iter().filter_map(|p| p.mesh.bounds());
        let lines = self.lines.iter().filter_map(Lines::bounds);
        parts.chain(lines).reduce(Aabb::union)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives;

    #[test]
    fn bounds_cover_parts_and_lines() {
        let mut model = Model::single("box", Color::default(), primitives::cuboid(DVec3::ONE));
        model.lines.push(Lines {
            name: "stroke".into(),
            color: Color::default(),
            points: vec![DVec3::new(-1.0, 0.5, 0.5), DVec3::new(0.5, 3.0, 0.5)],
            segments: vec![[0, 1]],
        });
        let bounds = model.bounds().unwrap();
        assert_eq!(bounds.min, DVec3::new(-1.0, 0.0, 0.0));
        assert_eq!(bounds.max, DVec3::new(1.0, 3.0, 1.0));
        model.parts.clear();
        let lines_only = model.bounds().unwrap();
        assert_eq!(lines_only.min, DVec3::new(-1.0, 0.5, 0.5));
        assert_eq!(lines_only.max, DVec3::new(0.5, 3.0, 0.5));
        assert_eq!(Model::default().bounds(), None);
    }

    #[test]
    fn copies_share_a_set_when_prototype_and_material_agree_as_written() {
        let copy = |prototype: u32, color: Color, material: Option<&str>| Part {
            instance: Some(Instance {
                prototype,
                transform: DAffine3::IDENTITY,
            }),
            material: material.map(Arc::from),
            ..Part::new("Tree".to_owned(), color, Mesh::new(), Vec::new())
        };
        let key = |part: &Part| InstanceSetKey::of_part(part).unwrap();
        let green = Color::rgb(0.2, 0.6, 0.2);
        let first = key(&copy(0, green, None));
        // Colours written alike are one set: -0 is 0, channels past 1 are 1.
        let zero = key(&copy(0, Color::rgb(0.0, 1.0, 0.0), None));
        assert_eq!(zero, key(&copy(0, Color::rgb(-0.0, 1.5, 0.0), None)));
        assert_eq!(first, key(&copy(0, green, None)));
        assert_ne!(first, key(&copy(1, green, None)));
        assert_ne!(first, key(&copy(0, Color::rgb(0.2, 0.6, 0.3), None)));
        assert_ne!(first, key(&copy(0, green, Some("bark"))));
        let flat = Part::new("Tree".to_owned(), green, Mesh::new(), Vec::new());
        assert_eq!(InstanceSetKey::of_part(&flat), None);
        assert_eq!(
            Color::rgb(f32::NAN, 2.0, -1.0).sanitized(),
            [0.0, 1.0, 0.0, 1.0]
        );
    }
}
