//! `GET /api/vocabulary`: the words the engine knows, for the editor's completion: operations
//! with their signatures and support, built-in functions and shape queries. Served from the
//! engine's own tables so that the page never keeps a copy that could drift.

use axum::Json;
use serde::Serialize;
use shapegram_eval::Support;

/// The answer of `GET /api/vocabulary`.
#[derive(Serialize)]
pub struct Vocabulary {
    /// Operations (`extrude`, `split`, …).
    pub operations: Vec<Word>,
    /// Built-in functions (`rand`, `min`, …).
    pub functions: Vec<Word>,
    /// Shape queries (`scope.sx`, `split.index`, …).
    pub queries: Vec<Word>,
}

/// One word and what the editor shows beside it.
#[derive(Serialize)]
pub struct Word {
    pub name: &'static str,
    /// How it is called, when the engine says.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub signature: Option<&'static str>,
    /// For operations: `implemented`, `visual-only` (accepted without effect) or `unsupported`
    /// (skipped with a warning).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub support: Option<&'static str>,
}

/// `GET /api/vocabulary`.
pub async fn vocabulary() -> Json<Vocabulary> {
    Json(Vocabulary {
        operations: shapegram_eval::operations()
            .map(|(name, support, signature)| Word {
                name,
                signature,
                support: Some(match support {
                    Support::Implemented => "implemented",
                    Support::VisualOnly => "visual-only",
                    Support::Unsupported => "unsupported",
                }),
            })
            .collect(),
        functions: shapegram_eval::functions()
            .map(|(name, signature)| Word {
                name,
                signature,
                support: None,
            })
            .collect(),
        queries: shapegram_eval::queries()
            .map(|name| Word {
                name,
                signature: None,
                support: None,
            })
            .collect(),
    })
}
