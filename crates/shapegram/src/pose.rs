//! `derive --pose pose.json`: joints of the model's skeletons posed by name after deriving.
//!
//! The file is a JSON object from section names (as in the GLB's joint names and `--stats`) to
//! `{"rotation": [x, y, z], "translation": [x, y, z]}`, degrees and metres in the joint's axes;
//! either may be left out to keep the grammar's. Every pose must lie within its joint's limits.

use std::path::Path;

use serde_json::Value as Json;
use shapegram_geom::{DVec3, Model};

use crate::Failure;

/// Reads `path` and poses the named joints of every skeleton of `model`.
pub fn apply(path: &Path, model: &mut Model) -> Result<(), Failure> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::new(format!("cannot read {name}: {e}")))?;
    apply_text(&text, model).map_err(|e| Failure::new(format!("{name}: {e}")))
}

/// Poses the joints named in the JSON `text`; the error names the joint and what is wrong.
pub(crate) fn apply_text(text: &str, model: &mut Model) -> Result<(), String> {
    let json: Json = serde_json::from_str(text).map_err(|e| format!("invalid JSON: {e}"))?;
    let joints = json
        .as_object()
        .ok_or("expected an object from joint names to poses")?;
    if model.skeletons.is_empty() {
        return Err("the grammar builds no skeleton: there are no joints to pose".into());
    }
    for (joint, pose) in joints {
        let mut found = false;
        for skeleton in &mut model.skeletons {
            let Some(section) = skeleton.find(joint) else {
                continue;
            };
            found = true;
            let mut posed = skeleton.section(section).pose();
            let fields = pose.as_object().ok_or_else(|| {
                format!("{joint}: expected {{\"rotation\": [x, y, z], \"translation\": [x, y, z]}}")
            })?;
            for (key, value) in fields {
                let v = triple(value).ok_or_else(|| {
                    format!("{joint}: \"{key}\" is not a list of three finite numbers: {value}")
                })?;
                match key.as_str() {
                    "rotation" => posed.rotation = v,
                    "translation" => posed.translation = v,
                    other => {
                        return Err(format!(
                            "{joint}: unknown key \"{other}\": expected \"rotation\" or \"translation\""
                        ));
                    }
                }
            }
            skeleton
                .pose_within(section, posed)
                .map_err(|e| format!("{joint}: {e}"))?;
        }
        if !found {
            let names: Vec<String> = model
                .skeletons
                .iter()
                .flat_map(|s| s.sections().map(|(_, s)| s.name().to_string()))
                .collect();
            let hint = shapegram_syntax::suggest(joint, names.iter().map(String::as_str))
                .map(|n| format!(" (did you mean {n}?)"))
                .unwrap_or_default();
            return Err(format!("the model has no joint named {joint}{hint}"));
        }
    }
    Ok(())
}

/// `[x, y, z]` of finite numbers.
fn triple(value: &Json) -> Option<DVec3> {
    let items = value.as_array().filter(|a| a.len() == 3)?;
    let mut v = DVec3::ZERO;
    for (i, item) in items.iter().enumerate() {
        v[i] = item.as_f64().filter(|x| x.is_finite())?;
    }
    Some(v)
}

#[cfg(test)]
mod tests {
    use shapegram_geom::kinematics::{Frame, Limits, Range, Skeleton};

    use super::*;

    fn model() -> Model {
        let mut skeleton = Skeleton::new(Frame::IDENTITY, "Base");
        let door = skeleton.add_child(skeleton.root(), Frame::IDENTITY, "Door_abc123");
        let mut limits = Limits::default();
        limits.rotation[1] = Range::new(0.0, 100.0);
        skeleton.set_limits(door, limits).unwrap();
        Model {
            skeletons: vec![skeleton],
            ..Model::default()
        }
    }

    #[test]
    fn joints_are_posed_by_name_within_their_limits() {
        let mut m = model();
        apply_text(r#"{"Door_abc123": {"rotation": [0, 75, 0]}}"#, &mut m).unwrap();
        let door = m.skeletons[0].find("Door_abc123").unwrap();
        assert_eq!(
            m.skeletons[0].section(door).pose().rotation,
            DVec3::new(0.0, 75.0, 0.0)
        );
    }

    #[test]
    fn bad_pose_files_are_one_line_errors() {
        for (text, expected) in [
            ("[1]", "expected an object from joint names to poses"),
            (
                "{",
                "invalid JSON: EOF while parsing an object at line 1 column 1",
            ),
            (
                r#"{"Door_abc124": {"rotation": [0, 1, 0]}}"#,
                "the model has no joint named Door_abc124 (did you mean Door_abc123?)",
            ),
            (
                r#"{"Door_abc123": {"rotation": [0, 120, 0]}}"#,
                "Door_abc123: the rotation about y of 120° is outside the joint's limits (0° to 100°)",
            ),
            (
                r#"{"Door_abc123": {"rotation": [0, "x", 0]}}"#,
                "Door_abc123: \"rotation\" is not a list of three finite numbers: [0,\"x\",0]",
            ),
            (
                r#"{"Door_abc123": {"spin": [0, 1, 0]}}"#,
                "Door_abc123: unknown key \"spin\": expected \"rotation\" or \"translation\"",
            ),
        ] {
            assert_eq!(apply_text(text, &mut model()).unwrap_err(), expected);
        }
        assert_eq!(
            apply_text("{}", &mut Model::default()).unwrap_err(),
            "the grammar builds no skeleton: there are no joints to pose"
        );
    }
}
