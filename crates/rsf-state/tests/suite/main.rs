//! The integration tests of `rsf-state`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-state --test suite [module::test]`.

mod constant_rate;
mod properties;
