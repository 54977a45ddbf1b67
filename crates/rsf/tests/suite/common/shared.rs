//! The helpers `rsf`'s suite shares with `rsf-seas`'s (whose `common` includes this file by
//! `#[path]`): a small BP1 and a folder's bytes.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A small BP1-like fault (W_f = 10 km, 2 km top, 1 km transition, in a 20 km square) at
/// Δz = 500 m, with the other parameters of `bp1`.
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
