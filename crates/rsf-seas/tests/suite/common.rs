//! What the tests share: a small BP1 and its files' headers, scratch folders, a folder's
//! bytes. (Also a module of `crates/rsf-hdf5/tests/series.rs`, by `#[path]`.)

use std::path::PathBuf;

use rsf_seas::{SeasSampling, SeasSetup, SECONDS_PER_YEAR};

#[path = "../../../rsf/tests/suite/common/shared.rs"]
mod shared;
pub use shared::{small_bp1, snapshot};

/// A new empty folder `rsf-seas-NAME-PID` in the temporary folder.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-seas-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The headers of `bp1`'s files at Δz = `dz` (m) in the tests: its first five stations,
/// profiles every km, the stations quiet for half a year and the profiles for five years
/// between events, modeler `A. Tester` on `date`.
pub fn five_stations(bp1: &rsf_scenes::SeasBp1, dz: f64, date: &str) -> SeasSetup {
    let sampling = SeasSampling {
        station_quiet: 0.5 * SECONDS_PER_YEAR,
        profile_quiet: 5.0 * SECONDS_PER_YEAR,
        ..SeasSampling::default()
    };
    let mut setup = SeasSetup {
        modeler: "A. Tester".into(),
        date: date.into(),
        profile_spacing: 1000.0,
        ..bp1.seas_setup(dz, false, sampling)
    };
    setup.stations.truncate(5);
    setup
}
