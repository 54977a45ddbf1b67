//! SEAS BP3-QD on MPI ranks: `rsf-programs`' `seas_bp3` (the same flags, the same files,
//! byte-identical) with every evaluation of its fault ODE shared by the ranks
//! (docs/scaling.md, "The fault ODE on MPI ranks").
//!
//! Built with `--features hdf5` (and the system's HDF5), `--hdf5 N` writes the fault's
//! fields every N steps from rank 0 (`OUT/fields.h5` and its Xdmf index, as crates/rsf-hdf5's
//! binary does in one process).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml
//! mpirun -n 2 crates/rsf-mpi/target/release/seas_bp3 --out out/bp3_mpi --threads 1
//! ```

fn main() -> std::process::ExitCode {
    rsf_mpi::main_on_ranks(|ranks| {
        rsf_programs::seas_bp3::main_on_ranks(ranks, rsf_mpi::field_writers())
    })
}
