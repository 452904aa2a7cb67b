//! The thesis's demonstration grammars, authored through the API the way a user cuts them in
//! the editor: the Mayan pyramid of the user tasks (4.1), the house grammar of 4.3 and the
//! spiralling steps of Figures 31–34; and a brick house past the thesis, with walls of constant
//! thickness and tiled materials. `examples/topo_*.sgproj.json` and `examples/topo_*.grammar`
//! are these projects saved and compiled.

use shapegram_geom::{Color, DVec2, DVec3};

use crate::anchor::Anchor;
use crate::cut::CutPlane;
use crate::material::Material;
use crate::polyhedron::Index;
use crate::project::{Assignment, EditError, NodeId, Project, RuleTree};

const X: DVec3 = DVec3::X;
const Y: DVec3 = DVec3::Y;
const Z: DVec3 = DVec3::Z;

/// The house's wall colour, also used for the gable ends of its roof.
const WALL_COLOR: &str = "#e6dcc6";

/// Shorthands over [`Project`] for writing grammars as code.
struct Author {
    project: Project,
}

impl Author {
    fn new() -> Self {
        Self {
            project: Project::new(),
        }
    }

    /// A box symbol, optionally coloured.
    fn symbol(&mut self, name: &str, size: DVec3, color: Option<&str>) -> Result<Index, EditError> {
        let symbol = self.project.add_box_symbol(name, size)?;
        self.project
            .set_color(symbol, color.and_then(Color::from_hex))?;
        Ok(symbol)
    }

    fn named(&self, name: &str) -> Index {
        self.project
            .symbol_named(name)
            .expect("demo symbols are declared before use")
    }

    fn rule(&mut self, symbol: &str, name: &str, weight: f64) -> Result<Index, EditError> {
        self.project.add_rule(self.named(symbol), name, weight)
    }

    /// Assigns `symbol` upright, its front along `front`.
    fn put_facing(
        &mut self,
        rule: Index,
        leaf: NodeId,
        symbol: &str,
        front: DVec3,
    ) -> Result<(), EditError> {
        let symbol = self.named(symbol);
        self.project
            .assign_facing(rule, leaf, symbol, Y, front)
            .map(|_| ())
    }

    /// Assigns `symbol` upright, facing +z.
    fn put(&mut self, rule: Index, leaf: NodeId, symbol: &str) -> Result<(), EditError> {
        self.put_facing(rule, leaf, symbol, Z)
    }

    fn epsilon(&mut self, rule: Index, leaf: NodeId) -> Result<(), EditError> {
        self.project.assign(rule, leaf, Assignment::Epsilon)
    }

    fn face(&self, rule: Index, leaf: NodeId, direction: DVec3) -> Result<Index, EditError> {
        self.project.face_towards(rule, leaf, direction)
    }

    /// Face cut `distance` inside the face towards `direction`: `[slice, rest]`.
    fn slice(
        &mut self,
        rule: Index,
        leaf: NodeId,
        direction: DVec3,
        distance: f64,
    ) -> Result<[NodeId; 2], EditError> {
        let face = self.face(rule, leaf, direction)?;
        self.project.face_cut(rule, leaf, face, distance)
    }

    /// Prism cut at `fraction` from the face towards `direction`: `[near, rest]`.
    fn split(
        &mut self,
        rule: Index,
        leaf: NodeId,
        direction: DVec3,
        fraction: f64,
    ) -> Result<[NodeId; 2], EditError> {
        let face = self.face(rule, leaf, direction)?;
        self.project.prism_cut(rule, leaf, face, fraction, None)
    }

    /// Symmetric three-part cut from the face towards `direction`.
    fn thirds(
        &mut self,
        rule: Index,
        leaf: NodeId,
        direction: DVec3,
        margin: f64,
    ) -> Result<[NodeId; 3], EditError> {
        let face = self.face(rule, leaf, direction)?;
        self.project.symmetric_cut(rule, leaf, face, margin)
    }

    fn multi(
        &mut self,
        rule: Index,
        leaf: NodeId,
        direction: DVec3,
        cuts: usize,
    ) -> Result<Vec<NodeId>, EditError> {
        let face = self.face(rule, leaf, direction)?;
        self.project.multi_cut(rule, leaf, face, cuts)
    }

    /// Lower and upper corner of a sub-shape's bounding box.
    fn bounds(&self, rule: Index, leaf: NodeId) -> Result<(DVec3, DVec3), EditError> {
        let shape = &self.project.rule(rule)?.tree.node(leaf)?.shape;
        Ok(shape
            .positions()
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            }))
    }

    /// The centre height of a sub-shape.
    fn height_of(&self, rule: Index, leaf: NodeId) -> Result<f64, EditError> {
        Ok(self.project.rule(rule)?.tree.node(leaf)?.shape.center().y)
    }

    /// The two parts of a cut as `(larger, smaller)` by volume.
    fn larger(&self, rule: Index, parts: [NodeId; 2]) -> Result<(NodeId, NodeId), EditError> {
        let tree = &self.project.rule(rule)?.tree;
        let [p, q] = parts;
        Ok(
            if tree.node(p)?.shape.volume() >= tree.node(q)?.shape.volume() {
                (p, q)
            } else {
                (q, p)
            },
        )
    }

    /// 3-point cut of one sub-shape: returns `[lower, upper]` by centre height.
    fn wedge(&mut self, rule: Index, points: [DVec3; 3]) -> Result<[NodeId; 2], EditError> {
        let cuts = self.project.three_point_cut(rule, points)?;
        let [a, b] = cuts[0];
        Ok(if self.height_of(rule, a)? <= self.height_of(rule, b)? {
            [a, b]
        } else {
            [b, a]
        })
    }
}

/// The spiralling-steps grammar of Figures 31–34: a cube `A` becomes a step (the bottom quarter)
/// and, on half of the rest, a smaller `A`. With `turned`, the new `A` is anchored a quarter
/// turn round (its front facing +x instead of +z), so each generation turns the stair by 90°.
pub fn spiral_steps(turned: bool) -> Result<Project, EditError> {
    let mut a = Author::new();
    a.symbol("A", DVec3::splat(4.0), None)?;
    a.symbol("Step", DVec3::new(4.0, 1.0, 4.0), Some("#c8a878"))?;
    let rule = a.rule("A", "step", 1.0)?;
    let [upper, step] = a.slice(rule, RuleTree::ROOT, Y, 3.0)?;
    a.put(rule, step, "Step")?;
    let [left, right] =
        a.project
            .plane_cut(rule, upper, CutPlane::new(DVec3::new(2.0, 0.0, 0.0), X))?;
    a.epsilon(rule, left)?;
    a.put_facing(rule, right, "A", if turned { X } else { Z })?;
    Ok(a.project)
}

/// The Mayan pyramid of the thesis's user tasks (4.1): a recursive tier rule. A `Pyramid` box
/// becomes a stone slab (its bottom quarter), a smaller `Pyramid` centred on it (10 % margins
/// all round, anchored like its parent) and a stair ramp in the middle of the front margin.
pub fn mayan_pyramid() -> Result<Project, EditError> {
    let mut a = Author::new();
    a.symbol("Pyramid", DVec3::new(16.0, 8.0, 16.0), Some("#c9b48a"))?;
    a.symbol("Stone", DVec3::new(16.0, 2.0, 16.0), Some("#b39d74"))?;
    let rule = a.rule("Pyramid", "tier", 1.0)?;
    let [slab, rest] = a.split(rule, RuleTree::ROOT, -Y, 0.25)?;
    a.put(rule, slab, "Stone")?;
    let [left, middle, right] = a.thirds(rule, rest, -X, 0.1)?;
    a.epsilon(rule, left)?;
    a.epsilon(rule, right)?;
    let [back, centre, front] = a.thirds(rule, middle, -Z, 0.1)?;
    a.epsilon(rule, back)?;
    a.put(rule, centre, "Pyramid")?;
    let [side, stairs, other_side] = a.thirds(rule, front, -X, 0.4)?;
    a.epsilon(rule, side)?;
    a.epsilon(rule, other_side)?;
    let [low, high] = a.split(rule, stairs, -Y, 0.25)?;
    a.epsilon(rule, high)?;
    let (lo, hi) = a.bounds(rule, low)?;
    let [ramp, air] = a.wedge(
        rule,
        [
            DVec3::new(lo.x, hi.y, lo.z),
            DVec3::new(hi.x, hi.y, lo.z),
            DVec3::new(lo.x, lo.y, hi.z),
        ],
    )?;
    a.epsilon(rule, air)?;
    let stairs = a
        .project
        .symbol_from_leaf(rule, ramp, "Stairs", Anchor::new(0, 0))?;
    a.project.set_color(stairs, Color::from_hex("#8f7a55"))?;
    Ok(a.project)
}

/// The house grammar of thesis 4.3: one- or two-storey hollow houses with a door on the ground
/// floor (a wide door alone, or a smaller door between windows), walls of four-pane windows and
/// a gable or pyramid roof. 15 non-terminal symbols and 18 rules; three symbols have two rules
/// each, which makes eight kinds of house. Eight generations derive it completely.
pub fn house() -> Result<Project, EditError> {
    let mut a = Author::new();
    let wall = DVec3::new(10.0, 3.3, 0.3);
    for (name, size, color) in [
        ("House", DVec3::new(10.0, 9.0, 8.0), None),
        ("GroundFloor", DVec3::new(10.0, 3.5, 8.0), None),
        ("UpperFloor", DVec3::new(10.0, 3.0, 8.0), None),
        ("Roof", DVec3::new(10.0, 2.5, 8.0), None),
        ("WindowWall", wall, None),
        ("DoorWall", wall, None),
        ("DoorWindowWall", wall, None),
        ("WindowBay", DVec3::new(5.0, 3.3, 0.3), None),
        ("DoorBay", DVec3::new(3.3, 3.3, 0.3), None),
        ("WindowColumn", DVec3::new(2.0, 3.3, 0.3), None),
        ("DoorColumn", DVec3::new(4.0, 3.3, 0.3), None),
        ("Window", DVec3::new(2.0, 1.65, 0.3), None),
        ("Door", DVec3::new(4.0, 2.5, 0.3), None),
        ("Panes", DVec3::new(1.7, 1.4, 0.3), None),
        ("PaneColumn", DVec3::new(0.8, 1.4, 0.3), None),
        ("Wall", wall, Some(WALL_COLOR)),
        ("Floor", DVec3::new(10.0, 0.2, 8.0), Some("#8a8580")),
        ("Frame", DVec3::new(0.1, 1.0, 0.3), Some("#f6f4ee")),
        ("Glass", DVec3::new(1.0, 1.0, 0.1), Some("#5b8db8")),
        ("DoorPanel", DVec3::new(1.0, 2.0, 0.2), Some("#7a4a2a")),
    ] {
        a.symbol(name, size, color)?;
    }

    for (name, storeys) in [("one storey", 1), ("two storeys", 2)] {
        let rule = a.rule("House", name, 1.0)?;
        let [ground, rest] = a.split(rule, RuleTree::ROOT, -Y, 3.5 / 9.0)?;
        a.put(rule, ground, "GroundFloor")?;
        if storeys == 1 {
            let [roof, air] = a.split(rule, rest, -Y, 2.5 / 5.5)?;
            a.put(rule, roof, "Roof")?;
            a.epsilon(rule, air)?;
        } else {
            let [upper, roof] = a.split(rule, rest, -Y, 3.0 / 5.5)?;
            a.put(rule, upper, "UpperFloor")?;
            a.put(rule, roof, "Roof")?;
        }
    }
    for (symbol, name, front) in [
        ("GroundFloor", "wide door", "DoorWall"),
        ("GroundFloor", "door and windows", "DoorWindowWall"),
        ("UpperFloor", "windows all round", "WindowWall"),
    ] {
        let rule = a.rule(symbol, name, 1.0)?;
        hollow_storey(&mut a, rule, front)?;
    }
    gable_roof(&mut a)?;
    pyramid_roof(&mut a)?;

    let rule = a.rule("WindowWall", "two bays", 1.0)?;
    for bay in a.multi(rule, RuleTree::ROOT, -X, 1)? {
        a.put(rule, bay, "WindowBay")?;
    }
    let rule = a.rule("DoorWindowWall", "window door window", 1.0)?;
    let bays = a.multi(rule, RuleTree::ROOT, -X, 2)?;
    for (bay, symbol) in bays.into_iter().zip(["WindowBay", "DoorBay", "WindowBay"]) {
        a.put(rule, bay, symbol)?;
    }
    for (symbol, name, direction, margin, middle) in [
        ("DoorWall", "centred door", -X, 0.3, "DoorColumn"),
        (
            "WindowBay",
            "centred window column",
            -X,
            0.3,
            "WindowColumn",
        ),
        ("DoorBay", "centred door column", -X, 0.25, "DoorColumn"),
        ("WindowColumn", "sill and lintel", -Y, 0.25, "Window"),
    ] {
        let rule = a.rule(symbol, name, 1.0)?;
        let [one, centre, other] = a.thirds(rule, RuleTree::ROOT, direction, margin)?;
        a.put(rule, one, "Wall")?;
        a.put(rule, centre, middle)?;
        a.put(rule, other, "Wall")?;
    }
    let rule = a.rule("DoorColumn", "door and lintel", 1.0)?;
    let [door, lintel] = a.split(rule, RuleTree::ROOT, -Y, 0.75)?;
    a.put(rule, door, "Door")?;
    a.put(rule, lintel, "Wall")?;

    let rule = a.rule("Window", "frame", 1.0)?;
    let [left, middle, right] = a.thirds(rule, RuleTree::ROOT, -X, 0.08)?;
    let [bottom, panes, top] = a.thirds(rule, middle, -Y, 0.08)?;
    for frame in [left, right, bottom, top] {
        a.put(rule, frame, "Frame")?;
    }
    a.put(rule, panes, "Panes")?;
    let rule = a.rule("Panes", "vertical mullion", 1.0)?;
    let [left, mullion, right] = a.thirds(rule, RuleTree::ROOT, -X, 0.47)?;
    a.put(rule, left, "PaneColumn")?;
    a.put(rule, mullion, "Frame")?;
    a.put(rule, right, "PaneColumn")?;
    let rule = a.rule("PaneColumn", "transom and glass", 1.0)?;
    let [lower, transom, upper] = a.thirds(rule, RuleTree::ROOT, -Y, 0.47)?;
    a.put(rule, transom, "Frame")?;
    for pane in [lower, upper] {
        recessed(&mut a, rule, pane, 0.2, "Glass")?;
    }
    let rule = a.rule("Door", "frame and panel", 1.0)?;
    let [left, middle, right] = a.thirds(rule, RuleTree::ROOT, -X, 0.06)?;
    let [panel, top] = a.split(rule, middle, -Y, 0.95)?;
    for frame in [left, right, top] {
        a.put(rule, frame, "Frame")?;
    }
    recessed(&mut a, rule, panel, 0.1, "DoorPanel")?;
    Ok(a.project)
}

/// How thick the brick house's walls are, in metres, on blocks of every size.
pub const BRICK_WALL: f64 = 0.3;

/// A house of brick past the thesis: a main block and a lower wing, both `Block`s of their own
/// size, whose one rule cuts a stone plinth, four walls [`BRICK_WALL`] metres thick (offset
/// cuts: the same thickness on both blocks) and a gable roof of tiles; each wall is a `Facade`
/// with a recessed window. The outer faces are painted brick before the walls are cut, so the
/// walls keep it, and the facades' pieces inherit it from their wall when derived.
pub fn brick_house() -> Result<Project, EditError> {
    let mut a = Author::new();
    let brick = a.project.add_material(Material::textured(
        "Brick",
        "textures/brick.png",
        DVec2::new(1.2, 0.6),
    ))?;
    let mut tiles = Material::textured("RoofTiles", "textures/tiles.png", DVec2::splat(0.8));
    tiles.color = Color::from_hex("#c0624a");
    let tiles = a.project.add_material(tiles)?;
    let stone = a.project.add_material(Material::colored(
        "Stone",
        Color::from_hex("#8c877f").unwrap_or_default(),
    ))?;
    let glass = a.project.add_material(Material::colored(
        "Glass",
        Color::from_hex("#5b8db8").unwrap_or_default(),
    ))?;
    a.symbol("House", DVec3::new(14.0, 7.0, 8.0), None)?;
    a.symbol("Block", DVec3::new(8.0, 6.0, 8.0), None)?;
    a.symbol("Facade", DVec3::new(8.0, 3.6, BRICK_WALL), None)?;

    let rule = a.rule("House", "main block and wing", 1.0)?;
    let [main, wing] = a.split(rule, RuleTree::ROOT, -X, 0.6)?;
    a.put(rule, main, "Block")?;
    let [wing, air] = a.split(rule, wing, -Y, 5.0 / 7.0)?;
    a.put(rule, wing, "Block")?;
    a.epsilon(rule, air)?;

    let rule = a.rule("Block", "walls and roof", 1.0)?;
    let [body, roof] = a.split(rule, RuleTree::ROOT, -Y, 0.65)?;
    // The roof first: its cuts would cross no other sub-shape, but the plinth is cuttable.
    let roof = gable_cuts(&mut a, rule, roof)?;
    for face in 0..a.project.rule(rule)?.tree.node(roof)?.shape.face_count() {
        let normal = a
            .project
            .rule(rule)?
            .tree
            .node(roof)?
            .shape
            .face_normal(face);
        let material = if normal.x.abs() > 0.5 {
            brick
        } else if normal.y > 0.1 {
            tiles
        } else {
            stone
        };
        a.project
            .assign_face_material(rule, roof, face, Some(material))?;
    }
    for side in [X, -X, Z, -Z] {
        let face = a.face(rule, body, side)?;
        a.project
            .assign_face_material(rule, body, face, Some(brick))?;
    }
    let face = a.face(rule, body, -Y)?;
    let [plinth, rest] = a.project.offset_cut(rule, body, face, 0.4)?;
    for side in [X, -X, Z, -Z] {
        let face = a.face(rule, plinth, side)?;
        a.project
            .assign_face_material(rule, plinth, face, Some(stone))?;
    }
    let mut rest = rest;
    for side in [Z, -Z, -X, X] {
        let face = a.face(rule, rest, side)?;
        let [wall, inside] = a.project.offset_cut(rule, rest, face, BRICK_WALL)?;
        a.put_facing(rule, wall, "Facade", side)?;
        rest = inside;
    }
    a.epsilon(rule, rest)?;

    let rule = a.rule("Facade", "recessed window", 1.0)?;
    let [_, middle, _] = a.thirds(rule, RuleTree::ROOT, -X, 0.35)?;
    let [_, window, _] = a.thirds(rule, middle, -Y, 0.3)?;
    let face = a.face(rule, window, Z)?;
    let [recess, pane] = a.project.offset_cut(rule, window, face, 0.12)?;
    a.epsilon(rule, recess)?;
    let face = a.face(rule, pane, Z)?;
    a.project
        .assign_face_material(rule, pane, face, Some(glass))?;
    Ok(a.project)
}

/// Cuts the front and back slopes off sub-shape `leaf` (a box), ridge along x; returns the
/// prism left.
fn gable_cuts(a: &mut Author, rule: Index, leaf: NodeId) -> Result<NodeId, EditError> {
    let (lo, hi) = a.bounds(rule, leaf)?;
    let ridge_z = (lo.z + hi.z) / 2.0;
    let mut body = leaf;
    for z in [lo.z, hi.z] {
        let cuts = a.project.three_point_cut(
            rule,
            [
                DVec3::new(lo.x, lo.y, z),
                DVec3::new(hi.x, lo.y, z),
                DVec3::new(lo.x, hi.y, ridge_z),
            ],
        )?;
        let (keep, drop) = a.larger(rule, cuts[0])?;
        a.epsilon(rule, drop)?;
        body = keep;
    }
    Ok(body)
}

/// A storey with a floor slab, four walls 0.3 thick (`front` at +z, window walls elsewhere)
/// and an empty inside.
fn hollow_storey(a: &mut Author, rule: Index, front: &str) -> Result<(), EditError> {
    let [floor, rest] = a.slice(rule, RuleTree::ROOT, -Y, 0.2)?;
    a.put(rule, floor, "Floor")?;
    let [front_wall, rest] = a.slice(rule, rest, Z, 0.3)?;
    a.put_facing(rule, front_wall, front, Z)?;
    let [back_wall, rest] = a.slice(rule, rest, -Z, 0.3)?;
    a.put_facing(rule, back_wall, "WindowWall", -Z)?;
    let [left_wall, rest] = a.slice(rule, rest, -X, 0.3)?;
    a.put_facing(rule, left_wall, "WindowWall", -X)?;
    let [right_wall, inside] = a.slice(rule, rest, X, 0.3)?;
    a.put_facing(rule, right_wall, "WindowWall", X)?;
    a.epsilon(rule, inside)
}

/// Sets a pane back from the front face by `depth` (the slice in front is removed).
fn recessed(
    a: &mut Author,
    rule: Index,
    leaf: NodeId,
    depth: f64,
    symbol: &str,
) -> Result<(), EditError> {
    let [front, back] = a.slice(rule, leaf, Z, depth)?;
    a.epsilon(rule, front)?;
    a.put(rule, back, symbol)
}

/// The roof box cut by two 3-point cuts into a triangular prism, ridge along x, its gable ends
/// coloured as wall.
fn gable_roof(a: &mut Author) -> Result<Index, EditError> {
    let rule = a.rule("Roof", "gable", 1.0)?;
    let body = gable_cuts(a, rule, RuleTree::ROOT)?;
    let roof = a
        .project
        .symbol_from_leaf(rule, body, "GableRoof", Anchor::new(0, 0))?;
    a.project.set_color(roof, Color::from_hex("#a63d2f"))?;
    // The triangular gable ends are wall, not roof tiles.
    let shape = a.project.symbol(roof)?.shape.clone();
    for face in 0..shape.face_count() {
        if shape.face_normal(face).x.abs() > 0.5 {
            a.project
                .set_face_color(roof, face, Color::from_hex(WALL_COLOR))?;
        }
    }
    Ok(rule)
}

/// The roof box cut by four 3-point cuts into a pyramid.
fn pyramid_roof(a: &mut Author) -> Result<Index, EditError> {
    let rule = a.rule("Roof", "pyramid", 1.0)?;
    let body = gable_cuts(a, rule, RuleTree::ROOT)?;
    let (lo, hi) = a.bounds(rule, body)?;
    let apex = DVec3::new((lo.x + hi.x) / 2.0, hi.y, (lo.z + hi.z) / 2.0);
    let mut body = body;
    for x in [lo.x, hi.x] {
        let cuts = a.project.three_point_cut(
            rule,
            [DVec3::new(x, lo.y, lo.z), DVec3::new(x, lo.y, hi.z), apex],
        )?;
        let (keep, drop) = a.larger(rule, cuts[0])?;
        a.epsilon(rule, drop)?;
        body = keep;
    }
    let roof = a
        .project
        .symbol_from_leaf(rule, body, "PyramidRoof", Anchor::new(0, 0))?;
    a.project.set_color(roof, Color::from_hex("#8a3324"))?;
    Ok(rule)
}
