//! The paper's slider extruded to three dimensions (issue 12; docs/math.md §10): the
//! program `rsf_programs::slider_3d` (its flags and files are documented there).
//!
//! ```sh
//! cargo run --release --example slider_3d                          # j = 2, W = 1 m, free faces
//! cargo run --release --example slider_3d -- --level 3 --plane-strain --solver tnnmg
//! cargo run --release --example slider_3d -- --scene my_3d_scene.toml --steps 2e3
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::slider_3d::main()
}
