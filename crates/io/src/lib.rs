//! # beltrami-io
//!
//! Mesh readers and writers (PLY, STL, OBJ). Work in progress.
