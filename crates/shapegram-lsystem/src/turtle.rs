//! The turtle: a derived word read as drawing commands (ABOP §1.2 and §1.5).
//!
//! The turtle starts at the origin heading up (+y) with its left side towards −x and its up
//! vector towards the viewer (+z), so 2D systems draw in the xy-plane and stand upright in a
//! glTF scene. Angles are in degrees; a command with a parameter uses it instead of the
//! setting (`F(2)` steps 2, `+(30)` turns 30°).
//!
//! | symbol | command |
//! | --- | --- |
//! | `F` `G` (and `draw:` symbols) | move forward, drawing a line |
//! | `f` (and `move:` symbols) | move forward without drawing |
//! | `+` `-` | turn left / right (about the up vector) |
//! | `&` `^` | pitch down / up (about the left vector) |
//! | `\` `/` | roll left / right (about the heading) |
//! | `\|` | turn around |
//! | `$` | roll until the left vector is horizontal |
//! | `[` `]` | push / pop the turtle state |
//! | `!` | `!(w)` sets the width; `!` multiplies it by `width-factor` |
//! | `'` | `'(i)` sets the colour index; `'` adds one |
//! | `{` `.` `}` | start a polygon, record a vertex, close the polygon |
//!
//! Inside `{ }` moves draw nothing; the polygon's vertices are the positions recorded by `.`,
//! or, when a polygon has no `.`, its start and the position after every move. Every other
//! symbol is ignored by the turtle.

use glam::DVec3;

use crate::system::{LSystem, Settings};
use crate::word::Word;

/// A drawn line: connected segments with a width each, in one colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// The turtle's positions; segment `k` runs from `points[k]` to `points[k + 1]`.
    pub points: Vec<DVec3>,
    /// The width of each segment (one fewer than `points`).
    pub widths: Vec<f64>,
    /// Index into the palette.
    pub color: usize,
}

/// A filled polygon (`{ … }`), such as a leaf.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// Its vertices in order.
    pub points: Vec<DVec3>,
    /// Index into the palette.
    pub color: usize,
}

/// What the turtle drew.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    /// Lines, in the order they were started.
    pub strokes: Vec<Stroke>,
    /// Polygons, in the order they were closed.
    pub polygons: Vec<Polygon>,
    /// Where the turtle ended.
    pub end: DVec3,
}

impl Drawing {
    /// The number of drawn segments.
    pub fn segment_count(&self) -> usize {
        self.strokes.iter().map(|s| s.widths.len()).sum()
    }

    /// All points of strokes and polygons.
    pub fn points(&self) -> impl Iterator<Item = DVec3> + '_ {
        self.strokes
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .chain(self.polygons.iter().flat_map(|p| p.points.iter().copied()))
    }
}

/// What a symbol makes the turtle do.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Command {
    Nothing,
    Forward { draw: bool },
    Turn,
    Pitch,
    Roll,
    TurnAround,
    Level,
    Push,
    Pop,
    Width,
    Color,
    PolygonStart,
    Vertex,
    PolygonEnd,
}

impl Command {
    /// The command of a symbol name, with `+`, `&` and `\` positive and their partners negative.
    fn of(name: char, settings: &Settings) -> (Self, f64) {
        match name {
            'F' | 'G' => (Self::Forward { draw: true }, 1.0),
            'f' => (Self::Forward { draw: false }, 1.0),
            c if settings.draw.contains(&c) => (Self::Forward { draw: true }, 1.0),
            c if settings.moves.contains(&c) => (Self::Forward { draw: false }, 1.0),
            '+' => (Self::Turn, 1.0),
            '-' => (Self::Turn, -1.0),
            '&' => (Self::Pitch, 1.0),
            '^' => (Self::Pitch, -1.0),
            '\\' => (Self::Roll, 1.0),
            '/' => (Self::Roll, -1.0),
            '|' => (Self::TurnAround, 1.0),
            '$' => (Self::Level, 1.0),
            '[' => (Self::Push, 1.0),
            ']' => (Self::Pop, 1.0),
            '!' => (Self::Width, 1.0),
            '\'' => (Self::Color, 1.0),
            '{' => (Self::PolygonStart, 1.0),
            '.' => (Self::Vertex, 1.0),
            '}' => (Self::PolygonEnd, 1.0),
            _ => (Self::Nothing, 1.0),
        }
    }
}

/// The turtle's state, saved by `[` and restored by `]`.
#[derive(Clone, Copy, Debug)]
struct State {
    position: DVec3,
    heading: DVec3,
    left: DVec3,
    up: DVec3,
    width: f64,
    color: usize,
    /// The stroke that a drawing move extends, if it can be extended.
    stroke: Option<usize>,
}

/// A polygon being recorded.
struct OpenPolygon {
    explicit: Vec<DVec3>,
    implicit: Vec<DVec3>,
    color: usize,
}

/// `a` turned towards `b` by `degrees` (and `b` away from `a`), both rotated in their plane.
fn rotate(a: &mut DVec3, b: &mut DVec3, (sin, cos): (f64, f64)) {
    let (x, y) = (*a, *b);
    *a = x * cos + y * sin;
    *b = y * cos - x * sin;
}

/// Interprets `word` (derived from `system`) with the turtle.
pub fn interpret(system: &LSystem, word: &Word) -> Drawing {
    let settings = &system.settings;
    let commands: Vec<(Command, f64)> = system
        .alphabet
        .symbols()
        .iter()
        .map(|s| Command::of(s.name, settings))
        .collect();
    let arities: Vec<usize> = system
        .alphabet
        .symbols()
        .iter()
        .map(|s| s.arity as usize)
        .collect();
    let default_turn = settings.angle.to_radians().sin_cos();
    let mut state = State {
        position: DVec3::ZERO,
        heading: DVec3::Y,
        left: DVec3::NEG_X,
        up: DVec3::Z,
        width: settings.width,
        color: 0,
        stroke: None,
    };
    let mut stack: Vec<State> = Vec::new();
    let mut polygons: Vec<OpenPolygon> = Vec::new();
    // Every stroke starts with a drawing move, so there are at most as many strokes as those:
    // a branching word of a million segments makes hundreds of thousands of strokes, which
    // would otherwise be copied as their list grows.
    let draws = word
        .symbols
        .iter()
        .filter(|&&id| commands[id as usize].0 == Command::Forward { draw: true })
        .count();
    let mut drawing = Drawing {
        strokes: Vec::with_capacity(draws),
        ..Drawing::default()
    };
    let mut p = 0;
    for &id in &word.symbols {
        let arity = arities[id as usize];
        let param = (arity > 0).then(|| word.params[p]);
        p += arity;
        let (command, sign) = commands[id as usize];
        let turn = || match param {
            Some(degrees) => (sign * degrees).to_radians().sin_cos(),
            None => (sign * default_turn.0, default_turn.1),
        };
        match command {
            Command::Nothing => {}
            Command::Forward { draw } => {
                let length = param.unwrap_or(settings.step);
                let start = state.position;
                state.position += state.heading * length;
                // A step too short to register, or one that leaves the finite numbers, draws
                // nothing: it would only make degenerate geometry.
                let drawable = (state.position - start).length_squared() > 0.0
                    && state.position.is_finite()
                    && state.width > 0.0;
                if let Some(polygon) = polygons.last_mut() {
                    polygon.implicit.push(state.position);
                    state.stroke = None;
                } else if draw && drawable {
                    let index = *state.stroke.get_or_insert_with(|| {
                        // Room for a few segments from the start: most strokes of a
                        // branching word are short, and growing from one point reallocates.
                        let mut points = Vec::with_capacity(4);
                        points.push(start);
                        drawing.strokes.push(Stroke {
                            points,
                            widths: Vec::with_capacity(3),
                            color: state.color,
                        });
                        drawing.strokes.len() - 1
                    });
                    let stroke = &mut drawing.strokes[index];
                    stroke.points.push(state.position);
                    stroke.widths.push(state.width);
                } else {
                    state.stroke = None;
                }
            }
            Command::Turn => rotate(&mut state.heading, &mut state.left, turn()),
            Command::Pitch => {
                let (sin, cos) = turn();
                rotate(&mut state.heading, &mut state.up, (-sin, cos));
            }
            Command::Roll => rotate(&mut state.left, &mut state.up, turn()),
            Command::TurnAround => {
                state.heading = -state.heading;
                state.left = -state.left;
            }
            Command::Level => {
                let left = DVec3::Y.cross(state.heading);
                if left.length_squared() > 1e-18 {
                    state.left = left.normalize();
                    state.up = state.heading.cross(state.left);
                }
            }
            Command::Push => {
                stack.push(state);
                state.stroke = None;
            }
            Command::Pop => {
                if let Some(saved) = stack.pop() {
                    state = saved;
                }
            }
            Command::Width => match param {
                Some(width) => state.width = width,
                None => state.width *= settings.width_factor,
            },
            Command::Color => {
                state.color = match param {
                    Some(index) => index.round().max(0.0).min(u32::MAX as f64) as usize,
                    None => state.color + 1,
                };
                state.stroke = None;
            }
            Command::PolygonStart => polygons.push(OpenPolygon {
                explicit: Vec::new(),
                implicit: vec![state.position],
                color: state.color,
            }),
            Command::Vertex => {
                if let Some(polygon) = polygons.last_mut() {
                    polygon.explicit.push(state.position);
                }
            }
            Command::PolygonEnd => {
                if let Some(polygon) = polygons.pop() {
                    let points = if polygon.explicit.is_empty() {
                        polygon.implicit
                    } else {
                        polygon.explicit
                    };
                    drawing.polygons.push(Polygon {
                        points,
                        color: polygon.color,
                    });
                }
            }
        }
    }
    drawing.end = state.position;
    drawing
}
