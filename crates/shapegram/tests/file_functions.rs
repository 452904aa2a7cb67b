//! The CGA file functions through `shapegram derive`: `fileSearch`, `filesSearch`, `fileRandom`
//! over the grammar's project, and tables read with `readStringTable`.

mod common;

use common::{TempDir, example, shapegram, stderr};

#[test]
fn files_are_searched_in_the_project_and_drawn_at_random() {
    let dir = TempDir::new("file-functions");
    let project = dir.path("Town");
    for name in ["a.obj", "b.obj", "c.txt"] {
        let path = project.join("assets/trees").join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::copy(example("roof.obj"), &path).unwrap();
    }
    std::fs::write(project.join("assets/heights.csv"), "h\n4\n").unwrap();
    let grammar = project.join("rules/lot.cga");
    std::fs::create_dir_all(grammar.parent().unwrap()).unwrap();
    std::fs::write(
        &grammar,
        "const h = float(readStringTable(\"heights.csv\")[1, 0])\n\
         Lot --> print(fileSearch(\"assets/trees/*.obj\")) split(x) { { ~4 : Cell }* }\n\
         Cell --> s('1, h, '1) i(fileRandom(\"*trees/*.obj\")) report(\"n\", size(filesSearch(\"*.OBJ\")))\n",
    )
    .unwrap();
    let output = shapegram(&["derive".as_ref(), grammar.as_os_str(), "--stats".as_ref()]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(
        err.contains("print: /Town/assets/trees/a.obj;/Town/assets/trees/b.obj;\n"),
        "{err}"
    );
    let stats: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(stats["reports"]["n"]["count"], 5);
    assert_eq!(stats["reports"]["n"]["min"], 2.0);
    assert_eq!(stats["leaves"], 5);
}

#[test]
fn a_missing_table_is_a_warning_and_an_empty_table() {
    // CityEngine's readStringTable reports a file it cannot read and goes on with an empty
    // table; so does derive, without `--missing-assets`.
    let dir = TempDir::new("missing-table");
    let grammar = dir.path("lot.cga");
    std::fs::write(
        &grammar,
        "const rows = nRows(readStringTable(\"plants.csv\"))\n\
         Lot --> report(\"rows\", rows) extrude(rows + 2) X.\n",
    )
    .unwrap();
    let output = shapegram(&["derive".as_ref(), grammar.as_os_str(), "--stats".as_ref()]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(
        err.contains("plants.csv") && err.contains(": reading an empty table instead"),
        "{err}"
    );
    let stats: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(stats["reports"]["rows"]["sum"], 0.0);
    assert_eq!(stats["triangles"], 12);
}
