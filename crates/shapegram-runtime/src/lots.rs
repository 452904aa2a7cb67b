//! Initial shapes (lots) from OBJ and GeoJSON files, as `shapegram derive --lots` and the tiled
//! runs of the Python module read them: in local metres or a geographic CRS, and the frame they
//! are derived in.

use std::path::Path;

use shapegram_eval::InitialShape;
use shapegram_export::Footprints;
use shapegram_export::tiles::{Crs, EnuFrame, Geodetic};
use shapegram_geom::{DVec2, DVec3, mesh::newell};

use crate::{Error, default_lot};

/// How `derive` reads lot coordinates: their coordinate system, and whether local lots are
/// moved to the middle of the frame (tiled output keeps large coordinates in the transform).
#[derive(Clone, Copy, Debug)]
pub struct Placing {
    /// The coordinate system of GeoJSON positions.
    pub crs: Crs,
    /// Whether local lots are derived around the centre of their bounds.
    pub recentre: bool,
}

/// Where the frame lots are derived in lies, in the input's terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Frame {
    /// The input's own metres, moved by `offset` (east, north): the frame's origin is there.
    Local {
        /// The input position of the frame's origin.
        offset: DVec2,
    },
    /// The east-north-up tangent plane at a point of the globe.
    Globe(EnuFrame),
}

impl Frame {
    /// The 3D Tiles root transform from the frame (z up) to the tileset's coordinates: ECEF
    /// on the globe, the input's metres otherwise.
    pub fn transform(&self) -> [f64; 16] {
        match self {
            Frame::Globe(enu) => enu.matrix(),
            Frame::Local { offset } => [
                1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, offset.x, offset.y,
                0.0, 1.0,
            ],
        }
    }
}

/// The lots of `derive`, the warnings about what was skipped, and the frame they are in.
#[derive(Debug)]
pub struct Collected {
    /// The initial shapes, in order.
    pub lots: Vec<InitialShape>,
    /// Parts of the files that were skipped.
    pub warnings: Vec<String>,
    /// Where the lots' frame lies.
    pub frame: Frame,
}

/// The lots given (in order) and then the lots of each file (in order), or the default lot
/// when there are none; with warnings about parts of the files that were skipped. GeoJSON
/// positions are in `placing.crs`; on the globe the lots are derived in the east-north-up
/// plane at the centre of their bounds (in the input's coordinates), which given lots and OBJ
/// files cannot name. An OBJ file with a geographic CRS is an [`ErrorKind::InvalidArgument`]
/// error; a file that cannot be read as lots is an [`ErrorKind::Io`] error naming it.
///
/// [`ErrorKind::InvalidArgument`]: crate::ErrorKind::InvalidArgument
/// [`ErrorKind::Io`]: crate::ErrorKind::Io
pub fn collect(
    given: Vec<InitialShape>,
    files: &[impl AsRef<Path>],
    placing: Placing,
) -> Result<Collected, Error> {
    let none_given = given.is_empty();
    let mut lots = given;
    let mut warnings = Vec::new();
    // Files are read first and placed once the frame is known; their lots keep file order.
    let mut read = Vec::new();
    for file in files {
        let file = file.as_ref();
        let name = file.display().to_string();
        match kind(&name) {
            Some(LotFile::Obj) if placing.crs.is_geographic() => {
                return Err(Error::invalid(format!(
                    "{name}: OBJ lots are local metres; --crs {} applies to GeoJSON files",
                    placing.crs
                )));
            }
            Some(LotFile::Obj) => {
                let model = shapegram_export::load(file).map_err(|e| Error::io(e.to_string()))?;
                let (found, notes) = from_obj(&model, &name);
                if found.is_empty() {
                    return Err(Error::io(no_polygons(&name)));
                }
                read.push(LotsRead::Placed(found));
                warnings.extend(notes);
            }
            Some(LotFile::GeoJson) => {
                let text = std::fs::read_to_string(file)
                    .map_err(|e| Error::io(format!("cannot read {name}: {e}")))?;
                let found = shapegram_export::read_geojson(&text)
                    .map_err(|e| Error::io(format!("invalid GeoJSON in {name}: {e}")))?;
                read.push(LotsRead::GeoJson(name, found));
            }
            None => return Err(Error::io(not_a_lot_file(&name))),
        }
    }
    let frame = match placing.crs {
        Crs::Local => Frame::Local {
            offset: DVec2::ZERO,
        },
        crs => Frame::Globe(globe_frame(crs, &read)?),
    };
    for file in read {
        match file {
            LotsRead::Placed(found) => lots.extend(found),
            LotsRead::GeoJson(name, found) => {
                let (found, notes) =
                    lots_from_rings(&found, &name, |p| to_frame(placing.crs, &frame, p))
                        .map_err(Error::io)?;
                if found.is_empty() {
                    return Err(Error::io(no_polygons(&name)));
                }
                lots.extend(found);
                warnings.extend(notes);
            }
        }
    }
    if none_given && files.is_empty() {
        lots.push(default_lot());
    }
    let frame = match frame {
        Frame::Local { .. } if placing.recentre => recentre(&mut lots),
        frame => frame,
    };
    Ok(Collected {
        lots,
        warnings,
        frame,
    })
}

/// A lot file as read: its lots, or GeoJSON footprints still in the input's coordinates.
enum LotsRead {
    Placed(Vec<InitialShape>),
    GeoJson(String, Footprints),
}

/// The east-north-up frame at the centre of the bounds of every GeoJSON position (in the
/// input's coordinates), on the ellipsoid; an out-of-range position is an error naming its
/// file and feature.
fn globe_frame(crs: Crs, files: &[LotsRead]) -> Result<EnuFrame, Error> {
    let mut min = DVec2::INFINITY;
    let mut max = DVec2::NEG_INFINITY;
    for file in files {
        let LotsRead::GeoJson(name, found) = file else {
            continue;
        };
        for (ring, place) in found.rings.iter().zip(&found.places) {
            for &p in ring {
                let input = DVec2::new(p.x, -p.y);
                crs.to_geodetic(input.x, input.y)
                    .map_err(|e| Error::io(format!("{name}: {place}: {e}")))?;
                min = min.min(input);
                max = max.max(input);
            }
        }
    }
    if !min.is_finite() {
        // No positions: the files' own errors (no polygons) say so.
        return Ok(EnuFrame::at(Geodetic {
            longitude: 0.0,
            latitude: 0.0,
        }));
    }
    let centre = (min + max) / 2.0;
    let origin = crs
        .to_geodetic(centre.x, centre.y)
        .map_err(|e| Error::io(format!("the centre of the lots: {e}")))?;
    Ok(EnuFrame::at(origin))
}

/// A ground position as read (x, −y of the file) in the frame lots are derived in.
fn to_frame(crs: Crs, frame: &Frame, p: DVec2) -> Result<DVec2, String> {
    match frame {
        Frame::Globe(enu) => {
            let (east, north) = enu.east_north(crs.to_geodetic(p.x, -p.y)?);
            Ok(DVec2::new(east, -north))
        }
        Frame::Local { .. } => Ok(p),
    }
}

/// Moves local lots so that the centre of their bounds is the origin; the frame keeps where it
/// was. Subtracting in f64 is exact for coordinates given to the millimetre up to 10⁹ m.
fn recentre(lots: &mut [InitialShape]) -> Frame {
    let mut min = DVec2::INFINITY;
    let mut max = DVec2::NEG_INFINITY;
    for p in lots.iter().flat_map(|lot| &lot.footprint) {
        min = min.min(DVec2::new(p.x, p.z));
        max = max.max(DVec2::new(p.x, p.z));
    }
    let centre = (min + max) / 2.0;
    if !centre.is_finite() {
        return Frame::Local {
            offset: DVec2::ZERO,
        };
    }
    let shift = DVec3::new(centre.x, 0.0, centre.y);
    for p in lots.iter_mut().flat_map(|lot| &mut lot.footprint) {
        *p -= shift;
    }
    Frame::Local {
        offset: DVec2::new(centre.x, -centre.y),
    }
}

/// Lots from the text of a file named `name` (its extension tells OBJ from GeoJSON), read as
/// `--lots` reads a file: the studio's uploaded lots. The error is one line naming the file.
pub fn from_text(name: &str, text: &str) -> Result<(Vec<InitialShape>, Vec<String>), String> {
    let (lots, warnings) = match kind(name) {
        Some(LotFile::Obj) => {
            let model = shapegram_export::read_obj(text)
                .map_err(|e| format!("cannot read lots from {name}: {e}"))?;
            from_obj(&model, name)
        }
        Some(LotFile::GeoJson) => from_geojson(text, name)?,
        None => return Err(not_a_lot_file(name)),
    };
    if lots.is_empty() {
        return Err(no_polygons(name));
    }
    Ok((lots, warnings))
}

/// `3 faces`, `1 face`.
fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The kinds of file lots are read from.
enum LotFile {
    Obj,
    GeoJson,
}

fn kind(name: &str) -> Option<LotFile> {
    let extension = Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("obj") => Some(LotFile::Obj),
        Some("geojson" | "json") => Some(LotFile::GeoJson),
        _ => None,
    }
}

fn not_a_lot_file(name: &str) -> String {
    format!("cannot read lots from {name}: expected an .obj, .geojson or .json file")
}

fn no_polygons(name: &str) -> String {
    format!("{name} has no polygons to use as lots")
}

/// Every face of an OBJ file is a lot, in world coordinates; faces whose normal points down are
/// turned over so that every lot faces up (or sideways, for vertical faces).
fn from_obj(model: &shapegram_geom::Model, name: &str) -> (Vec<InitialShape>, Vec<String>) {
    let mut lots = Vec::new();
    let mut flat = 0;
    for part in &model.parts {
        for f in 0..part.mesh.face_count() {
            let mut footprint: Vec<DVec3> = part.mesh.face_points(f).collect();
            match lot_normal(&footprint) {
                Some(normal) => {
                    if normal.y < 0.0 {
                        footprint.reverse();
                    }
                    lots.push(InitialShape {
                        footprint,
                        index: None,
                    });
                }
                None => flat += 1,
            }
        }
    }
    let warnings = (flat > 0)
        .then(|| format!("{name}: skipped {} without area", faces(flat)))
        .into_iter()
        .collect();
    (lots, warnings)
}

fn faces(n: usize) -> String {
    counted(n, "face", "faces")
}

/// The unit normal of a polygon, `None` when it has no area or non-finite corners.
fn lot_normal(points: &[DVec3]) -> Option<DVec3> {
    if points.len() < 3 || !points.iter().all(|p| p.is_finite()) {
        return None;
    }
    newell(points.iter().copied()).try_normalize()
}

/// Lots from GeoJSON text (see [`shapegram_export::read_geojson`]) in local metres: holes,
/// other geometry types and polygons without area or crossing themselves are skipped with a
/// warning; anything malformed is an error (one line, naming the file).
pub fn from_geojson(text: &str, name: &str) -> Result<(Vec<InitialShape>, Vec<String>), String> {
    let found = shapegram_export::read_geojson(text)
        .map_err(|e| format!("invalid GeoJSON in {name}: {e}"))?;
    lots_from_rings(&found, name, Ok)
}

/// The lots of GeoJSON footprints, each position mapped by `place` into the frame (an error
/// there names the file and the feature); positions repeated one after the other count once.
fn lots_from_rings(
    found: &Footprints,
    name: &str,
    place: impl Fn(DVec2) -> Result<DVec2, String>,
) -> Result<(Vec<InitialShape>, Vec<String>), String> {
    let mut lots = Vec::new();
    let mut without_area = found.empty;
    let mut crossing = Vec::new();
    for (ring, at) in found.rings.iter().zip(&found.places) {
        let mut points = Vec::with_capacity(ring.len());
        for &p in ring {
            let p = place(p).map_err(|e| format!("{name}: {at}: {e}"))?;
            if points.last() != Some(&p) {
                points.push(p);
            }
        }
        if points.len() > 1 && points.first() == points.last() {
            points.pop();
        }
        if crosses_itself(&points) {
            crossing.push(at.as_str());
            continue;
        }
        match InitialShape::from_xz(&points) {
            Some(lot) => lots.push(lot),
            None => without_area += 1,
        }
    }
    let mut warnings = Vec::new();
    if found.holes > 0 {
        warnings.push(format!(
            "{name}: ignored {} (lots have no holes)",
            counted(found.holes, "hole", "holes")
        ));
    }
    if found.not_polygons > 0 {
        warnings.push(format!(
            "{name}: skipped {} that {} not polygons",
            counted(found.not_polygons, "geometry", "geometries"),
            if found.not_polygons == 1 { "is" } else { "are" }
        ));
    }
    if without_area > 0 {
        warnings.push(format!(
            "{name}: skipped {} without area",
            counted(without_area, "polygon", "polygons")
        ));
    }
    if !crossing.is_empty() {
        const SHOWN: usize = 5;
        let more = crossing.len().saturating_sub(SHOWN);
        warnings.push(format!(
            "{name}: skipped {} whose outer ring crosses or touches itself: {}{}",
            counted(crossing.len(), "polygon", "polygons"),
            crossing[..crossing.len().min(SHOWN)].join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    Ok((lots, warnings))
}

/// Whether two edges of a closed ring that are not neighbours meet (a ring through one point
/// twice meets itself too). Quadratic: lot outlines have few corners.
fn crosses_itself(ring: &[DVec2]) -> bool {
    let n = ring.len();
    if n < 4 {
        return false;
    }
    let edge = |i: usize| (ring[i], ring[(i + 1) % n]);
    (0..n).any(|i| {
        ((i + 2)..n)
            .filter(|&j| !(i == 0 && j == n - 1))
            .any(|j| segments_meet(edge(i), edge(j)))
    })
}

/// Whether two closed segments share a point (orientation tests, collinear overlaps included).
fn segments_meet((a, b): (DVec2, DVec2), (c, d): (DVec2, DVec2)) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let within = |p: DVec2, q: DVec2, r: DVec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    let (d1, d2) = (side(c, d, a), side(c, d, b));
    let (d3, d4) = (side(a, b, c), side(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && within(c, d, a))
        || (d2 == 0.0 && within(c, d, b))
        || (d3 == 0.0 && within(a, b, c))
        || (d4 == 0.0 && within(a, b, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn up(lot: &InitialShape) -> bool {
        newell(lot.footprint.iter().copied()).y > 0.0
    }

    #[test]
    fn geojson_polygons_map_north_to_minus_z() {
        let text = r#"{"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": {}, "geometry":
                {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 5], [0, 5], [0, 0]]]}},
            {"type": "Feature", "geometry": null},
            {"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}},
            {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [
                [[[20, 0], [30, 0], [30, 10], [20, 0]], [[21, 1], [22, 1], [22, 2], [21, 1]]],
                [[[40, 0], [50, 0], [60, 0], [40, 0]]]
            ]}}
        ]}"#;
        let (lots, warnings) = from_geojson(text, "city.geojson").unwrap();
        assert_eq!(lots.len(), 2);
        assert_eq!(
            lots[0].footprint.len(),
            4,
            "the closing position is dropped"
        );
        assert!(lots.iter().all(up));
        let zs: Vec<f64> = lots[0].footprint.iter().map(|p| p.z).collect();
        assert!(zs.iter().all(|&z| z == 0.0 || z == -5.0), "{zs:?}");
        assert_eq!(
            warnings,
            [
                "city.geojson: ignored 1 hole (lots have no holes)",
                "city.geojson: skipped 2 geometries that are not polygons",
                "city.geojson: skipped 1 polygon without area",
            ]
        );
    }

    #[test]
    fn bare_geometries_are_accepted() {
        let (lots, _) = from_geojson(
            r#"{"type": "Polygon", "coordinates": [[[0, 0, 7], [4, 0, 7], [4, 3, 7]]]}"#,
            "x.json",
        )
        .unwrap();
        assert_eq!(lots.len(), 1);
        assert!(lots[0].footprint.iter().all(|p| p.y == 0.0));
    }

    #[test]
    fn malformed_geojson_is_a_one_line_error_naming_the_file() {
        for (text, expected) in [
            (
                "{",
                "invalid GeoJSON in f.json: EOF while parsing an object",
            ),
            ("[1, 2]", "the top level is not a GeoJSON object"),
            (
                r#"{"type": "Feature"}"#,
                "the top level (a Feature) has no \"geometry\"",
            ),
            (
                r#"{"type": "Polygon", "coordinates": [[[0, 0], [1], [1, 1]]]}"#,
                "[1]",
            ),
            (
                r#"{"type": "FeatureCollection", "features": 3}"#,
                "is not an array",
            ),
            (r#"{"type": "Circle"}"#, "unknown type \"Circle\""),
        ] {
            let error = from_geojson(text, "f.json").map(|_| ()).unwrap_err();
            assert!(error.starts_with("invalid GeoJSON in f.json: "), "{error}");
            assert!(error.contains(expected), "{error} lacks {expected}");
            assert!(!error.contains('\n'), "{error}");
        }
    }

    #[test]
    fn rings_that_cross_or_touch_themselves_are_found() {
        let ring = |points: &[(f64, f64)]| -> Vec<DVec2> {
            points.iter().map(|&(x, y)| DVec2::new(x, y)).collect()
        };
        assert!(!crosses_itself(&ring(&[
            (0., 0.),
            (4., 0.),
            (4., 4.),
            (0., 4.)
        ])));
        assert!(!crosses_itself(&ring(&[
            (0., 0.),
            (4., 0.),
            (1., 1.),
            (0., 4.)
        ])));
        assert!(crosses_itself(&ring(&[
            (0., 0.),
            (4., 4.),
            (4., 0.),
            (0., 4.)
        ])));
        // Through (2, 2) twice: two squares touching at a corner.
        assert!(crosses_itself(&ring(&[
            (0., 0.),
            (2., 0.),
            (2., 2.),
            (4., 2.),
            (4., 4.),
            (2., 4.),
            (2., 2.),
            (0., 2.)
        ])));
        // An edge doubling back over its neighbour's neighbour.
        assert!(crosses_itself(&ring(&[
            (0., 0.),
            (4., 0.),
            (4., 1.),
            (2., 0.),
            (2., -1.)
        ])));
    }
}
