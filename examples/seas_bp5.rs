//! SEAS BP5-QD (a vertical strike-slip fault in a half-space, two slip components, 3-D;
//! docs/seas-bp5.md), integrated by the fault ODE with either kernel: `--kernel okada`
//! (the default) a fault alone with Okada's half-space operator, loaded by back slip;
//! `--kernel fe` the finite-element volume model condensed onto the fault. The program
//! lives in [`rsf_programs::seas_bp5`] (its flags there and in `--help`), so that the
//! `rsf-mpi` crate runs the same program on MPI ranks.
//!
//! ```sh
//! cargo run --release --example seas_bp5 -- --out out/bp5            # Δx = 2 km, 1800 years
//! cargo run --release --example seas_bp5 -- --dx 1000 --out out/bp5_1km --threads 2
//! cargo run --release --example seas_bp5 -- --kernel fe --dx 2500 --out out/bp5_fe
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp5::main()
}
