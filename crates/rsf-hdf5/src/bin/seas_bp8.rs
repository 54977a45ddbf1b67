//! SEAS BP8 with the fault's fields in one HDF5 file: `rsf-programs`' `seas_bp8` — the
//! same flags, the same files, byte-identical — and with `--hdf5 N` the fault's fields
//! every N steps in `OUT/fields.h5` with its Xdmf index `OUT/fields.xmf` (a poly-vertex
//! at each cell's centre; docs/hdf5.md).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/seas_bp8 --dx 40 --hdf5 10 --out out/seas_bp8
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp8::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared())
}
