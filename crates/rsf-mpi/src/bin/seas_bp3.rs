//! SEAS BP3-QD on MPI ranks: `rsf-programs`' `seas_bp3` (the same flags, the same files,
//! byte-identical) with every evaluation of its fault ODE shared by the ranks
//! (docs/scaling.md, "The fault ODE on MPI ranks").
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml
//! mpirun -n 2 crates/rsf-mpi/target/release/seas_bp3 --out out/bp3_mpi --threads 1
//! ```

fn main() -> std::process::ExitCode {
    rsf_mpi::main_on_ranks(rsf_programs::seas_bp3::main_on_ranks)
}
