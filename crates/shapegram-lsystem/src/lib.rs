//! L-systems: rewriting and turtle interpretation.
