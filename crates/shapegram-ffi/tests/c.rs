//! `tests/c/house.c`, compiled with gcc against the header and the shared library, derives
//! `examples/house.cga` and the rule package `examples/town.rpk` through the C ABI and checks
//! their counts against the Rust API's.
//! Skipped (with a note) without gcc; run under valgrind when `SHAPEGRAM_FFI_VALGRIND` is set
//! (as `.ci/run` does), where any leak or invalid access fails it.

use std::path::{Path, PathBuf};
use std::process::Command;

use shapegram_export::Buffers;
use shapegram_runtime::{Grammar, Settings};

/// A package of one compiled rule file and no CGA source, as PRT's runtime packages are.
fn compiled_only(path: &Path) {
    let mut writer = sevenz_rust2::ArchiveWriter::new(std::io::Cursor::new(Vec::new())).unwrap();
    let compiled: &[u8] = b"compiled";
    writer
        .push_archive_entry(
            sevenz_rust2::ArchiveEntry::new_file("bin/main.cgb"),
            Some(compiled),
        )
        .unwrap();
    std::fs::write(path, writer.finish().unwrap().into_inner()).unwrap();
}

fn counts(grammar: &Grammar, seed: u64, storeys: Option<f64>) -> [usize; 3] {
    let settings = Settings {
        seed,
        attrs: storeys
            .map(|n| ("storeys".to_owned(), shapegram_eval::Value::Number(n)))
            .into_iter()
            .collect(),
        lots: Vec::new(),
        generations: None,
        control: Default::default(),
    };
    let mut buffers = Buffers::default();
    grammar
        .derive(&settings)
        .expect("the house derives")
        .fill(&mut buffers);
    [
        buffers.positions.len(),
        buffers.indices.len(),
        buffers.parts.len(),
    ]
}

/// Where `cargo test` built the shared library: beside the test binary, in `deps` (it copies
/// it to the folder above only for `cargo build`, so a copy there may be stale).
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("the test knows where it is");
    exe.parent().expect("target/<profile>/deps").to_path_buf()
}

#[test]
fn the_c_program_derives_the_house_with_the_counts_of_the_rust_api() {
    if Command::new("gcc").arg("--version").output().is_err() {
        eprintln!("skipped: gcc is not installed");
        return;
    }
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let house = crate_dir.join("../../examples/house.cga");
    let text = std::fs::read_to_string(&house).expect("examples/house.cga");
    let grammar = Grammar::load("house.cga", &text, None).expect("the house loads");
    let first = counts(&grammar, 0, None);
    let second = counts(&grammar, 7, Some(3.0));
    assert_ne!(first, second, "three storeys make more geometry than two");
    let package = crate_dir.join("../../examples/town.rpk");
    let town = Grammar::load_package(&package, None).expect("the town loads");
    let packaged = counts(&town, 0, None);

    let libs = library_dir();
    assert!(
        libs.join("libshapegram_ffi.so").is_file(),
        "cargo builds the cdylib beside the test"
    );
    let out = std::env::temp_dir().join(format!("shapegram-ffi-house-{}", std::process::id()));
    let compiled = Command::new("gcc")
        .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-g", "-o"])
        .arg(&out)
        .arg(crate_dir.join("tests/c/house.c"))
        .arg("-I")
        .arg(crate_dir.join("include"))
        .arg("-L")
        .arg(&libs)
        .arg(format!("-Wl,-rpath,{}", libs.display()))
        .arg("-lshapegram_ffi")
        .status()
        .expect("gcc runs");
    assert!(compiled.success(), "house.c compiles against shapegram.h");

    let valgrind = std::env::var_os("SHAPEGRAM_FFI_VALGRIND").is_some();
    let mut command = if valgrind {
        let mut c = Command::new("valgrind");
        c.args(["--leak-check=full", "--error-exitcode=1"])
            .arg(format!(
                "--suppressions={}",
                crate_dir.join("tests/c/valgrind.supp").display()
            ))
            .arg(&out);
        c
    } else {
        Command::new(&out)
    };
    command.arg(&house);
    for n in first.iter().chain(&second) {
        command.arg(n.to_string());
    }
    command.arg(&package);
    for n in &packaged {
        command.arg(n.to_string());
    }
    let compiled = out.with_extension("compiled.rpk");
    compiled_only(&compiled);
    command.arg(&compiled);
    let output = command.output().expect("the C program runs");
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(&compiled);
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "house.c failed{}:\n{stdout}\n{stderr}",
        if valgrind { " under valgrind" } else { "" }
    );
    println!("{stdout}");
    assert!(stdout.contains("all checks passed"), "{stdout}");
    if valgrind {
        assert!(stderr.contains("ERROR SUMMARY: 0 errors"), "{stderr}");
    }
}
