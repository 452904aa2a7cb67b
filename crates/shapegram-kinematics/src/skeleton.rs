//! The skeleton: an arena of sections linked into one rooted tree, with the operations the
//! grammar's rules perform on it (§4.1 of the paper).

use glam::{DQuat, DVec3};

use crate::name::{NameKey, Names, SectionName};
use crate::{Clamped, Frame, KinematicError, Limits, Name, Pose};

/// A section's index in its skeleton.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SectionId(pub u32);

impl SectionId {
    /// The index as `usize`.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A parent for messages: "section 3", or "no parent".
fn parent_text(parent: Option<SectionId>) -> String {
    parent.map_or_else(|| "no parent".to_owned(), |p| format!("section {}", p.0))
}

/// No section (the end of a list of children, the root's parent) and no motion.
const NONE: u32 = u32::MAX;

/// A rigid part of the skeleton and the joint that links it to its parent, as kept: a city has
/// millions, so a section is 56 bytes with no pointer. Its joint's rotation and its rule name
/// are indices into tables of the skeleton (the parts of a split share their rotation), limits
/// and pose are kept apart once set (most joints stay locked at rest), and children are a
/// linked list.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Stored {
    /// The joint's position in model space in the rest pose.
    translation: DVec3,
    /// The joint's orientation in the rest pose, in [`Skeleton::rotations`].
    rotation: u32,
    name: NameKey,
    parent: u32,
    /// Limits and pose, in [`Skeleton::motions`], or `NONE` while locked at rest.
    motion: u32,
    first_child: u32,
    last_child: u32,
    next_sibling: u32,
}

/// A joint's limits and pose, once either is set.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Motion {
    // The pose first: motions that differ mostly differ in it, and equality compares in order.
    pose: Pose,
    limits: Limits,
}

/// A section of a skeleton, to read: its name, joint, limits, pose and links.
#[derive(Clone, Copy)]
pub struct Section<'s> {
    skeleton: &'s Skeleton,
    stored: &'s Stored,
}

impl Section<'_> {
    /// A name that stays the same when the grammar is derived again (the engine's choice).
    pub fn name(&self) -> Name {
        self.skeleton.names.name(self.stored.name)
    }

    /// The rule part of the name.
    pub fn base(&self) -> &str {
        self.skeleton.names.base(self.stored.name)
    }

    /// Whether the name reads `text`, without writing it out.
    pub fn name_reads(&self, text: &str) -> bool {
        self.skeleton.names.reads(self.stored.name, text)
    }

    /// The joint's frame in model space in the rest pose.
    #[inline]
    pub fn rest(&self) -> Frame {
        Frame {
            rotation: self.skeleton.rotations[self.stored.rotation as usize],
            translation: self.stored.translation,
        }
    }

    /// The parent section; `None` for the root.
    #[inline]
    pub fn parent(&self) -> Option<SectionId> {
        (self.stored.parent != NONE).then_some(SectionId(self.stored.parent))
    }

    /// How far the joint may move (locked unless set).
    #[inline]
    pub fn limits(&self) -> Limits {
        self.kept_motion()
            .map_or_else(Limits::default, |m| m.limits)
    }

    /// Whether the joint may move at all (its limits leave some axis free).
    #[inline]
    pub fn is_free(&self) -> bool {
        self.kept_motion().is_some_and(|m| m.limits.is_free())
    }

    /// The joint's current pose, within its limits (the rest pose unless set).
    #[inline]
    pub fn pose(&self) -> Pose {
        self.kept_motion().map_or_else(Pose::default, |m| m.pose)
    }

    /// Whether the section has kinematic children.
    #[inline]
    pub fn has_children(&self) -> bool {
        self.stored.first_child != NONE
    }

    #[inline]
    fn kept_motion(&self) -> Option<&Motion> {
        self.skeleton.motions.get(self.stored.motion as usize)
    }

    fn motion(&self) -> Motion {
        self.kept_motion().copied().unwrap_or_default()
    }
}

/// A section of another skeleton names a new section alike.
impl SectionName for Section<'_> {
    fn key(self, names: &mut Names) -> NameKey {
        self.skeleton.names.copy_to(self.stored.name, names)
    }
}

impl std::fmt::Debug for Section<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Section")
            .field("name", &self.name().to_string())
            .field("rest", &self.rest())
            .field("parent", &self.parent())
            .field("limits", &self.limits())
            .field("pose", &self.pose())
            .finish()
    }
}

/// The children of a section, in the order they were linked.
pub struct Children<'s> {
    sections: &'s [Stored],
    next: u32,
}

impl Iterator for Children<'_> {
    type Item = SectionId;

    fn next(&mut self) -> Option<SectionId> {
        let id = self.next;
        let section = self.sections.get(id as usize)?;
        self.next = section.next_sibling;
        Some(SectionId(id))
    }
}

/// The sections of the parts a split or component split made, in part order, without a list:
/// new sections are numbered consecutively, and the first part of a sequential split keeps the
/// section that was split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parts {
    kept: Option<SectionId>,
    first_new: u32,
    len: u32,
}

impl Parts {
    /// Number of parts.
    #[inline]
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// Whether there are no parts.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The section of part `i`.
    ///
    /// # Panics
    /// If `i` is not below [`Parts::len`].
    #[inline]
    pub fn get(&self, i: usize) -> SectionId {
        assert!(i < self.len(), "part {i} of {}", self.len);
        match self.kept {
            Some(kept) if i == 0 => kept,
            Some(_) => SectionId(self.first_new + i as u32 - 1),
            None => SectionId(self.first_new + i as u32),
        }
    }

    /// The parts' sections in order.
    pub fn iter(&self) -> impl Iterator<Item = SectionId> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    /// The parts' sections as a list.
    pub fn to_vec(&self) -> Vec<SectionId> {
        self.iter().collect()
    }
}

/// A pose of the whole skeleton kept under a name (`@Pose("open", 95)` in a grammar): each
/// section's pose, indexed by section.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedPose {
    /// The pose's name.
    pub name: String,
    /// Each section's pose in it, by section index.
    pub poses: Vec<Pose>,
}

impl NamedPose {
    /// The pose of one section in this named pose (the rest pose for an unknown id).
    pub fn pose(&self, section: SectionId) -> Pose {
        self.poses.get(section.index()).copied().unwrap_or_default()
    }
}

/// A tree of sections. Section 0 is the root; the paper's rules never make a second one.
#[derive(Clone, Debug)]
pub struct Skeleton {
    sections: Vec<Stored>,
    /// The joints' rotations, shared by sections that have the same one.
    rotations: Vec<DQuat>,
    /// The limits and poses of the sections that have them.
    motions: Vec<Motion>,
    names: Names,
    /// Named poses, in the order they were added.
    named_poses: Vec<NamedPose>,
}

impl Skeleton {
    /// A skeleton of one section, the root, with its joint at `rest` (the model's pivot).
    pub fn new(rest: Frame, name: impl SectionName) -> Self {
        Self::with_capacity(rest, name, 1)
    }

    /// [`Skeleton::new`] with room for `sections` sections, so that growing to about that many
    /// moves none.
    pub fn with_capacity(rest: Frame, name: impl SectionName, sections: usize) -> Self {
        let mut names = Names::default();
        let mut all = Vec::with_capacity(sections.max(1));
        all.push(Stored {
            translation: rest.translation,
            rotation: 0,
            name: name.key(&mut names),
            parent: NONE,
            motion: NONE,
            first_child: NONE,
            last_child: NONE,
            next_sibling: NONE,
        });
        Self {
            sections: all,
            rotations: vec![rest.rotation],
            motions: Vec::new(),
            names,
            named_poses: Vec::new(),
        }
    }

    /// The root section.
    #[inline]
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
    ///
    /// # Panics
    /// For an id the skeleton does not have.
    #[inline]
    pub fn section(&self, id: SectionId) -> Section<'_> {
        Section {
            skeleton: self,
            stored: &self.sections[id.index()],
        }
    }

    /// The children of a section, in the order they were linked.
    pub fn children(&self, id: SectionId) -> Children<'_> {
        Children {
            sections: &self.sections,
            next: self.sections[id.index()].first_child,
        }
    }

    /// Every section with its id, in id order.
    pub fn sections(&self) -> impl Iterator<Item = (SectionId, Section<'_>)> {
        (0..)
            .map(SectionId)
            .zip(self.sections.iter().map(|stored| Section {
                skeleton: self,
                stored,
            }))
    }

    /// The index of `rotation` in the table, checking the rotations most likely to be the same
    /// first: `hint`'s (the parent's, or the section's own) and the last one added.
    #[inline]
    fn rotation(&mut self, rotation: DQuat, hint: u32) -> u32 {
        if self.rotations.get(hint as usize) == Some(&rotation) {
            return hint;
        }
        let last = self.rotations.len() - 1;
        if self.rotations[last] == rotation {
            return last as u32;
        }
        self.rotations.push(rotation);
        last as u32 + 1
    }

    /// A new section under `parent` with its joint at `rest`, locked, in the rest pose.
    #[inline]
    pub fn add_child(
        &mut self,
        parent: SectionId,
        rest: Frame,
        name: impl SectionName,
    ) -> SectionId {
        let id = u32::try_from(self.sections.len())
            .ok()
            .filter(|&id| id != NONE)
            .expect("fewer than 2³² − 1 sections");
        let rotation = self.rotation(rest.rotation, self.sections[parent.index()].rotation);
        let name = name.key(&mut self.names);
        self.sections.push(Stored {
            translation: rest.translation,
            rotation,
            name,
            parent: parent.0,
            motion: NONE,
            first_child: NONE,
            last_child: NONE,
            next_sibling: NONE,
        });
        self.link(parent, id, id);
        SectionId(id)
    }

    /// Appends the list of siblings `first..=last` (already linked among themselves) to the
    /// children of `parent`.
    #[inline]
    fn link(&mut self, parent: SectionId, first: u32, last: u32) {
        let p = &mut self.sections[parent.index()];
        let previous = std::mem::replace(&mut p.last_child, last);
        if previous == NONE {
            p.first_child = first;
        } else {
            self.sections[previous as usize].next_sibling = first;
        }
    }

    /// A component split: one new child of `section` per frame (each component's joint at its
    /// centre, z along its normal).
    pub fn components<N: SectionName>(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, N)>,
    ) -> Parts {
        self.children_of(section, None, frames)
    }

    /// New children of `parent`, one per frame, after the part `kept` if any.
    fn children_of<N: SectionName>(
        &mut self,
        parent: SectionId,
        kept: Option<SectionId>,
        frames: impl IntoIterator<Item = (Frame, N)>,
    ) -> Parts {
        let first_new = self.sections.len() as u32;
        for (rest, name) in frames {
            self.add_child(parent, rest, name);
        }
        Parts {
            kept,
            first_new,
            len: self.sections.len() as u32 - first_new + u32::from(kept.is_some()),
        }
    }

    /// A sequential split into a chain: the first part keeps `section`, each further part is a
    /// child of the one before with its joint at its frame (on the split plane), and the
    /// section's children move to the last part. Returns the parts' sections in order.
    pub fn sequential<N: SectionName>(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, N)>,
    ) -> Parts {
        let s = &mut self.sections[section.index()];
        let children = (
            std::mem::replace(&mut s.first_child, NONE),
            std::mem::replace(&mut s.last_child, NONE),
        );
        let first_new = self.sections.len() as u32;
        let mut last = section;
        for (rest, name) in frames {
            last = self.add_child(last, rest, name);
        }
        self.adopt(last, children);
        Parts {
            kept: Some(section),
            first_new,
            len: self.sections.len() as u32 - first_new + 1,
        }
    }

    /// A parallel split (a fork): one new child of the section's parent per frame. The section
    /// must have a parent and no children.
    pub fn parallel<N: SectionName>(
        &mut self,
        section: SectionId,
        frames: impl IntoIterator<Item = (Frame, N)>,
    ) -> Result<Parts, KinematicError> {
        let s = self.section(section);
        let parent = s.parent().ok_or(KinematicError::ParallelAtRoot)?;
        if s.has_children() {
            return Err(KinematicError::ParallelWithChildren);
        }
        Ok(self.children_of(parent, None, frames))
    }

    /// Makes the sibling list `(first, last)` children of `parent`. Their rest frames stay, so
    /// nothing moves: their joints are now measured from `parent`.
    fn adopt(&mut self, parent: SectionId, (first, last): (u32, u32)) {
        if first == NONE {
            return;
        }
        let mut child = first;
        while child != NONE {
            let c = &mut self.sections[child as usize];
            c.parent = parent.0;
            child = c.next_sibling;
        }
        self.link(parent, first, last);
    }

    /// The joint placement rule: the section's joint moves to `rest`; its children keep their
    /// rest frames, so only the pivot changes.
    pub fn place_joint(&mut self, section: SectionId, rest: Frame) {
        let s = self.sections[section.index()];
        let hint = if s.parent == NONE {
            s.rotation
        } else {
            self.sections[s.parent as usize].rotation
        };
        let rotation = if self.rotations[s.rotation as usize] == rest.rotation {
            s.rotation
        } else {
            self.rotation(rest.rotation, hint)
        };
        let s = &mut self.sections[section.index()];
        s.translation = rest.translation;
        s.rotation = rotation;
    }

    /// Gives the section a new motion. Motions are shared and never changed in place: the
    /// joints of a city's windows all move alike, so a new motion is looked for among the last
    /// few kept before it is added.
    fn set_motion(&mut self, section: SectionId, motion: Motion) {
        const LOOK_BACK: usize = 2;
        let recent = self.motions.len().saturating_sub(LOOK_BACK);
        let index = match self.motions[recent..].iter().rposition(|m| *m == motion) {
            Some(i) => recent + i,
            None => {
                self.motions.push(motion);
                self.motions.len() - 1
            }
        };
        self.sections[section.index()].motion =
            u32::try_from(index).expect("fewer than 2³² motions");
    }

    /// The limitation rule: new limits, with the current pose clamped into them.
    pub fn set_limits(
        &mut self,
        section: SectionId,
        limits: Limits,
    ) -> Result<Vec<Clamped>, KinematicError> {
        limits.validate()?;
        let (pose, clamped) = limits.clamp(&self.section(section).pose());
        self.set_motion(section, Motion { limits, pose });
        Ok(clamped)
    }

    /// A new pose, which must lie within the limits (see [`Limits::admit`]); a refused pose
    /// changes nothing.
    pub fn pose_within(&mut self, section: SectionId, pose: Pose) -> Result<(), KinematicError> {
        let limits = self.section(section).limits();
        limits.admit(&pose)?;
        self.set_motion(section, Motion { limits, pose });
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
        let limits = self.section(section).limits();
        let (pose, clamped) = limits.clamp(&pose);
        self.set_motion(section, Motion { limits, pose });
        Ok(clamped)
    }

    /// The joint as the paper defines it: the section's rest frame relative to its parent's
    /// (the root's relative to the model).
    pub fn joint(&self, section: SectionId) -> Frame {
        let s = self.section(section);
        match s.parent() {
            Some(parent) => self.section(parent).rest().inverse().mul(&s.rest()),
            None => s.rest(),
        }
    }

    /// The joint with its pose applied: the section's transformation relative to its parent
    /// (a glTF joint node's TRS).
    pub fn local(&self, section: SectionId) -> Frame {
        self.local_in(section, &self.section(section).pose())
    }

    /// The joint with `pose` applied instead of the current pose: what [`Skeleton::local`]
    /// would be with the section in that pose (for a named pose, say).
    pub fn local_in(&self, section: SectionId, pose: &Pose) -> Frame {
        if pose.is_rest() {
            self.joint(section)
        } else {
            self.joint(section).mul(&pose.frame())
        }
    }

    /// Keeps the poses of `posed` under `name` (replacing a named pose of that name): `posed`
    /// is this skeleton derived again with other attribute values, so it must have the same
    /// structure, section for section (count, names and parents); each section's
    /// [`Section::pose`] is recorded. An error says what differs.
    pub fn add_named_pose(&mut self, name: &str, posed: &Skeleton) -> Result<(), String> {
        if posed.len() != self.len() {
            return Err(format!(
                "{} sections instead of {}",
                posed.len(),
                self.len()
            ));
        }
        for ((id, mine), (_, theirs)) in self.sections().zip(posed.sections()) {
            if mine.name() != theirs.name() || mine.parent() != theirs.parent() {
                return Err(format!(
                    "section {} is `{}` under {}, not `{}` under {}",
                    id.0,
                    theirs.name(),
                    parent_text(theirs.parent()),
                    mine.name(),
                    parent_text(mine.parent())
                ));
            }
        }
        let pose = NamedPose {
            name: name.to_owned(),
            poses: posed.sections().map(|(_, s)| s.pose()).collect(),
        };
        match self.named_poses.iter_mut().find(|p| p.name == name) {
            Some(existing) => *existing = pose,
            None => self.named_poses.push(pose),
        }
        Ok(())
    }

    /// The named poses, in the order they were first added.
    pub fn named_poses(&self) -> &[NamedPose] {
        &self.named_poses
    }

    /// The named pose called `name`, if any.
    pub fn named_pose(&self, name: &str) -> Option<&NamedPose> {
        self.named_poses.iter().find(|p| p.name == name)
    }

    /// The skeleton with every locked section folded into its nearest ancestor that may move
    /// (or the root), and for each old section its section in the new one. A locked joint never
    /// moves its section against its parent, so everything posed stays where it was: a rig
    /// with a bone per free joint instead of one per part.
    pub fn without_locked(&self) -> (Skeleton, Vec<SectionId>) {
        let root = self.section(self.root());
        let mut kept = Skeleton::new(root.rest(), root.name());
        let copy_motion = |kept: &mut Skeleton, new: SectionId, old: Section<'_>| {
            if old.stored.motion != NONE {
                kept.set_motion(new, old.motion());
            }
        };
        copy_motion(&mut kept, SectionId(0), root);
        let mut map = vec![SectionId(0); self.sections.len()];
        // The old section of each new one, for the named poses.
        let mut old = vec![SectionId(0)];
        for id in self.order().into_iter().skip(1) {
            let s = self.section(id);
            let parent = map[s.parent().expect("only the root has no parent").index()];
            map[id.index()] = if s.limits().is_free() {
                let new = kept.add_child(parent, s.rest(), s.name());
                copy_motion(&mut kept, new, s);
                old.push(id);
                new
            } else {
                parent
            };
        }
        kept.named_poses = self
            .named_poses
            .iter()
            .map(|named| NamedPose {
                name: named.name.clone(),
                poses: old.iter().map(|&id| named.pose(id)).collect(),
            })
            .collect();
        (kept, map)
    }

    /// The first section called `name`.
    pub fn find(&self, name: &str) -> Option<SectionId> {
        self.sections()
            .find(|(_, s)| s.name_reads(name))
            .map(|(id, _)| id)
    }

    /// Sections in an order where every parent comes before its children (depth first from
    /// the root, children in link order).
    pub fn order(&self) -> Vec<SectionId> {
        let mut order = Vec::with_capacity(self.sections.len());
        let mut id = 0u32;
        // A cycle cannot arise from the operations above; the bound keeps a corrupted skeleton
        // from looping, and `is_tree` reports it.
        while order.len() <= self.sections.len() {
            order.push(SectionId(id));
            let s = &self.sections[id as usize];
            if s.first_child != NONE {
                id = s.first_child;
                continue;
            }
            // Up to the nearest ancestor with a next sibling.
            let mut at = id;
            loop {
                let s = &self.sections[at as usize];
                if s.next_sibling != NONE {
                    id = s.next_sibling;
                    break;
                }
                match s.parent {
                    NONE | 0 => return order,
                    parent => at = parent,
                }
            }
        }
        order
    }

    /// Every section's frame in model space with all poses applied, indexed by section.
    pub fn posed(&self) -> Vec<Frame> {
        let mut posed = vec![Frame::IDENTITY; self.sections.len()];
        for id in self.order() {
            let local = self.local(id);
            posed[id.index()] = match self.section(id).parent() {
                Some(parent) => posed[parent.index()].mul(&local),
                None => local,
            };
        }
        posed
    }

    /// The rigid motion of one section from the rest pose to the current pose (see
    /// [`Skeleton::skinning`]), walking only its chain to the root; `None` for an unknown id.
    pub fn motion(&self, section: SectionId) -> Option<Frame> {
        let mut chain = Vec::new();
        let mut at = Some(section);
        while let Some(id) = at {
            let s = self.sections.get(id.index())?;
            chain.push(id);
            at = (s.parent != NONE && chain.len() <= self.sections.len())
                .then_some(SectionId(s.parent));
        }
        let posed = chain
            .iter()
            .rev()
            .fold(Frame::IDENTITY, |posed, &id| posed.mul(&self.local(id)));
        Some(posed.mul(&self.section(section).rest().inverse()))
    }

    /// Per section, the rigid motion that takes geometry attached to it from the rest pose to
    /// the current pose: `posed · rest⁻¹`.
    pub fn skinning(&self) -> Vec<Frame> {
        self.posed()
            .iter()
            .zip(self.sections())
            .map(|(posed, (_, s))| posed.mul(&s.rest().inverse()))
            .collect()
    }

    /// Whether the sections form one tree rooted at section 0: every child link is matched by
    /// the child's parent link and every section is reached from the root exactly once.
    pub fn is_tree(&self) -> bool {
        let order = self.order();
        if order.len() != self.sections.len() || self.sections[0].parent != NONE {
            return false;
        }
        let mut seen = vec![false; self.sections.len()];
        for id in order {
            if std::mem::replace(&mut seen[id.index()], true) {
                return false;
            }
        }
        self.sections.iter().enumerate().all(|(id, s)| {
            let id = SectionId(id as u32);
            let mut count = 0;
            let matched = self.children(id).all(|c| {
                count += 1;
                count <= self.sections.len() && self.sections[c.index()].parent == id.0
            });
            matched
                && (s.last_child == NONE) == (s.first_child == NONE)
                && self.children(id).last().map_or(NONE, |c| c.0) == s.last_child
        })
    }
}

/// Skeletons are equal when their sections are, section for section (name, joint, links,
/// limits and pose), and their named poses are: how the tables behind them are laid out does
/// not matter.
impl PartialEq for Skeleton {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len()
            && self.named_poses == other.named_poses
            && self
                .sections()
                .zip(other.sections())
                .all(|((_, a), (_, b))| {
                    let (x, y) = (a.stored, b.stored);
                    (x.parent, x.first_child, x.last_child, x.next_sibling)
                        == (y.parent, y.first_child, y.last_child, y.next_sibling)
                        && a.rest() == b.rest()
                        && a.name() == b.name()
                        && a.motion() == b.motion()
                })
    }
}
