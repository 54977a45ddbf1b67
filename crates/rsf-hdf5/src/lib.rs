//! HDF5 output for rsf, through the `hdf5-metno` binding of the HDF5 C library:
//!
//! - [`Hdf5Fields`]: a run's fields in one HDF5 file with an Xdmf index — the mesh once,
//!   one time axis, each field one dataset over (time, vertex[, component]), the values
//!   of the VTU frames ([`rsf::observe::point_fields`]) — what h5py and xarray read
//!   directly and ParaView opens through the `.xmf` file;
//! - [`write_seas_series`] and the observer [`SeasSeries`]: the time series of a SEAS
//!   benchmark run (the stations, `global.dat`, the profiles, the event catalogue) in one
//!   HDF5 file beside the benchmark's text files, `seas.h5`
//!   ([`SEAS_SERIES_FILE`]);
//! - [`write_greens`] and [`read_greens`]: the Green's functions of a model's faults
//!   ([`rsf::greens::GreensFunctions`]) with the dense fault operator `S`, its geometry,
//!   components, units and accuracy;
//! - the programs (feature `programs`, the default): `seas_bp1`, `seas_bp3`, `seas_bp5`,
//!   `seas_bp6` — the programs of `rsf-programs`, the same flags and files, and `seas.h5` in
//!   their `--out` folder ([`programs::main_with_series`]) — and `seas_hdf5 DIR`, which
//!   writes the `seas.h5` of any SEAS run's folder.
//!
//! This crate is outside the workspace's default build, so that the README's commands
//! need no HDF5 library: on Debian/Ubuntu `apt-get install libhdf5-dev pkg-config`, then
//! `cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml`. Errors are this
//! crate's [`Error`], which converts into [`rsf::Error`] (an observer's methods return
//! one).
#![warn(missing_docs)]

mod attributes;
mod error;
mod fault_fields;
mod fields;
pub(crate) mod frames;
mod greens;
#[cfg(feature = "programs")]
pub mod programs;
mod series;

pub use error::{Error, Result};
pub use fault_fields::{Hdf5FaultFields, FAULT_FIELDS};
pub use fields::Hdf5Fields;
pub use greens::{read_greens, write_greens, GREENS_FORMAT};
pub use series::{seas_files, write_seas_series, SeasSeries, SeriesSummary, SEAS_SERIES_FILE};
