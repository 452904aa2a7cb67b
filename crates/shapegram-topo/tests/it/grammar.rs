//! The grammar pipeline end to end: authoring, compiling, files, generation and meshing.

use shapegram_geom::{DAffine3, DMat3, DVec3};
use shapegram_topo::demos;
use shapegram_topo::{
    Anchor, Assignment, CutPlane, EditError, Editor, GenerateError, Grammar, GrammarMesh,
    GrammarState, Project, RuleTree, compile,
};

/// `A` → three equal slices along x: an `A`, a terminal `B` and nothing.
fn chain() -> Project {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(3.0, 1.0, 1.0)).unwrap();
    let b = p.add_box_symbol("B", DVec3::ONE).unwrap();
    let rule = p.add_rule(a, "thirds", 1.0).unwrap();
    let base = p.face_towards(rule, RuleTree::ROOT, -DVec3::X).unwrap();
    let parts = p.multi_cut(rule, RuleTree::ROOT, base, 2).unwrap();
    p.assign_facing(rule, parts[0], a, DVec3::Y, DVec3::Z)
        .unwrap();
    p.assign_facing(rule, parts[1], b, DVec3::Y, DVec3::Z)
        .unwrap();
    p.assign(rule, parts[2], Assignment::Epsilon).unwrap();
    p
}

/// `A` → two `A`s: never terminates, doubles every generation.
fn doubling() -> Project {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(2.0, 1.0, 1.0)).unwrap();
    let rule = p.add_rule(a, "halves", 1.0).unwrap();
    let base = p.face_towards(rule, RuleTree::ROOT, -DVec3::X).unwrap();
    let [left, right] = p.prism_cut(rule, RuleTree::ROOT, base, 0.5, None).unwrap();
    for half in [left, right] {
        p.assign_facing(rule, half, a, DVec3::Y, DVec3::Z).unwrap();
    }
    p
}

#[test]
fn generations_and_bookkeeping_match_hand_counts() {
    let grammar = compile(&chain()).unwrap();
    let mut state = GrammarState::new(&grammar, "A")
        .unwrap()
        .with_generations(5);
    state.start();
    assert_eq!(
        (state.terminals().len(), state.non_terminals().len()),
        (0, 1)
    );
    state.next_generation().unwrap();
    assert_eq!(
        (state.terminals().len(), state.non_terminals().len()),
        (1, 1)
    );
    state.generate_all().unwrap();
    assert_eq!(state.generation(), 5);
    assert_eq!(
        (state.terminals().len(), state.non_terminals().len()),
        (5, 1)
    );
    // Each generation keeps the first third: the last A spans x in [0, 3 / 3^5].
    let last = state.non_terminals().vertices(0);
    let max_x = last.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    assert!((max_x - 3.0 / 243.0).abs() < 1e-12);
    // next_generation may run past the configured count.
    state.next_generation().unwrap();
    assert_eq!(state.generation(), 6);
    assert_eq!(state.terminals().len(), 6);
}

#[test]
fn symbols_that_never_terminate_hit_the_shape_limit_with_a_clear_error() {
    let grammar = compile(&doubling()).unwrap();
    let mut state = GrammarState::new(&grammar, "A")
        .unwrap()
        .with_generations(30);
    state.max_shapes = 100;
    let error = state.generate_all().unwrap_err();
    assert_eq!(
        error,
        GenerateError::TooManyShapes {
            limit: 100,
            generation: 7,
            symbol: "A".into()
        }
    );
    assert_eq!(
        error.to_string(),
        "generation 7 would make more than 100 shapes, most of them 'A' (symbols that keep \
         producing themselves never stop: use fewer generations or a higher shape limit)"
    );
    // The state stays at the last complete generation.
    assert_eq!(state.generation(), 6);
    assert_eq!(state.non_terminals().len(), 64);
    // A vertex limit works the same way: 8 vertices a box, 2^4 boxes in generation 4.
    let mut state = GrammarState::new(&grammar, "A")
        .unwrap()
        .with_generations(30);
    state.max_vertices = 100;
    assert_eq!(
        state.generate_all().unwrap_err().to_string(),
        "generation 4 would hold more than 100 vertices (use fewer generations or a higher \
         vertex limit)"
    );
    assert_eq!(state.generation(), 3);
    // Bounded by generations instead, it simply stops.
    let mut state = GrammarState::new(&grammar, "A")
        .unwrap()
        .with_generations(4);
    state.generate_all().unwrap();
    assert_eq!(state.non_terminals().len(), 16);
    let mesh = GrammarMesh::new(&state);
    assert_eq!(mesh.triangle_count(), 16 * 12);
}

#[test]
fn unknown_initial_symbols_list_the_symbols_there_are() {
    let grammar = compile(&chain()).unwrap();
    let error = GrammarState::new(&grammar, "C").unwrap_err();
    assert_eq!(
        error.to_string(),
        "the grammar has no symbol 'C' (symbols: A, B)"
    );
}

#[test]
fn compiled_rules_follow_a_sheared_instance() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let map = DAffine3::from_mat3_translation(
        DMat3::from_cols(
            DVec3::new(1.2, 0.0, 0.3),
            DVec3::new(0.4, 0.8, 0.0),
            DVec3::new(0.0, 0.1, 1.5),
        ),
        DVec3::new(5.0, -2.0, 7.0),
    );
    let symbol = grammar.symbol_named("House").unwrap();
    let sheared: Vec<DVec3> = grammar
        .shape_of(symbol)
        .unwrap()
        .vertices
        .iter()
        .map(|&p| map.transform_point3(p))
        .collect();
    let mut plain = GrammarState::new(&grammar, "House")
        .unwrap()
        .with_seed(7)
        .with_generations(8);
    let mut bent = plain.clone().with_initial_shape(sheared).unwrap();
    plain.generate_all().unwrap();
    bent.generate_all().unwrap();
    let (a, b) = (plain.terminals(), bent.terminals());
    assert_eq!(a.len(), b.len());
    assert!(a.len() > 100);
    for i in 0..a.len() {
        assert_eq!(a.symbol(i), b.symbol(i));
        for (p, q) in a.vertices(i).iter().zip(b.vertices(i)) {
            assert!((map.transform_point3(*p) - *q).length() < 1e-9);
        }
    }
}

#[test]
fn grammar_files_round_trip_exactly() {
    for project in [
        demos::house().unwrap(),
        demos::mayan_pyramid().unwrap(),
        demos::spiral_steps(true).unwrap(),
    ] {
        let grammar = compile(&project).unwrap();
        let text = grammar.to_json();
        let loaded = Grammar::from_json(&text).unwrap();
        assert_eq!(loaded, grammar);
        assert_eq!(loaded.to_json(), text);
    }
}

#[test]
fn project_files_round_trip_exactly() {
    for project in [
        demos::house().unwrap(),
        demos::mayan_pyramid().unwrap(),
        demos::spiral_steps(false).unwrap(),
        chain(),
    ] {
        let text = project.to_json();
        let loaded = Project::from_json(&text).unwrap();
        assert_eq!(loaded, project);
        assert_eq!(loaded.to_json(), text);
    }
}

#[test]
fn the_house_grammar_has_the_size_of_the_thesis_demo() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let non_terminals = grammar
        .symbols
        .iter()
        .filter(|s| !s.rules.is_empty())
        .count();
    assert_eq!(non_terminals, 15);
    assert_eq!(grammar.rules.len(), 18);
    let with_two_rules: Vec<&str> = grammar
        .symbols
        .iter()
        .filter(|s| s.rules.len() == 2)
        .filter_map(|s| s.name.as_deref())
        .collect();
    assert_eq!(with_two_rules, ["House", "GroundFloor", "Roof"]);
}

/// Counts of terminal shapes by symbol name after a full derivation.
fn house_counts(grammar: &Grammar, seed: u64) -> Vec<(String, usize)> {
    let mut state = GrammarState::new(grammar, "House")
        .unwrap()
        .with_seed(seed)
        .with_generations(8);
    state.generate_all().unwrap();
    assert!(state.non_terminals().is_empty(), "seed {seed}");
    let mut counts: Vec<(String, usize)> = Vec::new();
    for i in 0..state.terminals().len() {
        let name = grammar.display_name(state.terminals().symbol(i)).to_owned();
        match counts.iter_mut().find(|(n, _)| *n == name) {
            Some((_, c)) => *c += 1,
            None => counts.push((name, 1)),
        }
    }
    counts.sort();
    counts
}

#[test]
fn houses_have_doors_windows_and_a_roof_in_eight_variants() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let mut variants = Vec::new();
    for seed in 0..64 {
        let counts = house_counts(&grammar, seed);
        let count = |name: &str| {
            counts
                .iter()
                .find(|(n, _)| n == name)
                .map_or(0, |(_, c)| *c)
        };
        assert_eq!(count("DoorPanel"), 1, "one door, seed {seed}");
        assert_eq!(count("GableRoof") + count("PyramidRoof"), 1);
        let floors = count("Floor");
        assert!(floors == 1 || floors == 2);
        // Every window has four panes: glass comes in fours.
        assert_eq!(count("Glass") % 4, 0);
        // Window walls have two windows each: 3 of them per storey, plus the front's.
        let front_windows = count("Glass") / 4 - 6 * floors;
        assert!(
            front_windows == 2 * (floors - 1) || front_windows == 2 * (floors - 1) + 2,
            "seed {seed}: {counts:?}"
        );
        if !variants.contains(&counts) {
            variants.push(counts);
        }
    }
    assert_eq!(variants.len(), 8);
}

#[test]
fn a_one_storey_house_with_a_wide_door_has_the_expected_parts() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let wide_gable = (0..64)
        .map(|seed| house_counts(&grammar, seed))
        .find(|c| {
            c.contains(&("Floor".into(), 1)) && c.contains(&("GableRoof".into(), 1)) && {
                c.contains(&("Glass".into(), 24))
            }
        })
        .unwrap();
    // 3 window walls × 2 windows × 4 panes; frames: per window 4 + 1 mullion + 2 transoms = 7,
    // so 42, plus the door's 3; walls: per window bay 2 + per window column 2 = 4 → 24, plus the
    // door wall's 2 and the door column's lintel.
    assert_eq!(
        wide_gable,
        [
            ("DoorPanel".into(), 1),
            ("Floor".into(), 1),
            ("Frame".into(), 45),
            ("GableRoof".into(), 1),
            ("Glass".into(), 24),
            ("Wall".into(), 27),
        ]
    );
}

#[test]
fn faces_with_their_own_colour_get_their_own_part() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let gable = grammar.symbol_named("GableRoof").unwrap();
    let colors = &grammar.symbols[gable as usize].face_colors;
    assert_eq!(colors.len(), 5);
    assert_eq!(colors.iter().filter(|c| c.is_some()).count(), 2);
    let seed = (0..64)
        .find(|&seed| {
            let mut state = GrammarState::new(&grammar, "House")
                .unwrap()
                .with_seed(seed)
                .with_generations(8);
            state.generate_all().unwrap();
            (0..state.terminals().len()).any(|i| state.terminals().symbol(i) == gable)
        })
        .unwrap();
    let mut state = GrammarState::new(&grammar, "House")
        .unwrap()
        .with_seed(seed)
        .with_generations(8);
    state.generate_all().unwrap();
    let mesh = GrammarMesh::new(&state);
    let roof_parts: Vec<_> = mesh.parts.iter().filter(|p| p.symbol == gable).collect();
    assert_eq!(roof_parts.len(), 2);
    // Two slopes and the underside, two triangles each, in the roof colour; the two gable
    // triangles in the wall colour.
    let triangles = |hex: &str| {
        roof_parts
            .iter()
            .find(|p| p.color.to_hex() == hex)
            .map(|p| p.triangles.len())
    };
    assert_eq!(triangles("#a63d2f"), Some(6));
    assert_eq!(triangles("#e6dcc6"), Some(2));
    assert!(roof_parts.iter().all(|p| p.name == "GableRoof"));
}

#[test]
fn generation_is_deterministic_and_seeds_are_48_bit() {
    let grammar = compile(&demos::house().unwrap()).unwrap();
    let mesh = |seed: u64| {
        let mut state = GrammarState::new(&grammar, "House")
            .unwrap()
            .with_seed(seed)
            .with_generations(8);
        state.generate_all().unwrap();
        GrammarMesh::new(&state)
    };
    assert_eq!(mesh(0x2a), mesh(0x2a));
    assert_eq!(mesh(0x2a), mesh(0x2a | (1 << 48)));
    let state = GrammarState::new(&grammar, "House")
        .unwrap()
        .with_seed(u64::MAX);
    assert_eq!(state.seed(), (1 << 48) - 1);
}

/// Centres of the successive `A` shapes over `generations` generations.
fn a_centres(project: &Project, generations: u32) -> Vec<DVec3> {
    let grammar = compile(project).unwrap();
    let mut state = GrammarState::new(&grammar, "A").unwrap();
    state.start();
    let mut centres = Vec::new();
    for _ in 0..generations {
        state.next_generation().unwrap();
        assert_eq!(state.non_terminals().len(), 1);
        let v = state.non_terminals().vertices(0);
        centres.push(v.iter().sum::<DVec3>() / v.len() as f64);
    }
    centres
}

#[test]
fn the_anchor_turns_the_steps_into_a_spiral() {
    // Figures 31–32: the anchor as the reference anchor, every step goes the same way (+x).
    let straight = a_centres(&demos::spiral_steps(false).unwrap(), 4);
    for pair in straight.windows(2) {
        let d = pair[1] - pair[0];
        assert!(d.x > 0.0 && d.z.abs() < 1e-9, "{d}");
    }
    // Figures 33–34: the anchor a quarter turn round; each step turns by 90° the same way.
    let spiral = a_centres(&demos::spiral_steps(true).unwrap(), 5);
    let steps: Vec<DVec3> = spiral
        .windows(2)
        .map(|p| (p[1] - p[0]) * DVec3::new(1.0, 0.0, 1.0))
        .collect();
    for pair in steps.windows(2) {
        let (a, b) = (pair[0].normalize(), pair[1].normalize());
        assert!(a.dot(b).abs() < 1e-9, "{a} {b}");
        // Always the same way round: counter-clockwise seen from above.
        assert!(a.cross(b).y > 0.0, "{a} {b}");
    }
}

#[test]
fn the_turned_anchor_is_the_reference_anchor_moved_one_corner() {
    let project = demos::spiral_steps(false).unwrap();
    let turned = demos::spiral_steps(true).unwrap();
    let anchor_of = |p: &Project| {
        let tree = &p.rules[0].tree;
        let leaf = *tree.leaves().last().unwrap();
        let shape = tree.node(leaf).unwrap().shape.clone();
        match tree.node(leaf).unwrap().kind {
            shapegram_topo::NodeKind::Leaf(Assignment::Symbol { anchor, .. }) => (shape, anchor),
            other => panic!("{other:?}"),
        }
    };
    let (shape, straight) = anchor_of(&project);
    let (_, rotated) = anchor_of(&turned);
    assert_ne!(straight, rotated);
    let one_corner = [
        straight.clockwise(&shape).unwrap(),
        straight.counter_clockwise(&shape).unwrap(),
    ];
    assert!(one_corner.contains(&rotated), "{straight:?} → {rotated:?}");
}

#[test]
fn the_pyramid_steps_up_in_tiers_with_stairs() {
    let grammar = compile(&demos::mayan_pyramid().unwrap()).unwrap();
    let mut state = GrammarState::new(&grammar, "Pyramid")
        .unwrap()
        .with_generations(4);
    state.generate_all().unwrap();
    let names: Vec<&str> = (0..state.terminals().len())
        .map(|i| grammar.display_name(state.terminals().symbol(i)))
        .collect();
    assert_eq!(names.iter().filter(|n| **n == "Stone").count(), 4);
    assert_eq!(names.iter().filter(|n| **n == "Stairs").count(), 4);
    assert_eq!(state.non_terminals().len(), 1);
    // The top tier: 16 × 0.8⁴ wide, 8 × 0.75⁴ high, resting on the fourth slab.
    let top = state.non_terminals().vertices(0);
    let (lo, hi) = top
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    assert!(((hi - lo).x - 16.0 * 0.8f64.powi(4)).abs() < 1e-9);
    assert!(((hi - lo).y - 8.0 * 0.75f64.powi(4)).abs() < 1e-9);
    assert!((hi.y - 8.0).abs() < 1e-9);
}

#[test]
fn undo_and_redo_restore_every_step() {
    let mut editor = Editor::new(Project::new());
    let a = editor.apply(|p| p.add_box_symbol("A", DVec3::ONE)).unwrap();
    let rule = editor.apply(|p| p.add_rule(a, "r", 1.0)).unwrap();
    let before = editor.project().clone();
    let [slice, _] = editor
        .apply(|p| p.face_cut(rule, RuleTree::ROOT, 3, 0.25))
        .unwrap();
    let after_cut = editor.project().clone();
    editor
        .apply(|p| p.assign(rule, slice, Assignment::Epsilon))
        .unwrap();
    // A failed step changes nothing and is not recorded.
    let error = editor
        .apply(|p| p.face_cut(rule, slice, 0, 0.1))
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        format!("sub-shape {slice} is epsilon; make it a terminal before cutting it")
    );
    assert_eq!(editor.undo_depth(), 4);
    assert!(editor.undo());
    assert_eq!(editor.project(), &after_cut);
    assert!(editor.undo());
    assert_eq!(editor.project(), &before);
    assert!(editor.redo());
    assert_eq!(editor.project(), &after_cut);
    assert_eq!(editor.redo_depth(), 1);
    editor.apply(|p| p.set_weight(rule, 2.0)).unwrap();
    assert_eq!(editor.redo_depth(), 0);
    assert!(!editor.redo());
}

#[test]
fn cutting_tools_place_their_planes_as_described() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(10.0, 3.0, 2.0)).unwrap();
    let rule = p.add_rule(a, "tools", 1.0).unwrap();
    let volume = |p: &Project, leaf| p.rules[0].tree.node(leaf).unwrap().shape.volume();
    let left = p.face_towards(rule, RuleTree::ROOT, -DVec3::X).unwrap();
    // Prism cut at 0.33 of 10 snapped to a grid of 1: 3 from the left face.
    let [near, rest] = p
        .prism_cut(rule, RuleTree::ROOT, left, 0.33, Some(1.0))
        .unwrap();
    assert!((volume(&p, near) - 18.0).abs() < 1e-9);
    // Multi-cut of the remaining 7 into 4 equal parts.
    let face = p.face_towards(rule, rest, -DVec3::X).unwrap();
    let parts = p.multi_cut(rule, rest, face, 3).unwrap();
    assert_eq!(parts.len(), 4);
    for &part in &parts {
        assert!((volume(&p, part) - 10.5).abs() < 1e-9);
    }
    // Symmetric cut with 20 % margins along y.
    let bottom = p.face_towards(rule, parts[3], -DVec3::Y).unwrap();
    let [low, middle, high] = p.symmetric_cut(rule, parts[3], bottom, 0.2).unwrap();
    assert!((volume(&p, low) - volume(&p, high)).abs() < 1e-9);
    assert!((volume(&p, middle) - 10.5 * 0.6).abs() < 1e-9);
    // A 3-point cut crosses every sub-shape its triangle overlaps: the triangle in the plane
    // z = 1 with corners at x = 0 and x = 8 (y = 0) and y = 3 (x = 0) overlaps the sub-shapes
    // starting left of x = 8 (0–3, 3–4.75, 4.75–6.5, 6.5–8.25), not the three beyond.
    let leaves_before = p.rules[0].tree.leaves().len();
    let cuts = p
        .three_point_cut(
            rule,
            [
                DVec3::new(0.0, 0.0, 1.0),
                DVec3::new(8.0, 0.0, 1.0),
                DVec3::new(0.0, 3.0, 1.0),
            ],
        )
        .unwrap();
    assert_eq!(cuts.len(), 4);
    assert_eq!(p.rules[0].tree.leaves().len(), leaves_before + 4);
    let collinear = p.three_point_cut(rule, [DVec3::ZERO, DVec3::X, DVec3::X * 2.0]);
    assert_eq!(
        collinear.unwrap_err().to_string(),
        "the three points lie on one line: they define no plane"
    );
    let miss = p.face_cut(rule, low, 0, 50.0);
    assert!(matches!(miss, Err(EditError::Cut(_))));
    assert!(matches!(
        p.face_cut(rule, near, 0, 0.5),
        Err(EditError::NotCuttable(_))
    ));
    // The global option cuts every cuttable sub-shape the plane passes through: the plane
    // y = 1.4 crosses the 8 halves of the 3-point cut and the middle third, not `low`.
    let top = p.face_towards(rule, middle, DVec3::Y).unwrap();
    let global = p.global_face_cut(rule, middle, top, 1.0).unwrap();
    assert_eq!(global.len(), 9);
}

#[test]
fn three_cut_points_can_sit_on_edges_snapped_to_a_grid() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(4.0, 2.0, 2.0)).unwrap();
    let rule = p.add_rule(a, "corner", 1.0).unwrap();
    // Face 2 is the bottom [0, 1, 5, 4]; corner 0 runs from (0,0,0) to (4,0,0).
    let along = Anchor::new(2, 0);
    let p1 = p
        .edge_point(rule, RuleTree::ROOT, along, 0.3, Some(1.0))
        .unwrap();
    assert_eq!(p1, DVec3::new(1.0, 0.0, 0.0));
    // Corner 3 of the bottom runs from (0,0,2) back to (0,0,0).
    let p2 = p
        .edge_point(rule, RuleTree::ROOT, Anchor::new(2, 3), 0.5, None)
        .unwrap();
    assert_eq!(p2, DVec3::new(0.0, 0.0, 1.0));
    // Face 0 is −x [0, 4, 6, 2]; corner 3 runs down from (0,2,0) to (0,0,0).
    let p3 = p
        .edge_point(rule, RuleTree::ROOT, Anchor::new(0, 3), 0.75, None)
        .unwrap();
    assert_eq!(p3, DVec3::new(0.0, 0.5, 0.0));
    let cuts = p.three_point_cut(rule, [p1, p2, p3]).unwrap();
    assert_eq!(cuts.len(), 1);
    let tree = &p.rules[0].tree;
    let corner = tree.node(cuts[0][0]).unwrap();
    let rest = tree.node(cuts[0][1]).unwrap();
    // The corner tetrahedron (0,0,0), (1,0,0), (0,0,1), (0,0.5,0): volume 1 × 1 × 0.5 / 6.
    let small = corner.shape.volume().min(rest.shape.volume());
    assert!((small - 0.5 / 6.0).abs() < 1e-12);
    assert!(
        p.edge_point(rule, RuleTree::ROOT, along, 1.5, None)
            .is_err()
    );
    assert!(
        p.edge_point(rule, RuleTree::ROOT, Anchor::new(9, 0), 0.5, None)
            .is_err()
    );
}

#[test]
fn a_three_cut_point_at_the_end_of_an_edge_is_that_vertex_exactly() {
    // A box from x = 5.101 to x = 15.275, where 5.101 + (15.275 − 5.101) is 15.274999999999999.
    let (low, high) = (5.101_f64, 15.275_f64);
    assert_ne!(low + (high - low), high);
    let unit = shapegram_topo::Polyhedron::cuboid(DVec3::ZERO, DVec3::ONE).unwrap();
    let stretched = unit
        .positions()
        .iter()
        .map(|p| DVec3::new(if p.x > 0.0 { high } else { low }, p.y, p.z))
        .collect();
    let mut p = Project::new();
    let a = p
        .add_symbol(
            "A",
            unit.with_positions(stretched).unwrap(),
            Anchor::new(3, 0),
        )
        .unwrap();
    let rule = p.add_rule(a, "corner", 1.0).unwrap();
    // Face 2 is the bottom [0, 1, 5, 4]; corner 0 runs from (5.101,0,0) to (15.275,0,0).
    let along = Anchor::new(2, 0);
    let end = DVec3::new(high, 0.0, 0.0);
    assert_eq!(
        p.edge_point(rule, RuleTree::ROOT, along, 1.0, None)
            .unwrap(),
        end
    );
    assert_eq!(
        p.edge_point(rule, RuleTree::ROOT, along, 0.99, Some(4.0))
            .unwrap(),
        end
    );
}

#[test]
fn topology_mismatches_are_refused_with_a_reason() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::ONE).unwrap();
    let rule = p.add_rule(a, "corner", 1.0).unwrap();
    let [corner, rest] = p
        .plane_cut(
            rule,
            RuleTree::ROOT,
            CutPlane::new(DVec3::new(0.5, 0.0, 0.0), DVec3::ONE),
        )
        .unwrap();
    let error = p
        .assign(
            rule,
            corner,
            Assignment::Symbol {
                symbol: a,
                anchor: Anchor::new(0, 0),
            },
        )
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        "the shape (4 vertices, 4 faces) does not have the topology of symbol 'A' (8 vertices, \
         6 faces)"
    );
    assert!(p.assign(rule, rest, Assignment::Epsilon).is_ok());
    let tetra = p
        .symbol_from_leaf(rule, corner, "T", Anchor::new(0, 0))
        .unwrap();
    assert_eq!(p.symbols[tetra as usize].shape.vertex_count(), 4);
    assert!(
        p.face_cut(rule, corner, 0, 0.01)
            .unwrap_err()
            .to_string()
            .contains("has a symbol")
    );
}
