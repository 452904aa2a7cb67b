//! Undo and redo for authoring steps (the thesis's users asked for them in 4.1).

use crate::project::{EditError, Project};

/// Most steps kept for undo; older ones are forgotten.
pub const MAX_UNDO: usize = 1000;

/// A project with an undo and a redo stack. Every step is one call of [`Editor::apply`]: a
/// failed step changes nothing and is not recorded.
#[derive(Clone, Debug, Default)]
pub struct Editor {
    project: Project,
    undo: Vec<Project>,
    redo: Vec<Project>,
}

impl Editor {
    /// An editor over `project`, with empty histories.
    pub fn new(project: Project) -> Self {
        Self {
            project,
            undo: Vec::new(),
            redo: Vec::new(),
        }
    }

    /// The current project.
    pub fn project(&self) -> &Project {
        &self.project
    }

    /// The current project, leaving the editor.
    pub fn into_project(self) -> Project {
        self.project
    }

    /// Runs one authoring step. On success it can be undone; on failure the project is restored
    /// and the error returned.
    pub fn apply<T>(
        &mut self,
        step: impl FnOnce(&mut Project) -> Result<T, EditError>,
    ) -> Result<T, EditError> {
        let before = self.project.clone();
        match step(&mut self.project) {
            Ok(value) => {
                if self.undo.len() == MAX_UNDO {
                    self.undo.remove(0);
                }
                self.undo.push(before);
                self.redo.clear();
                Ok(value)
            }
            Err(e) => {
                self.project = before;
                Err(e)
            }
        }
    }

    /// Undoes the last step; `false` when there is none.
    pub fn undo(&mut self) -> bool {
        match self.undo.pop() {
            Some(previous) => {
                self.redo
                    .push(std::mem::replace(&mut self.project, previous));
                true
            }
            None => false,
        }
    }

    /// Redoes the last undone step; `false` when there is none.
    pub fn redo(&mut self) -> bool {
        match self.redo.pop() {
            Some(next) => {
                self.undo.push(std::mem::replace(&mut self.project, next));
                true
            }
            None => false,
        }
    }

    /// Number of steps that can be undone.
    pub fn undo_depth(&self) -> usize {
        self.undo.len()
    }

    /// Number of steps that can be redone.
    pub fn redo_depth(&self) -> usize {
        self.redo.len()
    }
}
