//! Rule packages (`.rpk`) loaded by a host: from a file or from bytes, the rule file chosen as
//! `shapegram derive` chooses it or named, imports, assets and textures read from inside the
//! package, and bad packages as errors of their own kind. Each test writes its own small
//! package with sevenz-rust2, as shapegram-load's tests do.

use std::io::Cursor;
use std::path::PathBuf;

use sevenz_rust2::{ArchiveEntry, ArchiveWriter};
use shapegram_eval::Value;
use shapegram_export::Buffers;
use shapegram_runtime::{ErrorKind, Grammar, Package, Settings};

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

/// A box of 6 quads.
const BOX_OBJ: &[u8] = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
const PNG: &[u8] = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x01\0\0\0\x01\x08\x02\0\0\0";

/// The town's main rule file: a mass whose sides are textured walls and whose top is a box
/// inserted by the rule file it imports.
const TOWN: &[u8] = b"import parts : \"parts.cga\"\n\
attr height = 4\n\
@StartRule\n\
Lot --> extrude(height) comp(f) { top : parts.Roof | side : Wall | bottom : NIL }\n\
Wall --> setupProjection(0, scope.xy, 1, 1) texture(\"wall.png\") projectUV(0) Brick.\n";

/// A package as CityEngine exports one: rule sources, the compiled main rule file that says
/// which one PRT runs, assets.
fn town() -> Vec<u8> {
    archive(&[
        ("rules/town.cga", TOWN),
        ("rules/parts.cga", b"Roof --> i(\"box.obj\") Box.\n"),
        ("rules/flat.cga", b"Lot --> color(\"#ff0000\") Flat.\n"),
        ("bin/town.cgb", b"compiled"),
        ("assets/box.obj", BOX_OBJ),
        ("assets/wall.png", PNG),
    ])
}

fn buffers(grammar: &Grammar, settings: &Settings) -> Buffers {
    let mut buffers = Buffers::default();
    grammar
        .derive(settings)
        .expect("the package derives")
        .fill(&mut buffers);
    buffers
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "shapegram-runtime-packages-{}-{name}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_package_derives_its_main_rule_file_with_imports_assets_and_textures() {
    let dir = scratch("main");
    let path = dir.join("town.rpk");
    std::fs::write(&path, town()).unwrap();
    let from_file = Grammar::load_package(&path, None).unwrap();
    let from_bytes = Grammar::load_package_bytes("town.rpk", town(), None).unwrap();
    let settings = Settings::default();
    let derived = from_file.derive(&settings).unwrap();
    let mut built = Buffers::default();
    derived.fill(&mut built);
    // Four walls of two triangles each and the imported rule's box of six quads on top.
    assert_eq!(built.indices.len(), 3 * (4 * 2 + 6 * 2));
    let names: Vec<&str> = built
        .parts
        .iter()
        .map(|p| derived.part_name(p.part))
        .collect();
    assert_eq!(names, ["Box", "Brick"]);
    // The wall's texture is the package's image.
    assert_eq!(built.textures.len(), 1);
    assert_eq!(&*built.textures[0].path, "wall.png");
    assert_eq!(built.textures[0].image.as_deref(), Some(PNG));
    assert_eq!(built.uvs.len(), built.positions.len());
    let again = buffers(&from_bytes, &settings);
    assert_eq!(
        (&built.positions, &built.indices),
        (&again.positions, &again.indices)
    );
    // Its attributes, named by their place in the package.
    let attrs = from_file.attrs();
    assert_eq!(attrs.len(), 1);
    assert_eq!(attrs[0].name, "height");
    assert_eq!(attrs[0].default, Some(Value::Number(4.0)));
    assert_eq!(
        attrs[0].location,
        format!("{}!/rules/town.cga:2:6", path.display())
    );
    let higher = Settings {
        attrs: vec![("height".to_owned(), Value::Number(9.0))],
        ..Settings::default()
    };
    // The walls (the second part) are as high as the attribute says.
    let top = |b: &Buffers| {
        let walls = &b.parts[1];
        let first = walls.first_vertex as usize;
        b.positions[first..first + walls.vertex_count as usize]
            .iter()
            .map(|p| p[1])
            .fold(f32::MIN, f32::max)
    };
    assert_eq!(top(&built), 4.0);
    assert_eq!(top(&buffers(&from_file, &higher)), 9.0);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn another_rule_file_is_chosen_by_its_name_or_path() {
    let package = Package::from_bytes("town.rpk", town()).unwrap();
    assert_eq!(package.name(), "town.rpk");
    assert_eq!(
        package.rule_files().unwrap(),
        ["rules/flat.cga", "rules/parts.cga", "rules/town.cga"]
    );
    assert_eq!(package.rule_file(None).unwrap(), "rules/town.cga");
    for asked in ["flat.cga", "rules/flat.cga", "bin/flat.cgb"] {
        let flat = package.load(Some(asked)).unwrap();
        let built = buffers(&flat, &Settings::default());
        // The default 20 × 30 lot, one quad.
        assert_eq!(built.indices.len(), 6, "{asked}");
        assert!(flat.attrs().is_empty());
    }
}

#[test]
fn a_missing_rule_file_lists_the_packages_rule_files() {
    let error = Grammar::load_package_bytes("town.rpk", town(), Some("roof.cga"))
        .err()
        .unwrap();
    assert_eq!(error.kind, ErrorKind::Package);
    assert_eq!(
        error.message,
        "town.rpk has no rule file `roof.cga`; its rule files are rules/flat.cga, rules/parts.cga, rules/town.cga"
    );
    // Nothing compiled and several sources: the host must name one.
    let two = archive(&[("rules/a.cga", b"A --> X."), ("rules/b.cga", b"B --> X.")]);
    let error = Grammar::load_package_bytes("two.rpk", two, None)
        .err()
        .unwrap();
    assert_eq!(error.kind, ErrorKind::Package);
    assert_eq!(
        error.message,
        "two.rpk holds 2 rule files: rules/a.cga, rules/b.cga (hint: choose one by naming its rule file)"
    );
}

#[test]
fn a_package_of_compiled_rules_only_is_refused() {
    let compiled = archive(&[
        ("bin/Candler Building.cgb", b"compiled"),
        ("assets/a.obj", b""),
    ]);
    let error = Package::from_bytes("candler.rpk", compiled)
        .unwrap()
        .load(None)
        .err()
        .unwrap();
    assert_eq!(error.kind, ErrorKind::Package);
    assert!(
        error.message.starts_with(
            "candler.rpk holds only compiled rules (bin/Candler Building.cgb) and no CGA source: Shapegram runs CGA source, not CityEngine's compiled .cgb files (hint: use a package that includes its rules/*.cga files"
        ),
        "{}",
        error.message
    );
}

#[test]
fn corrupt_truncated_and_missing_packages_are_errors() {
    let not_7z = Package::from_bytes("plain.rpk", b"Lot --> X.".to_vec())
        .err()
        .unwrap();
    assert_eq!(not_7z.kind, ErrorKind::Package);
    assert!(
        not_7z
            .message
            .starts_with("plain.rpk is not a readable rule package (a 7-Zip archive): "),
        "{}",
        not_7z.message
    );
    let whole = town();
    for cut in [whole.len() / 2, 40, 0] {
        let error = Grammar::load_package_bytes("cut.rpk", whole[..cut].to_vec(), None)
            .err()
            .unwrap_or_else(|| panic!("{cut} bytes loaded"));
        assert_eq!(error.kind, ErrorKind::Package, "{cut}");
    }
    let missing = Grammar::load_package(std::path::Path::new("/nowhere/town.rpk"), None)
        .err()
        .unwrap();
    assert_eq!(missing.kind, ErrorKind::Io);
    assert!(
        missing
            .message
            .starts_with("cannot read the rule package /nowhere/town.rpk: "),
        "{}",
        missing.message
    );
}

#[test]
fn errors_in_a_packaged_rule_file_point_into_the_package() {
    let broken = archive(&[("rules/bad.cga", b"Lot --> extrude(\n")]);
    let error = Grammar::load_package_bytes("bad.rpk", broken, None)
        .err()
        .unwrap();
    assert_eq!(error.kind, ErrorKind::Grammar);
    assert!(
        error.message.contains("bad.rpk!/rules/bad.cga:"),
        "{}",
        error.message
    );
    // An asset the package lacks fails the derivation, naming where it was looked for.
    let lacking = archive(&[("rules/a.cga", b"Lot --> i(\"door.obj\") Door.\n")]);
    let grammar = Grammar::load_package_bytes("lacking.rpk", lacking, None).unwrap();
    let error = grammar.derive(&Settings::default()).err().unwrap();
    assert_eq!(error.kind, ErrorKind::Derive);
    assert!(
        error
            .message
            .contains("cannot read lacking.rpk!/rules/door.obj: not in the rule package"),
        "{}",
        error.message
    );
}
