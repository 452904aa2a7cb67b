//! The runtime over the CityEngine corpus: the Candler building loaded from its rule package as a
//! host loads it gives the model `shapegram derive palladio__candler.rpk` makes. Without the
//! corpus these tests are reported as ignored (see `shapegram-corpus`).

use std::path::Path;
use std::sync::Arc;

use shapegram_corpus::{Corpus, corpus_tests};
use shapegram_export::Buffers;
use shapegram_load::{FileAssets, Files, MissingAssets, RulePackage};
use shapegram_runtime::{Grammar, Package, Settings};

/// The Candler building's buffers as `shapegram derive` makes its model: the package opened,
/// the rule file PRT runs read and compiled with its imports from the archive, derived on the
/// default lot with the package's assets.
fn derived_as_the_command_does(path: &Path) -> Buffers {
    let package = Arc::new(RulePackage::open(path).expect("the package"));
    let entry = package.rule_file(None).expect("the rule file PRT runs");
    let files = Files::Package(Arc::clone(&package));
    let read = shapegram_load::read_in(&files, Path::new(&entry)).expect("the rule file");
    let compiled = shapegram_load::compile_in(&read.source, None, &files, Path::new(&entry));
    let program = compiled.program.expect("the Candler building compiles");
    let options = shapegram_eval::DeriveOptions {
        assets: Some(Arc::new(FileAssets::in_package(
            package,
            &entry,
            MissingAssets::Error,
        ))),
        ..shapegram_eval::DeriveOptions::default()
    };
    let derivation =
        shapegram_eval::derive(&program, &[shapegram_runtime::default_lot()], &options)
            .expect("the Candler building derives");
    let mut buffers = Buffers::default();
    buffers.fill(&derivation.to_model());
    buffers
}

fn the_candler_building_from_its_package_is_the_commands_model(corpus: &Corpus) {
    let path = corpus.rpk().join("palladio__candler.rpk");
    let package = Package::open(&path).expect("the package");
    assert_eq!(
        package.rule_file(None).unwrap(),
        "rules/Candler Building.cga"
    );
    let grammar = Grammar::load_package(&path, None).expect("the Candler building loads");
    let mut ours = Buffers::default();
    grammar
        .derive(&Settings::default())
        .expect("the Candler building derives")
        .fill(&mut ours);
    let theirs = derived_as_the_command_does(&path);
    let triangles = ours.indices.len() / 3;
    assert_eq!(triangles, theirs.indices.len() / 3);
    assert_eq!(ours.positions, theirs.positions);
    // PRT's own count, within the 5 % the corpus tests allow.
    let prt = 66_646.0;
    assert!(
        (triangles as f64 - prt).abs() <= 0.05 * prt,
        "{triangles} triangles against PRT's {prt}"
    );
    // Its textures come from the archive: JPEG images, none missing.
    assert!(!ours.textures.is_empty());
    assert!(
        ours.textures.iter().all(|t| t
            .image
            .as_deref()
            .is_some_and(|i| i.starts_with(b"\xff\xd8"))),
        "{:?}",
        ours.textures.iter().map(|t| &t.path).collect::<Vec<_>>()
    );
    eprintln!(
        "Candler from its package: {triangles} triangles, {} textures",
        ours.textures.len()
    );
}

corpus_tests!(the_candler_building_from_its_package_is_the_commands_model);
