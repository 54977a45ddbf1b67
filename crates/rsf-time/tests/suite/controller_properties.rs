//! Property tests of the adaptive step controller ([`StepControl`] acting on a
//! [`ControllerState`]; docs/math.md §9).
//!
//! For arbitrary valid options (tolerance, length, `tau_min`, `tau_max = tau_min · 1…1e9`,
//! optionally safety, growth/shrink factors and the state-change cap `ξ`), an arbitrary
//! initial step (clamped by the controller) and an arbitrary sequence of `accept(err,
//! |Δα|)` (err ≤ 1) and `reject(err)` (err ≥ 1 or ∞) calls, every operation must keep:
//!
//! - (a) **bounds**: `tau_min ≤ τ ≤ tau_max` (relative slack 1e-12);
//! - (b) **ladder**: `τ = τ_ref · 2^k` with `τ_ref` the clamped initial step;
//! - (c) **accept**: growth at most `max_factor`, the cap `τ ≤ ξ τ_before / |Δα|` (unless
//!   that is below the lowest rung at or above `tau_min`, which is then taken), and the
//!   proposal `τ · clamp(s · err^{−1/2}, f_min, f_max)` (capped, clamped to the bounds) is
//!   rounded *down* to the ladder by less than a factor 2, never below the lowest rung;
//! - (d) **reject**: `Ok` with a strictly smaller step (at most `τ_before / 2`, at most the
//!   shrink factor rounded down to the ladder), or `Err(StepTooSmall)` exactly when the
//!   rung below, `τ_before / 2`, is under `tau_min`, with τ unchanged;
//! - (e) **counters**: `accepted()` / `rejected()` count the calls — a rejection that
//!   returns `Err` is counted as well (`reject` increments before checking) — and
//!   `last_error()` is the error of the last call;
//! - (f) **checkpoints**: `to_values` then `ControllerState::from_values` reproduces the
//!   controller's state (`==`), the reference of the ladder included.
//!
//! Two bugs these properties found are pinned by regression tests at the end of this file:
//! `reject` panicked for `min_factor > 0.5` (`f64::clamp` with lo > hi), and a state
//! written after `reject(∞)` (a failed attempt) could not be restored.

use proptest::prelude::*;
use rsf_time::{ControllerState, Error, StepControl};

/// Relative slack of the controller's own comparisons (`rung_below`, `reject`).
const SLACK: f64 = 1e-12;

/// `10^e` with the exponent `e` uniform in `[lo, hi]`.
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo..=hi).prop_map(|e: f64| 10f64.powf(e))
}

/// How the state-change cap of [`StepControl::new`] (`Some(0.5)`) is varied.
#[derive(Debug, Clone, Copy)]
enum Cap {
    Default,
    Set(Option<f64>),
}

fn options() -> impl Strategy<Value = StepControl> {
    let tau_max_factor = prop_oneof![
        1 => Just(1.0),
        1 => Just(2.0),
        8 => log_uniform(0.0, 9.0),
    ];
    let tuning = prop::option::of((
        (0.0..0.9_f64).prop_map(|x| 1.0 - x), // safety in (0.1, 1]
        0.05..=0.9_f64,
        1.1..=10.0_f64,
    ));
    let cap = prop_oneof![
        1 => Just(Cap::Default),
        1 => Just(Cap::Set(None)),
        2 => log_uniform(-3.0, 1.0).prop_map(|xi| Cap::Set(Some(xi))),
    ];
    (
        log_uniform(-8.0, -1.0),
        log_uniform(-9.0, 0.0),
        log_uniform(-12.0, -3.0),
        tau_max_factor,
        tuning,
        cap,
    )
        .prop_map(|(tol, length, tau_min, factor, tuning, cap)| {
            let mut o = StepControl::new(tol, length, tau_min, tau_min * factor).unwrap();
            if let Some((safety, min_factor, max_factor)) = tuning {
                o.safety = safety;
                o.min_factor = min_factor;
                o.max_factor = max_factor;
            }
            if let Cap::Set(cap) = cap {
                o.state_change_cap = cap;
            }
            o.validate().unwrap();
            o
        })
}

#[derive(Debug, Clone, Copy)]
enum Op {
    Accept { err: f64, state_change: f64 },
    Reject { err: f64 },
}

fn op() -> impl Strategy<Value = Op> {
    let accept_err = prop_oneof![Just(0.0), Just(1e-300), log_uniform(-12.0, 0.0), Just(1.0)];
    let state_change = prop_oneof![Just(0.0), log_uniform(-12.0, 3.0)];
    let reject_err = prop_oneof![Just(f64::INFINITY), log_uniform(0.0, 12.0)];
    prop_oneof![
        (accept_err, state_change).prop_map(|(err, state_change)| Op::Accept { err, state_change }),
        reject_err.prop_map(|err| Op::Reject { err }),
    ]
}

/// The lowest rung `τ_ref · 2^k` at or above `tau_min` (with the controller's slack); the
/// ladder never goes below it and `rung_below` rounds up to it.
fn lowest_rung(tau_ref: f64, tau_min: f64) -> f64 {
    let mut r = tau_ref;
    while r / 2.0 >= tau_min * (1.0 - SLACK) {
        r /= 2.0;
    }
    r
}

/// (a) and (b).
fn check_bounds_and_ladder(
    o: &StepControl,
    c: &ControllerState,
    tau_ref: f64,
) -> Result<(), TestCaseError> {
    let tau = c.tau();
    prop_assert!(
        tau >= o.tau_min * (1.0 - SLACK) && tau <= o.tau_max * (1.0 + SLACK),
        "τ = {tau:e} outside [{:e}, {:e}]",
        o.tau_min,
        o.tau_max
    );
    let k = (tau / tau_ref).log2();
    prop_assert!(
        (k - k.round()).abs() <= 1e-9,
        "τ = {tau:e} off the ladder of τ_ref = {tau_ref:e} (log2 ratio {k})"
    );
    Ok(())
}

/// (c): `c` after `accept(err, state_change)` from the step `tau`.
fn check_accept(
    o: &StepControl,
    c: &ControllerState,
    tau: f64,
    err: f64,
    state_change: f64,
    bottom: f64,
) -> Result<(), TestCaseError> {
    let new = c.tau();
    // Only err ≤ 1 is generated (a step with err > 1 is rejected, not accepted).
    prop_assert!(
        new <= o.max_factor * tau * (1.0 + SLACK),
        "grew from {tau:e} to {new:e}, more than max_factor = {}",
        o.max_factor
    );
    let factor = if err > 0.0 {
        (o.safety * err.powf(-0.5)).clamp(o.min_factor, o.max_factor)
    } else {
        o.max_factor
    };
    let mut proposal = tau * factor;
    if let (Some(xi), true) = (o.state_change_cap, state_change > 0.0) {
        let cap = xi * tau / state_change;
        // Rounded down to the ladder, but never below tau_min: when the cap is under the
        // lowest rung at or above tau_min, that rung is taken.
        prop_assert!(
            new <= (cap * (1.0 + SLACK)).max(bottom),
            "state cap ξτ/|Δα| = {cap:e} (lowest rung {bottom:e}) exceeded: {new:e}"
        );
        proposal = proposal.min(cap);
    }
    // The proposal, clamped to the bounds, is rounded down to the ladder (by less than a
    // factor 2), or up to the lowest rung when it is below tau_min.
    let clamped = proposal.clamp(o.tau_min, o.tau_max);
    prop_assert!(
        new <= (clamped * (1.0 + SLACK)).max(bottom) && 2.0 * new > clamped * (1.0 - SLACK),
        "proposal {proposal:e} (clamped {clamped:e}) became {new:e} (lowest rung {bottom:e})"
    );
    Ok(())
}

/// (d): `c` after `reject(err)` from the step `tau` returned `result`.
fn check_reject(
    o: &StepControl,
    c: &ControllerState,
    tau: f64,
    err: f64,
    result: &rsf_time::Result<()>,
    bottom: f64,
) -> Result<(), TestCaseError> {
    let new = c.tau();
    let no_rung_below = tau / 2.0 < o.tau_min * (1.0 - SLACK);
    match result {
        Err(Error::StepTooSmall { tau: t, tau_min }) => {
            prop_assert!(no_rung_below, "StepTooSmall at τ = {tau:e} > 2 tau_min");
            prop_assert_eq!(*t, tau);
            prop_assert_eq!(*tau_min, o.tau_min);
            prop_assert_eq!(new, tau, "τ changed by a failed rejection");
        }
        Err(e) => prop_assert!(false, "unexpected error {e:?}"),
        Ok(()) => {
            prop_assert!(!no_rung_below, "Ok at τ = {tau:e} < 2 tau_min");
            prop_assert!(
                new < tau && new <= tau / 2.0,
                "{tau:e} → {new:e} is not a rung lower"
            );
            let factor = if err.is_finite() && err > 0.0 {
                (o.safety * err.powf(-0.5)).clamp(o.min_factor.min(0.5), 0.5)
            } else {
                0.25
            };
            let target = (tau * factor).clamp(o.tau_min, o.tau_max);
            prop_assert!(
                new <= (target * (1.0 + SLACK)).max(bottom),
                "{tau:e} → {new:e}, more than the factor {factor} (lowest rung {bottom:e})"
            );
            prop_assert!(
                2.0 * new > target.min(tau) * (1.0 - SLACK),
                "{tau:e} → {new:e}: rounded down by more than a rung (factor {factor})"
            );
        }
    }
    Ok(())
}

/// (f): a checkpoint of the state restores it.
fn check_round_trip(c: &ControllerState) -> Result<(), TestCaseError> {
    let state = c.to_values();
    let d = ControllerState::from_values(&state);
    prop_assert!(d.is_ok(), "state {state:?} not restored");
    prop_assert_eq!(c, &d.unwrap());
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn controller_invariants(
        o in options(),
        tau0 in log_uniform(-15.0, 3.0),
        ops in prop::collection::vec(op(), 0..=200),
    ) {
        let mut c = o.start(tau0).unwrap();
        let tau_ref = c.tau();
        prop_assert_eq!(tau_ref, tau0.clamp(o.tau_min, o.tau_max));
        let bottom = lowest_rung(tau_ref, o.tau_min);
        check_bounds_and_ladder(&o, &c, tau_ref)?;
        check_round_trip(&c)?;
        let (mut accepted, mut rejected) = (0_u64, 0_u64);
        for op in ops {
            let tau = c.tau();
            let err = match op {
                Op::Accept { err, state_change } => {
                    o.accept(&mut c, err, state_change);
                    accepted += 1;
                    check_accept(&o, &c, tau, err, state_change, bottom)?;
                    err
                }
                Op::Reject { err } => {
                    let result = o.reject(&mut c, err);
                    rejected += 1; // also when `result` is an error
                    check_reject(&o, &c, tau, err, &result, bottom)?;
                    err
                }
            };
            prop_assert_eq!(c.accepted(), accepted);
            prop_assert_eq!(c.rejected(), rejected);
            prop_assert_eq!(c.last_error(), err);
            // (The options cannot change: `accept` and `reject` take them by `&self`.)
            check_bounds_and_ladder(&o, &c, tau_ref)?;
            check_round_trip(&c)?;
        }
    }
}

fn control() -> StepControl {
    StepControl::new(1e-3, 1e-5, 1e-6, 1.0).unwrap()
}

/// Regression: `validate` accepts `min_factor` in (0, 1), but `reject` computed
/// `(s · err^{−1/2}).clamp(min_factor, 0.5)`, and `f64::clamp` panics when `min > max`.
/// Minimal case found by the properties: `min_factor = 0.6`, `reject(4.0)`.
#[test]
fn reject_with_min_factor_above_one_half() {
    let mut o = control();
    o.min_factor = 0.6;
    o.validate().unwrap();
    let mut c = o.start(1e-3).unwrap();
    o.reject(&mut c, 4.0).unwrap();
    assert!(c.tau() < 1e-3);
}

/// Regression: `reject(f64::INFINITY)` (the documented call for a failed attempt) stores
/// `last_error = ∞` and `to_values` writes it; restoring refused non-finite values, so
/// such a checkpoint could not be restored. NaN and negative errors are still refused.
#[test]
fn round_trip_after_a_failed_attempt() {
    let o = control();
    let mut c = o.start(1e-3).unwrap();
    o.reject(&mut c, f64::INFINITY).unwrap();
    let d = ControllerState::from_values(&c.to_values()).unwrap();
    assert_eq!(c, d);
    let mut bad = c.to_values();
    for x in [f64::NAN, -1.0] {
        bad[4] = x;
        assert!(
            ControllerState::from_values(&bad).is_err(),
            "last error {x} accepted"
        );
    }
}
