//! The topological split grammar of the Shape Grammar Editor.
