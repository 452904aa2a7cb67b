//! Rule packages (`.rpk`) read straight from the archive: choosing the rule file as PRT does,
//! imports and assets found inside the package, and bad archives. Each test writes its own
//! small package with sevenz-rust2.

use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use sevenz_rust2::{ArchiveEntry, ArchiveWriter};
use shapegram_eval::AssetLoader;
use shapegram_load::{FileAssets, Files, MissingAssets, RulePackage};

/// A 7-Zip archive of `files` (path, contents), compressed with LZMA2 as CityEngine does.
fn archive(files: &[(&str, &[u8])]) -> Vec<u8> {
    let mut writer = ArchiveWriter::new(Cursor::new(Vec::new())).expect("a writer");
    for (name, bytes) in files {
        writer
            .push_archive_entry(ArchiveEntry::new_file(name), Some(*bytes))
            .expect("an entry");
    }
    writer.finish().expect("an archive").into_inner()
}

fn package(files: &[(&str, &[u8])]) -> Arc<RulePackage> {
    Arc::new(RulePackage::from_bytes("town.rpk".to_owned(), archive(files)).expect("a package"))
}

/// A unit cube with 8 vertices and 6 faces, 2 × 3 × 4 m, its corner at (1, 0, 0).
const BOX_OBJ: &[u8] =
    b"mtllib box.mtl\nv 1 0 0\nv 3 0 0\nv 3 3 0\nv 1 3 0\nv 1 0 4\nv 3 0 4\nv 3 3 4\nv 1 3 4\n\
usemtl red\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
const BOX_MTL: &[u8] = b"newmtl red\nKd 1 0 0\n";
const PNG: &[u8] = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x01\0\0\0\x01\x08\x02\0\0\0";

const RESOLVE_MAP: &[u8] = br#"<?xml version="1.0" encoding="UTF-8"?>
<resolvemap>
  <entry key="rules/a.cga" value="rules/a.cga" />
  <entry key="/My Town/rules/a.cga" value="rules/a.cga" />
  <entry key="/Shared.lib/assets/tree.obj" value=".ws/Shared.lib/assets/tree.obj" />
</resolvemap>"#;

#[test]
fn the_rule_file_is_the_source_of_the_compiled_one_as_prt_runs() {
    let package = package(&[
        ("rules/typology/main.cga", b"Lot --> X."),
        ("rules/typology/facade.cga", b"F --> X."),
        ("bin/typology/main.cgb", b"compiled"),
        ("bin/typology/main$facade.cgb", b"compiled import"),
        ("bin/typology/main$$facade.cgb", b"compiled import"),
    ]);
    assert_eq!(package.compiled_rules(), ["bin/typology/main.cgb"]);
    assert_eq!(
        package.rule_sources(),
        ["rules/typology/facade.cga", "rules/typology/main.cga"]
    );
    assert_eq!(package.rule_file(None).unwrap(), "rules/typology/main.cga");
    // Another rule file, by path, by name or by its compiled file.
    for asked in [
        "rules/typology/facade.cga",
        "typology/facade.cga",
        "facade.cga",
    ] {
        assert_eq!(
            package.rule_file(Some(asked)).unwrap(),
            "rules/typology/facade.cga"
        );
    }
    assert_eq!(
        package.rule_file(Some("bin/typology/main.cgb")).unwrap(),
        "rules/typology/main.cga"
    );
    let missing = package.rule_file(Some("roof.cga")).unwrap_err();
    assert_eq!(
        missing.message,
        "town.rpk has no rule file `roof.cga`; its rule files are rules/typology/facade.cga, rules/typology/main.cga"
    );
}

#[test]
fn several_rule_files_without_a_compiled_one_must_be_chosen() {
    let package = package(&[("rules/a.cga", b"A --> X."), ("rules/b.cga", b"B --> X.")]);
    let error = package.rule_file(None).unwrap_err();
    assert_eq!(
        error.message,
        "town.rpk holds 2 rule files: rules/a.cga, rules/b.cga"
    );
    assert_eq!(error.hint.as_deref(), Some("choose one with --rule-file"));
    assert_eq!(package.rule_file(Some("b.cga")).unwrap(), "rules/b.cga");
    // One source and nothing compiled: that one.
    let single = self::package(&[("rules/only.cga", b"A --> X.")]);
    assert_eq!(single.rule_file(None).unwrap(), "rules/only.cga");
}

#[test]
fn a_package_of_compiled_rules_only_says_so() {
    let package = package(&[
        ("bin/Candler Building.cgb", b"compiled"),
        ("assets/a.obj", b""),
    ]);
    let error = package.rule_file(None).unwrap_err();
    assert_eq!(
        error.message,
        "town.rpk holds only compiled rules (bin/Candler Building.cgb) and no CGA source: Shapegram runs CGA source, not CityEngine's compiled .cgb files"
    );
    assert!(error.hint.as_deref().unwrap().contains("rules/*.cga"));
    assert_eq!(
        package.rule_file(Some("Candler Building.cga")).unwrap_err(),
        error
    );
    assert_eq!(package.runnable_sources().unwrap_err(), error);
    // Assets alone: no rules of either kind.
    let assets = self::package(&[("assets/a.obj", b"")]);
    let none = "town.rpk holds no rule file (rules/*.cga)";
    assert_eq!(assets.rule_file(None).unwrap_err().message, none);
    assert_eq!(assets.runnable_sources().unwrap_err().message, none);
}

#[test]
fn corrupt_and_truncated_archives_are_named_errors() {
    let not_7z = RulePackage::from_bytes("plain.rpk".to_owned(), b"Lot --> X.".to_vec())
        .err()
        .unwrap();
    assert!(
        not_7z
            .message
            .starts_with("plain.rpk is not a readable rule package (a 7-Zip archive): "),
        "{not_7z}"
    );
    let whole = archive(&[("rules/a.cga", &[b'x'; 4000])]);
    for cut in [whole.len() / 2, 40, 0] {
        let error = RulePackage::from_bytes("cut.rpk".to_owned(), whole[..cut].to_vec())
            .err()
            .unwrap_or_else(|| panic!("{cut} bytes read"));
        assert!(
            error
                .message
                .starts_with("cut.rpk is not a readable rule package (a 7-Zip archive): "),
            "{cut}: {error}"
        );
    }
    let missing = RulePackage::open(Path::new("/nowhere/x.rpk"))
        .err()
        .unwrap();
    assert!(
        missing
            .message
            .starts_with("cannot read the rule package /nowhere/x.rpk: "),
        "{missing}"
    );
}

#[test]
fn assets_are_found_in_the_package_as_cityengine_finds_them() {
    let package = package(&[
        (".resolvemap.xml", RESOLVE_MAP),
        ("rules/a.cga", b"Lot --> X."),
        ("rules/near.obj", BOX_OBJ),
        ("assets/facade/box.obj", BOX_OBJ),
        ("assets/facade/box.mtl", BOX_MTL),
        ("assets/wall.png", PNG),
        ("assets/wall.tif", b"II*\0"),
        ("assets/heights.csv", b"a;1\nb;2\n"),
        ("assets/facade/win.obj", BOX_OBJ),
        ("data/table.csv", b"x\n"),
        (".ws/Shared.lib/assets/tree.obj", BOX_OBJ),
    ]);
    assert_eq!(package.project(), "My Town");
    let assets = FileAssets::in_package(Arc::clone(&package), "rules/a.cga", MissingAssets::Error);
    // Beside the grammar, then in assets/, then in the project, then workspace paths: the
    // package's own project and the workspace files it brings in .ws/.
    for (asked, found) in [
        ("near.obj", "rules/near.obj"),
        ("facade/box.obj", "assets/facade/box.obj"),
        ("data/table.csv", "data/table.csv"),
        ("/My Town/assets/facade/box.obj", "assets/facade/box.obj"),
        (
            "/Shared.lib/assets/tree.obj",
            ".ws/Shared.lib/assets/tree.obj",
        ),
    ] {
        assert_eq!(assets.find(asked), PathBuf::from(found), "{asked}");
    }
    let mesh = assets.load("facade/box.obj").unwrap();
    assert_eq!((mesh.vertex_count(), mesh.face_count()), (8, 6));
    let tree = assets.load("/Shared.lib/assets/tree.obj").unwrap();
    assert_eq!(tree.face_count(), 6);
    assert_eq!(&*assets.text("heights.csv").unwrap(), "a;1\nb;2\n");
    assert_eq!(assets.image("wall.png").unwrap().as_deref(), Some(PNG));
    // Another image format is a warning and no image, as on disk.
    assert_eq!(assets.image("wall.tif").unwrap(), None);
    assert_eq!(
        assets.search("assets/facade/*.obj").unwrap(),
        [
            Arc::from("/My Town/assets/facade/box.obj"),
            Arc::from("/My Town/assets/facade/win.obj"),
        ]
    );
    // fileSearch's workspace paths insert as they were found.
    assert_eq!(
        assets
            .load("/My Town/assets/facade/win.obj")
            .unwrap()
            .face_count(),
        6
    );
    let missing = assets.load("facade/door.obj").unwrap_err();
    assert_eq!(
        missing,
        "cannot read town.rpk!/rules/facade/door.obj: not in the rule package"
    );
}

#[test]
fn image_sizes_part_names_and_regular_expressions_read_inside_the_package() {
    // A JPEG's frame header says 7 × 5 pixels; the PNG's header 1 × 1.
    const JPEG: &[u8] =
        b"\xff\xd8\xff\xc0\0\x11\x08\0\x05\0\x07\x03\x01\x22\0\x02\x11\x01\x03\x11\x01\xff\xd9";
    let package = package(&[
        (".resolvemap.xml", RESOLVE_MAP),
        ("rules/a.cga", b"Lot --> X."),
        ("assets/facade/box.obj", BOX_OBJ),
        ("assets/facade/box.mtl", BOX_MTL),
        ("assets/wall.png", PNG),
        ("assets/sky.jpg", JPEG),
        ("assets/wall.tif", b"II*\0"),
    ]);
    let assets = FileAssets::in_package(package, "rules/a.cga", MissingAssets::Error);
    assert_eq!(assets.image_size("wall.png"), Ok((1, 1)));
    assert_eq!(assets.image_size("/My Town/assets/sky.jpg"), Ok((7, 5)));
    assert!(
        assets
            .image_size("wall.tif")
            .unwrap_err()
            .starts_with("cannot read the size of the image town.rpk!/assets/wall.tif: "),
    );
    assert_eq!(
        assets.image_size("gone.png").unwrap_err(),
        "cannot read town.rpk!/rules/gone.png: not in the rule package"
    );
    let naming = assets.naming("facade/box.obj").unwrap();
    assert_eq!(naming.materials, [Arc::from("red")]);
    assert_eq!(naming.groups, [Arc::from("unnamed_object")]);
    assert_eq!(
        assets.search("$(wall|sky)[.](png|jpg)").unwrap(),
        [
            Arc::from("/My Town/assets/sky.jpg"),
            Arc::from("/My Town/assets/wall.png"),
        ]
    );
}

#[test]
fn missing_assets_in_a_package_get_stand_ins_as_asked() {
    let package = package(&[("rules/a.cga", b"Lot --> X.")]);
    let cube = FileAssets::in_package(Arc::clone(&package), "rules/a.cga", MissingAssets::Cube);
    assert_eq!(cube.load("door.obj").unwrap().face_count(), 6);
    let skip = FileAssets::in_package(package, "rules/a.cga", MissingAssets::Skip);
    assert!(skip.load("door.obj").unwrap().is_empty());
    assert_eq!(&*skip.text("t.csv").unwrap(), "");
}

#[test]
fn imports_resolve_inside_the_package() {
    let package = package(&[
        (".resolvemap.xml", RESOLVE_MAP),
        (
            "rules/typology/main.cga",
            b"import facade : \"facade.cga\"\nimport shared : \"/Shared.lib/rules/trees.cga\"\n@StartRule\nLot --> facade.F shared.T",
        ),
        ("rules/typology/facade.cga", b"F --> X."),
        (".ws/Shared.lib/rules/trees.cga", b"T --> Y."),
    ]);
    let files = Files::Package(package);
    let path = Path::new("rules/typology/main.cga");
    let read = shapegram_load::read_in(&files, path).unwrap();
    assert_eq!(read.source.name(), "town.rpk!/rules/typology/main.cga");
    let compiled = shapegram_load::compile_in(&read.source, None, &files, path);
    assert_eq!(compiled.errors(), 0, "{:?}", compiled.diagnostics);
    assert!(compiled.program.is_some());
    let names: Vec<&str> = compiled.sources.iter().map(|s| s.name()).collect();
    assert_eq!(names.len(), 3);
    assert!(
        names.contains(&"town.rpk!/rules/typology/facade.cga"),
        "{names:?}"
    );
    assert!(
        names.contains(&"town.rpk!/.ws/Shared.lib/rules/trees.cga"),
        "{names:?}"
    );
    // An import the package does not have is an error at the import.
    let broken = Files::Package(self::package(&[(
        "rules/a.cga",
        b"import x : \"missing.cga\"\nLot --> X.",
    )]));
    let path = Path::new("rules/a.cga");
    let read = shapegram_load::read_in(&broken, path).unwrap();
    let compiled = shapegram_load::compile_in(&read.source, None, &broken, path);
    assert_eq!(compiled.errors(), 1);
    assert_eq!(
        compiled.diagnostics[0].1.message,
        "cannot find the imported file \"missing.cga\""
    );
}

#[test]
fn an_extracted_package_finds_its_workspace_files_as_the_archive_does() {
    let root = std::env::temp_dir().join(format!("shapegram-extracted-{}", std::process::id()));
    for (file, bytes) in [
        ("uvs/rules/r1.cga", b"Lot --> X." as &[u8]),
        ("uvs/.ws/Shared.lib/assets/uvtest.png", PNG),
    ] {
        let path = root.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, bytes).unwrap();
    }
    // No assets/ folder: the project is not found, and the package's root holds `.ws/`.
    let assets = FileAssets::new(root.join("uvs/rules"), MissingAssets::Error);
    let found = assets.find("/Shared.lib/assets/uvtest.png");
    assert_eq!(
        found,
        std::fs::canonicalize(root.join("uvs/.ws/Shared.lib/assets/uvtest.png")).unwrap()
    );
    assert_eq!(
        assets
            .image("/Shared.lib/assets/uvtest.png")
            .unwrap()
            .as_deref(),
        Some(PNG)
    );
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn damaged_packages_are_read_or_refused_never_a_panic() {
    let whole = archive(&[
        (
            "rules/a.cga",
            b"@StartRule\nLot --> extrude(3) i(\"box.obj\")",
        ),
        ("assets/box.obj", BOX_OBJ),
        (".resolvemap.xml", RESOLVE_MAP),
    ]);
    let mut refused = 0;
    for at in 0..whole.len() {
        for damage in [0x01u8, 0x80, 0xff] {
            let mut bytes = whole.clone();
            bytes[at] ^= damage;
            refused += usize::from(RulePackage::from_bytes("x.rpk".into(), bytes).is_err());
        }
        refused +=
            usize::from(RulePackage::from_bytes("x.rpk".into(), whole[..at].to_vec()).is_err());
    }
    // Every cut is refused; most flipped bytes are caught by the checksums.
    assert!(
        refused >= whole.len() * 3,
        "{refused} of {}",
        whole.len() * 4
    );
}
