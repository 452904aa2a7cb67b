//! Shapes: solids together with their bonds, moved and combined as one.

use glam::{DAffine3, DMat3, DQuat, DVec3};

use crate::bond::Bond;
use crate::error::Result;
use crate::primitive::Primitive;
use crate::solid::Solid;

/// A solid and the bonds where other shapes may be joined to it (Definition 4).
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// The geometry.
    pub solid: Solid,
    /// Bonds in the same frame as the solid.
    pub bonds: Vec<Bond>,
}

impl Shape {
    /// A checked primitive with its bonds (see [`Primitive::bonds`]).
    pub fn primitive(primitive: Primitive) -> Result<Self> {
        Ok(Self {
            solid: Solid::primitive(primitive)?,
            bonds: primitive.bonds(),
        })
    }

    /// The shape moved by `offset`.
    pub fn translate(&self, offset: DVec3) -> Result<Self> {
        Ok(Self {
            solid: self.solid.translate(offset)?,
            bonds: self.map_bonds(&DAffine3::from_translation(offset)),
        })
    }

    /// The shape turned by `degrees` about `axis` through the origin.
    pub fn rotate(&self, axis: DVec3, degrees: f64) -> Result<Self> {
        let solid = self.solid.rotate(axis, degrees)?;
        let turn = DQuat::from_axis_angle(axis.normalize(), degrees.to_radians());
        Ok(Self {
            solid,
            bonds: self.map_bonds(&DAffine3::from_quat(turn)),
        })
    }

    /// The shape scaled about the origin.
    pub fn scale(&self, scale: DVec3) -> Result<Self> {
        Ok(Self {
            solid: self.solid.scale(scale)?,
            bonds: self.map_bonds(&DAffine3::from_mat3(DMat3::from_diagonal(scale))),
        })
    }

    /// The shape under any invertible affine map (see [`Solid::transform`]).
    pub fn transform(&self, map: &DAffine3) -> Result<Self> {
        Ok(Self {
            solid: self.solid.transform(map)?,
            bonds: self.map_bonds(map),
        })
    }

    fn map_bonds(&self, map: &DAffine3) -> Vec<Bond> {
        self.bonds.iter().map(|b| b.transformed(map)).collect()
    }

    /// The sum of two shapes, with the bonds of both.
    pub fn union(&self, other: &Shape) -> Self {
        Self {
            solid: self.solid.union(&other.solid),
            bonds: self.bonds.iter().chain(&other.bonds).copied().collect(),
        }
    }

    /// This shape with `other` taken away; the bonds are this shape's.
    pub fn difference(&self, other: &Shape) -> Self {
        Self {
            solid: self.solid.difference(&other.solid),
            bonds: self.bonds.clone(),
        }
    }

    /// The intersection; the bonds are this shape's.
    pub fn intersection(&self, other: &Shape) -> Self {
        Self {
            solid: self.solid.intersection(&other.solid),
            bonds: self.bonds.clone(),
        }
    }

    /// The morph towards `other` by `a` (eq. 5); the bonds are this shape's.
    pub fn morph(&self, other: &Shape, a: f64) -> Result<Self> {
        Ok(Self {
            solid: self.solid.morph(&other.solid, a)?,
            bonds: self.bonds.clone(),
        })
    }

    /// The point a shape is centred on when it is joined by its free bond: its first bond without
    /// a direction, else the centre of its bounds, else the origin.
    pub fn centre(&self) -> DVec3 {
        self.bonds
            .iter()
            .find(|b| b.is_free())
            .map(|b| b.point)
            .or_else(|| self.solid.bounds().map(|b| b.center()))
            .unwrap_or(DVec3::ZERO)
    }
}
