//! `shapegram derive` and `check` follow a grammar's imports on disk.

use crate::common;

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

/// A `w` × 1 quad standing in the xy-plane, as an OBJ.
fn quad_obj(w: u32) -> String {
    format!("v 0 0 0\nv {w} 0 0\nv {w} 1 0\nv 0 1 0\nf 1 2 3 4\n")
}

#[test]
fn files_an_imported_rule_names_are_found_beside_its_file_then_in_the_projects_assets() {
    let dir = TempDir::new("import-assets");
    let write = |path: &str, bytes: &[u8]| {
        let path = dir.path(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    };
    let brick = include_bytes!("../../../../examples/textures/brick.png");
    let lattice = include_bytes!("../../../../examples/textures/lattice.png");
    write(
        "project/rules/main.cga",
        b"import lib : \"lib/other.cga\"\n@StartRule\nLot --> [ lib.Win ] [ lib.Door ] Mine\n\
          Mine --> i(\"win.obj\", yUp, keepSizeAndPosition) report(\"main\", scope.sx) M.\n",
    );
    write(
        "project/rules/lib/other.cga",
        b"Win --> i(\"win.obj\", yUp, keepSizeAndPosition) report(\"win\", scope.sx)\n\
          setupProjection(0, scope.xy, 1, 1) projectUV(0) texture(\"a.png\") W.\n\
          Door --> i(\"door.obj\", yUp, keepSizeAndPosition) report(\"door\", scope.sx) D.\n",
    );
    // The same names beside the grammar, beside the imported file and in the assets.
    write("project/rules/win.obj", quad_obj(1).as_bytes());
    write("project/rules/a.png", lattice);
    write("project/rules/lib/win.obj", quad_obj(2).as_bytes());
    write("project/rules/lib/a.png", brick);
    write("project/assets/door.obj", quad_obj(3).as_bytes());
    write("project/rules/door.obj", quad_obj(4).as_bytes());
    let out = dir.path("out.glb");
    let output = shapegram(&[
        "derive".as_ref(),
        dir.path("project/rules/main.cga").as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--stats".as_ref(),
        "-q".as_ref(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let stats: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    // The imported rule inserts its own folder's window, and a door from the project's assets
    // (not the one beside the grammar, which CityEngine does not search for an imported
    // file's names); the grammar's rule its own window.
    assert_eq!(stats["reports"]["win"]["sum"], 2.0);
    assert_eq!(stats["reports"]["main"]["sum"], 1.0);
    // The imported file's texture is the image beside it.
    let gltf = gltf::Gltf::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    let blob = gltf.blob.as_deref().unwrap();
    let images: Vec<&[u8]> = gltf
        .images()
        .map(|image| match image.source() {
            gltf::image::Source::View { view, .. } => {
                &blob[view.offset()..view.offset() + view.length()]
            }
            gltf::image::Source::Uri { .. } => panic!("images are embedded"),
        })
        .collect();
    assert_eq!(images, [&brick[..]]);
    assert_eq!(stats["reports"]["door"]["sum"], 3.0);
}
