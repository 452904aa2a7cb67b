//! A CityEngine rule package (`.rpk`) as `shapegram derive` takes it: read from its 7-Zip
//! archive, its rule file chosen as PRT chooses it, read and compiled with its imports from
//! the package, and derived on the default lot under small limits with the package's assets
//! (missing ones skipped), the model measured and written.

#![no_main]

use std::path::Path;
use std::sync::Arc;

use libfuzzer_sys::fuzz_target;
use shapegram_eval::DeriveOptions;
use shapegram_fuzz::{default_lot, finish, render, small_limits};
use shapegram_load::{FileAssets, Files, MissingAssets, RulePackage};

fuzz_target!(|bytes: &[u8]| {
    let package = match RulePackage::from_bytes("fuzz.rpk".to_owned(), bytes.to_vec()) {
        Ok(package) => Arc::new(package),
        Err(error) => return drop(error.to_string()),
    };
    let entry = match package.rule_file(None) {
        Ok(entry) => entry,
        Err(error) => return drop(error.to_string()),
    };
    let files = Files::Package(Arc::clone(&package));
    let path = Path::new(&entry);
    let read = match shapegram_load::read_in(&files, path) {
        Ok(read) => read,
        Err(error) => return drop(error),
    };
    let compiled = shapegram_load::compile_in(&read.source, None, &files, path);
    for (file, diagnostic) in &compiled.diagnostics {
        render(&compiled.sources[*file], std::slice::from_ref(diagnostic));
    }
    let Some(program) = compiled.program else {
        return;
    };
    let options = DeriveOptions {
        assets: Some(Arc::new(FileAssets::in_package(
            package,
            &entry,
            MissingAssets::Skip,
        ))),
        ..small_limits()
    };
    if let Ok(derivation) = shapegram_eval::derive(&program, &[default_lot()], &options) {
        finish(&derivation.to_model());
    }
});
