//! What the tests share: a small BP1, scratch folders, a folder's bytes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// BP1 made small: a 10 km fault (2 km top, 1 km transition) on a 500 m grid in a 20 km
/// domain.
pub fn small_bp1(bp1: &rsf_scenes::SeasBp1) -> (rsf_scenes::SeasBp1, rsf_scenes::SeasBp1Grid) {
    (
        rsf_scenes::SeasBp1 {
            h_top: 2e3,
            h_transition: 1e3,
            w_f: 10e3,
            ..*bp1
        },
        rsf_scenes::SeasBp1Grid {
            dz: 500.0,
            domain: 20e3,
            ratio: 1.1,
        },
    )
}

/// A new empty folder `rsf-seas-NAME-PID` in the temporary folder.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rsf-seas-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every file under `dir` (recursively) with its bytes.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(snapshot(&p));
        } else {
            out.insert(p.clone(), std::fs::read(&p).unwrap());
        }
    }
    out
}
