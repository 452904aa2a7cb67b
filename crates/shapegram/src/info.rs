//! `shapegram info`: counts, bounds, area, volume and watertightness of a mesh file.

use std::fmt;

use serde::Serialize;
use shapegram_export::Format;
use shapegram_geom::{EdgeReport, Mesh, Model};

use crate::cli::InfoArgs;
use crate::{Failure, print_stdout};

/// Vertices closer than this times the bounds diagonal are merged before counting. Files store
/// f32, and a corner shared by two faces is written as the same f32 both times, so a tight
/// tolerance finds every shared corner without merging fine detail.
const WELD_TOLERANCE: f64 = 1e-9;
/// Triangles with an area below this times diagonal² count as degenerate.
const DEGENERATE_AREA: f64 = 1e-12;

/// Loads the file and prints its [`MeshInfo`] as text or JSON.
pub fn run(args: &InfoArgs) -> Result<(), Failure> {
    let format = Format::from_path(&args.file)?;
    let model = shapegram_export::load(&args.file)?;
    let info = MeshInfo::from_model(&model);
    let file = args.file.display().to_string();
    let text = if args.json {
        let report = FileReport {
            file: &file,
            format: format.extension(),
            info: &info,
        };
        // One line, so that scripts can treat the output of many files as JSON Lines.
        let mut json = serde_json::to_string(&report)
            .map_err(|e| Failure::new(format!("cannot render JSON: {e}")))?;
        json.push('\n');
        json
    } else {
        format!(
            "{:<LABEL$}{file}\n{:<LABEL$}{}\n{info}",
            "file",
            "format",
            format.extension()
        )
    };
    print_stdout(&text)
}

/// The JSON object `info --json` prints: the file, then the [`MeshInfo`] fields.
#[derive(Serialize)]
struct FileReport<'a> {
    file: &'a str,
    format: &'static str,
    #[serde(flatten)]
    info: &'a MeshInfo,
}

/// Statistics of a model, measured after welding each part (see [`MeshInfo::from_model`]).
///
/// Field order is the order of the text and JSON output.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshInfo {
    /// Number of parts (groups, nodes, materials: whatever the file format splits by).
    pub parts: usize,
    /// Vertices after welding.
    pub vertices: usize,
    /// Faces (polygons) after welding dropped collapsed ones.
    pub faces: usize,
    /// Triangles covering the faces.
    pub triangles: usize,
    /// Line segments (of line sets, such as L-system strokes drawn as lines).
    pub segments: usize,
    /// Axis-aligned bounds, `None` for a model without vertices.
    pub bounds: Option<Bounds>,
    /// Total surface area.
    pub area: f64,
    /// Signed enclosed volume; meaningful only when `watertight`.
    pub volume: f64,
    /// Whether every edge is shared by exactly two oppositely oriented faces.
    pub watertight: bool,
    /// How the edges pair up.
    pub edges: EdgeCounts,
    /// Triangles with an area below 1e-12 × diagonal².
    pub degenerate_triangles: usize,
}

/// Axis-aligned bounds with their size.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bounds {
    /// Smallest coordinates.
    pub min: [f64; 3],
    /// Largest coordinates.
    pub max: [f64; 3],
    /// `max - min`.
    pub size: [f64; 3],
}

/// The counts of an [`EdgeReport`], under the names the output uses.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct EdgeCounts {
    /// Undirected edges.
    pub total: usize,
    /// Edges used by one face only (holes, open borders).
    pub boundary: usize,
    /// Edges used by more than two faces.
    pub non_manifold: usize,
    /// Edges whose two faces run along them in the same direction (flipped faces).
    pub misoriented: usize,
}

impl From<EdgeReport> for EdgeCounts {
    fn from(report: EdgeReport) -> Self {
        Self {
            total: report.edges,
            boundary: report.boundary,
            non_manifold: report.non_manifold,
            misoriented: report.misoriented,
        }
    }
}

impl MeshInfo {
    /// Measures a model. Each part is welded with a tolerance of 1e-9 × bounds diagonal first, so formats that store one vertex per corner report their real connectivity.
    pub fn from_model(model: &Model) -> Self {
        let aabb = model.bounds();
        let diagonal = aabb.map_or(0.0, |b| b.diagonal());
        let tolerance = WELD_TOLERANCE * diagonal;
        let min_area = DEGENERATE_AREA * diagonal * diagonal;
        // Weld parts one by one: two parts that touch (a wall and its window) share positions but
        // are separate solids, and welding across them would report their seams as non-manifold.
        let mut welded = Mesh::new();
        for part in &model.parts {
            welded.append(&part.mesh.welded(tolerance));
        }
        // One triangulation serves both counts (Mesh::degenerate_triangle_count would redo it).
        let triangles = welded.triangulate();
        let degenerate_triangles = triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| welded.position(i));
                0.5 * (b - a).cross(c - a).length() < min_area
            })
            .count();
        let report = welded.edge_report();
        Self {
            parts: model.parts.len(),
            vertices: welded.vertex_count(),
            faces: welded.face_count(),
            triangles: triangles.len(),
            segments: model.lines.iter().map(|l| l.segments.len()).sum(),
            bounds: aabb.map(|b| Bounds {
                min: b.min.to_array(),
                max: b.max.to_array(),
                size: b.size().to_array(),
            }),
            area: welded.area(),
            volume: welded.signed_volume(),
            watertight: report.is_watertight(),
            edges: report.into(),
            degenerate_triangles,
        }
    }
}

/// Width of the label column of the text output.
const LABEL: usize = 12;

impl fmt::Display for MeshInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let line = |f: &mut fmt::Formatter<'_>, label: &str, value: fmt::Arguments<'_>| {
            writeln!(f, "{label:<LABEL$}{value}")
        };
        line(f, "parts", format_args!("{}", self.parts))?;
        line(f, "vertices", format_args!("{} (welded)", self.vertices))?;
        line(f, "faces", format_args!("{}", self.faces))?;
        line(f, "triangles", format_args!("{}", self.triangles))?;
        line(f, "segments", format_args!("{}", self.segments))?;
        match &self.bounds {
            Some(b) => {
                let [x, y, z] = b.size.map(number);
                line(
                    f,
                    "bounds",
                    format_args!("{} to {}", point(b.min), point(b.max)),
                )?;
                line(f, "size", format_args!("{x} × {y} × {z}"))?;
            }
            None => line(f, "bounds", format_args!("none (no vertices)"))?,
        }
        line(f, "area", format_args!("{}", number(self.area)))?;
        line(
            f,
            "volume",
            format_args!(
                "{} (signed; meaningful only when watertight)",
                number(self.volume)
            ),
        )?;
        let e = &self.edges;
        line(
            f,
            "watertight",
            format_args!(
                "{} ({} edges: {} boundary, {} non-manifold, {} misoriented)",
                if self.watertight { "yes" } else { "no" },
                e.total,
                e.boundary,
                e.non_manifold,
                e.misoriented
            ),
        )?;
        line(
            f,
            "degenerate",
            format_args!("{} triangles", self.degenerate_triangles),
        )
    }
}

/// A point as `(x, y, z)` with [`number`]s.
fn point(p: [f64; 3]) -> String {
    let [x, y, z] = p.map(number);
    format!("({x}, {y}, {z})")
}

/// A number for people: seven significant digits, trailing zeros dropped, so that
/// 999.99999999997 (f32 round-off) reads as 1000. JSON output keeps full precision.
fn number(v: f64) -> String {
    if v == 0.0 {
        return "0".to_owned(); // also for -0
    }
    if !v.is_finite() {
        return v.to_string();
    }
    let magnitude = v.abs().log10().floor();
    if !(-4.0..15.0).contains(&magnitude) {
        let text = format!("{v:.6e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        return format!("{}e{exponent}", trim_zeros(mantissa));
    }
    let decimals = (6.0 - magnitude).max(0.0) as usize;
    trim_zeros(&format!("{v:.decimals$}")).to_owned()
}

/// `s` without trailing fractional zeros (and without a dangling decimal point).
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use shapegram_geom::{Color, DVec3, Part, primitives};

    use super::*;

    #[test]
    fn a_box_split_into_triangle_soup_is_welded_back_into_a_closed_solid() {
        let cuboid = primitives::cuboid(DVec3::new(10.0, 20.0, 5.0));
        // One vertex per corner, as STL stores it.
        let mut soup = Mesh::new();
        for [a, b, c] in cuboid.triangulate() {
            let v = [a, b, c].map(|i| soup.add_vertex(cuboid.position(i)));
            soup.add_face(&v);
        }
        let info = MeshInfo::from_model(&Model::single("box", Color::default(), soup));
        assert_eq!(info.vertices, 8);
        assert_eq!(info.faces, 12);
        assert_eq!(info.triangles, 12);
        assert!(info.watertight);
        assert_eq!(
            info.edges,
            EdgeCounts {
                total: 18,
                boundary: 0,
                non_manifold: 0,
                misoriented: 0
            }
        );
        assert!((info.volume - 1000.0).abs() < 1e-9);
        assert!((info.area - 700.0).abs() < 1e-9);
        assert_eq!(info.bounds.unwrap().size, [10.0, 20.0, 5.0]);
        assert_eq!(info.degenerate_triangles, 0);
    }

    #[test]
    fn touching_parts_are_not_welded_together() {
        let unit = primitives::cuboid(DVec3::ONE);
        let mut shifted = unit.clone();
        shifted.transform(&shapegram_geom::DAffine3::from_translation(DVec3::X));
        let part = |mesh| Part {
            mesh,
            ..Part::default()
        };
        let model = Model {
            skeletons: Vec::new(),
            parts: vec![part(unit), part(shifted)],
            lines: Vec::new(),
        };
        let info = MeshInfo::from_model(&model);
        assert_eq!(info.parts, 2);
        assert_eq!(info.vertices, 16);
        assert!(info.watertight);
        assert!((info.volume - 2.0).abs() < 1e-12);
    }

    #[test]
    fn an_open_quad_has_boundary_edges_and_an_empty_model_has_no_bounds() {
        let quad = Model::single("lot", Color::default(), primitives::quad(4.0, 3.0));
        let info = MeshInfo::from_model(&quad);
        assert!(!info.watertight);
        assert_eq!(info.edges.boundary, 4);
        assert_eq!(info.area, 12.0);

        let empty = MeshInfo::from_model(&Model::default());
        assert_eq!(empty.bounds, None);
        assert_eq!(empty.vertices, 0);
        assert!(!empty.watertight);
        assert!(empty.to_string().contains("none (no vertices)"));
    }

    #[test]
    fn collapsed_triangles_count_as_degenerate() {
        let mut mesh = primitives::quad(1.0, 1.0);
        let a = mesh.add_vertex(DVec3::new(0.0, 0.0, 0.0));
        let b = mesh.add_vertex(DVec3::new(0.5, 0.0, 0.0));
        let c = mesh.add_vertex(DVec3::new(1.0, 0.0, 0.0));
        mesh.add_face(&[a, b, c]);
        let info = MeshInfo::from_model(&Model::single("x", Color::default(), mesh));
        assert_eq!(info.degenerate_triangles, 1);
    }

    #[test]
    fn text_output_has_one_labelled_line_per_field() {
        let model = Model::single(
            "box",
            Color::default(),
            primitives::cuboid(DVec3::new(10.0, 20.0, 5.0)),
        );
        let text = MeshInfo::from_model(&model).to_string();
        let labels: Vec<&str> = text
            .lines()
            .map(|l| l.split_whitespace().next().unwrap())
            .collect();
        assert_eq!(
            labels,
            [
                "parts",
                "vertices",
                "faces",
                "triangles",
                "segments",
                "bounds",
                "size",
                "area",
                "volume",
                "watertight",
                "degenerate"
            ]
        );
        assert!(text.contains("bounds      (0, 0, 0) to (10, 20, 5)\n"));
        assert!(text.contains("size        10 × 20 × 5\n"));
        assert!(
            text.contains("watertight  yes (12 edges: 0 boundary, 0 non-manifold, 0 misoriented)")
        );
    }

    #[test]
    fn json_keeps_the_field_order() {
        let model = Model::single("q", Color::default(), primitives::quad(2.0, 3.0));
        let json = serde_json::to_string(&MeshInfo::from_model(&model)).unwrap();
        assert!(json.starts_with(r#"{"parts":1,"vertices":4,"faces":1,"triangles":2,"segments":0,"bounds":{"min":[0.0,0.0,0.0],"max":[2.0,0.0,3.0],"size":[2.0,0.0,3.0]},"area":6.0,"volume":"#));
        assert!(json.ends_with(r#""watertight":false,"edges":{"total":4,"boundary":4,"non_manifold":0,"misoriented":0},"degenerate_triangles":0}"#));
    }

    #[test]
    fn numbers_read_well() {
        assert_eq!(number(1000.0), "1000");
        assert_eq!(number(999.999_999_999_97), "1000");
        assert_eq!(number(-2.5), "-2.5");
        assert_eq!(number(std::f64::consts::PI), "3.141593");
        assert_eq!(number(0.000_123_456_789), "0.0001234568");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(1.5e-7), "1.5e-7");
        assert_eq!(number(2e20), "2e20");
        assert_eq!(number(f64::NAN), "NaN");
    }
}
