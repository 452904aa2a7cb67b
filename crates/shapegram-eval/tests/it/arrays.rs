//! Arrays as CityEngine reads them: the colon operator, 2D arrays and indexing by ranges and
//! arrays of indices (the forms of Esri's plant library).

use crate::common;

use common::{lot, run, try_run};
use shapegram_eval::DeriveOptions;

/// What `print` shows for each expression, one per line of the rule.
fn printed(exprs: &[&str]) -> Vec<String> {
    let prints: String = exprs.iter().map(|e| format!(" print({e})")).collect();
    let text = format!(
        "const m = [1, 2, 3; 4, 5, 6; 7, 8, 9]\nconst a = [10, 20, 30, 40]\nLot -->{prints} X.\n"
    );
    run(&text, lot(4.0, 4.0)).prints
}

#[test]
fn the_colon_operator_makes_ranges_in_brackets() {
    assert_eq!(
        printed(&[
            "[1:5]",
            "[1:2:6]",
            "[5:-2:1]",
            "[0:0.1:0.3]",
            "[3:1]",
            "[0:2 ; 3, 3, 3]"
        ]),
        [
            "[1,2,3,4,5]",
            "[1,3,5]",
            "[5,3,1]",
            "[0,0.1,0.2,0.30000000000000004]",
            "[]",
            "[[0,1,2],[3,3,3]]"
        ]
    );
    // Ranges join the other elements of their row.
    assert_eq!(printed(&["[7, 1:3, 9]"]), ["[7,1,2,3,9]"]);
}

#[test]
fn indices_pick_elements_rows_columns_and_tables() {
    assert_eq!(
        printed(&[
            "a[1]",
            "a[1:2]",
            "a[[3, 0]]",
            "m[1, 0]",
            "m[1]",
            "m[0:1, 2]",
            "m[2, 0:1]",
            "m[1:2, 1:2]",
            "m[2:-1:0, 0]",
        ]),
        [
            "20",
            "[20,30]",
            "[40,10]",
            "4",
            "[4,5,6]",
            "[3,6]",
            "[7,8]",
            "[[5,6],[8,9]]",
            "[7,4,1]"
        ]
    );
}

#[test]
fn bad_ranges_and_indices_are_errors_at_the_expression() {
    let error = |expr: &str| {
        let text = format!("const a = [10, 20, 30]\nLot --> print({expr}) X.\n");
        let e = try_run(&text, lot(4.0, 4.0), &DeriveOptions::default()).unwrap_err();
        let span = e.span.expect("an error with a place");
        (e.message, text[span.range()].to_owned())
    };
    assert_eq!(
        error("[1:0:5]"),
        (
            "the range 1:0:5 needs finite ends and a step other than 0".to_owned(),
            "1:0:5".to_owned()
        )
    );
    assert_eq!(
        error("a[1:5]"),
        (
            "index 3 is out of range for an array of 3".to_owned(),
            "1:5".to_owned()
        )
    );
    assert_eq!(
        error("a[0, 1]"),
        (
            "two indices need a 2D array (rows written `[a, b; c, d]`)".to_owned(),
            "a".to_owned()
        )
    );
    assert_eq!(
        error("[0:1:1e9]"),
        (
            "the range 0:1:1000000000 has more than 10000000 numbers".to_owned(),
            "0:1:1e9".to_owned()
        )
    );
}

#[test]
fn string_and_list_functions_run_in_grammars() {
    assert_eq!(
        printed(&[
            "findFirst(\"oak;elm;\", \"elm\")",
            "count(\"a-b-c\", \"-\")",
            "substring(\"facade\", 1, 4)",
            "listItem(\"oak;elm;ash;\", 2)",
            "listSize(\"oak;elm;ash;\")",
            "listFromArray([\"a\", \"b\"])",
            "splitString(\"1,2,3\", \",\")",
            "getSuffix(\"tex/wall.jpg\", \".\")",
            "findFirst(m[0:2, 1], 5)",
            "findFirst([\"oak\", \"elm\"], \"ash\")",
        ]),
        [
            "4", "2", "aca", "ash", "3", "a;b;", "[1,2,3]", "jpg", "1", "-1"
        ]
    );
    // listRandom draws from the shape's stream: the same seed picks the same item.
    let text = "Lot --> print(listRandom(\"a;b;c;d;e;f;g;h;\")) X.\n";
    let first = run(text, lot(4.0, 4.0)).prints;
    assert_eq!(first, run(text, lot(4.0, 4.0)).prints);
    assert_eq!(first[0].len(), 1);
}

#[test]
fn geometry_functions_ask_about_the_shape_s_faces() {
    let ask = "print(geometry.isRectangular(1) + \" \" + geometry.isConcave() + \" \" + geometry.isPlanar(0.1) + \" \" + geometry.isClosedSurface() + \" \" + geometry.nEdges() + \" \" + geometry.boundaryLength() + \" \" + geometry.height() + \" \" + geometry.nHoles)";
    let lot_l = shapegram_eval::InitialShape::from_xz(&[
        shapegram_geom::DVec2::new(0.0, 0.0),
        shapegram_geom::DVec2::new(6.0, 0.0),
        shapegram_geom::DVec2::new(6.0, 2.0),
        shapegram_geom::DVec2::new(2.0, 2.0),
        shapegram_geom::DVec2::new(2.0, 5.0),
        shapegram_geom::DVec2::new(0.0, 5.0),
    ])
    .unwrap();
    let text = format!("Lot --> {ask} extrude(3) Mass\nMass --> {ask} X.\n");
    assert_eq!(
        run(&text, lot(4.0, 3.0)).prints,
        [
            "true false true false 4 14 0 0",
            "true false true true 12 0 3 0"
        ]
    );
    assert_eq!(
        run(&text, lot_l).prints,
        [
            "false true true false 6 22 0 0",
            "false true true true 18 0 3 0"
        ]
    );
}

#[test]
fn every_string_function_is_known_to_the_compiler() {
    assert_eq!(
        printed(&[
            "fileBasename(\"tex/wall.01.jpg\")",
            "fileExtension(\"tex/wall.01.jpg\")",
            "fileDirectory(\"tex/wall.jpg\")",
            "fileName(\"tex/wall.jpg\")",
            "findLast(\"a.b.c\", \".\")",
            "getPrefix(\"a_b\", \"_\")",
            "getRange(\"[a]\", \"[\", \"]\")",
            "replace(\"a-b\", \"-\", \"+\")",
            "len(\"abc\")",
            "listFirst(\"a;b;\") + listLast(\"a;b;\")",
            "listRange(\"a;b;c;\", 1, 3)",
            "listIndex(\"a;b;\", \"b\") + listCount(\"a;b;a;\", \"a\")",
            "listAdd(\"a\", \"b\") + listRemove(\"a;b;\", \"a\")",
            "listRemoveAll(\"a;b;\", \"b;\") + listRetainAll(\"a;b;\", \"b;\")",
            "listClean(\";a;;\") + listTerminate(\"a\")",
            "listToArray(\"a;b;\")",
        ]),
        [
            "wall.01", "jpg", "tex/", "wall.jpg", "3", "a", "a", "a+b", "3", "ab", "b;c;", "3",
            "a;b;b;", "a;b;", "a;a;", "[a,b]"
        ]
    );
}
