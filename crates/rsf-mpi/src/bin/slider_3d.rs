//! The 3-D slider on MPI ranks: `rsf-programs`' `slider_3d` (the same flags and files)
//! with every velocity problem solved by TNNMG on the ranks, every rank running the same
//! time steps; rank 0 writes the files, byte-identical at every rank count, but for the
//! VTU frames, which on more than one rank every rank writes in parallel pieces
//! (`frames/frame_NNNNNN_rRRRR.vtu`, indexed by rank 0's `frames/frame_NNNNNN.pvtu`;
//! docs/scaling.md, "Phase 5").
//!
//! Built with `--features hdf5` (and the system's HDF5), `--hdf5 N` writes the body's
//! fields every N steps from rank 0 (`OUT/fields.h5` and its Xdmf index, as crates/rsf-hdf5's
//! binary does in one process).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-mpi/Cargo.toml
//! mpirun -n 2 crates/rsf-mpi/target/release/slider_3d --level 3 --out out/slider_3d_mpi --threads 1
//! ```

fn main() -> std::process::ExitCode {
    rsf_mpi::main_on_ranks(|ranks| {
        rsf_programs::slider_3d::main_on_ranks(ranks, rsf_mpi::field_writers())
    })
}
