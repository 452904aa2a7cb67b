//! Implicit solids, CSG, morphing and procedural caves.
