//! `shapegram derive` and `check` follow a grammar's imports on disk.

mod common;

use common::{TempDir, shapegram, stderr};

#[test]
fn imports_are_found_beside_the_file_in_the_project_and_in_the_workspace() {
    let dir = TempDir::new("imports");
    let write = |path: &str, text: &str| {
        let path = dir.path(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    };
    // A project with rules in subfolders, and a library in the workspace's `.ws` folder.
    write(
        "project/rules/main/lot.cga",
        "import near : \"near.cga\" (h = 4)\nimport far : \"rules/shared/far.cga\"\nimport lib : \"/Lib/rules/roof.cga\"\n@StartRule\nLot --> near.Base far.Mark lib.Roof\n",
    );
    write(
        "project/rules/main/near.cga",
        "attr h = 1\nBase --> extrude(h) report(\"h\", scope.sy)\n",
    );
    write(
        "project/rules/shared/far.cga",
        "Mark --> report(\"far\", 1)\n",
    );
    write(
        "project/.ws/Lib/rules/roof.cga",
        "Roof --> report(\"roof\", 1)\n",
    );
    let grammar = dir.path("project/rules/main/lot.cga");
    let output = shapegram(&[
        "derive".as_ref(),
        grammar.as_os_str(),
        "--stats".as_ref(),
        "-q".as_ref(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let stats: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(stats["reports"]["h"]["sum"], 4.0);
    assert_eq!(stats["reports"]["far"]["count"], 1);
    assert_eq!(stats["reports"]["roof"]["count"], 1);
}

#[test]
fn a_missing_import_is_an_error_at_its_path() {
    let dir = TempDir::new("missing-import");
    let grammar = dir.path("lot.cga");
    std::fs::write(&grammar, "import x : \"nowhere.cga\"\nLot --> x.A\n").unwrap();
    let output = shapegram(&["check".as_ref(), grammar.as_os_str()]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: cannot find the imported file \"nowhere.cga\"\n"),
        "{err}"
    );
    assert!(err.contains("lot.cga:1:12"), "{err}");
}
