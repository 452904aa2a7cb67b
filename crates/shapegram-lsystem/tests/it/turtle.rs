//! The turtle: end positions, segment and stroke counts, widths, colours, polygons, and the
//! tube model built from a drawing.

use glam::DVec3;
use shapegram_geom::{Scope, primitives};
use shapegram_lsystem::{
    DeriveOptions, Drawing, LSystem, drawing_to_lines, drawing_to_lines_within, drawing_to_model,
    drawing_to_model_within, fit_into_box, fit_into_scope, interpret, model_in_scope,
};

fn draw(text: &str) -> Drawing {
    let system = LSystem::parse(text).unwrap();
    interpret(&system, &system.derive(&DeriveOptions::default()).unwrap())
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn a_square_returns_to_its_start() {
    let drawing = draw("n: 0\nangle: 90\naxiom: F+F+F+F\n");
    assert_eq!(drawing.strokes.len(), 1);
    assert_eq!(drawing.segment_count(), 4);
    assert!(close(drawing.end, DVec3::ZERO), "{}", drawing.end);
    let points = &drawing.strokes[0].points;
    // Heading up first, then + turns left (counter-clockwise seen from +z).
    assert!(close(points[1], DVec3::Y));
    assert!(close(points[2], DVec3::new(-1.0, 1.0, 0.0)));
}

#[test]
fn moves_without_drawing_split_strokes() {
    let drawing = draw("n: 0\naxiom: FfF(2)\n");
    assert_eq!(drawing.strokes.len(), 2);
    assert_eq!(drawing.segment_count(), 2);
    assert!(close(drawing.end, DVec3::new(0.0, 4.0, 0.0)));
    assert!(close(
        drawing.strokes[1].points[1],
        DVec3::new(0.0, 4.0, 0.0)
    ));
}

#[test]
fn branches_restore_the_state_and_the_main_stroke_continues() {
    let drawing = draw("n: 0\nangle: 90\naxiom: F[+F]F[-F(3)]F\n");
    assert_eq!(drawing.strokes.len(), 3);
    assert_eq!(drawing.strokes[0].widths.len(), 3);
    assert!(close(drawing.end, DVec3::new(0.0, 3.0, 0.0)));
    assert!(close(
        drawing.strokes[1].points[1],
        DVec3::new(-1.0, 1.0, 0.0)
    ));
    assert!(close(
        drawing.strokes[2].points[1],
        DVec3::new(3.0, 2.0, 0.0)
    ));
}

#[test]
fn koch_island_is_closed_with_exact_segment_counts() {
    for n in 0..=3u32 {
        let drawing = draw(&format!(
            "n: {n}\nangle: 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F\n"
        ));
        assert_eq!(drawing.segment_count(), 4 * 8usize.pow(n));
        assert_eq!(drawing.strokes.len(), 1);
        assert!(close(drawing.end, DVec3::ZERO));
    }
}

#[test]
fn widths_and_colours() {
    let drawing = draw("n: 0\nwidth: 0.5\nwidth-factor: 0.5\naxiom: F!F!(3)F'F'(5)F\n");
    assert_eq!(drawing.strokes.len(), 3);
    assert_eq!(drawing.strokes[0].widths, [0.5, 0.25, 3.0]);
    let colors: Vec<usize> = drawing.strokes.iter().map(|s| s.color).collect();
    assert_eq!(colors, [0, 1, 5]);
}

#[test]
fn three_d_rotations() {
    // Pitch down: the heading turns away from the up vector (+z).
    assert!(close(draw("n: 0\naxiom: &F\n").end, DVec3::NEG_Z));
    assert!(close(draw("n: 0\naxiom: ^F\n").end, DVec3::Z));
    // Roll right, then pitch down.
    assert!(close(draw("n: 0\naxiom: /&F\n").end, DVec3::X));
    assert!(close(draw("n: 0\naxiom: \\&F\n").end, DVec3::NEG_X));
    assert!(close(draw("n: 0\naxiom: |F\n").end, DVec3::NEG_Y));
    // $ levels the left vector: after pitching down and rolling, a turn stays horizontal.
    let end = draw("n: 0\nangle: 90\naxiom: &(90)/(30)$+F\n").end;
    assert!(end.y.abs() < 1e-9, "{end}");
    assert!((end.length() - 1.0).abs() < 1e-9);
}

#[test]
fn polygons_record_their_vertices() {
    let drawing = draw("n: 0\nangle: 90\naxiom: F{.f.+f.+f.}F\n");
    assert_eq!(drawing.polygons.len(), 1);
    let expected = [
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
        DVec3::new(-1.0, 2.0, 0.0),
        DVec3::new(-1.0, 1.0, 0.0),
    ];
    for (p, e) in drawing.polygons[0].points.iter().zip(expected) {
        assert!(close(*p, e));
    }
    // Moves inside the polygon drew nothing, and the last F starts a new stroke.
    assert_eq!(drawing.segment_count(), 2);
    assert_eq!(drawing.strokes.len(), 2);
    // Without `.`, the start and every move make the vertices.
    let implicit = draw("n: 0\nangle: 120\naxiom: {F+F+F}\n");
    assert_eq!(implicit.polygons[0].points.len(), 4);
}

#[test]
fn a_straight_tube_is_a_closed_prism() {
    let system = LSystem::parse("n: 0\nwidth: 0.2\nsides: 6\naxiom: FF\n").unwrap();
    let drawing = interpret(&system, system.axiom());
    let model = drawing_to_model(&drawing, &system.settings);
    assert_eq!(model.parts.len(), 1);
    let mesh = &model.parts[0].mesh;
    assert_eq!(mesh.face_count(), 6 * 2 + 2);
    assert!(mesh.is_watertight());
    let prism = primitives::cylinder(DVec3::new(0.2, 2.0, 0.2), 6);
    assert!((mesh.signed_volume() - prism.signed_volume()).abs() < 1e-12);
}

#[test]
fn bent_tubes_stay_closed() {
    let system = LSystem::parse("n: 2\nangle: 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F\n").unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let model = drawing_to_model(&interpret(&system, &word), &system.settings);
    let mesh = &model.parts[0].mesh;
    assert!(mesh.is_watertight());
    // 256 segments, 8 quads each; a straight run of segments shares rings, and 90° bends are
    // mitred, so there is one tube with two caps.
    assert_eq!(mesh.face_count(), 256 * 8 + 2);
    assert!(mesh.signed_volume() > 0.0);
    // A turn around (180°) cannot be mitred: the tube ends and a new one starts.
    let system = LSystem::parse("n: 0\naxiom: F|F\n").unwrap();
    let model = drawing_to_model(&interpret(&system, system.axiom()), &system.settings);
    assert_eq!(model.parts[0].mesh.face_count(), 2 * (8 + 2));
}

#[test]
fn tubes_are_smooth_with_radial_normals() {
    let system = LSystem::parse("n: 0\nwidth: 0.2\nsides: 6\naxiom: FF\n").unwrap();
    let model = drawing_to_model(&interpret(&system, system.axiom()), &system.settings);
    let part = &model.parts[0];
    assert_eq!(part.normals.len(), part.mesh.vertex_count());
    assert_eq!(part.normals.len(), 3 * 6);
    // The stroke runs up the y axis: each normal is horizontal, pointing at its vertex.
    for (p, n) in part.mesh.positions().iter().zip(&part.normals) {
        let radial = DVec3::new(p.x, 0.0, p.z) / 0.1;
        assert!(close(*n, radial), "{p}: {n}");
    }
    // Bent, branching tubes: unit normals pointing away from the stroke at each ring.
    let system = LSystem::parse("n: 2\nangle: 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F\n").unwrap();
    let drawing = interpret(&system, &system.derive(&DeriveOptions::default()).unwrap());
    let model = drawing_to_model(&drawing, &system.settings);
    let part = &model.parts[0];
    let stroke = &drawing.strokes[0];
    assert_eq!(part.mesh.vertex_count(), 8 * stroke.points.len());
    for (v, (p, n)) in part.mesh.positions().iter().zip(&part.normals).enumerate() {
        assert!((n.length() - 1.0).abs() < 1e-12);
        assert!(n.dot(*p - stroke.points[v / 8]) > 0.0, "vertex {v}");
    }
}

#[test]
fn fitting_carries_normals_and_lines_into_the_scope() {
    let system = LSystem::parse("n: 0\nwidth: 0.2\nsides: 6\nangle: 90\naxiom: FF+F\n").unwrap();
    let drawing = interpret(&system, system.axiom());
    let mut scope = Scope::axis_aligned(DVec3::new(10.0, 0.0, -4.0), DVec3::new(3.0, 8.0, 3.0));
    scope.rotate_world(DVec3::Y, 30.0, scope.origin);
    let rotation = glam::DQuat::from_axis_angle(DVec3::Y, 30f64.to_radians());
    let tubes = drawing_to_model(&drawing, &system.settings);
    let placed = fit_into_scope(&tubes, &scope);
    let (before, after) = (&tubes.parts[0], &placed.parts[0]);
    assert_eq!(after.normals.len(), before.normals.len());
    for (n, m) in before.normals.iter().zip(&after.normals) {
        assert!(close(rotation * *n, *m), "{n} became {m}");
    }
    // A mirrored box flips loops and normals alike: they still point out of the tube.
    let mirrored = fit_into_box(&tubes, DVec3::new(-3.0, 8.0, 3.0));
    assert!(mirrored.parts[0].mesh.signed_volume() > 0.0);

    let lines = fit_into_scope(&drawing_to_lines(&drawing, &system.settings), &scope);
    assert_eq!(lines.lines[0].points.len(), 4);
    for &p in &lines.lines[0].points {
        let local = scope.to_local(p);
        assert!(local.cmpge(DVec3::splat(-1e-9)).all(), "{local}");
        assert!(local.cmple(scope.size + 1e-9).all(), "{local}");
    }
}

#[test]
fn strokes_as_lines_share_their_points() {
    let system = LSystem::parse("n: 0\nangle: 90\naxiom: FF[+F'F]F'{.f.+f.+f.}\n").unwrap();
    let drawing = interpret(&system, system.axiom());
    assert_eq!(drawing.strokes.len(), 3);
    let model = drawing_to_lines(&drawing, &system.settings);
    let names: Vec<&str> = model.lines.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["branches-0", "branches-1"]);
    let parts: Vec<&str> = model.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(parts, ["leaves-1"]);
    // Colour 0: the trunk, which goes on after the branch (four points, three segments), and
    // the branch's first segment; colour 1: the branch's second segment.
    let zero = &model.lines[0];
    assert_eq!(zero.points.len(), 6);
    assert_eq!(zero.segments, [[0, 1], [1, 2], [2, 3], [4, 5]]);
    assert_eq!(zero.color, system.settings.colors[0]);
    let one = &model.lines[1];
    assert_eq!(one.points.len(), 2);
    assert_eq!(one.segments, [[0, 1]]);
    let segments: usize = model.lines.iter().map(|l| l.segments.len()).sum();
    assert_eq!(segments, drawing.segment_count());
    for lines in &model.lines {
        for &[a, b] in &lines.segments {
            let length = lines.points[a as usize].distance(lines.points[b as usize]);
            assert!((length - 1.0).abs() < 1e-12, "{length}");
        }
    }
    // The budget counts points and leaf vertices: 6 + 2 + 2 · 4.
    assert!(drawing_to_lines_within(&drawing, &system.settings, 16).is_ok());
    assert_eq!(
        drawing_to_lines_within(&drawing, &system.settings, 15)
            .unwrap_err()
            .to_string(),
        "the model would have up to 16 vertices, over the limit of 15 (derive fewer steps or draw an SVG)"
    );
}

#[test]
fn models_over_the_vertex_limit_are_refused_before_they_are_built() {
    // Two tubes (the turn around splits the stroke) of two rings each, and a square leaf drawn
    // on both sides: 4 · 8 + 2 · 4 vertices.
    let system = LSystem::parse("n: 0\nangle: 90\naxiom: F|F{.f.+f.+f.}\n").unwrap();
    let drawing = interpret(&system, system.axiom());
    let model = drawing_to_model(&drawing, &system.settings);
    let vertices: usize = model.parts.iter().map(|p| p.mesh.vertex_count()).sum();
    assert_eq!(vertices, 40);
    let within = drawing_to_model_within(&drawing, &system.settings, 40).unwrap();
    assert_eq!(within.parts.len(), model.parts.len());
    assert_eq!(
        drawing_to_model_within(&drawing, &system.settings, 39)
            .unwrap_err()
            .to_string(),
        "the model would have up to 40 vertices, over the limit of 39 (derive fewer steps, use fewer sides, draw lines, or draw an SVG)"
    );
    // A plain line of 2¹⁷ segments with 64 sides is over 8 million vertices.
    let system = LSystem::parse("n: 17\nsides: 64\naxiom: F\nF -> FF\n").unwrap();
    let word = system.derive(&DeriveOptions::default()).unwrap();
    let drawing = interpret(&system, &word);
    let err = drawing_to_model_within(&drawing, &system.settings, 1_000_000).unwrap_err();
    assert!(
        err.message.starts_with(
            "the model would have up to 8,388,672 vertices, over the limit of 1,000,000"
        ),
        "{err}"
    );
}

#[test]
fn leaves_are_two_sided_parts_of_their_colour() {
    let system = LSystem::parse("n: 0\nangle: 90\naxiom: F'{.f.+f.+f.}\n").unwrap();
    let model = drawing_to_model(&interpret(&system, system.axiom()), &system.settings);
    let names: Vec<&str> = model.parts.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["branches-0", "leaves-1"]);
    let leaves = &model.parts[1].mesh;
    assert_eq!(leaves.face_count(), 2);
    assert!((leaves.area() - 2.0).abs() < 1e-12);
    assert_eq!(model.parts[1].color, system.settings.colors[1]);
}

#[test]
fn fitting_keeps_proportions_and_stands_on_the_floor() {
    let system = LSystem::parse("n: 0\nwidth: 0.2\naxiom: FFFF\n").unwrap();
    let model = drawing_to_model(&interpret(&system, system.axiom()), &system.settings);
    let fitted = fit_into_box(&model, DVec3::new(10.0, 2.0, 10.0));
    let bounds = fitted.bounds().unwrap();
    // The height, 4 (caps are flat), scales to 2: the box is lowest along y.
    assert!((bounds.size().y - 2.0).abs() < 1e-9, "{:?}", bounds);
    assert!(bounds.min.y.abs() < 1e-9);
    assert!((bounds.center().x - 5.0).abs() < 1e-9);
    assert!((bounds.center().z - 5.0).abs() < 1e-9);
    let ratio = bounds.size().x / bounds.size().y;
    let original = model.bounds().unwrap().size();
    assert!((ratio - original.x / original.y).abs() < 1e-9);
    let scope = Scope::axis_aligned(DVec3::new(100.0, 0.0, 50.0), DVec3::new(10.0, 2.0, 10.0));
    let placed = fit_into_scope(&model, &scope).bounds().unwrap();
    assert!((placed.min.y).abs() < 1e-9);
    assert!((placed.center().x - 105.0).abs() < 1e-9);
}

#[test]
fn a_polygon_that_walks_back_to_its_start_closes_without_a_sliver() {
    // With 72° turns the last vertex lands on the first only up to rounding.
    let system = LSystem::parse("n: 0\nangle: 72\naxiom: {.f.+f.+f.+f.+f.}\n").unwrap();
    let drawing = interpret(&system, system.axiom());
    assert_eq!(drawing.polygons[0].points.len(), 6);
    let model = drawing_to_model(&drawing, &system.settings);
    let leaves = &model.parts[0].mesh;
    assert_eq!(leaves.face(0).len(), 5);
    assert_eq!(leaves.triangulate().len(), 2 * 3);
    // A regular pentagon of side 1.
    let area = 5.0 / 4.0 / (36f64).to_radians().tan();
    assert!((leaves.area() - 2.0 * area).abs() < 1e-9);
}

#[test]
fn an_l_system_planted_in_a_rotated_scope_stays_inside_it() {
    let tree =
        LSystem::parse("n: 4\nangle: 25\nwidth: 0.3\naxiom: F\nF -> F[+F]F[-F][&F]F\n").unwrap();
    let mut scope = Scope::axis_aligned(DVec3::new(10.0, 0.0, -4.0), DVec3::new(3.0, 8.0, 3.0));
    scope.rotate_world(DVec3::Y, 30.0, scope.origin);
    let model = model_in_scope(&tree, &DeriveOptions::default(), &scope).unwrap();
    assert!(!model.parts.is_empty());
    let eps = 1e-9;
    let mut top: f64 = 0.0;
    for part in &model.parts {
        for &p in part.mesh.positions() {
            let local = scope.to_local(p);
            assert!(local.cmpge(DVec3::splat(-eps)).all(), "{local}");
            assert!(local.cmple(scope.size + eps).all(), "{local}");
            top = top.max(local.y);
        }
    }
    // The tree is taller than wide, so it reaches the top of the scope.
    assert!((top - 8.0).abs() < 1e-9, "{top}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// Any word of turtle commands, with any parameters, draws finite geometry without panicking,
    /// and every tube of the model is closed.
    #[test]
    fn any_turtle_word_gives_finite_closed_tubes(
        commands in proptest::collection::vec((0usize..17, proptest::option::of(-1e3f64..1e3)), 0..60),
        tiny in proptest::bool::ANY,
    ) {
        const NAMES: [char; 17] = ['F', 'f', 'G', '+', '-', '&', '^', '\\', '/', '|', '$', '[', ']', '!', '\'', '{', '.'];
        let mut axiom = String::new();
        for (k, param) in commands {
            axiom.push(NAMES[k]);
            if let (Some(p), false) = (param, matches!(NAMES[k], '[' | ']')) {
                let p = if tiny && NAMES[k] == 'F' { p * 1e-300 } else { p };
                axiom.push_str(&format!("({p})"));
            }
        }
        axiom.push('}');
        let system = LSystem::parse(&format!("n: 0\nangle: 33\naxiom: {axiom}\n")).unwrap();
        let drawing = interpret(&system, system.axiom());
        let model = drawing_to_model(&drawing, &system.settings);
        for part in &model.parts {
            proptest::prop_assert!(part.mesh.positions().iter().all(|p| p.is_finite()));
            if part.name.starts_with("branches") {
                proptest::prop_assert!(part.mesh.is_watertight(), "{}", axiom);
                proptest::prop_assert_eq!(part.normals.len(), part.mesh.vertex_count());
                proptest::prop_assert!(part.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-9));
            }
        }
        let lines = drawing_to_lines(&drawing, &system.settings);
        let segments: usize = lines.lines.iter().map(|l| l.segments.len()).sum();
        proptest::prop_assert_eq!(segments, drawing.segment_count());
    }
}
