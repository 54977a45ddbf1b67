//! Two parallel strike-slip faults with SEAS BP5's physics, run with the boundary-element
//! kernel or the finite-element volume (docs/fault-networks.md, "Two parallel faults in
//! 3-D"). The program lives in [`rsf_programs::bp5_pair`] (its flags there and in `--help`).
//!
//! ```sh
//! cargo run --release --example bp5_pair -- --kernel okada --dx 2000 --out out/bp5_pair_okada
//! cargo run --release --example bp5_pair -- --kernel fe --dx 2000 --out out/bp5_pair_fe
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::bp5_pair::main()
}
