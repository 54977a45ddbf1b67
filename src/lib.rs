//! The examples, benches and end-to-end tests of the rsf workspace (`examples/`, `benches/`,
//! `tests/`). Nothing here is a library: the programs the examples run (flags, run folders,
//! the guard, figures) are the crate `rsf-programs`, the libraries the other `rsf*` crates.
//! Cargo needs one library or binary target per package; this is it.
