//! Goal grammars: rules found by goals, tags and attributes; what they fulfil; local goals,
//! synchronization, attributes, errors.

use crate::common;

use shapegram_eval::{Derivation, DeriveError, DeriveOptions, Leaf, Program, derive};
use shapegram_geom::{Color, DVec3};

fn try_library(files: &[(&str, &str)], strict: bool) -> Result<Program, String> {
    common::goal_library(files, strict)
}

fn library(files: &[(&str, &str)]) -> Program {
    try_library(files, true).unwrap_or_else(|e| panic!("{e}"))
}

fn run(program: &Program, seed: u64) -> Derivation {
    try_run(program, seed).unwrap_or_else(|e| panic!("{e}"))
}

fn try_run(program: &Program, seed: u64) -> Result<Derivation, DeriveError> {
    let options = DeriveOptions {
        seed,
        ..DeriveOptions::default()
    };
    derive(program, &[], &options)
}

fn names(d: &Derivation) -> Vec<&str> {
    d.leaves.iter().map(|l| d.name(l.name)).collect()
}

fn tags(leaf: &Leaf) -> Vec<&str> {
    let s = leaf.semantics().expect("goal leaves have semantics");
    s.tags.iter().map(|t| &**t).collect()
}

fn goals(leaf: &Leaf) -> Vec<&str> {
    let s = leaf.semantics().expect("goal leaves have semantics");
    s.goals.iter().map(|t| &**t).collect()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-12
}

const CHAIR: &str = common::NATIVE_CHAIR;
const WOOD: &str = common::WOOD;

const METALLIC: &str = r##"
axiom chair, wooden size(0.4, 0.8, 0.4)

fulfills(wooden, metallic) --> color("#9aa4ad")
fulfills(support) adds(metallic) --> split(y) { 0.1 : +stand | ~1 : +leg }
fulfills(leg) --> s('0.5, '1, '0.5) center(xz)
fulfills(stand) --> s('0.25, '1, '0.25) center(xz)
"##;

#[test]
fn the_chair_has_four_legs_a_seat_and_a_lean_of_the_right_sizes_all_brown() {
    let program = library(&[("chair", CHAIR), ("wood", WOOD)]);
    let d = run(&program, 1);
    assert_eq!(names(&d), ["leg", "leg", "leg", "leg", "seat", "lean"]);
    let brown = Color::from_hex("#8b5a2b").unwrap();
    assert!(d.leaves.iter().all(|l| d.color(l) == brown));
    let leg = d.leaves[0].semantics().unwrap().attributes[0].clone();
    assert_eq!(&*leg.0, "Leg.Size");
    let shapegram_eval::Value::Number(size) = leg.1 else {
        panic!("{:?}", leg.1)
    };
    assert!((0.03..0.05).contains(&size), "{size}");
    let corners = [
        (0.0, 0.0),
        (0.0, 0.4 - size),
        (0.4 - size, 0.0),
        (0.4 - size, 0.4 - size),
    ];
    for (leaf, (x, z)) in d.leaves[..4].iter().zip(corners) {
        assert!(
            close(leaf.scope.size, DVec3::new(size, 0.32, size)),
            "{:?}",
            leaf.scope
        );
        assert!(
            close(leaf.scope.origin, DVec3::new(x, 0.0, z)),
            "{:?}",
            leaf.scope
        );
    }
    assert!(close(d.leaves[4].scope.size, DVec3::new(0.4, 0.04, 0.4)));
    assert!(close(d.leaves[4].scope.origin, DVec3::new(0.0, 0.32, 0.0)));
    assert!(close(d.leaves[5].scope.size, DVec3::new(0.4, 0.44, 0.04)));
    assert!(close(d.leaves[5].scope.origin, DVec3::new(0.0, 0.36, 0.0)));
    // Another seed, other legs: the attribute is drawn per chair.
    let other = run(&program, 2).leaves[0].scope.size.x;
    assert!((0.03..0.05).contains(&other) && other != size);
}

#[test]
fn fulfilled_goals_become_tags_on_every_shape_the_rule_makes() {
    let program = library(&[("chair", CHAIR), ("wood", WOOD)]);
    let d = run(&program, 1);
    assert_eq!(
        tags(&d.leaves[0]),
        ["chair", "wooden", "support", "split-legs"]
    );
    assert_eq!(goals(&d.leaves[0]), ["leg"]);
    // A goal no rule fulfils stays open, and its shape keeps its geometry.
    assert_eq!(tags(&d.leaves[4]), ["chair", "wooden"]);
    assert_eq!(goals(&d.leaves[4]), ["seat"]);
    assert_eq!(tags(&d.leaves[5]), ["chair", "wooden", "lean"]);
    assert!(goals(&d.leaves[5]).is_empty());
    assert_eq!(d.stats.steps, 11);
    let per_grammar: Vec<(&str, usize)> = d
        .stats
        .grammars
        .iter()
        .map(|(n, s)| (n.as_str(), *s))
        .collect();
    assert_eq!(per_grammar, [("chair", 5), ("wood", 6)]);
}

#[test]
fn void_parts_leave_nothing_between_the_legs() {
    let program = library(&[("chair", CHAIR)]);
    let d = run(&program, 1);
    let volume: f64 = d
        .leaves
        .iter()
        .map(|l| l.world_mesh().unwrap().signed_volume())
        .sum();
    let size = d.leaves[0].scope.size.x;
    let expected = 4.0 * size * 0.32 * size + 0.4 * 0.04 * 0.4 + 0.4 * 0.44 * 0.04;
    assert!((volume - expected).abs() < 1e-12, "{volume} vs {expected}");
    // Without the wood grammar the chair stays grey and keeps its open goal.
    assert!(d.leaves.iter().all(|l| goals(l).contains(&"wooden")));
    assert!(d.leaves.iter().all(|l| d.color(l) == Color::default()));
}

#[test]
fn the_grammar_being_derived_overrides_the_library_and_a_design_keeps_to_its_own_rules() {
    // Fig. 2 right: the metallic grammar's support replaces the chair's.
    let program = library(&[("metallic", METALLIC), ("chair", CHAIR), ("wood", WOOD)]);
    let d = run(&program, 1);
    assert_eq!(names(&d), ["stand", "leg", "seat", "lean"]);
    let (stand, leg) = (&d.leaves[0], &d.leaves[1]);
    assert!(
        close(stand.scope.size, DVec3::new(0.1, 0.1, 0.1)),
        "{:?}",
        stand.scope
    );
    assert!(close(stand.scope.origin, DVec3::new(0.15, 0.0, 0.15)));
    assert!(
        close(leg.scope.size, DVec3::new(0.2, 0.22, 0.2)),
        "{:?}",
        leg.scope
    );
    assert!(close(leg.scope.origin, DVec3::new(0.1, 0.1, 0.1)));
    let grey = Color::from_hex("#9aa4ad").unwrap();
    assert_eq!((d.color(stand), d.color(leg)), (grey, grey));
    assert_eq!(d.color(&d.leaves[2]), Color::from_hex("#8b5a2b").unwrap());
    assert_eq!(
        tags(stand),
        ["chair", "wooden", "metallic", "support", "stand"]
    );
    // The basic chair derived with the metallic grammar in its library keeps its own legs.
    let program = library(&[("chair", CHAIR), ("metallic", METALLIC), ("wood", WOOD)]);
    assert_eq!(
        names(&run(&program, 1)),
        ["leg", "leg", "leg", "leg", "seat", "lean"]
    );
}

#[test]
fn predicates_decide_which_rule_fires() {
    let rules = r##"
axiom box, paint size(2, 1, 1)
fulfills(box) --> set(@n, 3) +a
goal(a) !is(box) fulfills(a) --> color("#00ff00")
goal(a) is(box) has(n) if(@n > 2 && scope.sx > 1.5) fulfills(a) --> color("#ff0000")
goal(a) is(box) !if(@n > 2) fulfills(a) --> color("#0000ff")
"##;
    let d = run(&library(&[("rules", rules)]), 0);
    assert_eq!(d.leaves.len(), 1);
    assert_eq!(d.color(&d.leaves[0]), Color::from_hex("#ff0000").unwrap());
    assert_eq!(tags(&d.leaves[0]), ["box", "a"]);
    assert_eq!(goals(&d.leaves[0]), ["paint"]);
    // A narrower box fails the condition: no rule fulfils `a`.
    let narrow = rules.replace("size(2, 1, 1)", "size(1, 1, 1)");
    let d = run(&library(&[("rules", &narrow)]), 0);
    assert_eq!(d.color(&d.leaves[0]), Color::default());
    assert_eq!(goals(&d.leaves[0]), ["paint", "a"]);
    // With n = 1 the negated condition holds.
    let small = rules.replace("set(@n, 3)", "set(@n, 1)");
    let d = run(&library(&[("rules", &small)]), 0);
    assert_eq!(d.color(&d.leaves[0]), Color::from_hex("#0000ff").unwrap());
}

#[test]
fn attribute_getters_ask_for_their_attribute() {
    // The second rule reads @w: it applies only to the shape that has it.
    let rules = r#"
axiom row size(4, 1, 1)
fulfills(row) --> split(x) { ~1 : set(@w, 0.5) +cell | ~1 : +cell }
fulfills(cell) --> s(@w, '1, '1)
"#;
    let d = run(&library(&[("rules", rules)]), 0);
    assert_eq!(d.leaves.len(), 2);
    assert!(close(d.leaves[0].scope.size, DVec3::new(0.5, 1.0, 1.0)));
    assert!(goals(&d.leaves[0]).is_empty());
    assert!(close(d.leaves[1].scope.size, DVec3::new(2.0, 1.0, 1.0)));
    assert_eq!(goals(&d.leaves[1]), ["cell"]);
}

#[test]
fn using_gives_every_rule_inside_its_predicates() {
    let rules = r##"
axiom a size(1, 1, 1)
axiom b size(1, 1, 1)
fulfills(a) --> +item
fulfills(b) --> +item
using is(a) {
    fulfills(item) --> color("#ff0000")
}
"##;
    let d = run(&library(&[("rules", rules)]), 0);
    assert_eq!(d.leaves.len(), 2);
    assert_eq!(d.color(&d.leaves[0]), Color::from_hex("#ff0000").unwrap());
    assert_eq!(d.color(&d.leaves[1]), Color::default());
    assert_eq!(goals(&d.leaves[1]), ["item"]);
    // The second axiom stands beside the first, a metre apart.
    assert!(close(d.leaves[1].scope.origin, DVec3::new(2.0, 0.0, 0.0)));
}

#[test]
fn local_goals_match_only_rules_of_their_own_grammar() {
    let main = r#"
local part
axiom thing size(1, 1, 1)
fulfills(thing) --> split(x) { ~1 : +part | ~1 : +shared }
"#;
    let other = r##"
fulfills(part) --> color("#ff0000")
fulfills(shared) --> color("#00ff00")
"##;
    let e = errors(&[("main", main), ("other", other)]);
    assert!(
        e.contains("warning: no rule of `main` fulfils its local goal `part`"),
        "{e}"
    );
    assert!(e.contains("main.goal:4:37"), "{e}");
    let program = try_library(&[("main", main), ("other", other)], false).unwrap();
    let d = run(&program, 0);
    assert_eq!(d.color(&d.leaves[0]), Color::default());
    assert_eq!(goals(&d.leaves[0]), ["part"]);
    assert_eq!(d.color(&d.leaves[1]), Color::from_hex("#00ff00").unwrap());
    // The grammar's own rule fulfils its local goal.
    let own = format!("{main}\nfulfills(part) --> color(\"#0000ff\")\n");
    let program = try_library(&[("main", &own), ("other", other)], false).unwrap();
    let d = run(&program, 0);
    assert_eq!(d.color(&d.leaves[0]), Color::from_hex("#0000ff").unwrap());
}

const FACADE: &str = r##"
sync windows
axiom facade size(12, 9, 0.2)
fulfills(facade) --> split(y) { { ~3 : +floor }* }
fulfills(floor) --> split(x) { { ~2 : SYNC +window }* }
fulfills(window) --> color("#aa3333") s('0.5, '0.6, '1) center(xy) +glass
fulfills(window) --> color("#33aa33") s('0.7, '0.7, '1) center(xy) +glass
fulfills(window) --> color("#3333aa") s('0.4, '0.8, '1) center(xy) +glass
fulfills(glass) --> split(x) { ~1 : +pane | ~1 : +pane }
"##;

fn window_looks(d: &Derivation) -> Vec<([u32; 4], [u64; 2])> {
    d.leaves
        .chunks(2)
        .map(|panes| {
            let size = panes[0].scope.size;
            (
                d.color(&panes[0]).to_array().map(f32::to_bits),
                [size.x.to_bits(), size.y.to_bits()],
            )
        })
        .collect()
}

#[test]
fn synchronized_windows_are_identical_and_unsynchronized_ones_vary() {
    let synced = library(&[("facade", &FACADE.replace("SYNC", "sync(windows)"))]);
    for seed in 0..4 {
        let looks = window_looks(&run(&synced, seed));
        assert_eq!(looks.len(), 18);
        assert!(
            looks.iter().all(|l| *l == looks[0]),
            "seed {seed}: {looks:?}"
        );
    }
    let free = library(&[("facade", &FACADE.replace("SYNC", ""))]);
    let looks = window_looks(&run(&free, 0));
    let distinct: std::collections::BTreeSet<_> = looks.iter().collect();
    assert_eq!(distinct.len(), 3, "{looks:?}");
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // An axiom without a size: one derivation per lot, in parallel.
    let rules = r##"
axiom parcel, wooden
fulfills(parcel) --> extrude(rand(3, 9)) split(y) { { ~2.5 : +floor }* }
fulfills(floor) --> split(x) { ~1 : +room | ~rand(1, 2) : +room }
fulfills(room) --> s('0.9, '1, '0.9) center(xz)
fulfills(room) --> color("#aa8866")
fulfills(wooden) --> color("#8b5a2b")
"##;
    let program = library(&[("parcels", rules)]);
    let lots = common::lots_in_a_row(6, 8.0, 6.0, 10.0);
    let options = DeriveOptions {
        seed: 9,
        ..DeriveOptions::default()
    };
    let one = common::derive_on_threads(&program, &lots, &options, 1);
    let four = common::derive_on_threads(&program, &lots, &options, 4);
    let lots_seen: std::collections::BTreeSet<u32> = one.leaves.iter().map(|l| l.lot).collect();
    assert_eq!(lots_seen.len(), 6);
    assert!(one.leaves.len() > 12, "{}", one.leaves.len());
    assert_eq!(one.leaves, four.leaves);
    let glb = |d: &Derivation| {
        shapegram_export::write_glb(&d.to_model(), &shapegram_export::ExportOptions::default())
    };
    assert_eq!(glb(&one), glb(&four));
}

#[test]
fn a_rule_that_sets_an_attribute_may_read_it() {
    let rules = "axiom a size(1, 1, 1)\nfulfills(a) --> set(@x, 0.5) s(@x, '1, '1)\n";
    let d = run(&library(&[("self", rules)]), 0);
    assert!(close(d.leaves[0].scope.size, DVec3::new(0.5, 1.0, 1.0)));
}

#[test]
fn rules_that_would_match_their_own_shapes_are_warned_about_and_weights_are_bounded() {
    let e = errors(&[(
        "loop",
        "axiom a size(1, 1, 1)\ngoal(a) --> color(\"#ff0000\")\n",
    )]);
    assert!(
        e.contains("warning: this rule fulfils no goal and has no condition"),
        "{e}"
    );
    let e = errors(&[(
        "heavy",
        "axiom a size(1, 1, 1)\n@Weight(1e308)\nfulfills(a) --> color(\"#ff0000\")\n",
    )]);
    assert!(
        e.contains("error: a rule's weight is a number above 0 and at most a million"),
        "{e}"
    );
}

#[test]
fn a_library_grammar_has_no_axiom_and_cannot_be_derived_alone() {
    let program = library(&[("wood", WOOD)]);
    let e = try_run(&program, 0).unwrap_err();
    assert_eq!(e.message, "the grammar `wood` has no axiom to start from");
}

#[test]
fn rules_that_lead_back_to_each_other_are_stopped_with_their_goal_named() {
    let rules = "axiom a size(1, 1, 1)\nfulfills(a) --> +b\nfulfills(b) --> +a\n";
    let e = try_run(&library(&[("ping", rules)]), 0).unwrap_err();
    assert_eq!(
        e.message,
        "the derivation is more than 1000 shapes deep at `b`: goal rules keep making shapes whose goals call for them again"
    );
}

fn errors(files: &[(&str, &str)]) -> String {
    match try_library(files, true) {
        Ok(_) => String::new(),
        Err(e) => e,
    }
}

#[test]
fn a_rule_that_gives_back_its_own_goal_is_refused() {
    let e = errors(&[(
        "loop",
        "axiom a size(1, 1, 1)\nfulfills(a) --> split(x) { ~1 : +a | ~1 : +b }\n",
    )]);
    assert!(
        e.contains("error: this rule fulfils `a` and gives it back to the shapes it makes: it would rewrite them forever"),
        "{e}"
    );
    assert!(e.contains("loop.goal:2:34"), "{e}");
    // With a condition the recursion ends, and the rule is fine.
    let ok =
        "axiom a size(4, 1, 1)\nfulfills(a) if(scope.sx > 1) --> split(x) { ~1 : +a | ~1 : +a }\n";
    let d = run(&library(&[("ok", ok)]), 0);
    assert_eq!(d.leaves.len(), 4);
}

#[test]
fn rules_that_keep_calling_each_other_stop_at_the_step_limit() {
    let rules = "axiom a size(1, 1, 1)\nfulfills(a) --> +b\nfulfills(b) --> +a\n";
    let program = library(&[("ping", rules)]);
    let options = DeriveOptions {
        max_steps: 500,
        max_depth: 100_000,
        ..DeriveOptions::default()
    };
    let e = derive(&program, &[], &options).unwrap_err();
    assert_eq!(
        e.message,
        "the derivation took more than 500 steps: goal `a` kept being sought (rule `ping:a` applied last)"
    );
    assert!(e.span.is_some());
}

#[test]
fn misspelt_goals_and_missing_attributes_are_reported() {
    let e = errors(&[(
        "typo",
        "axiom chair size(1, 1, 1)\nfulfills(chiar) --> color(\"#fff\")\n",
    )]);
    assert!(
        e.contains("warning: no grammar of the library gives any shape the goal `chiar`"),
        "{e}"
    );
    assert!(e.contains("did you mean `chair`?"), "{e}");
    let e = errors(&[(
        "getter",
        "axiom a size(1, 1, 1)\nfulfills(a) --> set(@Leg.Size, 1) +b\nfulfills(b) --> s(@Leg.Sise, '1, '1)\n",
    )]);
    assert!(
        e.contains("error: no grammar of the library sets the attribute `Leg.Sise`: the rule can never apply"),
        "{e}"
    );
    assert!(e.contains("did you mean `Leg.Size`?"), "{e}");
    assert!(e.contains("getter.goal:3:19"), "{e}");
}

#[test]
fn conflicting_or_unknown_synchronizations_are_errors() {
    let e = errors(&[(
        "sync",
        "sync a, b\naxiom x size(1, 1, 1)\nfulfills(x) --> split(x) { ~1 : sync(a) sync(b) +y }\n",
    )]);
    assert!(
        e.contains("error: conflicting synchronization: a shape follows one synchronization"),
        "{e}"
    );
    let e = errors(&[(
        "sync",
        "sync windows\naxiom x size(1, 1, 1)\nfulfills(x) --> split(x) { ~1 : sync(windos) +y }\n",
    )]);
    assert!(e.contains("error: unknown synchronization `windos`"), "{e}");
    assert!(e.contains("did you mean `windows`?"), "{e}");
}

#[test]
fn an_attribute_of_the_wrong_type_is_an_error_at_its_use() {
    let source = "axiom a size(1, 1, 1)\nfulfills(a) --> set(@w, \"wide\") +b\nfulfills(b) --> s(@w, '1, '1)\n";
    let e = try_run(&library(&[("types", source)]), 0).unwrap_err();
    assert_eq!(e.message, "expected a number, found a string");
    assert_eq!(
        e.span.map(|s| s.start),
        Some(source.find("@w, '1").unwrap() as u32)
    );
}

#[test]
fn axioms_without_a_size_start_from_every_lot_and_need_some() {
    let rules = "axiom parcel\nfulfills(parcel) --> extrude(3) +house\n";
    let program = library(&[("lots", rules)]);
    let lots = common::lots_in_a_row(3, 10.0, 8.0, 12.0);
    let d = derive(&program, &lots, &DeriveOptions::default()).unwrap();
    assert_eq!(d.leaves.len(), 3);
    assert!(close(d.leaves[2].scope.size, DVec3::new(10.0, 3.0, 8.0)));
    let e = derive(&program, &[], &DeriveOptions::default()).unwrap_err();
    assert_eq!(
        e.message,
        "the axiom `parcel` has no size, and there are no lots for it to start from"
    );
    let options = DeriveOptions {
        start_rule: Some("parcel".into()),
        ..DeriveOptions::default()
    };
    let e = derive(&program, &lots, &options).unwrap_err();
    assert_eq!(
        e.message,
        "goal grammars start from their axioms, not from a rule (`parcel`)"
    );
}

#[test]
fn a_derivation_lists_what_its_shapes_sought_without_local_goals() {
    let d = run(&library(&[("chair", CHAIR)]), 1);
    let queries: Vec<String> = d
        .queries
        .iter()
        .map(|q| format!("{:?} {:?} {:?}", q.goals, q.tags, q.attributes))
        .collect();
    assert_eq!(
        queries,
        [
            r#"["chair", "wooden"] [] []"#,
            r#"["lean", "wooden"] ["chair"] []"#,
            r#"["leg", "wooden"] ["chair", "support"] ["Leg.Size"]"#,
            r#"["seat", "wooden"] ["chair"] []"#,
            r#"["support", "wooden"] ["chair"] ["Leg.Size"]"#,
            r#"["wooden"] ["chair", "lean"] []"#,
            // The pairs of legs: their open goal `split-legs` is local to the chair.
            r#"["wooden"] ["chair", "support"] ["Leg.Size"]"#,
        ]
    );
}

#[test]
fn a_derivation_lists_what_shapes_no_rule_applied_to_sought() {
    let d = run(&library(&[("chair", CHAIR)]), 1);
    let unmatched: Vec<String> = d
        .unmatched
        .iter()
        .map(|q| format!("{:?} {:?} {:?}", q.goals, q.tags, q.attributes))
        .collect();
    // Nothing makes things wooden, nor legs and seats.
    assert_eq!(
        unmatched,
        [
            r#"["leg", "wooden"] ["chair", "support"] ["Leg.Size"]"#,
            r#"["seat", "wooden"] ["chair"] []"#,
            r#"["wooden"] ["chair", "lean"] []"#,
        ]
    );
    let d = run(&library(&[("chair", CHAIR), ("wood", WOOD)]), 1);
    let unmatched: Vec<String> = d
        .unmatched
        .iter()
        .map(|q| format!("{:?}", q.goals))
        .collect();
    assert_eq!(unmatched, [r#"["leg"]"#, r#"["seat"]"#]);
}

/// Red paint for wooden things, written by the user.
const RED_WOOD: &str = r##"fulfills(wooden) --> color("#aa2020")"##;

#[test]
fn rules_from_a_repository_come_after_the_users_own() {
    let brown = Color::from_hex("#8b5a2b").unwrap();
    let red = Color::from_hex("#aa2020").unwrap();
    let repository = |files: &[(&str, &str)], from| {
        common::goal_library_with_repository(files, from, true).unwrap_or_else(|e| panic!("{e}"))
    };
    // The repository's wood alone paints the chair brown.
    let d = run(&repository(&[("chair", CHAIR), ("ana/wood", WOOD)], 1), 3);
    assert!(d.leaves.iter().all(|l| d.color(l) == brown));
    // With the user's red paint beside it, the user's rule wins, whatever the seed.
    for seed in 0..8 {
        let program = repository(
            &[("chair", CHAIR), ("red", RED_WOOD), ("ana/wood", WOOD)],
            2,
        );
        let d = run(&program, seed);
        assert!(d.leaves.iter().all(|l| d.color(l) == red), "seed {seed}");
    }
    // Both in the user's library: one tier, drawn between them.
    let program = library(&[("chair", CHAIR), ("red", RED_WOOD), ("wood", WOOD)]);
    let colors: std::collections::BTreeSet<String> = (0..16)
        .flat_map(|seed| {
            let d = run(&program, seed);
            d.leaves
                .iter()
                .map(|l| format!("{:?}", d.color(l)))
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(colors.len(), 2, "{colors:?}");
}

#[test]
fn goal_grammars_are_derived_afresh_when_derived_again() {
    let program = library(&[("chair", CHAIR), ("wood", WOOD)]);
    let options = DeriveOptions {
        trace: true,
        ..DeriveOptions::default()
    };
    let first = derive(&program, &[], &options).unwrap();
    let again = shapegram_eval::derive_again(&first, &program, &[], &options).unwrap();
    assert_eq!(
        again.fallback,
        Some("goal grammars are always derived afresh")
    );
    assert_eq!(again.derivation.leaves, first.leaves);
}
