//! The skeleton: an arena of sections linked into one rooted tree, with the operations the
//! grammar's rules perform on it (§4.1 of the paper).

use crate::{Clamped, Frame, KinematicError, Limits, Pose};

/// A section's index in its skeleton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SectionId(pub u32);

impl SectionId {
    /// The index as `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A rigid part of the skeleton and the joint that links it to its parent.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// A name that stays the same when the grammar is derived again (the engine's choice).
    pub name: String,
    /// The joint's frame in model space in the rest pose.
    pub rest: Frame,
    /// How far the joint may move.
    pub limits: Limits,
    /// The joint's current pose, within `limits`.
    pub pose: Pose,
    /// The parent section; `None` for the root.
    pub parent: Option<SectionId>,
    children: Vec<SectionId>,
}

impl Section {
    /// The sections whose parent this is, in the order they were linked.
    pub fn children(&self) -> &[SectionId] {
        &self.children
    }
}

/// A tree of sections. Section 0 is the root; the paper's rules never make a second one.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    sections: Vec<Section>,
}

impl Skeleton {
    /// A skeleton of one section, the root, with its joint at `rest` (the model's pivot).
    pub fn new(rest: Frame, name: impl Into<String>) -> Self {
        Self {
            sections: vec![Section {
                name: name.into(),
                rest,
                limits: Limits::default(),
                pose: Pose::default(),
                parent: None,
                children: Vec::new(),
            }],
        }
    }

    /// The root section.
    pub fn root(&self) -> SectionId {
        SectionId(0)
    }

    /// Number of sections.
    pub fn len(&self) -> usize {
        self.sections.len()
    }

    /// Whether the skeleton has no section (never: it always has a root).
    pub fn is_empty(&self) -> bool {
        self.sections.is_empty()
    }

    /// A section.
    pub fn section(&self, id: SectionId) -> &Section {
        &self.sections[id.index()]
    }

    /// Every section with its id, in id order.
    pub fn sections(&self) -> impl Iterator<Item = (SectionId, &Section)> {
        (0..).map(SectionId).zip(&self.sections)
    }

    /// A new section under `parent` with its joint at `rest`, locked, in the rest pose.
    pub fn add_child(
        &mut self,
        parent: SectionId,
        rest: Frame,
        name: impl Into<String>,
    ) -> SectionId {
        let id = SectionId(u32::try_from(self.sections.len()).expect("fewer than 2³² sections"));
        self.sections.push(Section {
            name: name.into(),
            rest,
            limits: Limits::default(),
            pose: Pose::default(),
            parent: Some(parent),
            children: Vec::new(),
        });
        self.sections[parent.index()].children.push(id);
        id
    }

    /// A component split: one new child of `section` per frame (each component's joint at its
    /// centre, z along its normal).
    pub fn components(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, String)>,
    ) -> Vec<SectionId> {
        frames
            .into_iter()
            .map(|(rest, name)| self.add_child(section, rest, name))
            .collect()
    }

    /// A sequential split into a chain: the first part keeps `section`, each further part is a
    /// child of the one before with its joint at its frame (on the split plane), and the
    /// section's children move to the last part. Returns the parts' sections in order.
    pub fn sequential(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, String)>,
    ) -> Vec<SectionId> {
        let children = std::mem::take(&mut self.sections[section.index()].children);
        let mut chain = vec![section];
        for (rest, name) in frames {
            let previous = *chain.last().expect("the chain starts with the section");
            chain.push(self.add_child(previous, rest, name));
        }
        let last = *chain.last().expect("the chain starts with the section");
        self.adopt(last, children);
        chain
    }

    /// A parallel split (a fork): one new child of the section's parent per frame. The section
    /// must have a parent and no children.
    pub fn parallel(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, String)>,
    ) -> Result<Vec<SectionId>, KinematicError> {
        let parent = self
            .section(section)
            .parent
            .ok_or(KinematicError::ParallelAtRoot)?;
        if !self.section(section).children.is_empty() {
            return Err(KinematicError::ParallelWithChildren);
        }
        Ok(frames
            .into_iter()
            .map(|(rest, name)| self.add_child(parent, rest, name))
            .collect())
    }

    /// Makes `children` children of `parent`. Their rest frames stay, so nothing moves: their
    /// joints are now measured from `parent`.
    fn adopt(&mut self, parent: SectionId, children: Vec<SectionId>) {
        for &child in &children {
            self.sections[child.index()].parent = Some(parent);
        }
        self.sections[parent.index()].children.extend(children);
    }

    /// The joint placement rule: the section's joint moves to `rest`; its children keep their
    /// rest frames, so only the pivot changes.
    pub fn place_joint(&mut self, section: SectionId, rest: Frame) {
        self.sections[section.index()].rest = rest;
    }

    /// The limitation rule: new limits, with the current pose clamped into them.
    pub fn set_limits(
        &mut self,
        section: SectionId,
        limits: Limits,
    ) -> Result<Vec<Clamped>, KinematicError> {
        limits.validate()?;
        let s = &mut self.sections[section.index()];
        s.limits = limits;
        let (pose, clamped) = limits.clamp(&s.pose);
        s.pose = pose;
        Ok(clamped)
    }

    /// A new pose, which must lie within the limits (see [`Limits::admit`]); a refused pose
    /// changes nothing.
    pub fn pose_within(&mut self, section: SectionId, pose: Pose) -> Result<(), KinematicError> {
        let s = &mut self.sections[section.index()];
        s.limits.admit(&pose)?;
        s.pose = pose;
        Ok(())
    }

    /// The current translation and rotation rules: a new pose, clamped into the limits (what
    /// was clamped is returned, for a warning).
    pub fn set_pose(
        &mut self,
        section: SectionId,
        pose: Pose,
    ) -> Result<Vec<Clamped>, KinematicError> {
        pose.validate()?;
        let s = &mut self.sections[section.index()];
        let (pose, clamped) = s.limits.clamp(&pose);
        s.pose = pose;
        Ok(clamped)
    }

    /// The joint as the paper defines it: the section's rest frame relative to its parent's
    /// (the root's relative to the model).
    pub fn joint(&self, section: SectionId) -> Frame {
        let s = self.section(section);
        match s.parent {
            Some(parent) => self.section(parent).rest.inverse().mul(&s.rest),
            None => s.rest,
        }
    }

    /// The joint with its pose applied: the section's transformation relative to its parent
    /// (a glTF joint node's TRS).
    pub fn local(&self, section: SectionId) -> Frame {
        self.joint(section).mul(&self.section(section).pose.frame())
    }

    /// The first section called `name`.
    pub fn find(&self, name: &str) -> Option<SectionId> {
        self.sections()
            .find(|(_, s)| s.name == name)
            .map(|(id, _)| id)
    }

    /// Sections in an order where every parent comes before its children (depth first from
    /// the root, children in link order).
    pub fn order(&self) -> Vec<SectionId> {
        let mut order = Vec::with_capacity(self.sections.len());
        let mut stack = vec![self.root()];
        // A cycle cannot arise from the operations above; the bound keeps a corrupted skeleton
        // from looping, and `is_tree` reports it.
        while let Some(id) = stack.pop()
            && order.len() <= self.sections.len()
        {
            order.push(id);
            stack.extend(self.section(id).children.iter().rev());
        }
        order
    }

    /// Every section's frame in model space with all poses applied, indexed by section.
    pub fn posed(&self) -> Vec<Frame> {
        let mut posed = vec![Frame::IDENTITY; self.sections.len()];
        for id in self.order() {
            let local = self.local(id);
            posed[id.index()] = match self.section(id).parent {
                Some(parent) => posed[parent.index()].mul(&local),
                None => local,
            };
        }
        posed
    }

    /// Per section, the rigid motion that takes geometry attached to it from the rest pose to
    /// the current pose: `posed · rest⁻¹`.
    pub fn skinning(&self) -> Vec<Frame> {
        self.posed()
            .iter()
            .zip(&self.sections)
            .map(|(posed, s)| posed.mul(&s.rest.inverse()))
            .collect()
    }

    /// Whether the sections form one tree rooted at section 0: every parent link is matched by
    /// a child link and every section is reached from the root exactly once.
    pub fn is_tree(&self) -> bool {
        let order = self.order();
        if order.len() != self.sections.len() || self.sections[0].parent.is_some() {
            return false;
        }
        let mut seen = vec![false; self.sections.len()];
        for id in order {
            if std::mem::replace(&mut seen[id.index()], true) {
                return false;
            }
        }
        self.sections().all(|(id, s)| {
            s.children
                .iter()
                .all(|c| self.section(*c).parent == Some(id))
        })
    }
}
