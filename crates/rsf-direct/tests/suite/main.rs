//! The integration tests of `rsf-direct`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-direct --test suite [module::test]`.

mod common;
mod elasticity_box;

mod interior_ordering;
mod schur_only;
mod solver;
