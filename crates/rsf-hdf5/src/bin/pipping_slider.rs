//! The paper's slider (the workspace's main job) with its fields also in one HDF5 file:
//! `rsf-programs`' `pipping_slider` — the same flags, the same files — and, with
//! `--hdf5 N`, the body's fields every N steps in `OUT/fields.h5` with the Xdmf index
//! `OUT/fields.xmf` (`rsf_hdf5::Hdf5Fields`).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/pipping_slider --hdf5 100   # … and out/pipping_slider/fields.{h5,xmf}
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::pipping_slider::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared())
}
