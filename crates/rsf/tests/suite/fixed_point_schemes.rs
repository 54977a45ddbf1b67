//! The default fixed point scheme (Anderson acceleration, extrapolated predictor, stop on
//! the estimated error; docs/math.md §8) against the paper's relaxed iteration (§6.2, the
//! scheme of every earlier result of this workspace), on the paper's scene at level 3 over
//! the whole T = 15 s (seven slip events), for both state laws (issue 9).
//!
//! Both schemes iterate to the same fixed point; they stop at different iterates, each within
//! the tolerance (1e-10 in the energy norm) of it. That moves the trajectory by the effect of
//! the tolerance only: measured, the slip at x0 agrees to 1.3e-10 of its range and ln of the
//! largest slip rate to 3.5e-8 through all events. Asserted, with margins of 10²–10³ over
//! those values:
//! - the same number of slip events, their start times to 1e-6 s (τ = 1.5e-3 s);
//! - the first-slip time (interpolated in ln V) to 1e-7 s;
//! - u_x(x0) over [0.9 T, T]: its range to 1e-7 relative;
//! - the peak slip rate to 1e-6 relative;
//! - the slip at x0 at every step to 1e-7 of its range.
//!
//! And the point of the new scheme: it needs fewer iterations (measured 2.83 against 4.26
//! for Dieterich's law, 3.03 against 5.00 for Ruina's).
//!
//! Both runs use the direct solver (TNNMG gives the same trajectory to 1e-11 in ln V,
//! `slip_event.rs`), so the comparison isolates the fixed point scheme.

use crate::common::*;
use rsf::method::{FixedPointScheme, InnerSolves};
use rsf::{SolverKind, StateLawKind};
use rsf_scenes::SliderScene;

const SLIP: f64 = 1e-3;
const SLIP_OFF: f64 = 1e-4;

fn record(law: StateLawKind, scheme: FixedPointScheme) -> Recorder {
    record_scene(&SliderScene {
        fixed_point: scheme,
        ..with_law(paper(3, SolverKind::Direct), law)
    })
}

fn record_scene(scene: &SliderScene) -> Recorder {
    let scene = scene.clone();
    let mut sim = build(&scene);
    let mut rec = Recorder::new(&sim);
    run_until(&mut sim, end_time(&scene), &mut [&mut rec]);
    rec
}

fn range_last_tenth(r: &Recorder, t_end: f64) -> (f64, f64) {
    r.t.iter()
        .zip(&r.u_x0)
        .filter(|(t, _)| **t >= 0.9 * t_end)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, &u)| {
            (lo.min(u), hi.max(u))
        })
}

fn compare(law: StateLawKind) {
    let new = record(law, FixedPointScheme::Anderson);
    let old = record(law, FixedPointScheme::Paper);
    same_trajectory(law, &new, &old);
    // Fewer iterations with the new scheme.
    let (m_new, _) = new.fpi_stats();
    let (m_old, _) = old.fpi_stats();
    assert!(
        m_new < 0.8 * m_old,
        "{law:?}: mean iterations {m_new} (default) vs {m_old} (paper)"
    );
}

/// The assertions of the module's header: `new` follows `old` to the effect of the
/// tolerances.
fn same_trajectory(law: StateLawKind, new: &Recorder, old: &Recorder) {
    assert_eq!(new.len(), old.len());
    let t_end = *old.t.last().unwrap();
    // Events.
    let (e_new, e_old) = (
        event_starts(&new.t, &new.max_v, SLIP, SLIP_OFF),
        event_starts(&old.t, &old.max_v, SLIP, SLIP_OFF),
    );
    assert!(e_old.len() >= 5, "{law:?}: the run has its slip events");
    assert_eq!(e_new.len(), e_old.len(), "{law:?}: event count");
    for (a, b) in e_new.iter().zip(&e_old) {
        assert!((a - b).abs() <= 1e-6, "{law:?}: event start {a} vs {b}");
    }
    let (f_new, f_old) = (
        first_crossing(&new.t, &new.max_v, SLIP, 0.0).unwrap(),
        first_crossing(&old.t, &old.max_v, SLIP, 0.0).unwrap(),
    );
    assert!(
        (f_new - f_old).abs() <= 1e-7,
        "{law:?}: first slip {f_new} vs {f_old}"
    );
    // Late displacement range and peak slip rate.
    let (r_new, r_old) = (range_last_tenth(new, t_end), range_last_tenth(old, t_end));
    let width = r_old.1 - r_old.0;
    assert!(width > 0.0);
    assert!(
        (r_new.0 - r_old.0).abs() <= 1e-7 * r_old.1.abs()
            && (r_new.1 - r_old.1).abs() <= 1e-7 * r_old.1.abs(),
        "{law:?}: u_x0 range {r_new:?} vs {r_old:?}"
    );
    let peak = |r: &Recorder| r.max_v.iter().copied().fold(0.0, f64::max);
    let (p_new, p_old) = (peak(new), peak(old));
    assert!(
        (p_new - p_old).abs() <= 1e-6 * p_old,
        "{law:?}: peak slip rate {p_new} vs {p_old}"
    );
    // The slip history at x0.
    let u0 = old.u_x0[0];
    let slip_range = old.u_x0.iter().map(|u| (u - u0).abs()).fold(0.0, f64::max);
    let worst = new
        .u_x0
        .iter()
        .zip(&old.u_x0)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        worst <= 1e-7 * slip_range,
        "{law:?}: slip at x0 differs by {worst:e} of {slip_range:e}"
    );
}

#[test]
fn default_scheme_keeps_the_paper_schemes_trajectory_dieterich() {
    compare(StateLawKind::Aging);
}

#[test]
fn default_scheme_keeps_the_paper_schemes_trajectory_ruina() {
    compare(StateLawKind::Slip);
}

/// Inexact inner solves ([`InnerSolves::BySolver`]: TNNMG's solve of a fixed point iteration
/// stops at a tenth of the previous change, the first after one iteration; docs/math.md
/// §8, issue 25) keep the exact solves' trajectory to the effect of the tolerances, with the
/// same assertions as the schemes above, and need fewer TNNMG iterations (measured here:
/// 5.11 against 8.41 per step; on the 3-D slider at level 3: 5.1 against 9.3). With the
/// direct solver the rule is exact solves, so its steps are those of
/// [`InnerSolves::Exact`] bit for bit.
#[test]
fn inexact_inner_solves_keep_the_trajectory_with_fewer_tnnmg_iterations() {
    let law = StateLawKind::Aging;
    let scene = |inner: InnerSolves| SliderScene {
        fixed_point_inner_solves: inner,
        ..with_law(paper(3, SolverKind::Tnnmg), law)
    };
    let exact = record_scene(&scene(InnerSolves::Exact));
    let inexact = record_scene(&scene(InnerSolves::BySolver));
    same_trajectory(law, &inexact, &exact);
    let total = |r: &Recorder| r.solver_its.iter().sum::<usize>() as f64;
    let (n_inexact, n_exact) = (total(&inexact), total(&exact));
    println!(
        "TNNMG iterations per step: inexact {} / exact {}",
        n_inexact / inexact.len() as f64,
        n_exact / exact.len() as f64
    );
    assert!(
        n_inexact < 0.8 * n_exact,
        "TNNMG iterations {n_inexact} (inexact) vs {n_exact} (exact)"
    );
    assert_eq!(
        InnerSolves::BySolver.rule(SolverKind::Direct),
        InnerSolves::Exact.rule(SolverKind::Direct)
    );
}
