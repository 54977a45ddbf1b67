//! The integration tests of `rsf-seas`, one binary: each file is a module, run with
//! `cargo test -p rsf-seas --test suite [module::test]`.

mod common;

mod first_event;
mod resume;
mod seas_files;
mod strike_dip;
