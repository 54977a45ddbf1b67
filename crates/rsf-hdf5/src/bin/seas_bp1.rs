//! The SCEC SEAS benchmark BP1-QD (BP1-FD with `--inertia`) with its time series also in
//! one HDF5 file: `rsf-programs`' `seas_bp1` — the same flags, the same files,
//! byte-identical — and `seas.h5` in its `--out` folder when it ends
//! (`rsf_hdf5::write_seas_series`).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/seas_bp1 --out out/seas_bp1   # … and out/seas_bp1/seas.h5
//! ```

fn main() -> std::process::ExitCode {
    rsf_hdf5::programs::main_with_series(
        || rsf_programs::seas_bp1::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared()),
        None,
    )
}
