//! Initial shapes (lots) for `shapegram derive`: from `--lot`, from OBJ and GeoJSON files, or
//! the default 20 × 30 lot.

use std::path::Path;

use shapegram_eval::InitialShape;
use shapegram_geom::{DVec2, DVec3, mesh::newell};

use crate::Failure;
use crate::primitive::parse_points;

/// The default lot's size along x and z.
pub const DEFAULT_LOT: (f64, f64) = (20.0, 30.0);

/// The lots of `--lot` (in order) and then of each `--lots` file (in order), or the default lot
/// when there are none; with warnings about parts of the files that were skipped.
pub fn collect(
    lot_args: &[String],
    files: &[impl AsRef<Path>],
) -> Result<(Vec<InitialShape>, Vec<String>), Failure> {
    let mut lots = Vec::new();
    let mut warnings = Vec::new();
    for text in lot_args {
        let points = parse_points(text, "--lot").map_err(Failure::new)?;
        lots.push(InitialShape::from_xz(&points).ok_or_else(|| {
            Failure::new(format!(
                "invalid --lot '{}': the polygon has no area",
                text.escape_debug()
            ))
        })?);
    }
    for file in files {
        let file = file.as_ref();
        let (found, notes) = read_file(file)?;
        lots.extend(found);
        warnings.extend(notes);
    }
    if lot_args.is_empty() && files.is_empty() {
        lots.push(default_lot());
    }
    Ok((lots, warnings))
}

/// The lot used without `--lot` and `--lots`: x from 0 to 20, z from 0 to 30, facing up.
pub fn default_lot() -> InitialShape {
    let (x, z) = DEFAULT_LOT;
    let corners = [(0.0, 0.0), (x, 0.0), (x, z), (0.0, z)].map(|(x, z)| DVec2::new(x, z));
    InitialShape::from_xz(&corners).expect("the default lot has an area")
}

/// Lots from an .obj (every face) or a .geojson/.json file (every polygon).
fn read_file(path: &Path) -> Result<(Vec<InitialShape>, Vec<String>), Failure> {
    let name = path.display().to_string();
    let (lots, warnings) = match kind(&name) {
        Some(LotFile::Obj) => from_obj(&shapegram_export::load(path)?, &name),
        Some(LotFile::GeoJson) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| Failure::new(format!("cannot read {name}: {e}")))?;
            from_geojson(&text, &name).map_err(Failure::new)?
        }
        None => return Err(Failure::new(not_a_lot_file(&name))),
    };
    if lots.is_empty() {
        return Err(Failure::new(no_polygons(&name)));
    }
    Ok((lots, warnings))
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
                    lots.push(InitialShape { footprint });
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
    crate::counted(n, "face", "faces")
}

/// The unit normal of a polygon, `None` when it has no area or non-finite corners.
fn lot_normal(points: &[DVec3]) -> Option<DVec3> {
    if points.len() < 3 || !points.iter().all(|p| p.is_finite()) {
        return None;
    }
    newell(points.iter().copied()).try_normalize()
}

/// Lots from GeoJSON text (see [`shapegram_export::read_geojson`]): holes, other geometry
/// types and polygons without area are skipped with a warning; anything malformed is an error
/// (one line, naming the file).
pub fn from_geojson(text: &str, name: &str) -> Result<(Vec<InitialShape>, Vec<String>), String> {
    let found = shapegram_export::read_geojson(text)
        .map_err(|e| format!("invalid GeoJSON in {name}: {e}"))?;
    let mut lots = Vec::new();
    let mut without_area = found.empty;
    for ring in &found.rings {
        match InitialShape::from_xz(ring) {
            Some(lot) => lots.push(lot),
            None => without_area += 1,
        }
    }
    let mut warnings = Vec::new();
    if found.holes > 0 {
        warnings.push(format!(
            "{name}: ignored {} (lots have no holes)",
            crate::counted(found.holes, "hole", "holes")
        ));
    }
    if found.not_polygons > 0 {
        warnings.push(format!(
            "{name}: skipped {} that {} not polygons",
            crate::counted(found.not_polygons, "geometry", "geometries"),
            if found.not_polygons == 1 { "is" } else { "are" }
        ));
    }
    if without_area > 0 {
        warnings.push(format!(
            "{name}: skipped {} without area",
            crate::counted(without_area, "polygon", "polygons")
        ));
    }
    Ok((lots, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xz(lot: &InitialShape) -> Vec<(f64, f64)> {
        lot.footprint.iter().map(|p| (p.x, p.z)).collect()
    }

    fn up(lot: &InitialShape) -> bool {
        newell(lot.footprint.iter().copied()).y > 0.0
    }

    #[test]
    fn the_default_lot_is_20_by_30_facing_up() {
        let lot = default_lot();
        assert!(up(&lot));
        let mut corners = xz(&lot);
        corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            corners,
            [(0.0, 0.0), (0.0, 30.0), (20.0, 0.0), (20.0, 30.0)]
        );
        assert!(lot.footprint.iter().all(|p| p.y == 0.0));
    }

    #[test]
    fn lots_come_from_every_lot_option_in_order() {
        let (lots, warnings) = collect(
            &["0,0 1,0 1,1".to_owned(), "5,5 6,5 6,7 5,7".to_owned()],
            &[] as &[&Path],
        )
        .unwrap();
        assert!(warnings.is_empty());
        assert_eq!(lots.len(), 2);
        assert_eq!(lots[1].footprint.len(), 4);
        assert!(lots.iter().all(up));
    }

    #[test]
    fn bad_lot_options_are_one_line_errors() {
        let message = |text: &str| {
            collect(&[text.to_owned()], &[] as &[&Path])
                .unwrap_err()
                .message
                .unwrap()
        };
        assert_eq!(
            message("0,0 1,x 1,1"),
            "invalid --lot: '1,x' is not an x,z pair of numbers like 4,2.5"
        );
        assert!(message("0,0 1,0").starts_with("invalid --lot '0,0 1,0': expected at least three"));
        assert_eq!(
            message("0,0 1,0 2,0"),
            "invalid --lot '0,0 1,0 2,0': the polygon has no area"
        );
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
}
