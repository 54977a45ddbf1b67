//! The 3-D slider with its fields also in one HDF5 file: `rsf-programs`' `slider_3d` —
//! the same flags, the same files — and, with `--hdf5 N`, the body's fields every N steps
//! in `OUT/fields.h5` with the Xdmf index `OUT/fields.xmf` (`rsf_hdf5::Hdf5Fields`: the
//! VTU frames' values on one time axis, for h5py and ParaView).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/slider_3d --hdf5 10 --out out/slider_3d   # … and out/slider_3d/fields.{h5,xmf}
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::slider_3d::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared())
}
