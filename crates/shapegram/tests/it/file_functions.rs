//! The CGA file functions through `shapegram derive`: `fileSearch`, `filesSearch`, `fileRandom`
//! over the grammar's project, and tables read with `readStringTable`.

use crate::common;

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

#[test]
fn asset_and_image_functions_read_the_project_files() {
    // Two textures (128 × 64 and 64 × 64 pixels), two boxes and a tree of two named groups
    // with a material each, found by regular expressions and fitted to the 20 × 30 lot.
    let dir = TempDir::new("asset-functions");
    let assets = dir.path("Town/assets");
    std::fs::create_dir_all(assets.join("tex")).unwrap();
    std::fs::create_dir_all(assets.join("boxes")).unwrap();
    std::fs::copy(example("textures/brick.png"), assets.join("tex/brick.png")).unwrap();
    std::fs::copy(
        example("textures/lattice.png"),
        assets.join("tex/lattice.png"),
    )
    .unwrap();
    // An OBJ object of a box `x` × `y` × `z` at the origin whose vertices follow `before`
    // others in the file.
    let cuboid = |name: &str, [x, y, z]: [f64; 3], before: usize| {
        let corners: String = (0..8)
            .map(|i| {
                let pick = |bit: usize, size: f64| if i & bit == 0 { 0.0 } else { size };
                format!("v {} {} {}\n", pick(1, x), pick(2, y), pick(4, z))
            })
            .collect();
        let faces: String = [
            [1, 2, 4, 3],
            [5, 7, 8, 6],
            [1, 5, 6, 2],
            [3, 4, 8, 7],
            [1, 3, 7, 5],
            [2, 6, 8, 4],
        ]
        .iter()
        .map(|f| {
            format!(
                "f {} {} {} {}\n",
                f[0] + before,
                f[1] + before,
                f[2] + before,
                f[3] + before
            )
        })
        .collect();
        format!("o {name}\n{corners}{faces}")
    };
    std::fs::write(assets.join("boxes/small.obj"), cuboid("Small", [1.0; 3], 0)).unwrap();
    std::fs::write(
        assets.join("boxes/big.obj"),
        cuboid("Big", [16.0, 3.0, 24.0], 0),
    )
    .unwrap();
    let trunk = cuboid("Trunk", [1.0, 4.0, 1.0], 0).replacen('\n', "\nusemtl Bark\n", 1);
    let crown = cuboid("Crown", [3.0; 3], 8).replacen('\n', "\nusemtl Leaves\n", 1);
    std::fs::write(
        assets.join("tree.obj"),
        format!("mtllib tree.mtl\n{trunk}{crown}"),
    )
    .unwrap();
    std::fs::write(
        assets.join("tree.mtl"),
        "newmtl Bark\nKd 0.4 0.2 0\nnewmtl Leaves\nKd 0 0.6 0\n",
    )
    .unwrap();
    let grammar = dir.path("Town/rules/lot.cga");
    std::fs::create_dir_all(grammar.parent().unwrap()).unwrap();
    std::fs::write(
        &grammar,
        "Lot --> print(imageInfo(\"tex/brick.png\", sx)) print(imageInfo(\"tex/brick.png\", sy))\n\
         print(imageBestRatio(\"$tex/.*[.]png\", \"xz\")) print(imageBestRatio(\"$tex/.*[.]png\", \"zx\"))\n\
         print(assetBestSize(\"$boxes/.*\", \"xz\")) print(assetsSortSize(fileSearch(\"$boxes/.*\"), xyz, 0))\n\
         print(assetNamingInfo(\"tree.obj\", m)) print(assetNamingInfos(\"tree.obj\", g))\n\
         print(fileSearch(\"$tex/(brick|tiles)[.]png\")) X.\n",
    )
    .unwrap();
    let output = shapegram(&["derive".as_ref(), grammar.as_os_str(), "--stats".as_ref()]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    let prints: Vec<&str> = err
        .lines()
        .filter_map(|l| l.strip_prefix("print: "))
        .collect();
    assert_eq!(
        prints,
        [
            "128",
            "64",
            "/Town/assets/tex/lattice.png",
            "/Town/assets/tex/brick.png",
            "/Town/assets/boxes/big.obj",
            "/Town/assets/boxes/big.obj;/Town/assets/boxes/small.obj;",
            "Bark;Leaves;",
            "[Trunk,Crown]",
            "/Town/assets/tex/brick.png;",
        ],
        "{err}"
    );
    // A selector outside the reference's is an error at its place in the grammar.
    std::fs::write(
        &grammar,
        "Lot --> print(imageInfo(\"tex/brick.png\", sz)) X.\n",
    )
    .unwrap();
    let output = shapegram(&["derive".as_ref(), grammar.as_os_str()]);
    let err = stderr(&output);
    assert!(!output.status.success());
    assert!(
        err.contains("`sz`: expected sx (the width) or sy (the height)")
            && err.contains("lot.cga:1:"),
        "{err}"
    );
}
