//! Mesh renders (in progress).
