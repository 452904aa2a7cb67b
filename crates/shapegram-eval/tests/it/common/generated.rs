//! Generated kinematic grammars: a chain of rules, each one operation whose successors are
//! later rules, for property tests.

use proptest::prelude::*;

/// One rule's body; `next` picks later rules (or a leaf) for its successors.
#[derive(Clone, Debug)]
pub enum Body {
    Split {
        axis: usize,
        kind: usize,
        parts: Vec<u8>,
        repeat: bool,
    },
    Comp(Vec<u8>),
    Joint(u8),
    Pose(u8),
    /// Reports a constant drawn at random once per lot and prints a random number.
    Report(u8),
    Nil,
    Leaf,
}

pub fn body() -> impl Strategy<Value = Body> {
    let next = || prop::collection::vec(any::<u8>(), 1..4);
    prop_oneof![
        (0..3usize, 0..3usize, next(), any::<bool>()).prop_map(|(axis, kind, parts, repeat)| {
            Body::Split {
                axis,
                kind,
                parts,
                repeat,
            }
        }),
        next().prop_map(Body::Comp),
        any::<u8>().prop_map(Body::Joint),
        any::<u8>().prop_map(Body::Pose),
        any::<u8>().prop_map(Body::Report),
        Just(Body::Nil),
        Just(Body::Leaf),
    ]
}

/// The successor of rule `i` picked by `n`: a later rule, or a leaf.
fn successor(i: usize, rules: usize, n: u8) -> String {
    let j = i + 1 + usize::from(n) % (rules - i);
    if j >= rules {
        "Leaf.".into()
    } else {
        format!("R{j}")
    }
}

pub fn grammar(bodies: &[Body]) -> String {
    let rules = bodies.len();
    let mut text = String::from("const c = rand(0, 10)\n@StartRule\nLot --> extrude(9) R0\n");
    for (i, b) in bodies.iter().enumerate() {
        let next = |n: u8| successor(i, rules, n);
        let body = match b {
            Body::Split {
                axis,
                kind,
                parts,
                repeat,
            } => {
                let axis = ["x", "y", "z"][*axis];
                let kind = ["", ", sequential", ", parallel"][*kind];
                let entries: Vec<String> =
                    parts.iter().map(|&n| format!("~1 : {}", next(n))).collect();
                if *repeat {
                    format!("split({axis}{kind}) {{ {{ {} }}* }}", entries.join(" | "))
                } else {
                    format!("split({axis}{kind}) {{ {} }}", entries.join(" | "))
                }
            }
            Body::Comp(parts) => {
                let selectors = ["side", "top", "bottom"];
                let entries: Vec<String> = parts
                    .iter()
                    .zip(selectors)
                    .map(|(&n, s)| format!("{s} : {}", next(n)))
                    .collect();
                format!("comp(f) {{ {} }}", entries.join(" | "))
            }
            Body::Joint(n) => format!("joint('0.3, 0, '0.7) {}", next(*n)),
            Body::Pose(n) => {
                format!(
                    "rotationLimits(y, -30, 30) rotateJoint(0, 10, 0) {}",
                    next(*n)
                )
            }
            Body::Report(n) => format!("report(\"c\", c) print(rand(1)) {}", next(*n)),
            Body::Nil => "NIL".into(),
            Body::Leaf => "Leaf.".into(),
        };
        text.push_str(&format!("R{i} --> {body}\n"));
    }
    text
}
