//! The integration tests of `rsf-halfspace`, one binary (one link of the crate and its
//! dependencies instead of one per file): each file is a module, run with
//! `cargo test -p rsf-halfspace --test suite [module::test]`.

mod bem;
mod element_set;
mod okada_fixture;
mod okada_properties;
mod triangle;
mod two_d;
