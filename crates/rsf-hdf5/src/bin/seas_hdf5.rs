//! The time series of a SEAS run's folder in one HDF5 file (`rsf_hdf5::write_seas_series`):
//! for a folder written by the programs of `rsf-programs` (`cargo run --release --example
//! seas_bp1 -- --out DIR`), which need no HDF5, or after a run stopped at `--max-steps`.
//!
//! ```text
//! cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml
//! crates/rsf-hdf5/target/release/seas_hdf5 out/seas_bp1            # → out/seas_bp1/seas.h5
//! crates/rsf-hdf5/target/release/seas_hdf5 out/seas_bp1 --output bp1.h5
//! ```
//!
//! The folder's `seas.h5` is rebuilt from its files (it is theirs); another `--output`
//! file is replaced only with `--overwrite`. The folder's lock is held while it is read.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rsf_hdf5::{write_seas_series, SEAS_SERIES_FILE};

#[derive(Parser, Debug)]
#[command(about = "The time series of a SEAS run's folder in one HDF5 file")]
struct Args {
    /// The run's folder (its `--out`).
    dir: PathBuf,
    /// The HDF5 file (default: `seas.h5` in the folder).
    #[arg(long)]
    output: Option<PathBuf>,
    /// Replace an existing `--output` file.
    #[arg(long)]
    overwrite: bool,
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    if !args.dir.is_dir() {
        return Err(format!("`{}` is not a folder", args.dir.display()).into());
    }
    let Some(output) = &args.output else {
        return rsf_hdf5::programs::write_series_locked(&args.dir);
    };
    if !args.overwrite {
        rsf::observe::refuse_existing(output)
            .map_err(|e| format!("--output: {e}; pass --overwrite to replace it"))?;
    }
    let _lock = rsf_programs::guard::lock(&args.dir)?;
    let summary = write_seas_series(&args.dir, output)?;
    let rows: usize = summary.groups.iter().map(|g| g.1).sum();
    eprintln!(
        "{}: {} groups, {rows} rows (the SEAS files of `{}`; by default `{SEAS_SERIES_FILE}` there)",
        output.display(),
        summary.groups.len(),
        args.dir.display()
    );
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
