//! The integration tests of `rsf-time`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-time --test suite [module::test]`.

mod controller_properties;
mod elastodynamics;
