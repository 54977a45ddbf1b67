//! The integration tests of `rsf-hmatrix`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-hmatrix --test suite [module::test]`.

mod columns;
mod components;
mod hmatrix;
