//! The `beltrami` command-line tool.
fn main() {}
