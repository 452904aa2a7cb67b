//! GeoJSON polygons as footprints on the ground: the lots of a city or a block.

use serde_json::Value as Json;
use shapegram_geom::DVec2;

/// The polygons of a GeoJSON text, as rings in the xz-plane, and what was left out.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Footprints {
    /// The exterior ring of every polygon, as world (x, z) = (GeoJSON x, −GeoJSON y), so north is
    /// −z; the closing position GeoJSON repeats is dropped.
    pub rings: Vec<Vec<DVec2>>,
    /// Where each ring is in the file, for messages: `features[3]`, `polygon 1 of features[3]`.
    pub places: Vec<String>,
    /// Interior rings (holes) that were ignored.
    pub holes: usize,
    /// Geometries that are not polygons (points, lines, null geometries).
    pub not_polygons: usize,
    /// Polygons without any ring.
    pub empty: usize,
}

/// Reads the exterior ring of every Polygon and MultiPolygon in a FeatureCollection, Feature,
/// geometry or GeometryCollection. Anything malformed is a one-line error saying where.
pub fn read_geojson(text: &str) -> Result<Footprints, String> {
    let json: Json = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let mut found = Footprints::default();
    walk(&json, "the top level", &mut found)?;
    Ok(found)
}

fn walk(json: &Json, at: &str, found: &mut Footprints) -> Result<(), String> {
    let kind = json
        .get("type")
        .and_then(Json::as_str)
        .ok_or_else(|| format!("{at} is not a GeoJSON object with a \"type\""))?;
    let member = |key: &str| {
        json.get(key)
            .ok_or_else(|| format!("{at} (a {kind}) has no \"{key}\""))
    };
    let array = |key: &str| {
        member(key)?
            .as_array()
            .ok_or_else(|| format!("\"{key}\" of {at} is not an array"))
    };
    match kind {
        "FeatureCollection" => {
            for (i, feature) in array("features")?.iter().enumerate() {
                walk(feature, &format!("features[{i}]"), found)?;
            }
        }
        "Feature" => match member("geometry")? {
            Json::Null => found.not_polygons += 1,
            // A polygon is named after its feature: that is what users find in their file.
            geometry if geometry.get("type").and_then(Json::as_str) == Some("Polygon") => {
                walk(geometry, at, found)?
            }
            geometry => walk(geometry, &format!("the geometry of {at}"), found)?,
        },
        "GeometryCollection" => {
            for (i, geometry) in array("geometries")?.iter().enumerate() {
                walk(geometry, &format!("geometries[{i}] of {at}"), found)?;
            }
        }
        "Polygon" => polygon(member("coordinates")?, at, found)?,
        "MultiPolygon" => {
            for (i, rings) in array("coordinates")?.iter().enumerate() {
                polygon(rings, &format!("polygon {i} of {at}"), found)?;
            }
        }
        "Point" | "MultiPoint" | "LineString" | "MultiLineString" => found.not_polygons += 1,
        other => return Err(format!("{at} has the unknown type \"{other}\"")),
    }
    Ok(())
}

/// The exterior ring of a polygon's `coordinates`.
fn polygon(rings: &Json, at: &str, found: &mut Footprints) -> Result<(), String> {
    let rings = rings
        .as_array()
        .ok_or_else(|| format!("the coordinates of {at} are not a list of rings"))?;
    let Some(exterior) = rings.first() else {
        found.empty += 1;
        return Ok(());
    };
    found.holes += rings.len() - 1;
    let positions = exterior
        .as_array()
        .ok_or_else(|| format!("the outer ring of {at} is not a list of positions"))?;
    let mut points = positions
        .iter()
        .map(|p| position(p).ok_or_else(|| format!("{at} has a position that is not [x, y]: {p}")))
        .collect::<Result<Vec<DVec2>, String>>()?;
    // GeoJSON rings repeat their first position at the end.
    if points.len() > 1 && points.first() == points.last() {
        points.pop();
    }
    found.rings.push(points);
    found.places.push(at.to_owned());
    Ok(())
}

/// A GeoJSON position `[x, y]` or `[x, y, z]` as world (x, z) = (x, −y); coordinates must be
/// finite and within f32's range, as the exporters need.
fn position(p: &Json) -> Option<DVec2> {
    let numbers = p.as_array()?;
    let coordinate = |i: usize| {
        numbers
            .get(i)?
            .as_f64()
            .filter(|v| v.is_finite() && v.abs() <= f64::from(f32::MAX))
    };
    if !(2..=3).contains(&numbers.len()) {
        return None;
    }
    Some(DVec2::new(coordinate(0)?, -coordinate(1)?))
}
