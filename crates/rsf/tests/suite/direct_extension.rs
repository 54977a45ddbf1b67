//! The direct solver's stopping norm with its harmonic extension formed block by block
//! (`DirectOptions::max_extension_bytes`, docs/math.md §8, issue 25) follows the trajectory
//! of the stored extension: the same matrix N up to the order of its sums, so the same
//! steps up to round-off.

use crate::common::*;
use rsf::SolverKind;

/// The paper's slider at level 3 (N = 10⁴, T = 15 s, direct solver) with the extension
/// stored up to `max_extension_bytes`.
fn track(max_extension_bytes: usize) -> Recorder {
    let scene = paper(3, SolverKind::Direct);
    let mut options = scene.solver_options();
    options.direct.max_extension_bytes = max_extension_bytes;
    let mut sim = build_with_options(&scene, options);
    let mut rec = Recorder::new(&sim);
    run_until(&mut sim, end_time(&scene), &mut [&mut rec]);
    rec
}

#[test]
fn a_block_by_block_extension_follows_the_stored_one() {
    let stored = track(usize::MAX);
    let blocks = track(0);
    assert_eq!(stored.len(), blocks.len());
    let first = |r: &Recorder| first_crossing(&r.t, &r.max_v, 1e-3, 0.0).expect("an event");
    let (t0, t1) = (first(&stored), first(&blocks));
    let peak = |r: &Recorder| r.max_v.iter().fold(0.0_f64, |m, &v| m.max(v));
    let scale = stored.u_x0.iter().fold(0.0_f64, |m, u| m.max(u.abs()));
    let du = stored
        .u_x0
        .iter()
        .zip(&blocks.u_x0)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    let (f0, f1) = (stored.fpi_stats(), blocks.fpi_stats());
    println!(
        "first slip {t0} s / {t1} s, peak {:e} / {:e} m/s, max |Δu_x0| = {du:e} of {scale:e} m, \
         FPI mean {} / {}",
        peak(&stored),
        peak(&blocks),
        f0.0,
        f1.0
    );
    assert!((t0 - t1).abs() <= 1e-9 * t0, "first slip {t0} against {t1}");
    assert!((peak(&stored) - peak(&blocks)).abs() <= 1e-6 * peak(&stored));
    assert!(du <= 1e-9 * scale, "max |Δu_x0| = {du:e}");
    assert!(
        (f0.0 - f1.0).abs() <= 1e-3 * f0.0,
        "FPI {f0:?} against {f1:?}"
    );
}
