//! Past the thesis: tiled materials on faces (kept by the pieces of cut faces, in the editor and
//! at derivation) and cuts at a fixed distance from a face, with undo and redo and their errors.

use shapegram_geom::{Color, DVec2, DVec3};
use shapegram_topo::{
    Anchor, Assignment, Editor, GenerateError, Grammar, GrammarMesh, GrammarState, Material,
    NodeKind, Polyhedron, Project, RuleTree, compile, demos,
};

const BRICK: u32 = 0;

fn brick() -> Material {
    Material::textured("Brick", "brick.png", DVec2::new(2.0, 0.5))
}

/// A 4 × 3 × 2 box `A` whose one rule gives its front face (+z) brick and keeps it whole.
fn painted_box() -> Project {
    painted_box_anchored(Anchor::new(3, 0))
}

/// [`painted_box`] with the symbol's reference anchor at `anchor`.
fn painted_box_anchored(anchor: Anchor) -> Project {
    let mut p = Project::new();
    let shape = Polyhedron::cuboid(DVec3::ZERO, DVec3::new(4.0, 3.0, 2.0)).unwrap();
    let a = p.add_symbol("A", shape, anchor).unwrap();
    p.add_material(brick()).unwrap();
    let rule = p.add_rule(a, "paint", 1.0).unwrap();
    let front = p.face_towards(rule, RuleTree::ROOT, DVec3::Z).unwrap();
    p.assign_face_material(rule, RuleTree::ROOT, front, Some(BRICK))
        .unwrap();
    p
}

fn derive(grammar: &Grammar, symbol: &str, generations: u32) -> GrammarMesh {
    let mut state = GrammarState::new(grammar, symbol)
        .unwrap()
        .with_generations(generations);
    state.generate_all().unwrap();
    GrammarMesh::new(&state)
}

/// The corners (position, uv) of the mesh's faces that have material `m`, sorted.
fn corners_of(mesh: &GrammarMesh, m: u32) -> Vec<([f64; 3], [f64; 2])> {
    let mut corners: Vec<_> = mesh
        .parts
        .iter()
        .filter(|p| p.material == Some(m))
        .flat_map(|p| {
            p.positions
                .iter()
                .zip(&p.uvs)
                .map(|(x, uv)| (x.to_array(), uv.to_array()))
        })
        .collect();
    corners.sort_by(|a, b| a.partial_cmp(b).unwrap());
    corners
}

/// Total area of the triangles of material `m`.
fn area_of(mesh: &GrammarMesh, m: u32) -> f64 {
    mesh.parts
        .iter()
        .filter(|p| p.material == Some(m))
        .flat_map(|p| {
            p.triangles.iter().map(|t| {
                let [a, b, c] = t.map(|i| p.positions[i as usize]);
                (b - a).cross(c - a).length() / 2.0
            })
        })
        .sum()
}

#[test]
fn a_front_face_gets_planar_uvs_in_tiles_of_the_material() {
    let grammar = compile(&painted_box()).unwrap();
    let mesh = derive(&grammar, "A", 1);
    // x / 2 m across, y / 0.5 m up, from the world origin.
    assert_eq!(
        corners_of(&mesh, BRICK),
        vec![
            ([0.0, 0.0, 2.0], [0.0, 0.0]),
            ([0.0, 3.0, 2.0], [0.0, 6.0]),
            ([4.0, 0.0, 2.0], [2.0, 0.0]),
            ([4.0, 3.0, 2.0], [2.0, 6.0]),
        ]
    );
    let part = mesh
        .parts
        .iter()
        .find(|p| p.material == Some(BRICK))
        .unwrap();
    assert_eq!(part.name, "terminal");
    assert_eq!(part.color, Color::rgb(1.0, 1.0, 1.0));
    assert_eq!(part.triangles.len(), 2);
    // The other five faces keep the symbol's colour and have no uvs.
    let plain: Vec<_> = mesh.parts.iter().filter(|p| p.material.is_none()).collect();
    assert_eq!(plain.len(), 1);
    assert_eq!(plain[0].triangles.len(), 10);
    assert!(plain[0].uvs.is_empty());
}

#[test]
fn uvs_do_not_depend_on_where_the_face_loop_starts() {
    // The same box anchored a quarter turn round or on another face: its faces are numbered
    // in another order and their loops start at other corners.
    let straight = derive(&compile(&painted_box()).unwrap(), "A", 1);
    for anchor in [Anchor::new(3, 1), Anchor::new(5, 2)] {
        let turned = derive(&compile(&painted_box_anchored(anchor)).unwrap(), "A", 1);
        assert_eq!(corners_of(&turned, BRICK), corners_of(&straight, BRICK));
    }
}

#[test]
fn uvs_follow_the_face_not_the_world_axes_on_other_faces() {
    let mut p = painted_box();
    for (k, direction) in [DVec3::X, -DVec3::Z, DVec3::Y].into_iter().enumerate() {
        let face = p.face_towards(0, RuleTree::ROOT, direction).unwrap();
        let m = p
            .add_material(Material::textured(&format!("M{k}"), "m.png", DVec2::ONE))
            .unwrap();
        p.assign_face_material(0, RuleTree::ROOT, face, Some(m))
            .unwrap();
    }
    let mesh = derive(&compile(&p).unwrap(), "A", 1);
    // +x face: right (seen from outside) is −z, up is y.
    assert_eq!(
        corners_of(&mesh, 1),
        vec![
            ([4.0, 0.0, 0.0], [0.0, 0.0]),
            ([4.0, 0.0, 2.0], [-2.0, 0.0]),
            ([4.0, 3.0, 0.0], [0.0, 3.0]),
            ([4.0, 3.0, 2.0], [-2.0, 3.0]),
        ]
    );
    // −z face: right is −x.
    assert_eq!(corners_of(&mesh, 2)[3], ([4.0, 3.0, 0.0], [-4.0, 3.0]));
    // Top face: u along x, v along −z.
    assert_eq!(corners_of(&mesh, 3)[1], ([0.0, 3.0, 2.0], [0.0, -2.0]));
}

#[test]
fn the_pieces_of_a_painted_face_keep_its_material_in_the_editor_and_at_derivation() {
    let mut p = painted_box();
    let b = p.add_box_symbol("B", DVec3::new(4.0, 3.0, 0.5)).unwrap();
    let rule = 0;
    // Cut a 0.5 slab off the painted front: both parts of the cut keep brick where they touch
    // the front face; the cut's own faces have none.
    let front = p.face_towards(rule, RuleTree::ROOT, DVec3::Z).unwrap();
    let [slab, rest] = p.face_cut(rule, RuleTree::ROOT, front, 0.5).unwrap();
    let tree = &p.rule(rule).unwrap().tree;
    let painted = |id| {
        tree.node(id)
            .unwrap()
            .face_materials
            .iter()
            .filter(|m| **m == Some(BRICK))
            .count()
    };
    assert_eq!((painted(slab), painted(rest)), (1, 0));
    p.assign_facing(rule, slab, b, DVec3::Y, DVec3::Z).unwrap();
    p.assign(rule, rest, Assignment::Epsilon).unwrap();
    // B is cut into three columns; at derivation each inherits brick on its front.
    let columns = p.add_rule(b, "columns", 1.0).unwrap();
    let side = p.face_towards(columns, RuleTree::ROOT, -DVec3::X).unwrap();
    let parts = p.multi_cut(columns, RuleTree::ROOT, side, 2).unwrap();
    assert_eq!(parts.len(), 3);
    let grammar = compile(&p).unwrap();
    let mesh = derive(&grammar, "A", 2);
    let brick_parts: Vec<_> = mesh
        .parts
        .iter()
        .filter(|p| p.material == Some(BRICK))
        .collect();
    assert_eq!(brick_parts.len(), 1);
    assert_eq!(
        brick_parts[0].triangles.len(),
        6,
        "three fronts of two triangles"
    );
    assert!((area_of(&mesh, BRICK) - 12.0).abs() < 1e-12);
    // The pattern runs on across the columns: the uvs are those of the uncut face.
    let corners = corners_of(&mesh, BRICK);
    assert!(
        corners
            .iter()
            .all(|(x, uv)| (uv[0] - x[0] / 2.0).abs() < 1e-12 && (uv[1] - x[1] / 0.5).abs() < 1e-12)
    );
    // A rule's own material overrides the inherited one.
    let glass = p
        .add_material(Material::colored("Glass", Color::rgb(0.0, 0.0, 1.0)))
        .unwrap();
    let front = p.face_towards(columns, parts[1], DVec3::Z).unwrap();
    p.assign_face_material(columns, parts[1], front, Some(glass))
        .unwrap();
    let mesh = derive(&compile(&p).unwrap(), "A", 2);
    assert!((area_of(&mesh, BRICK) - 8.0).abs() < 1e-12);
    assert!((area_of(&mesh, glass) - 4.0).abs() < 1e-12);
}

#[test]
fn painting_a_cut_face_paints_its_pieces() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(4.0, 3.0, 2.0)).unwrap();
    p.add_material(brick()).unwrap();
    let rule = p.add_rule(a, "halves", 1.0).unwrap();
    let side = p.face_towards(rule, RuleTree::ROOT, -DVec3::X).unwrap();
    let halves = p.multi_cut(rule, RuleTree::ROOT, side, 1).unwrap();
    let front = p.face_towards(rule, RuleTree::ROOT, DVec3::Z).unwrap();
    p.assign_face_material(rule, RuleTree::ROOT, front, Some(BRICK))
        .unwrap();
    let tree = &p.rule(rule).unwrap().tree;
    for half in halves {
        let node = tree.node(half).unwrap();
        let f = p.face_towards(rule, half, DVec3::Z).unwrap();
        assert_eq!(node.face_materials[f as usize], Some(BRICK));
        assert_eq!(node.face_materials.iter().flatten().count(), 1);
    }
    let mesh = derive(&compile(&p).unwrap(), "A", 1);
    assert!((area_of(&mesh, BRICK) - 12.0).abs() < 1e-12);
}

/// A 10 × 3 × 8 box `A` whose rule keeps a wall `distance` thick along its front (+z) and drops
/// the rest; with `offset` the thickness is in metres, otherwise a fraction of the prototype.
fn walled(distance: f64, offset: bool) -> Grammar {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(10.0, 3.0, 8.0)).unwrap();
    let rule = p.add_rule(a, "wall", 1.0).unwrap();
    let front = p.face_towards(rule, RuleTree::ROOT, DVec3::Z).unwrap();
    let [_wall, rest] = if offset {
        p.offset_cut(rule, RuleTree::ROOT, front, distance).unwrap()
    } else {
        p.face_cut(rule, RuleTree::ROOT, front, distance).unwrap()
    };
    p.assign(rule, rest, Assignment::Epsilon).unwrap();
    compile(&p).unwrap()
}

/// The prototype box of `grammar`'s first symbol scaled by `scale`.
fn scaled(grammar: &Grammar, scale: DVec3) -> Vec<DVec3> {
    grammar.shapes[0]
        .vertices
        .iter()
        .map(|&v| v * scale)
        .collect()
}

/// The depth (z extent) of the only terminal shape after one generation from `vertices`.
fn wall_depth(grammar: &Grammar, vertices: Vec<DVec3>) -> Result<f64, GenerateError> {
    let mut state = GrammarState::new(grammar, "A")
        .unwrap()
        .with_initial_shape(vertices)
        .unwrap();
    state.generate_all()?;
    assert_eq!(state.terminals().len(), 1);
    let z = state.terminals().vertices(0).iter().map(|v| v.z);
    let (lo, hi) = z.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
        (lo.min(z), hi.max(z))
    });
    Ok(hi - lo)
}

#[test]
fn an_offset_cut_keeps_its_distance_on_shapes_of_other_sizes() {
    let offset = walled(0.3, true);
    let relative = walled(0.3, false);
    for scale in [
        DVec3::ONE,
        DVec3::new(3.0, 1.5, 2.5),
        DVec3::new(0.5, 1.0, 0.25),
    ] {
        let depth = wall_depth(&offset, scaled(&offset, scale)).unwrap();
        assert!((depth - 0.3).abs() < 1e-12, "{scale}: {depth}");
        let depth = wall_depth(&relative, scaled(&relative, scale)).unwrap();
        assert!((depth - 0.3 * scale.z).abs() < 1e-12, "{scale}: {depth}");
    }
    // Sheared (the front leaning back): still 0.3 m from the front face, measured square to it.
    let mut sheared = scaled(&offset, DVec3::ONE);
    for v in &mut sheared {
        v.z += 0.5 * v.y;
    }
    let mut state = GrammarState::new(&offset, "A")
        .unwrap()
        .with_initial_shape(sheared)
        .unwrap();
    state.generate_all().unwrap();
    let wall = state.terminals().vertices(0);
    let (p, n) = (wall[0], DVec3::new(0.0, -0.5, 1.0).normalize());
    let distances: Vec<f64> = wall.iter().map(|&v| n.dot(v - p)).collect();
    let span = distances.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - distances.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!((span - 0.3).abs() < 1e-12, "{span}");
}

#[test]
fn the_brick_houses_blocks_of_two_sizes_have_walls_of_the_same_thickness() {
    let grammar = compile(&demos::brick_house().unwrap()).unwrap();
    let mut state = GrammarState::new(&grammar, "House")
        .unwrap()
        .with_generations(2);
    state.generate_all().unwrap();
    let facade = grammar.symbol_named("Facade").unwrap();
    let walls = state.non_terminals();
    let mut sizes = Vec::new();
    for i in (0..walls.len()).filter(|&i| walls.symbol(i) == facade) {
        let v = walls.vertices(i);
        let (lo, hi) = v
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        let size = hi - lo;
        let thickness = size.x.min(size.z);
        assert!((thickness - demos::BRICK_WALL).abs() < 1e-12, "{size}");
        sizes.push((size.y * 1000.0).round() as i64);
    }
    assert_eq!(walls.len(), 8, "four walls on each of two blocks");
    sizes.sort();
    sizes.dedup();
    // Heights 0.65 × 5 − 0.4 and 0.65 × 7 − 0.4: the wing's and the main block's.
    assert_eq!(sizes, vec![2850, 4150]);
}

#[test]
fn an_offset_past_the_shape_is_an_error_naming_the_rule_and_the_cut() {
    let grammar = walled(0.3, true);
    // 8 m × 0.02 = 0.16 m deep: the wall would stick out of the back.
    let error = wall_depth(&grammar, scaled(&grammar, DVec3::new(1.0, 1.0, 0.02))).unwrap_err();
    assert_eq!(
        error.to_string(),
        "rule 'wall' of symbol 'A', cut 0: a cut 0.3 m inside its face leaves no volume beyond \
         it, the shape being 0.16 m deep there (generation 1)"
    );
    // Exactly as deep as the distance: the part beyond would have no volume.
    let error = wall_depth(&grammar, scaled(&grammar, DVec3::new(1.0, 1.0, 0.3 / 8.0)));
    assert!(
        matches!(error, Err(GenerateError::OffsetPastShape { step: 0, .. })),
        "{error:?}"
    );
    // The state is left as it was before the failed generation.
    let mut state = GrammarState::new(&grammar, "A")
        .unwrap()
        .with_initial_shape(scaled(&grammar, DVec3::new(1.0, 1.0, 0.02)))
        .unwrap();
    state.start();
    assert!(state.next_generation().is_err());
    assert_eq!((state.generation(), state.non_terminals().len()), (0, 1));
    assert!(state.terminals().is_empty());
}

#[test]
fn offset_cuts_need_a_positive_distance_inside_the_shape() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(10.0, 3.0, 8.0)).unwrap();
    let rule = p.add_rule(a, "wall", 1.0).unwrap();
    let front = p.face_towards(rule, RuleTree::ROOT, DVec3::Z).unwrap();
    for bad in [0.0, -1.0, f64::NAN] {
        let e = p.offset_cut(rule, RuleTree::ROOT, front, bad).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("the distance {bad} must be a positive number of metres")
        );
    }
    let e = p.offset_cut(rule, RuleTree::ROOT, front, 9.0).unwrap_err();
    assert!(e.to_string().contains("does not pass through"), "{e}");
    assert_eq!(p.rule(rule).unwrap().tree.nodes().len(), 1);
}

#[test]
fn both_new_actions_undo_and_redo() {
    let mut p = Project::new();
    let a = p.add_box_symbol("A", DVec3::new(10.0, 3.0, 8.0)).unwrap();
    let rule = p.add_rule(a, "wall", 1.0).unwrap();
    let mut editor = Editor::new(p);
    let brick = editor.apply(|p| p.add_material(brick())).unwrap();
    let front = editor
        .project()
        .face_towards(rule, RuleTree::ROOT, DVec3::Z)
        .unwrap();
    let [wall, _] = editor
        .apply(|p| p.offset_cut(rule, RuleTree::ROOT, front, 0.3))
        .unwrap();
    let face = editor.project().face_towards(rule, wall, DVec3::Z).unwrap();
    editor
        .apply(|p| p.assign_face_material(rule, wall, face, Some(brick)))
        .unwrap();
    let material_of = |e: &Editor| {
        e.project()
            .rule(rule)
            .unwrap()
            .tree
            .node(wall)
            .unwrap()
            .face_materials[face as usize]
    };
    let root = |e: &Editor| e.project().rule(rule).unwrap().tree.nodes()[0].clone();
    assert_eq!(material_of(&editor), Some(brick));
    assert!(editor.undo());
    assert_eq!(material_of(&editor), None);
    assert!(editor.undo());
    assert_eq!(root(&editor).kind, NodeKind::Leaf(Assignment::Terminal));
    assert_eq!(root(&editor).offset, None);
    assert!(editor.redo());
    let offset = root(&editor).offset.unwrap();
    assert_eq!((offset.face, offset.distance), (front, 0.3));
    assert!(editor.redo());
    assert_eq!(material_of(&editor), Some(brick));
    // A refused step is not recorded.
    let depth = editor.undo_depth();
    assert!(
        editor
            .apply(|p| p.assign_face_material(rule, wall, face, Some(7)))
            .is_err()
    );
    assert!(
        editor
            .apply(|p| p.assign_face_material(rule, wall, 99, None))
            .is_err()
    );
    assert_eq!(editor.undo_depth(), depth);
}

#[test]
fn materials_are_checked_and_named_once() {
    let mut p = Project::new();
    p.add_material(brick()).unwrap();
    let e = p.add_material(brick()).unwrap_err();
    assert_eq!(e.to_string(), "there is already a material 'Brick'");
    let mut renamed = brick();
    renamed.tile = DVec2::new(1.0, 1.0);
    p.set_material(0, renamed).unwrap();
    assert_eq!(p.materials[0].tile, DVec2::ONE);
    let e = p
        .set_material(0, Material::textured("Brick", "b.png", DVec2::ZERO))
        .unwrap_err();
    assert!(e.to_string().contains("two positive numbers"), "{e}");
    assert_eq!(p.material_named("Brick"), Some(0));
}

#[test]
fn projects_and_grammars_with_materials_and_offsets_round_trip() {
    let project = demos::brick_house().unwrap();
    let text = project.to_json();
    assert!(text.contains("\n  \"version\": 2,\n"));
    assert_eq!(Project::from_json(&text).unwrap(), project);
    let grammar = compile(&project).unwrap();
    assert!(grammar.needs_version_2());
    let json = grammar.to_json();
    assert!(json.contains("\n  \"version\": 2,\n"));
    assert_eq!(Grammar::from_json(&json).unwrap(), grammar);
}
