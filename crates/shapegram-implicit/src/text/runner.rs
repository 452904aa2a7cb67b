//! Running a parsed `.cave` text: its productions applied to a cave, with its limits.

use super::*;

/// A solid under evaluation, with its bonds and primitive count.
struct Value {
    shape: Shape,
    elements: usize,
}

struct Runner<'a> {
    builder: CaveBuilder,
    rng: Rng,
    definitions: &'a [Expr],
    direction: Direction,
    /// Expression nodes evaluated so far, against definitions that use each other many times.
    evaluated: u64,
    /// The production being applied.
    current: Pos,
}

/// Deepest nesting of operations, transforms and names in one production's solid: evaluation and
/// the solid's own walks recurse that deep.
const MAX_NESTING: usize = 128;

/// Most expression nodes one run may evaluate.
const MAX_EVALUATED: u64 = 1_000_000;

impl CaveProgram {
    /// Runs the productions on an empty base; `seed` overrides the text's `seed`.
    pub fn run(&self, seed: Option<u64>) -> Result<CaveRun, TextError> {
        let origin = Pos { line: 1, column: 1 };
        count_productions(&self.statements, 0)?;
        let mut runner = Runner {
            builder: CaveBuilder::new(self.overlap).map_err(|e| origin.wrap(e))?,
            rng: Rng::new(seed.unwrap_or(self.seed)),
            definitions: &self.definitions,
            direction: Direction::PosX,
            evaluated: 0,
            current: origin,
        };
        runner.run(&self.statements)?;
        Ok(CaveRun {
            builder: runner.builder,
        })
    }
}

impl<'a> Runner<'a> {
    fn run(&mut self, statements: &'a [Statement]) -> Result<(), TextError> {
        for statement in statements {
            match statement {
                Statement::Direction(d) => self.direction = *d,
                Statement::Repeat(count, body, _) => {
                    for _ in 0..*count {
                        self.run(body)?;
                    }
                }
                Statement::Production(operation, amount, expr, attach, pos) => {
                    self.current = *pos;
                    let value = self.eval(expr, 0)?;
                    let operation = match operation {
                        Operation::Morph(_) => {
                            let percent = amount.value(&mut self.rng);
                            if !(0.0..=100.0).contains(&percent) {
                                return Err(pos.error(format!(
                                    "invalid morphing parameter {percent}%: expected 0 to 100"
                                )));
                            }
                            Operation::Morph(percent / 100.0)
                        }
                        op => *op,
                    };
                    let attach = attach.unwrap_or(Attach::Bond(self.direction));
                    self.builder
                        .apply(
                            &value.shape,
                            value.elements,
                            operation,
                            attach,
                            &mut self.rng,
                        )
                        .map_err(|e| pos.wrap(e))?;
                }
                Statement::Generate(params, pos) => {
                    grow(&mut self.builder, params, &mut self.rng).map_err(|e| pos.wrap(e))?;
                }
            }
        }
        Ok(())
    }

    fn eval(&mut self, expr: &'a Expr, depth: usize) -> Result<Value, TextError> {
        self.evaluated += 1;
        if self.evaluated > MAX_EVALUATED {
            return Err(self.current.error(format!(
                "the solids are too large: more than {MAX_EVALUATED} parts evaluated"
            )));
        }
        if depth > MAX_NESTING {
            return Err(self.current.error(format!(
                "the solid nests deeper than {MAX_NESTING} operations and names: build it from \
                 fewer, wider parts"
            )));
        }
        // The recursion stays in this frame and the work of each node in a function of its
        // own, so that a frame holds the operands and little else: nesting runs to
        // MAX_NESTING deep on a thread's default stack, in debug builds too.
        match expr {
            Expr::Primitive(kind, args, pos) => self.primitive(kind, args, *pos),
            Expr::Name(index, _) => self.eval(&self.definitions[*index], depth + 1),
            Expr::Binary(op, a, b, _) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                Ok(combined(*op, a, b))
            }
            Expr::Morph(a, b, t, pos) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                let t = t.value(&mut self.rng);
                morphed(a, b, t, *pos)
            }
            Expr::Smooth(kind, a, b, k, pos) => {
                let (a, b) = (self.eval(a, depth + 1)?, self.eval(b, depth + 1)?);
                let k = k.value(&mut self.rng);
                smoothed(kind, a, b, k, *pos)
            }
            Expr::Move(e, v, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let offset = DVec3::from_array(v.map(|n| n.value(&mut self.rng)));
                transformed(inner, *pos, |shape| shape.translate(offset))
            }
            Expr::Rotate(e, axis, degrees, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let degrees = degrees.value(&mut self.rng);
                transformed(inner, *pos, |shape| shape.rotate(*axis, degrees))
            }
            Expr::Scale(e, v, pos) => {
                let inner = self.eval(e, depth + 1)?;
                let scale = DVec3::from_array(v.map(|n| n.value(&mut self.rng)));
                transformed(inner, *pos, |shape| shape.scale(scale))
            }
        }
    }

    /// A primitive with its arguments drawn.
    #[inline(never)]
    fn primitive(&mut self, kind: &str, args: &[Num], pos: Pos) -> Result<Value, TextError> {
        let v: Vec<f64> = args.iter().map(|n| n.value(&mut self.rng)).collect();
        let primitive = match kind {
            "sphere" => Primitive::Sphere { radius: v[0] },
            "box" => Primitive::Cuboid {
                size: DVec3::new(v[0], v[1], v[2]),
            },
            "cylinder" => Primitive::Cylinder {
                radius: v[0],
                height: v[1],
            },
            "cone" => Primitive::Cone {
                radius: v[0],
                height: v[1],
            },
            "pyramid" => Primitive::Pyramid {
                size: DVec3::new(v[0], v[1], v[2]),
            },
            "torus" => Primitive::Torus {
                major: v[0],
                minor: v[1],
            },
            _ => Primitive::Capsule {
                radius: v[0],
                length: v[1],
            },
        };
        Ok(Value {
            shape: Shape::primitive(primitive).map_err(|e| pos.wrap(e))?,
            elements: 1,
        })
    }
}

/// `a + b`, `a - b` or `a & b`.
#[inline(never)]
fn combined(op: char, a: Value, b: Value) -> Value {
    let shape = match op {
        '+' => a.shape.union(&b.shape),
        '-' => a.shape.difference(&b.shape),
        _ => a.shape.intersection(&b.shape),
    };
    Value {
        shape,
        elements: a.elements + b.elements,
    }
}

/// `morph(a, b, t)`.
#[inline(never)]
fn morphed(a: Value, b: Value, t: f64, pos: Pos) -> Result<Value, TextError> {
    Ok(Value {
        shape: a.shape.morph(&b.shape, t).map_err(|e| pos.wrap(e))?,
        elements: a.elements + b.elements,
    })
}

/// `smooth_union(a, b, k)` and its kin; only a union keeps the bonds of both.
#[inline(never)]
fn smoothed(kind: &str, a: Value, b: Value, k: f64, pos: Pos) -> Result<Value, TextError> {
    let solid = match kind {
        "smooth_union" => a.shape.solid.smooth_union(&b.shape.solid, k),
        "smooth_difference" => a.shape.solid.smooth_difference(&b.shape.solid, k),
        _ => a.shape.solid.smooth_intersection(&b.shape.solid, k),
    }
    .map_err(|e| pos.wrap(e))?;
    let mut bonds = a.shape.bonds;
    if kind == "smooth_union" {
        bonds.extend(&b.shape.bonds);
    }
    Ok(Value {
        shape: Shape { solid, bonds },
        elements: a.elements + b.elements,
    })
}

/// A moved, turned or scaled value.
#[inline(never)]
fn transformed(
    inner: Value,
    pos: Pos,
    map: impl FnOnce(&Shape) -> crate::Result<Shape>,
) -> Result<Value, TextError> {
    Ok(Value {
        shape: map(&inner.shape).map_err(|e| pos.wrap(e))?,
        elements: inner.elements,
    })
}

/// Adds up the productions `statements` apply (after `before` others), failing where the total
/// passes [`MAX_PRODUCTIONS`]: there are no conditions, so the count is known before running.
fn count_productions(statements: &[Statement], before: u64) -> Result<u64, TextError> {
    let mut total = before;
    let too_many = |pos: Pos| pos.error(format!("more than {MAX_PRODUCTIONS} productions"));
    for statement in statements {
        let (added, pos) = match statement {
            Statement::Production(.., pos) => (1, *pos),
            Statement::Generate(params, pos) => {
                (u64::from(params.classic) + u64::from(params.morphic), *pos)
            }
            Statement::Repeat(count, body, pos) => {
                let once = count_productions(body, total)? - total;
                (once.saturating_mul(*count), *pos)
            }
            Statement::Direction(_) => (0, Pos { line: 0, column: 0 }),
        };
        total = total.saturating_add(added);
        if total > MAX_PRODUCTIONS {
            return Err(too_many(pos));
        }
    }
    Ok(total)
}
