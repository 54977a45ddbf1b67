//! SEAS BP7-QD-A / BP7-QD-S: nucleation on a velocity-weakening disc of a square fault
//! in a whole space (docs/seas-bp7.md). The program lives in [`rsf_programs::seas_bp7`]
//! (its flags there and in `--help`).
//!
//! ```sh
//! cargo run --release --example seas_bp7 -- --law aging --out out/bp7a
//! cargo run --release --example seas_bp7 -- --law slip --dx 20 --out out/bp7s
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp7::main()
}
