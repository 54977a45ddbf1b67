//! The SCEC SEAS benchmark BP5-QD (a vertical strike-slip fault in a 3-D half-space) with
//! its time series also in one HDF5 file: `rsf-programs`' `seas_bp5` — the same flags,
//! the same files, byte-identical — and `seas.h5` in its `--out` folder when it ends
//! (`rsf_hdf5::write_seas_series`).
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/seas_bp5 --out out/seas_bp5   # … and out/seas_bp5/seas.h5
//! ```

fn main() -> std::process::ExitCode {
    // The program's default `--out`.
    rsf_hdf5::programs::main_with_series(
        || rsf_programs::seas_bp5::main_with_fields(rsf_hdf5::programs::Hdf5Writers::shared()),
        Some("out/seas_bp5"),
    )
}
