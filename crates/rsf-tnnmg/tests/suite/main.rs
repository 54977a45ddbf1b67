//! The integration tests of `rsf-tnnmg`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-tnnmg --test suite [module::test]`.

mod common;

mod smoother;
mod solvers;
