//! Reading the derivation's files: tables, text files and file searches.

use std::sync::Arc;

use shapegram_syntax::Span;

use super::{Evaluator, Result};
use crate::AssetLoader;
use crate::builtins::Builtin;
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl<'p> Evaluator<'p> {
    /// The derivation's files, or the error that `doing` ("read `x`") cannot be done without
    /// them, at `span`.
    pub(super) fn loader(&self, doing: &str, span: Span) -> Result<&'p dyn AssetLoader> {
        self.assets.ok_or_else(|| {
            DeriveError::at(
                format!("cannot {doing}: this derivation reads no files"),
                span,
            )
        })
    }

    /// `fileSearch(q)` (a string list, `a;b;`), `filesSearch(q)` (an array) and `fileRandom(q)`
    /// (one of them drawn from the shape's random stream, `""` when none): the files the
    /// derivation's assets find for the query, sorted.
    pub(super) fn search_files(
        &mut self,
        b: Builtin,
        query: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let found = self.searched(query, shape, args)?;
        Ok(match b {
            Builtin::FileSearch => {
                Value::string(&found.iter().map(|f| format!("{f};")).collect::<String>())
            }
            Builtin::FilesSearch => Value::Array(found.iter().map(|f| Value::string(f)).collect()),
            _ => match found.len() {
                0 => Value::string(""),
                n => {
                    let at = ((shape.rng.next_f64() * n as f64) as usize).min(n - 1);
                    Value::string(&found[at])
                }
            },
        })
    }

    /// The files a search query finds, sorted, as `fileSearch` has them.
    pub(super) fn searched(
        &mut self,
        query: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Vec<Arc<str>>> {
        let text = self.string_as("a search query", query, shape, args)?;
        self.loader(&format!("search for `{text}`"), query.span)?
            .search(&text)
            .map_err(|why| DeriveError::at(why, query.span))
    }

    /// `readStringTable(path)` and `readFloatTable(path)`: the file's table, read through the
    /// derivation's assets.
    pub(super) fn read_table(
        &mut self,
        b: Builtin,
        path: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = self.string_as("a file path", path, shape, args)?;
        let assets = self.loader(&format!("read `{name}`"), path.span)?;
        let text = assets
            .text(&name)
            .map_err(|why| DeriveError::at(why, path.span))?;
        let rows = crate::tables::rows(&text);
        if b == Builtin::ReadStringTable {
            return Ok(crate::tables::string_table(&rows));
        }
        crate::tables::float_table(&rows).map_err(|(r, c, field)| {
            DeriveError::at(
                format!("`{name}` row {r}, column {c}: `{field}` is not a number"),
                path.span,
            )
            .with_hint("read it with readStringTable, or convert fields with float()")
        })
    }

    /// `fileExists(path)`: whether the derivation's assets have the file (false when it reads
    /// no files); `readTextFile(path)`: the file's text.
    pub(super) fn read_file(
        &mut self,
        b: Builtin,
        path: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = self.string(path, shape, args)?;
        if b == Builtin::FileExists {
            return Ok(Value::Bool(self.assets.is_some_and(|a| a.exists(&name))));
        }
        let assets = self.loader(&format!("read `{name}`"), path.span)?;
        let text = assets
            .text(&name)
            .map_err(|why| DeriveError::at(why, path.span))?;
        Ok(Value::Str(text))
    }
}
