//! SEAS BP6-QD-A/S/C: fluid injection into a fault in an antiplane whole space
//! (docs/seas-bp6.md). The program lives in [`rsf_programs::seas_bp6`] (its flags there
//! and in `--help`).
//!
//! ```sh
//! cargo run --release --example seas_bp6 -- --variant a --out out/bp6a
//! cargo run --release --example seas_bp6 -- --variant c --dz 50 --out out/bp6c
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp6::main()
}
