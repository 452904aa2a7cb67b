//! What the studio's page sets besides the text, made into what the engine takes: the user's
//! attribute values (checked against the grammar's attributes, those that no longer fit
//! dropped with a note), the lot (drawn, or a GeoJSON or OBJ file read as `--lots` reads it),
//! the panel's view of each attribute, and the model written as the file a download asks for.

use serde_json::Value as Json;
use shapegram_eval::{
    AttrValue, DeriveOptions, InitialShape, Program, Unit, Value, attr_annotations, attr_values,
};
use shapegram_export::ExportOptions;
use shapegram_geom::{DVec2, Model};
use shapegram_server::studio::{ExportFormat, LotRequest, StudioAttr};
use shapegram_syntax::ast;

use crate::lots;

/// Most corners a drawn lot may have.
const MAX_CORNERS: usize = 10_000;

/// The lots to derive on, with notes on parts of a file that were skipped, or a one-line
/// message saying what is wrong with the lot.
pub fn lots(lot: Option<&LotRequest>) -> Result<(Vec<InitialShape>, Vec<String>), String> {
    match lot {
        None => Ok((vec![lots::default_lot()], Vec::new())),
        Some(LotRequest::Polygon { points }) => {
            if points.len() < 3 {
                return Err(format!(
                    "the drawn lot has {} corners: a lot needs at least three",
                    points.len()
                ));
            }
            if points.len() > MAX_CORNERS {
                return Err(format!(
                    "the drawn lot has {} corners, more than {MAX_CORNERS}",
                    points.len()
                ));
            }
            if let Some(bad) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
                return Err(format!(
                    "corner {} of the drawn lot is not a number",
                    bad + 1
                ));
            }
            let corners: Vec<DVec2> = points.iter().map(|[x, z]| DVec2::new(*x, *z)).collect();
            let lot = InitialShape::from_xz(&corners).ok_or_else(|| {
                "the drawn lot has no area (its corners are on one line or on one point)".to_owned()
            })?;
            Ok((vec![lot], Vec::new()))
        }
        Some(LotRequest::File { name, text }) => lots::from_text(name, text),
    }
}

/// The user's values that fit the grammar as overrides, and the names and notes of those
/// dropped. `types` are the attributes' values without overrides: a value must name one of
/// them and have its type (a number where the default is a string is dropped).
pub fn overrides(
    user: &[(String, Json)],
    types: &[AttrValue],
) -> (Vec<(String, Value)>, Vec<String>, Vec<String>) {
    let mut kept = Vec::new();
    let mut dropped = Vec::new();
    let mut notes = Vec::new();
    for (name, json) in user {
        let Some(attr) = types.iter().find(|a| &a.name == name) else {
            notes.push(format!(
                "`{name}` is no longer an attribute of the grammar: its value was dropped"
            ));
            dropped.push(name.clone());
            continue;
        };
        match from_json(json).filter(|v| v.type_name() == attr.default.type_name()) {
            Some(value) => kept.push((name.clone(), value)),
            None => {
                notes.push(format!(
                    "`{name}` is now a {}: the value {json} was dropped",
                    attr.default.type_name()
                ));
                dropped.push(name.clone());
            }
        }
    }
    (kept, dropped, notes)
}

/// The type names of the checks above, once the defaults are known; `None` when they cannot be
/// evaluated (the derivation will say why), in which case values are kept by name only.
pub fn defaults(
    program: &Program,
    lot: &InitialShape,
    options: &DeriveOptions,
) -> Option<Vec<AttrValue>> {
    let plain = DeriveOptions {
        attrs: Vec::new(),
        ..options.clone()
    };
    attr_values(program, lot, 0, &plain).ok()
}

/// The panel's attributes: the values on the first lot with the annotations of their
/// declarations in `grammar` (the edited file; imported attributes have none).
pub fn panel(
    grammar: &ast::Grammar,
    program: &Program,
    lot: &InitialShape,
    options: &DeriveOptions,
) -> Option<Vec<StudioAttr>> {
    let values = attr_values(program, lot, 0, options).ok()?;
    Some(
        values
            .into_iter()
            .map(|v| {
                let user = options.attrs.iter().any(|(name, _)| *name == v.name);
                let mut attr = StudioAttr {
                    kind: v.default.type_name(),
                    default: to_json(&v.default),
                    value: to_json(&v.value),
                    user,
                    restricted: true,
                    ..StudioAttr::default()
                };
                if let Some(decl) = grammar.attrs.iter().find(|a| a.name.name == v.name) {
                    let a = attr_annotations(decl);
                    attr.range = a
                        .range
                        .map(|r| serde_json::json!({ "min": r.min, "max": r.max, "step": r.step }));
                    attr.choices = a.choices.map(|c| c.iter().map(to_json).collect());
                    attr.restricted = a.restricted;
                    attr.color = a.color;
                    attr.group = a.group;
                    attr.group_order = a.group_order;
                    attr.order = a.order;
                    attr.hidden = a.hidden;
                    attr.description = a.description;
                    attr.display_name = a.display_name;
                    attr.unit = a.unit.map(|u| match u {
                        Unit::Angle => "angle",
                        Unit::Distance => "distance",
                        Unit::Percent => "percent",
                    });
                    attr.annotations = a.names;
                } else if let Some((namespace, _)) = v.name.rsplit_once('.') {
                    // An imported attribute: grouped under its import's name.
                    attr.group = vec![namespace.to_owned()];
                }
                attr.name = v.name;
                attr
            })
            .collect(),
    )
}

/// The model as the files of `format`, named after `stem`.
pub fn export(
    model: &Model,
    format: ExportFormat,
    stem: &str,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let options = ExportOptions::default();
    let mut bytes = Vec::new();
    match format {
        ExportFormat::Glb => {
            shapegram_export::write_glb_to(model, &options, &mut bytes)
                .map_err(|e| format!("cannot write the GLB: {e}"))?;
            Ok(vec![(format!("{stem}.glb"), bytes)])
        }
        ExportFormat::Stl => {
            shapegram_export::write_stl_to(model, &mut std::io::Cursor::new(&mut bytes))
                .map_err(|e| format!("cannot write the STL: {e}"))?;
            Ok(vec![(format!("{stem}.stl"), bytes)])
        }
        ExportFormat::Obj => {
            let mtl_name = format!("{stem}.mtl");
            let mtl = shapegram_export::write_obj_to(model, &options, &mtl_name, &mut bytes)
                .map_err(|e| format!("cannot write the OBJ: {e}"))?;
            Ok(vec![
                (format!("{stem}.obj"), bytes),
                (mtl_name, mtl.into_bytes()),
            ])
        }
    }
}

/// A JSON value the page sent as an attribute value: a number, string or boolean.
pub fn from_json(json: &Json) -> Option<Value> {
    match json {
        Json::Number(n) => n.as_f64().filter(|v| v.is_finite()).map(Value::Number),
        Json::String(s) => Some(Value::string(s)),
        Json::Bool(b) => Some(Value::Bool(*b)),
        _ => None,
    }
}

fn to_json(value: &Value) -> Json {
    match value {
        Value::Number(n) => serde_json::Number::from_f64(*n).map_or(Json::Null, Json::Number),
        Value::Str(s) => Json::String(s.to_string()),
        Value::Bool(b) => Json::Bool(*b),
        Value::Array(items) => Json::Array(items.iter().map(to_json).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn attr(name: &str, default: Value) -> AttrValue {
        AttrValue {
            name: name.to_owned(),
            value: default.clone(),
            default,
        }
    }

    #[test]
    fn values_that_no_longer_fit_are_dropped_with_a_note() {
        let types = [
            attr("height", Value::Number(10.0)),
            attr("style", Value::string("brick")),
        ];
        let user = [
            ("height".to_owned(), json!(14.5)),
            ("style".to_owned(), json!(3)),
            ("floors".to_owned(), json!(4)),
        ];
        let (kept, dropped, notes) = overrides(&user, &types);
        assert_eq!(kept, [("height".to_owned(), Value::Number(14.5))]);
        assert_eq!(dropped, ["style", "floors"]);
        assert_eq!(
            notes,
            [
                "`style` is now a string: the value 3 was dropped",
                "`floors` is no longer an attribute of the grammar: its value was dropped",
            ]
        );
    }

    #[test]
    fn bad_drawn_lots_say_what_is_wrong() {
        let polygon =
            |points: Vec<[f64; 2]>| lots(Some(&LotRequest::Polygon { points })).unwrap_err();
        assert_eq!(
            polygon(vec![[0.0, 0.0], [1.0, 0.0]]),
            "the drawn lot has 2 corners: a lot needs at least three"
        );
        assert_eq!(
            polygon(vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]),
            "the drawn lot has no area (its corners are on one line or on one point)"
        );
        let file = |name: &str, text: &str| {
            lots(Some(&LotRequest::File {
                name: name.to_owned(),
                text: text.to_owned(),
            }))
        };
        assert_eq!(
            file("lots.txt", "").unwrap_err(),
            "cannot read lots from lots.txt: expected an .obj, .geojson or .json file"
        );
        assert_eq!(
            file("empty.obj", "# nothing\n").unwrap_err(),
            "empty.obj has no polygons to use as lots"
        );
        let (found, _) = file(
            "square.obj",
            "v 0 0 0\nv 4 0 0\nv 4 0 -3\nv 0 0 -3\nf 1 2 3 4\n",
        )
        .unwrap();
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].footprint.len(), 4);
    }
}
