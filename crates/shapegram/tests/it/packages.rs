//! `shapegram derive` and `check` on CityEngine rule packages (`.rpk`): the rule file and its
//! assets read straight from the archive, and bad packages. Each test writes its own small
//! package with sevenz-rust2.

use crate::common;

use std::io::Cursor;
use std::path::{Path, PathBuf};

use common::{TempDir, shapegram, stderr};
use sevenz_rust2::{ArchiveEntry, ArchiveWriter};

/// Writes a 7-Zip archive of `files` (path, contents) at `path`.
fn write_package(path: &Path, files: &[(&str, &[u8])]) {
    let mut writer = ArchiveWriter::new(Cursor::new(Vec::new())).expect("a writer");
    for (name, bytes) in files {
        writer
            .push_archive_entry(ArchiveEntry::new_file(name), Some(*bytes))
            .expect("an entry");
    }
    let bytes = writer.finish().expect("an archive").into_inner();
    std::fs::write(path, bytes).unwrap();
}

/// A box 2 × 3 × 4 m as an OBJ asset.
const BOX_OBJ: &[u8] = b"v 0 0 0\nv 2 0 0\nv 2 3 0\nv 0 3 0\nv 0 0 4\nv 2 0 4\nv 2 3 4\nv 0 3 4\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

/// A package whose rule inserts its own asset at its own size (`s(0,0,0)`: the asset's size),
/// with a second rule file and compiled files beside the main one.
fn town(dir: &TempDir) -> PathBuf {
    let path = dir.path("town.rpk");
    write_package(
        &path,
        &[
            (
                "rules/main.cga",
                b"import parts : \"lib/parts.cga\"\n@StartRule\nLot --> parts.Box\nOther --> X.",
            ),
            (
                "rules/lib/parts.cga",
                b"Box --> s(0, 0, 0) i(\"house/box.obj\")",
            ),
            (
                "rules/flat.cga",
                b"@StartRule\nLot --> color(\"#ff0000\") X.",
            ),
            ("bin/main.cgb", b"compiled"),
            ("bin/main$parts.cgb", b"compiled import"),
            ("assets/house/box.obj", BOX_OBJ),
        ],
    );
    path
}

/// `shapegram info --json` of a model file.
fn info(path: &Path) -> serde_json::Value {
    let output = shapegram(&["info".as_ref(), "--json".as_ref(), path.as_os_str()]);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).unwrap()
}

#[test]
fn a_package_derives_its_rule_file_with_its_own_assets_and_imports() {
    let dir = TempDir::new("rpk-derive");
    let package = town(&dir);
    let out = dir.path("town.glb");
    let output = shapegram(&[
        "derive".as_ref(),
        package.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(err.contains("derived"), "{err}");
    let info = info(&out);
    assert_eq!(info["bounds"]["size"], serde_json::json!([2.0, 3.0, 4.0]));
    assert_eq!(info["triangles"], 12);
    // Nothing was extracted beside the package.
    let mut left: Vec<String> = std::fs::read_dir(dir.path(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["town.glb", "town.rpk"]);

    // Another rule file, asked for by name: a flat lot.
    let output = shapegram(&[
        "derive".as_ref(),
        package.as_os_str(),
        "--rule-file".as_ref(),
        "flat.cga".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        self::info(&out)["bounds"]["size"],
        serde_json::json!([20.0, 0.0, 30.0])
    );
}

#[test]
fn a_rule_file_the_package_lacks_is_an_error_listing_its_rule_files() {
    let dir = TempDir::new("rpk-rule-file");
    let package = town(&dir);
    let output = shapegram(&[
        "derive".as_ref(),
        package.as_os_str(),
        "--rule-file".as_ref(),
        "roof.cga".as_ref(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {} has no rule file `roof.cga`; its rule files are rules/flat.cga, rules/lib/parts.cga, rules/main.cga\n",
            package.display()
        )
    );
    // --rule-file is for packages only.
    let grammar = dir.path("a.cga");
    std::fs::write(&grammar, "Lot --> X.").unwrap();
    let output = shapegram(&[
        "derive".as_ref(),
        grammar.as_os_str(),
        "--rule-file".as_ref(),
        "a.cga".as_ref(),
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output)
            .starts_with("error: --rule-file picks a rule file of a rule package (.rpk)"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn several_rule_files_without_a_compiled_one_must_be_chosen() {
    let dir = TempDir::new("rpk-several");
    let package = dir.path("two.rpk");
    write_package(
        &package,
        &[
            ("rules/a.cga", b"Lot --> X."),
            ("rules/b.cga", b"Lot --> Y."),
        ],
    );
    let output = shapegram(&["derive".as_ref(), package.as_os_str()]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {} holds 2 rule files: rules/a.cga, rules/b.cga\n  = hint: choose one with --rule-file\n",
            package.display()
        )
    );
}

#[test]
fn check_checks_every_rule_file_of_a_package() {
    let dir = TempDir::new("rpk-check");
    let package = town(&dir);
    let output = shapegram(&["check".as_ref(), package.as_os_str()]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    let name = package.display();
    assert_eq!(
        err.lines().collect::<Vec<_>>(),
        [
            format!("ok: {name}!/rules/flat.cga (1 rule, 0 attributes, 0 warnings)"),
            format!("ok: {name}!/rules/lib/parts.cga (1 rule, 0 attributes, 0 warnings)"),
            format!("ok: {name}!/rules/main.cga (2 rules, 0 attributes, 0 warnings)"),
        ]
    );
}

#[test]
fn errors_in_a_packaged_rule_file_point_into_the_package() {
    let dir = TempDir::new("rpk-diagnostics");
    let package = dir.path("bad.rpk");
    write_package(&package, &[("rules/bad.cga", b"Lot --> extrude(\n")]);
    let output = shapegram(&["check".as_ref(), package.as_os_str()]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(
        err.contains(&format!("--> {}!/rules/bad.cga:", package.display())),
        "{err}"
    );
    assert!(
        err.ends_with(&format!("in {}!/rules/bad.cga\n", package.display())),
        "{err}"
    );
}

#[test]
fn a_package_of_compiled_rules_only_says_so() {
    let dir = TempDir::new("rpk-compiled");
    let package = dir.path("compiled.rpk");
    write_package(
        &package,
        &[("bin/house.cgb", b"compiled"), ("assets/a.obj", BOX_OBJ)],
    );
    for command in ["derive", "check"] {
        let output = shapegram(&[command.as_ref(), package.as_os_str()]);
        assert_eq!(output.status.code(), Some(1), "{command}");
        let err = stderr(&output);
        assert!(
            err.starts_with(&format!(
                "error: {} holds only compiled rules (bin/house.cgb) and no CGA source: Shapegram runs CGA source, not CityEngine's compiled .cgb files\n  = hint: ",
                package.display()
            )),
            "{command}: {err}"
        );
    }
}

#[test]
fn corrupt_packages_are_errors_naming_the_file() {
    let dir = TempDir::new("rpk-corrupt");
    let whole = dir.path("whole.rpk");
    write_package(&whole, &[("rules/a.cga", &[b' '; 5000])]);
    let bytes = std::fs::read(&whole).unwrap();
    let truncated = dir.path("truncated.rpk");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let text = dir.path("text.rpk");
    std::fs::write(&text, "Lot --> X.").unwrap();
    for package in [&truncated, &text] {
        for command in ["derive", "check"] {
            let output = shapegram(&[command.as_ref(), package.as_os_str()]);
            assert_eq!(output.status.code(), Some(1));
            let err = stderr(&output);
            assert!(
                err.starts_with(&format!(
                    "error: {} is not a readable rule package (a 7-Zip archive): ",
                    package.display()
                )),
                "{command}: {err}"
            );
            assert_eq!(err.lines().count(), 1, "{err}");
        }
    }
}

#[test]
fn a_missing_asset_in_a_package_is_an_error_or_a_stand_in() {
    let dir = TempDir::new("rpk-missing");
    let package = dir.path("door.rpk");
    write_package(
        &package,
        &[(
            "rules/a.cga",
            b"@StartRule\nLot --> extrude(4) i(\"door.obj\")",
        )],
    );
    let output = shapegram(&["derive".as_ref(), "-q".as_ref(), package.as_os_str()]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    let name = package.display();
    assert!(
        err.starts_with(&format!(
            "error: cannot insert `door.obj`: cannot read {name}!/rules/door.obj: not in the rule package\n --> {name}!/rules/a.cga:2:22\n"
        )),
        "{err}"
    );
    let out = dir.path("door.glb");
    let output = shapegram(&[
        "derive".as_ref(),
        "-q".as_ref(),
        package.as_os_str(),
        "--missing-assets".as_ref(),
        "cube".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        stderr(&output),
        format!(
            "warning: cannot read {name}!/rules/door.obj: not in the rule package: inserting a cube instead\n"
        )
    );
    assert_eq!(
        info(&out)["bounds"]["size"],
        serde_json::json!([20.0, 4.0, 30.0])
    );
}

#[test]
fn an_image_of_another_format_in_a_package_is_a_warning_naming_it() {
    let dir = TempDir::new("rpk-image");
    let package = dir.path("tiff.rpk");
    write_package(
        &package,
        &[
            (
                "rules/a.cga",
                b"@StartRule\nLot --> setupProjection(0, scope.xz, 1, 1) projectUV(0) texture(\"glass.tif\") X.",
            ),
            ("assets/glass.tif", b"II*\0\x08\0\0\0"),
        ],
    );
    let out = dir.path("tiff.glb");
    let output = shapegram(&[
        "derive".as_ref(),
        "-q".as_ref(),
        package.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        stderr(&output),
        format!(
            "warning: {}!/assets/glass.tif is not a PNG or JPEG image (the formats glTF embeds): the shapes keep their colour instead\n",
            package.display()
        )
    );
}
