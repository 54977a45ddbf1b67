//! The integration tests of `rsf-friction`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-friction --test suite [module::test]`.

mod normal_stress;
mod properties;
mod published_asinh;
mod slip_scaled;
