//! The SCEC SEAS benchmark BP1-QD on MPI ranks: `rsf-programs`' `seas_bp1` (the same
//! flags, the same files, byte-identical) with every evaluation of its Runge–Kutta run
//! shared by the ranks (docs/scaling.md, "Past one machine").
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml
//! mpirun -n 2 crates/rsf-mpi/target/release/seas_bp1 --out out/bp1_mpi --threads 1
//! ```

fn main() -> std::process::ExitCode {
    rsf_mpi::main_on_ranks(rsf_programs::seas_bp1::main_on_ranks)
}
