//! `readStringTable`, `readFloatTable`, `nRows` and `nColumns` through the derivation's assets.

use crate::common;

use std::sync::Arc;

use shapegram_eval::{AssetLoader, DeriveOptions, Value, derive};
use shapegram_geom::Mesh;

/// Assets that hold two tables.
struct Tables;

impl AssetLoader for Tables {
    fn load(&self, path: &str) -> Result<Arc<Mesh>, String> {
        Err(format!("no mesh `{path}`"))
    }

    fn text(&self, path: &str) -> Result<Arc<str>, String> {
        match path {
            "heights.csv" => Ok("3,4.5\n6,7\n".into()),
            "names.csv" => Ok("name;kind\n\"Oak; old\";tree\n".into()),
            other => Err(format!("no file `{other}`")),
        }
    }
}

fn reports(grammar: &str) -> Result<Vec<(String, Value)>, String> {
    let options = DeriveOptions {
        assets: Some(Arc::new(Tables)),
        ..DeriveOptions::default()
    };
    derive(
        &common::compile(grammar),
        &[common::lot(10.0, 10.0)],
        &options,
    )
    .map(|d| d.reports)
    .map_err(|e| e.message)
}

#[test]
fn tables_are_read_as_arrays_of_rows() {
    let r = reports(
        "const h = readFloatTable(\"heights.csv\")\nconst n = readStringTable(\"names.csv\")\n\
         Lot --> report(\"rows\", nRows(h)) report(\"columns\", nColumns(h)) report(\"h\", h[1, 0] + h[0, 1]) report(\"name\", n[1, 0]) report(\"kind\", n[1][1])",
    )
    .unwrap();
    assert_eq!(
        r,
        [
            ("rows".to_owned(), Value::Number(2.0)),
            ("columns".to_owned(), Value::Number(2.0)),
            ("h".to_owned(), Value::Number(10.5)),
            ("name".to_owned(), Value::string("Oak; old")),
            ("kind".to_owned(), Value::string("tree")),
        ]
    );
}

#[test]
fn a_missing_table_or_a_field_that_is_no_number_is_an_error() {
    assert_eq!(
        reports("Lot --> report(\"x\", nRows(readStringTable(\"gone.csv\")))").unwrap_err(),
        "no file `gone.csv`"
    );
    assert_eq!(
        reports("Lot --> report(\"x\", nRows(readFloatTable(\"names.csv\")))").unwrap_err(),
        "`names.csv` row 0, column 0: `name` is not a number"
    );
}
