//! `rsf-programs`' `bp5_pair` (docs/fault-networks.md) with the faults' fields in one HDF5
//! file: the same flags, the same files, byte-identical — and with `--hdf5 N` the fault
//! network's fields every N steps in `OUT/fields.h5` with its Xdmf index `OUT/fields.xmf`
//! (each node's fault in the field `fault`; docs/hdf5.md).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/bp5_pair --hdf5 10 --out out/bp5_pair
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::bp5_pair::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared())
}
