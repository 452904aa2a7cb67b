//! GeoJSON polygons as footprints on the ground: the lots of a city or a block.

use std::borrow::Cow;
use std::collections::BTreeMap;

use serde_json::Value as Json;
use serde_json::value::RawValue;
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
    if let Some(found) = feature_by_feature(text) {
        return found;
    }
    let json: Json = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let mut found = Footprints::default();
    walk(&json, "the top level", &mut found)?;
    Ok(found)
}

/// A FeatureCollection read one feature at a time: the parsed features of a city take many
/// times the memory of its text, the unparsed ones a pointer each. `None` for any other text,
/// read whole (and the errors said) by [`read_geojson`].
fn feature_by_feature(text: &str) -> Option<Result<Footprints, String>> {
    let top: BTreeMap<Cow<'_, str>, &RawValue> = serde_json::from_str(text).ok()?;
    let kind: Cow<'_, str> = serde_json::from_str(top.get("type")?.get()).ok()?;
    if kind != "FeatureCollection" {
        return None;
    }
    let features: Vec<&RawValue> = serde_json::from_str(top.get("features")?.get()).ok()?;
    let mut found = Footprints::default();
    for (i, feature) in features.iter().enumerate() {
        let read = serde_json::from_str(feature.get())
            .map_err(|e| e.to_string())
            .and_then(|json: Json| walk(&json, &format!("features[{i}]"), &mut found));
        if let Err(e) = read {
            return Some(Err(e));
        }
    }
    Some(Ok(found))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// What reading the text whole finds.
    fn whole(text: &str) -> Result<Footprints, String> {
        let json: Json = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let mut found = Footprints::default();
        walk(&json, "the top level", &mut found)?;
        Ok(found)
    }

    #[test]
    fn collections_read_feature_by_feature_find_what_the_whole_text_holds() {
        let collection = r#"{"features": [
            {"type": "Feature", "geometry": {"type": "Polygon",
                "coordinates": [[[0, 0], [1e-7, 0], [0.1, 0.3], [0, 0]], [[0, 0], [1, 1], [0, 1]]]}},
            {"type": "Feature", "geometry": null},
            {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [
                [[[20, 0], [30, 0], [30, 10], [20, 0]]], []]}},
            {"type": "Feature", "geometry": {"type": "GeometryCollection", "geometries": [
                {"type": "Point", "coordinates": [1, 2]},
                {"type": "Polygon", "coordinates": [[[5, 5, 1], [6, 5, 1], [6, 7, 1]]]}]}}
        ], "type": "FeatureCollection", "bbox": [0, 0, 30, 10]}"#;
        assert!(feature_by_feature(collection).is_some());
        let found = read_geojson(collection).unwrap();
        assert_eq!(found, whole(collection).unwrap());
        assert_eq!(found.rings.len(), 3);
        assert_eq!((found.holes, found.not_polygons, found.empty), (1, 2, 1));
        assert_eq!(found.places[1], "polygon 0 of the geometry of features[2]");
        // A broken feature is the same error either way.
        let broken = r#"{"type": "FeatureCollection", "features": [
            {"type": "Feature", "geometry": null},
            {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1]]]}}]}"#;
        assert!(feature_by_feature(broken).is_some());
        assert_eq!(read_geojson(broken), whole(broken));
        assert!(read_geojson(broken).unwrap_err().contains("features[1]"));
        // Anything else is read whole.
        for other in [
            r#"{"type": "Feature", "geometry": null}"#,
            r#"{"type": "FeatureCollection", "features": 3}"#,
            "[1, 2]",
            "{",
        ] {
            assert!(feature_by_feature(other).is_none(), "{other}");
            assert_eq!(read_geojson(other), whole(other), "{other}");
        }
    }
}
