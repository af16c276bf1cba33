//! The `surrogate` command-line tool.
fn main() {}
