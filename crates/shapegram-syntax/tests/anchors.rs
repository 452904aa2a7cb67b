//! The real CityEngine CGA files of the corpus (`cityengine-cga/`, and the sources inside the
//! rule packages of `cityengine-rpk/`) are the conformance target: every one parses without
//! errors, and a few are checked in detail. Without the corpus these tests are reported as
//! ignored (see `shapegram-corpus`).

mod common;

use std::path::{Path, PathBuf};

use common::{expr, parse_str, render_all, rule_body};
use shapegram_corpus::{Corpus, corpus_tests};
use shapegram_syntax::ast::{Body, ExprKind, Grammar, Stmt};
use shapegram_syntax::{SourceFile, parse};

/// Parses one anchor (path relative to the anchors folder), asserting that it has no errors.
fn anchor(corpus: &Corpus, relative: &str) -> (SourceFile, Grammar) {
    let path = corpus.cga().join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let source = SourceFile::new(relative, text);
    let parsed = parse(&source);
    let errors: Vec<_> = parsed
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .cloned()
        .collect();
    assert!(errors.is_empty(), "{}", render_all(&source, &errors));
    (source, parsed.grammar)
}

fn every_anchor_parses_without_errors(corpus: &Corpus) {
    let files = corpus.cga_files();
    assert_eq!(files.len(), 23, "the anchor set changed");
    parse_all(&corpus.cga(), &files);
}

/// The rule sources inside the extracted rule packages, among them rule files the CGA folder
/// lacks: envelope2002's typology imports, and the plant library it ships, which uses CGA's
/// colon operator in indices (`_metadata[1:nPlants, 0]`) and `scatter` with a bare successor.
fn every_rule_package_source_parses_without_errors(corpus: &Corpus) {
    let files = Corpus::files(&corpus.rpk(), "cga");
    assert_eq!(files.len(), 23, "the rule package set changed");
    let library: Vec<_> = files
        .iter()
        .filter(|f| f.components().any(|c| c.as_os_str() == "ESRI.lib"))
        .filter_map(|f| f.file_name())
        .collect();
    assert_eq!(library, ["Plant_Distributor.cga", "Plant_Loader.cga"]);
    parse_all(&corpus.rpk(), &files);
}

/// Parses every file, asserting no errors and as many rules as arrows (no rule swallowed
/// another); file names in messages are relative to `base`.
fn parse_all(base: &Path, files: &[PathBuf]) {
    let mut failures = String::new();
    for path in files {
        let text = std::fs::read_to_string(path).expect("readable anchor");
        let name = path
            .strip_prefix(base)
            .unwrap_or(path)
            .display()
            .to_string();
        let source = SourceFile::new(name, text);
        let parsed = parse(&source);
        let errors: Vec<_> = parsed
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .cloned()
            .collect();
        failures += &render_all(&source, &errors);
        assert_eq!(
            parsed.grammar.rules.len(),
            arrows(source.text()),
            "{}",
            path.display()
        );
    }
    assert!(failures.is_empty(), "{failures}");
}

/// The rule arrows of a CGA text: `-->` outside line comments (which may mention arrows).
fn arrows(text: &str) -> usize {
    text.lines()
        .filter_map(|line| line.find("-->").map(|at| &line[..at]))
        .filter(|before| !before.contains('#') && !before.contains("//"))
        .count()
}

/// A hundred Candler buildings back to back parse in one go (a large real input).
fn huge_inputs_parse(corpus: &Corpus) {
    let path = corpus.cga().join("pyprt__candler/rules/candler.cga");
    let text = std::fs::read_to_string(path)
        .expect("the candler anchor")
        .repeat(100);
    let (_, parsed) = parse_str(&text);
    assert!(parsed.diagnostics.is_empty());
    assert_eq!(parsed.grammar.rules.len(), 5700);
}

fn candler(corpus: &Corpus) {
    let (_, g) = anchor(corpus, "pyprt__candler/rules/candler.cga");
    assert_eq!(g.version.as_ref().map(|v| v.value.as_str()), Some("2023.0"));
    assert_eq!(g.rules.len(), 57);
    let start: Vec<&str> = g
        .rules
        .iter()
        .filter(|r| r.is_start_rule())
        .map(|r| r.name.name.as_str())
        .collect();
    assert_eq!(start, ["Footprint"]);

    assert_eq!(g.attrs.len(), 14);
    let height = &g.attrs[0];
    assert_eq!(height.name.name, "BuildingHeight");
    assert_eq!(height.value.kind, ExprKind::Number(62.0));
    let annotations: Vec<&str> = height
        .annotations
        .iter()
        .map(|a| a.name.name.as_str())
        .collect();
    assert_eq!(annotations, ["Order", "Range"]);

    let consts: Vec<&str> = g.consts.iter().map(|c| c.name.name.as_str()).collect();
    assert_eq!(consts, ["winSideW", "dividerW", "sillH", "thickness"]);
    assert!(g.consts.iter().all(|c| c.is_const));
    assert_eq!(
        expr(&g.consts[2].value),
        "(case [(FloorHeight > (WindowHeight + SillSize)) => ((FloorHeight - WindowHeight) * 0.66)] [else => SillSize])"
    );

    // Facade(m1,m2,u1,u2,u3): two projections, then a four-part split.
    let facade = g
        .rules
        .iter()
        .find(|r| r.name.name == "Facade")
        .expect("Facade");
    let params: Vec<&str> = facade.params.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(params, ["m1", "m2", "u1", "u2", "u3"]);
    let Body::Sequence(stmts) = &facade.body else {
        panic!("Facade is a sequence");
    };
    assert_eq!(stmts.len(), 5);
    let Stmt::Call(split) = &stmts[4] else {
        panic!("the split is a call");
    };
    let block = split.block.as_ref().expect("the split has a block");
    assert_eq!(block.entries.len(), 4);
    assert!(!block.repeat);
    assert_eq!(
        common::call(split),
        "split(y){~2.3 : (Base) | ~12 : (Mid(m1, m2)) | ~3 : (Upper(u1, u2, u3)) | 2.5 : (Top)}"
    );
    let shapegram_syntax::ast::BlockEntry::Part { key, .. } = &block.entries[0] else {
        panic!("a part");
    };
    let ExprKind::Floating(size) = &key.kind else {
        panic!("a floating size");
    };
    assert_eq!(size.kind, ExprKind::Number(2.3));

    // Overloaded rules and nested groups.
    assert_eq!(g.rules.iter().filter(|r| r.name.name == "Pipe").count(), 2);
    assert_eq!(
        rule_body(&g, "Windows"),
        "(split(x){{~(scope.sx / n) : (Window) | dividerW : (Wall)}* | ~(scope.sx / n) : (Window)})"
    );
    assert_eq!(
        rule_body(&g, "WindowOpening"),
        "(extrude((-depth)) comp(f){front : (reverseNormals SillTexture) | side = (WallOpening)})"
    );
    assert_eq!(
        rule_body(&g, "PipeHolders"),
        "(case [(scope.sx < 4) => (NIL)] [else => (split(x){~3 : (NIL) | {0.3 : (PipeHolder(diameter, h)) | 4 : (NIL)}* | 0.3 : (PipeHolder(diameter, h)) | ~3 : (NIL)})])"
    );
    assert_eq!(
        rule_body(&g, "RoofPlane"),
        "(RoofTexture alignScopeToGeometry(yUp, 0, 0) [ convexify comp(f){all : (RoofPlaneParts)} ] Pipes)"
    );
    assert_eq!(
        rule_body(&g, "RoofDoor"),
        "(WindowOpening(0.15) t(0, 0, (-0.15)) tileUV(0, '(1.85 * 8), '1.1) texture(\"facade/misc/groundFloorTiles_2048x256.jpg\") RoofDoor.)"
    );
}

fn the_candler_variants_declare_the_same_rules(corpus: &Corpus) {
    // The 2019 copy differs in annotations and a few operations (`primitiveCube()` for
    // `i("builtin:cube")`), not in its rules.
    let (_, a) = anchor(corpus, "pyprt__candler/rules/candler.cga");
    let (_, b) = anchor(corpus, "rhino__Candler_Building/rules/Candler Building.cga");
    let heads = |g: &Grammar| -> Vec<(String, usize)> {
        g.rules
            .iter()
            .map(|r| (r.name.name.clone(), r.params.len()))
            .collect()
    };
    assert_eq!(heads(&a), heads(&b));
    let range = &b.attrs[0].annotations[1];
    assert_eq!(range.name.name, "Range");
    let named: Vec<&str> = range
        .args
        .iter()
        .filter_map(|a| a.name.as_ref())
        .map(|n| n.name.as_str())
        .collect();
    assert_eq!(named, ["min", "max", "restricted"]);
}

fn complexpatterns(corpus: &Corpus) {
    let (_, g) = anchor(
        corpus,
        "rhino__complexpatterns_01/rules/complexpatterns_01.cga",
    );
    assert_eq!(g.rules.len(), 26);
    let tile_w = g
        .consts
        .iter()
        .find(|c| c.name.name == "tileW")
        .expect("tileW");
    assert!(!tile_w.is_const, "tileW is a parameterless function");
    assert_eq!(expr(&tile_w.value), "(windowW + milkGlassW)");
    assert_eq!(g.consts.iter().filter(|c| c.is_const).count(), 5);
    // Only the default style's attributes; the red style is recorded as unsupported.
    assert_eq!(g.attrs.len(), 16);
    let brightblue = g
        .attrs
        .iter()
        .find(|a| a.name.name == "brightblue")
        .expect("brightblue");
    assert_eq!(expr(&brightblue.value), "\"#86b1c7\"");
    let unsupported: Vec<&str> = g.unsupported.iter().map(|u| u.what.as_str()).collect();
    assert_eq!(unsupported, ["style"]);
    assert_eq!(
        rule_body(&g, "Facade"),
        "(split(y){~groundfloorH : (Floor(split.index)) | {~floorH : (Floor(split.index))}*})"
    );
    assert_eq!(
        rule_body(&g, "DoubleTile"),
        "(case [(((tileIndex % 2) + (floorIndex % 2)) == 1) => (split(x){~milkGlassW : (MilkGlass) | ~windowW : (Tile(tileIndex))}*)] [else => (split(x){~windowW : (Tile(tileIndex)) | ~milkGlassW : (MilkGlass)}*)])"
    );
}

fn envelope2002(corpus: &Corpus) {
    let (source, g) = anchor(
        corpus,
        "pyprt__envelope2002/rules/typology/envelope2002.cga",
    );
    let imports: Vec<&str> = g
        .imports
        .iter()
        .map(|i| &source.text()[i.span.range()])
        .collect();
    assert_eq!(imports.len(), 6);
    assert_eq!(imports[0], "import volume: \"volume0110.cga\"");
    assert_eq!(g.imports[0].id.as_ref().unwrap().name, "volume");
    assert_eq!(g.imports[0].path.value, "volume0110.cga");
    assert!(g.rules.iter().any(|r| r.name.name == "volume.Slab"));
    assert_eq!(
        rule_body(&g, "First_volume_top"),
        "(setback(comp(fe, all=first_setback_size)){all : (Remaining_around_first_setback) | remainder : (To_be_developped_further)})"
    );
    assert_eq!(
        rule_body(&g, "Remaining_around_first_setback"),
        "(case [(create_volume == true) => (case [(ground_floors_use == \"commercial\") => (volume.Remaining_roof_space)] [else => (NIL)])] [else => (extrude(0.5) color(0.4, 0.1, 0.2) End.)])"
    );
    assert_eq!(
        rule_body(&g, "Green_tile"),
        "(pct [0.3 => (set(plant_loader.Representation, Representation_of_plants) Big_plant_position Create_green_lawn_street_sidewalk)] [5 => (set(plant_loader.Representation, Representation_of_plants) Small_plant_position Create_green_lawn_street_sidewalk)] [else => (Create_green_lawn_street_sidewalk)])"
    );
    let slab = g
        .attrs
        .iter()
        .find(|a| a.name.name == "slab_material")
        .expect("slab_material");
    assert_eq!(
        expr(&slab.value),
        "(case [(type_of_wall_on_glazing_facade == \"vertical\") => \"plaster\"] [else => (pct [80 => \"concrete\"] [else => \"plaster\"])])"
    );
}

fn reporting(corpus: &Corpus) {
    let (_, g) = anchor(corpus, "rhino__reporting_01/rules/reporting_01.cga");
    assert_eq!(g.version.as_ref().map(|v| v.value.as_str()), Some("2012.1"));
    let street = g
        .attrs
        .iter()
        .find(|a| a.name.name == "distanceStreet")
        .expect("distanceStreet");
    assert_eq!(expr(&street.value), "(pct [20 => 0] [else => rand(3, 6)])");
    assert_eq!(
        rule_body(&g, "Lot"),
        "(case [p((greenspacePercentage / 100)) => (report(\"Area.Greenspace\", geometry.area) GreenSpace)] [else => (report(\"Area.BuildUp\", geometry.area) BuildingLot)])"
    );
    assert_eq!(
        rule_body(&g, "BuildingLot"),
        "(setback(distanceStreet){streetSide : (OpenSpace) | remainder : (Parcel)})"
    );
}

fn small_anchors(corpus: &Corpus) {
    let (_, g) = anchor(corpus, "pyprt__arrayAttrs2d/rules/arrayAttrs2d.cga");
    assert_eq!(expr(&g.attrs[0].value), "[[1, 2, 3], [4, 5, 6]]");
    assert_eq!(expr(&g.attrs[1].value), "[[false, true], [true, false]]");

    let (_, g) = anchor(corpus, "pyprt__identity/rules/identity.cga");
    assert_eq!(rule_body(&g, "Init"), "(X.)");

    let (_, g) = anchor(
        corpus,
        "pyprt__dynamic_imports/rules/prt3_dynamic_imports/ruleA.cga",
    );
    assert_eq!(g.imports.len(), 1);
    let import = &g.imports[0];
    assert_eq!(
        (
            import.id.as_ref().unwrap().name.as_str(),
            import.path.value.as_str()
        ),
        ("ruleB", "rules/prt3_dynamic_imports/ruleB.cga")
    );
    assert!(matches!(
        import.attributes.as_deref(),
        Some([shapegram_syntax::ast::ImportAttribute::Set(name, _)]) if name.name == "h"
    ));
    assert_eq!(rule_body(&g, "Init"), "(ruleB.foo)");

    let (_, g) = anchor(corpus, "serlio__CE-6813-wrong-attr-style/rules/r1.cga");
    assert_eq!(
        g.attrs.len(),
        1,
        "style attributes are not the default ones"
    );
    assert_eq!(expr(&g.attrs[0].value), "10");
    assert_eq!(g.unsupported.len(), 2);
    // PRT derives the default style (h = 10); style A's value is there to be chosen.
    let styled = g.with_style("A").unwrap();
    assert_eq!(expr(&styled.attrs[0].value), "20");

    let (_, g) = anchor(corpus, "pyprt__extrusion_rule/rules/extrusion_rule.cga");
    assert_eq!(
        rule_body(&g, "ReportNext"),
        "(case [(text == \"salut\") => (report(\"Value\", 1) report(\"Bool value\", true))] [else => (report(\"Value\", 56) report(\"Bool value\", false))])"
    );
}

corpus_tests!(
    every_anchor_parses_without_errors,
    every_rule_package_source_parses_without_errors,
    huge_inputs_parse,
    candler,
    the_candler_variants_declare_the_same_rules,
    complexpatterns,
    envelope2002,
    reporting,
    small_anchors,
);
