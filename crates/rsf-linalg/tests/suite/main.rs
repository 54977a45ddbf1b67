//! The integration tests of `rsf-linalg`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-linalg --test suite [module::test]`.

mod cholesky;
mod ops;
#[cfg(feature = "sprs")]
mod sprs_conversions;
