//! The authoring steps the page sends, as JSON, and how each runs on the project through
//! shapegram-topo's editor model (so that each is one step of undo).

use serde::{Deserialize, Serialize};
use shapegram_geom::{Color, DVec2, DVec3};
use shapegram_topo::{Anchor, Assignment, EditError, Material, NodeId, NodeKind, Project};

/// The largest side of a new box symbol: a prototype is a modelling unit, not a city.
const MAX_BOX_SIDE: f64 = 1e6;

/// One authoring step.
#[derive(Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Action {
    /// A new symbol whose prototype is a box of `size` (default 1 × 1 × 1).
    AddSymbol {
        name: String,
        size: Option<[f64; 3]>,
    },
    /// A new symbol made from a sub-shape, assigned to it.
    SymbolFromLeaf {
        rule: u32,
        node: NodeId,
        name: String,
    },
    /// A new rule of `symbol`, one uncut sub-shape.
    AddRule {
        symbol: u32,
        name: String,
        weight: Option<f64>,
    },
    RenameSymbol {
        symbol: u32,
        name: String,
    },
    RenameRule {
        rule: u32,
        name: String,
    },
    /// Deletes a symbol and its rules; refused while another rule assigns it.
    DeleteSymbol {
        symbol: u32,
    },
    DeleteRule {
        rule: u32,
    },
    SetWeight {
        rule: u32,
        weight: f64,
    },
    /// A colour `#rrggbb`, or `null` for the default grey.
    SetColor {
        symbol: u32,
        color: Option<String>,
    },
    /// Face cut `distance` inside `face`; `global` cuts every sub-shape the plane passes through;
    /// `absolute` keeps the distance in metres when the rule is applied to other sizes.
    FaceCut {
        rule: u32,
        node: NodeId,
        face: u32,
        distance: f64,
        #[serde(default)]
        global: bool,
        #[serde(default)]
        absolute: bool,
    },
    /// Gives `face` of sub-shape `node` the material named in `material` (added, or updated
    /// when one of that name exists), or clears it when `material` is `null`.
    FaceMaterial {
        rule: u32,
        node: NodeId,
        face: u32,
        material: Option<MaterialChoice>,
    },
    /// Prism cut at `fraction` of the height from base `face`, snapped to `grid` when given.
    PrismCut {
        rule: u32,
        node: NodeId,
        face: u32,
        fraction: f64,
        grid: Option<f64>,
    },
    /// `cuts` planes dividing the prism into equal parts from base `face`.
    MultiCut {
        rule: u32,
        node: NodeId,
        face: u32,
        cuts: usize,
    },
    /// The symmetric three-part cut (thesis 4.4): planes at `margin` and `1 − margin` of the
    /// prism's height from base `face`, so the outer parts are equal.
    SymmetricCut {
        rule: u32,
        node: NodeId,
        face: u32,
        margin: f64,
    },
    /// The plane through three points on edges of sub-shapes.
    ThreePointCut {
        rule: u32,
        points: [EdgePoint; 3],
    },
    /// What a sub-shape becomes.
    Assign {
        rule: u32,
        node: NodeId,
        to: Target,
    },
    /// Moves a sub-shape's anchor to `face`, `corner`.
    PlaceAnchor {
        rule: u32,
        node: NodeId,
        face: u32,
        corner: u32,
    },
    /// Turns a sub-shape's anchor one corner along its face.
    TurnAnchor {
        rule: u32,
        node: NodeId,
        clockwise: bool,
    },
}

/// A point on the directed edge `face`, `corner` of sub-shape `node`, at `fraction` of its length,
/// snapped to a multiple of `grid` (world units) when given.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdgePoint {
    pub node: NodeId,
    pub face: u32,
    pub corner: u32,
    pub fraction: f64,
    pub grid: Option<f64>,
}

/// A material as the picker sends it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialChoice {
    pub name: String,
    /// `#rrggbb`, or `null` for none (a texture drawn as it is).
    pub color: Option<String>,
    /// An image path relative to the project file.
    pub texture: Option<String>,
    /// Width and height in metres one copy of the texture covers.
    pub tile: [f64; 2],
}

impl MaterialChoice {
    fn material(self) -> Result<Material, EditError> {
        Ok(Material {
            color: self.color.as_deref().map(parse_color).transpose()?,
            name: self.name,
            texture: self.texture.filter(|t| !t.is_empty()),
            tile: DVec2::from_array(self.tile),
        })
    }
}

/// What a sub-shape is assigned.
#[derive(Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Target {
    /// An anonymous terminal (the empty symbol field).
    Terminal,
    /// Nothing: the volume is removed.
    Epsilon,
    /// A symbol, anchored upright and facing +z unless an anchor is given.
    Symbol {
        symbol: u32,
        anchor: Option<[u32; 2]>,
    },
}

/// What a step made, for the page to select.
#[derive(Serialize, Default)]
pub struct Made {
    /// A new symbol or rule.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub index: Option<u32>,
    /// New sub-shapes, in order.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nodes: Vec<NodeId>,
}

impl Action {
    /// The rule a cut is made in; `None` for steps that are not cuts.
    pub fn cut_rule(&self) -> Option<u32> {
        match self {
            Action::FaceCut { rule, .. }
            | Action::PrismCut { rule, .. }
            | Action::MultiCut { rule, .. }
            | Action::SymmetricCut { rule, .. }
            | Action::ThreePointCut { rule, .. } => Some(*rule),
            _ => None,
        }
    }

    /// Runs the step on `project`; on an error the caller's editor restores the project.
    pub fn run(self, project: &mut Project) -> Result<Made, EditError> {
        let index = |i: u32| Made {
            index: Some(i),
            nodes: Vec::new(),
        };
        let nodes = |nodes: Vec<NodeId>| Made { index: None, nodes };
        match self {
            Action::AddSymbol { name, size } => {
                let [x, y, z] = size.unwrap_or([1.0; 3]);
                if ![x, y, z]
                    .iter()
                    .all(|s| s.is_finite() && *s > 0.0 && *s <= MAX_BOX_SIDE)
                {
                    return Err(EditError::Invalid(format!(
                        "a box symbol's sides must be positive numbers up to {MAX_BOX_SIDE}"
                    )));
                }
                project
                    .add_box_symbol(&name, DVec3::new(x, y, z))
                    .map(index)
            }
            Action::SymbolFromLeaf { rule, node, name } => project
                .symbol_from_leaf(rule, node, &name, Anchor::new(0, 0))
                .map(index),
            Action::AddRule {
                symbol,
                name,
                weight,
            } => project
                .add_rule(symbol, &name, weight.unwrap_or(1.0))
                .map(index),
            Action::RenameSymbol { symbol, name } => {
                project.rename_symbol(symbol, &name).map(|()| index(symbol))
            }
            Action::RenameRule { rule, name } => {
                project.rule(rule)?;
                check_rule_name(&name)?;
                project.rules[rule as usize].name = name;
                Ok(index(rule))
            }
            Action::DeleteSymbol { symbol } => {
                delete_symbol(project, symbol).map(|()| Made::default())
            }
            Action::DeleteRule { rule } => {
                project.rule(rule)?;
                project.rules.remove(rule as usize);
                Ok(Made::default())
            }
            Action::SetWeight { rule, weight } => {
                project.set_weight(rule, weight).map(|()| index(rule))
            }
            Action::SetColor { symbol, color } => {
                let color = color.as_deref().map(parse_color).transpose()?;
                project.set_color(symbol, color).map(|()| index(symbol))
            }
            Action::FaceCut {
                rule,
                node,
                face,
                distance,
                global,
                absolute,
            } => match (global, absolute) {
                (false, false) => project
                    .face_cut(rule, node, face, distance)
                    .map(|parts| nodes(parts.to_vec())),
                (true, false) => project
                    .global_face_cut(rule, node, face, distance)
                    .map(|cuts| nodes(cuts.into_iter().flatten().collect())),
                (false, true) => project
                    .offset_cut(rule, node, face, distance)
                    .map(|parts| nodes(parts.to_vec())),
                (true, true) => Err(EditError::Invalid(
                    "a cut at an absolute distance cuts one sub-shape, not globally".into(),
                )),
            },
            Action::FaceMaterial {
                rule,
                node,
                face,
                material,
            } => {
                let chosen = match material {
                    None => None,
                    Some(choice) => {
                        let material = choice.material()?;
                        Some(match project.material_named(&material.name) {
                            Some(existing) => {
                                project.set_material(existing, material)?;
                                existing
                            }
                            None => project.add_material(material)?,
                        })
                    }
                };
                project.assign_face_material(rule, node, face, chosen)?;
                Ok(Made {
                    index: chosen,
                    nodes: vec![node],
                })
            }
            Action::PrismCut {
                rule,
                node,
                face,
                fraction,
                grid,
            } => {
                check_fraction(fraction)?;
                project
                    .prism_cut(rule, node, face, fraction, grid)
                    .map(|parts| nodes(parts.to_vec()))
            }
            Action::MultiCut {
                rule,
                node,
                face,
                cuts,
            } => project.multi_cut(rule, node, face, cuts).map(nodes),
            Action::SymmetricCut {
                rule,
                node,
                face,
                margin,
            } => project
                .symmetric_cut(rule, node, face, margin)
                .map(|parts| nodes(parts.to_vec())),
            Action::ThreePointCut { rule, points } => {
                let mut at = [DVec3::ZERO; 3];
                for (slot, p) in at.iter_mut().zip(&points) {
                    *slot = project.edge_point(
                        rule,
                        p.node,
                        Anchor::new(p.face, p.corner),
                        p.fraction,
                        p.grid,
                    )?;
                }
                project
                    .three_point_cut(rule, at)
                    .map(|cuts| nodes(cuts.into_iter().flatten().collect()))
            }
            Action::Assign { rule, node, to } => {
                match to {
                    Target::Terminal => project.assign(rule, node, Assignment::Terminal)?,
                    Target::Epsilon => project.assign(rule, node, Assignment::Epsilon)?,
                    Target::Symbol {
                        symbol,
                        anchor: Some([face, corner]),
                    } => project.assign(
                        rule,
                        node,
                        Assignment::Symbol {
                            symbol,
                            anchor: Anchor::new(face, corner),
                        },
                    )?,
                    Target::Symbol {
                        symbol,
                        anchor: None,
                    } => {
                        project.assign_facing(rule, node, symbol, DVec3::Y, DVec3::Z)?;
                    }
                }
                Ok(nodes(vec![node]))
            }
            Action::PlaceAnchor {
                rule,
                node,
                face,
                corner,
            } => {
                let symbol = assigned_symbol(project, rule, node)?.0;
                project.assign(
                    rule,
                    node,
                    Assignment::Symbol {
                        symbol,
                        anchor: Anchor::new(face, corner),
                    },
                )?;
                Ok(nodes(vec![node]))
            }
            Action::TurnAnchor {
                rule,
                node,
                clockwise,
            } => {
                let (symbol, anchor) = assigned_symbol(project, rule, node)?;
                let shape = &project.rule(rule)?.tree.node(node)?.shape;
                let turned = if clockwise {
                    anchor.clockwise(shape)
                } else {
                    anchor.counter_clockwise(shape)
                }
                .ok_or_else(|| EditError::NotFound("the anchor is not on the shape".into()))?;
                project.assign(
                    rule,
                    node,
                    Assignment::Symbol {
                        symbol,
                        anchor: turned,
                    },
                )?;
                Ok(nodes(vec![node]))
            }
        }
    }
}

/// A colour `#rrggbb`.
fn parse_color(text: &str) -> Result<Color, EditError> {
    Color::from_hex(text)
        .ok_or_else(|| EditError::Invalid(format!("`{text}` is not a colour (#rrggbb)")))
}

/// The symbol and anchor assigned to sub-shape `node` of `rule`.
fn assigned_symbol(project: &Project, rule: u32, node: NodeId) -> Result<(u32, Anchor), EditError> {
    match project.rule(rule)?.tree.node(node)?.kind {
        NodeKind::Leaf(Assignment::Symbol { symbol, anchor }) => Ok((symbol, anchor)),
        _ => Err(EditError::NotCuttable(format!(
            "sub-shape {node} has no symbol, so it has no anchor"
        ))),
    }
}

fn check_rule_name(name: &str) -> Result<(), EditError> {
    if name.trim().is_empty() || name.len() > 200 {
        return Err(EditError::Invalid(
            "a rule name must be 1 to 200 characters, not blank".into(),
        ));
    }
    Ok(())
}

fn check_fraction(fraction: f64) -> Result<(), EditError> {
    if fraction > 0.0 && fraction < 1.0 {
        Ok(())
    } else {
        Err(EditError::Invalid(format!(
            "a prism cut's fraction {fraction} must lie strictly between 0 and 1"
        )))
    }
}

/// Deletes `symbol` and its own rules, renumbering the symbols after it in the other rules'
/// assignments; refused while a rule of another symbol assigns it.
fn delete_symbol(project: &mut Project, symbol: u32) -> Result<(), EditError> {
    let name = project.symbol(symbol)?.name.clone();
    let assigns = |kind: &NodeKind, s: u32| matches!(kind, NodeKind::Leaf(Assignment::Symbol { symbol, .. }) if *symbol == s);
    if let Some(user) = project
        .rules
        .iter()
        .find(|r| r.symbol != symbol && r.tree.nodes().iter().any(|n| assigns(&n.kind, symbol)))
    {
        return Err(EditError::Invalid(format!(
            "symbol '{name}' is used by rule '{}' of symbol '{}'; assign something else there first",
            user.name, project.symbols[user.symbol as usize].name
        )));
    }
    project.rules.retain(|r| r.symbol != symbol);
    project.symbols.remove(symbol as usize);
    for rule in 0..project.rules.len() {
        if project.rules[rule].symbol > symbol {
            project.rules[rule].symbol -= 1;
        }
        let renumbered: Vec<(NodeId, u32, Anchor)> = project.rules[rule]
            .tree
            .nodes()
            .iter()
            .enumerate()
            .filter_map(|(id, n)| match n.kind {
                NodeKind::Leaf(Assignment::Symbol { symbol: s, anchor }) if s > symbol => {
                    Some((id as NodeId, s - 1, anchor))
                }
                _ => None,
            })
            .collect();
        for (node, symbol, anchor) in renumbered {
            project.assign(rule as u32, node, Assignment::Symbol { symbol, anchor })?;
        }
    }
    Ok(())
}
