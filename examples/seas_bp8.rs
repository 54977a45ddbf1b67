//! SEAS BP8-QD-GS / BP8-QD-PW: fluid injection into a velocity-strengthening square fault
//! in a whole space (docs/seas-bp8.md). The program lives in [`rsf_programs::seas_bp8`]
//! (its flags there and in `--help`).
//!
//! ```sh
//! cargo run --release --example seas_bp8 -- --source gs --out out/bp8gs
//! cargo run --release --example seas_bp8 -- --source pw --dx 20 --out out/bp8pw
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp8::main()
}
