//! The SCEC SEAS benchmark BP6-QD-A/S/C (fluid injection into a fault) with its time series
//! also in one HDF5 file: `rsf-programs`' `seas_bp6` — the same flags, the same files,
//! byte-identical — and `seas.h5` in its `--out` folder when it ends
//! (`rsf_hdf5::write_seas_series`).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/seas_bp6 --out out/seas_bp6   # … and out/seas_bp6/seas.h5
//! ```

fn main() -> std::process::ExitCode {
    // The program's default `--out`.
    rsf_hdf5::programs::main_with_series(
        || rsf_programs::seas_bp6::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared()),
        Some("out/seas_bp6"),
    )
}
