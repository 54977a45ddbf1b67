//! What the end-to-end tests share (a module of each test binary that declares `mod common;`).
// Each test binary uses a part of it.
#![allow(dead_code)]

use std::path::PathBuf;

/// The main job: the package's binary (src/main.rs), not an example.
pub const MAIN_JOB: &str = "pipping_slider";

/// The binary of the program `name`: the main job's (Cargo's `CARGO_BIN_EXE_…`) or the
/// example's, which `cargo test` builds beside the test's executable
/// (`target/<profile>/examples/`).
///
/// # Panics
/// The example is not built (the test was not run by `cargo test`).
pub fn program_binary(name: &str) -> PathBuf {
    if name == MAIN_JOB {
        return PathBuf::from(env!("CARGO_BIN_EXE_pipping_slider"));
    }
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap().join("examples");
    let path = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.is_file(),
        "{} not built: run the tests with `cargo test` (which builds the examples)",
        path.display()
    );
    path
}
