//! What the page draws while a cut is pending, computed by shapegram-topo rather than guessed
//! in the browser: the polygons where the cut's planes meet the sub-shapes it would cut
//! (`POST /api/topo/sections`), and the texture images of the project's materials
//! (`GET /api/topo/texture`), which the edit view draws on its faces.

use std::path::Path;

use axum::Json;
use axum::extract::State;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::{Deserialize, Serialize};
use shapegram_topo::{NodeKind, Project, cut};

use super::action::Action;
use super::{project_path, texture_beside, unprocessable};
use crate::error::ApiError;
use crate::extract::{ApiQuery, JsonBody};
use crate::studio::StudioState;

/// The body of `POST /api/topo/sections`: a cut as the page would send it to
/// `POST /api/topo/action`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionsRequest {
    pub path: String,
    pub action: Action,
}

/// The sections of a pending cut: one polygon (corners in order) per sub-shape it cuts.
#[derive(Serialize)]
pub struct Sections {
    pub sections: Vec<Vec<[f64; 3]>>,
    /// Why the cut would be refused (then there are no sections).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
}

/// `POST /api/topo/sections`: makes the cut on a copy of the project (the session is left as it
/// was) and answers where its planes meet the sub-shapes: exact for every tool, the global face
/// cut and the 3-point cut crossing several sub-shapes included. A cut that would be refused
/// (a plane moved past the shape, say) is no bad request: it has no sections and says why.
pub async fn sections(
    State(state): State<StudioState>,
    JsonBody(request): JsonBody<SectionsRequest>,
) -> Result<Json<Sections>, ApiError> {
    let real = project_path(&state, &request.path)?;
    let mut project = state.topo.with(&real, |s| Ok(s.editor.project().clone()))?;
    let rule = request
        .action
        .cut_rule()
        .ok_or_else(|| ApiError::bad_request("only a cut has sections"))?;
    let before = project
        .rule(rule)
        .map_err(unprocessable)?
        .tree
        .nodes()
        .len();
    Ok(Json(match request.action.run(&mut project) {
        Ok(_) => Sections {
            sections: new_sections(&project, rule, before),
            refused: None,
        },
        Err(e) => Sections {
            sections: Vec::new(),
            refused: Some(e.to_string()),
        },
    }))
}

/// The sections of the cuts that made nodes numbered from `first` on in `rule`'s tree.
fn new_sections(project: &Project, rule: u32, first: usize) -> Vec<Vec<[f64; 3]>> {
    let Ok(rule) = project.rule(rule) else {
        return Vec::new();
    };
    rule.tree
        .nodes()
        .iter()
        .filter_map(|node| match &node.kind {
            NodeKind::Cut { plane, children } if children[0] as usize >= first => {
                let parts = cut(&node.shape, plane).ok()?;
                let cap = &parts.below;
                Some(
                    cap.shape
                        .face_loop(cap.cap)
                        .map(|v| cap.shape.position(v).to_array())
                        .collect(),
                )
            }
            _ => None,
        })
        .collect()
}

/// The query of `GET /api/topo/texture`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureQuery {
    /// The project.
    pub path: String,
    /// The image, relative to the project's folder (a material's `texture`).
    pub texture: String,
}

/// `GET /api/topo/texture?path=…&texture=…`: a material's image, read as the export reads it:
/// only from within the project's folder; 404 when it is not there.
pub async fn texture(
    State(state): State<StudioState>,
    ApiQuery(query): ApiQuery<TextureQuery>,
) -> Result<Response, ApiError> {
    let real = project_path(&state, &query.path)?;
    let folder = real.parent().unwrap_or(Path::new("."));
    let bytes = texture_beside(folder, &query.texture).ok_or_else(|| {
        ApiError::new(
            StatusCode::NOT_FOUND,
            format!("no texture `{}` in the project's folder", query.texture),
        )
    })?;
    let mut response = bytes.to_vec().into_response();
    response.headers_mut().insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static(image_type(&query.texture)),
    );
    Ok(response)
}

/// The media type of an image by its extension.
fn image_type(name: &str) -> &'static str {
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".png") {
        "image/png"
    } else if lower.ends_with(".jpg") || lower.ends_with(".jpeg") {
        "image/jpeg"
    } else if lower.ends_with(".webp") {
        "image/webp"
    } else {
        "application/octet-stream"
    }
}
