//! The output files of the SCEC SEAS benchmarks (Erickson et al. 2020, Seismol. Res. Lett.
//! 91(2); Jiang et al. 2022, JGR Solid Earth 127) for runs of [`rsf`], as
//! [`Observer`](rsf::Observer)s:
//!
//! - the SCEC text format every file shares: the `#` header lines ([`common_header`]), one
//!   `# Column #k` line per column, the field-list line(s), rows of numbers in C's `%E`
//!   formats ([`c_exp`]), the run's date ([`utc_date_today`], [`is_iso_date`]);
//! - along dip, the 2-D benchmarks BP1 and BP3 ([`SeasOutput`], [`SeasLayout`]): stations by
//!   depth or down-dip distance (`fltst_dpXXX`), stations off the fault (`srfst_fn…`),
//!   profiles (`devol.dat`, `slip.dat`, the stresses), the event catalogue `events.csv`;
//! - on a strike–dip grid, the 3-D benchmarks BP5, BP7 and BP8 ([`SeasBp5Output`]):
//!   stations `fltst_strk±XXdp±YY` and `blkst_strk±XXfn±YYdp±ZZ` (BP5, km; BP7 and BP8
//!   in m, three digits, BP8's with the pore pressure and Darcy velocity), `global.dat`,
//!   profiles along strike and dip, `rupture.dat`, the catalogue;
//! - along strike, BP6 (fluid injection, [`SeasBp6Output`]): stations with pore pressure
//!   and Darcy velocity, `global.dat`, four profiles;
//! - the files read back ([`read_seas_file`]): header, columns, a profile's positions, the
//!   rows as numbers;
//! - their resume logs ([`SEAS_RESUME_LOG`], [`SEAS_BP5_RESUME_LOG`]): a run continued from
//!   a checkpoint continues the files, byte-identical to an uninterrupted run's.
//!
//! What a file's header holds is one description for every layout (a location, columns, a
//! profile's positions), and the resume of a station or profile file one check (its
//! field-list lines, the rows up to the checkpoint's step, complete, the last at the time
//! of the log); the layouts differ where the benchmarks do.
//!
//! The problems themselves (`SeasBp1`, `SeasBp3`, `SeasBp5`, their stations and set-ups)
//! are in the crate `rsf-scenes`, which uses this one. Errors are this crate's [`Error`],
//! which converts into [`rsf::Error`] (an observer's methods return one).
#![warn(missing_docs)]

mod along_dip;
mod bp6;
mod error;
mod read;
mod reserve;
mod resume;
mod setup;
mod strike_dip;
mod text;

pub use along_dip::resume::SEAS_RESUME_LOG;
pub use along_dip::SeasOutput;
pub use bp6::{
    bp6_profile_positions, bp6_station_name, Bp6Fault, SeasBp6Output, BP6_SLIP_RATE_FLOOR,
    SEAS_BP6_RESUME_LOG, SEAS_BP6_STATIONS,
};
pub use error::{Error, Result};
pub use read::{is_seas_file, read_seas_file, SeasColumn, SeasFile};
pub use reserve::RESERVE_FILE;
pub use setup::{
    SeasEvent, SeasLayout, SeasSampling, SeasSetup, SeasSurfaceStation, SEAS_BP1_STATION_COLUMNS,
    SEAS_BP3_STATION_COLUMNS, SECONDS_PER_YEAR,
};
pub use strike_dip::{
    bp5_body_station_points, bp7_body_station_points, Bp5Event, SeasBp5Output, StrikeDipFault,
    NEVER_RUPTURED, RUPTURE_THRESHOLD, SEAS_BP5_BODY_STATIONS, SEAS_BP5_FAULT_STATIONS,
    SEAS_BP5_RESUME_LOG, SEAS_BP7_BODY_STATIONS, SEAS_BP7_FAULT_STATIONS, SEAS_BP7_RESUME_LOG,
    SEAS_BP8_FAULT_STATIONS, SEAS_BP8_RESUME_LOG, SLIP_RATE_FLOOR,
};
pub use text::{c_exp, common_header, is_iso_date, utc_date_today, SEAS_FIRST_LINE};
