//! Stability on stiff and extreme cases (issue 6): the paper's slider at level 2, a few
//! hundred steps per case, parameters pushed one at a time far from Table 6.1.
//!
//! Every case must end either in `Ok` with all values finite, or in the typed error the
//! case expects (asserted by variant) — never NaN, ∞, a hang or a panic. The same case
//! list drives `examples/stability_table.rs`, which prints the table of `docs/stability.md`
//! (that example includes this file as a module, so the table and the test cannot drift).
//!
//! The physics of each `Ok` case is asserted too (issue 13): a case that stays stuck keeps
//! every slip rate below 10 V_m(α₀), its own cutoff velocity; a case that slips reaches a
//! peak slip rate within a decade of the spring–block estimate 2 V_L (see [`case`]); every
//! step's fixed point correction meets the tolerance.

use std::time::Instant;

use rsf::friction::{DieterichRuina, RateStateParams};
use rsf::method::FixedPointOptions;
use rsf::{Error, Integrator};
use rsf_scenes::{SceneSimulation, SliderScene};

/// What a case is expected to end in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expect {
    /// All steps succeed, all values finite.
    Ok,
    /// `Error::FixedPointNotConverged` (a limit of the method, not of the code).
    FixedPointNotConverged,
    /// A parameter error at set-up (`Error::InvalidParameter` or `Error::Friction`).
    InvalidParameter,
}

/// Frictional parameters along Γ_F.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// The scene's `a`, `b` everywhere.
    Uniform,
    /// Velocity-weakening patch `|x − 2.5| ≤ half_width` with the scene's `(a, b)`,
    /// velocity strengthening outside with `(a, b)` swapped.
    Patch {
        /// Half width of the patch (m).
        half_width: f64,
    },
}

/// One stability case.
#[derive(Debug, Clone)]
pub struct Case {
    /// Short name (table row).
    pub name: &'static str,
    /// What is pushed to the extreme, in words.
    pub what: &'static str,
    /// The scene (level, τ = T/N, parameters).
    pub scene: SliderScene,
    /// Steps to take.
    pub steps: usize,
    /// Heterogeneity of `a, b`.
    pub fault: Fault,
    /// `Some(ω)`: the paper's relaxed fixed point iteration with damping ω (paper: 0.5);
    /// `None`: the default scheme (Anderson acceleration, `FixedPointOptions::default`).
    pub paper_relaxation: Option<f64>,
    /// The expected outcome.
    pub expect: Expect,
    /// Bounds on the largest slip rate of an `Ok` run (m/s): a decade around the
    /// spring–block estimate 2 V_L for a case that slips ([`case`]), `[0, 10 V_m(α₀)]` for a
    /// case that stays stuck ([`stuck`]).
    pub peak: (f64, f64),
}

/// What running a case produced.
#[derive(Debug)]
pub struct Outcome {
    /// Steps completed successfully.
    pub steps_done: usize,
    /// Mean fixed point iterations per completed step.
    pub fpi_mean: f64,
    /// Maximum fixed point iterations of a completed step.
    pub fpi_max: usize,
    /// Velocity-solver iterations per velocity solve (mean).
    pub solver_per_solve: f64,
    /// Maximum velocity-solver iterations of one step.
    pub solver_max: usize,
    /// Steps that used the damped relaxation ω < 1 at least once.
    pub relaxed_steps: usize,
    /// Largest slip rate on Γ_F over the run (m/s).
    pub max_slip_rate: f64,
    /// Largest fixed point error of a completed step: the quantity its stopping test
    /// compared with the tolerance (`StepReport::fixed_point_error`).
    pub max_correction: f64,
    /// Smallest slip rate on Γ_F at the end (m/s).
    pub min_slip_rate_end: f64,
    /// Range of α on Γ_F at the end.
    pub alpha_range: (f64, f64),
    /// Whether every report, u, v, a and α stayed finite.
    pub finite: bool,
    /// Wall time (s).
    pub seconds: f64,
    /// The error that ended the run early, if any.
    pub error: Option<Error>,
}

impl Outcome {
    /// Whether the outcome is what the case expects.
    pub fn as_expected(&self, expect: Expect) -> bool {
        match expect {
            Expect::Ok => self.error.is_none() && self.finite,
            Expect::FixedPointNotConverged => {
                self.finite && matches!(self.error, Some(Error::FixedPointNotConverged { .. }))
            }
            Expect::InvalidParameter => {
                self.steps_done == 0
                    && matches!(
                        self.error,
                        Some(Error::InvalidParameter { .. } | Error::Friction(_))
                    )
            }
        }
    }
}

/// The base of all cases: the paper's scene (Table 6.1) at level 2 with τ = 1e-3 s, but
/// loaded without ramp at 2e-2 m/s so that the first slip event happens within the run
/// (the paper's ramp and 2e-4 m/s reach it only after ~10 s). α₀ = −10 as in the paper:
/// `V_m ≈ 1e-24 m/s`, the stiff sticking regime from the first step.
pub fn base() -> SliderScene {
    SliderScene {
        level: 2,
        steps: 300,
        end_time_s: 0.3,
        loading_velocity_m_per_s: 2e-2,
        ramp_fraction: 0.0,
        ..SliderScene::default()
    }
}

/// A case that slips. Its peak slip rate must lie within a decade of the spring–block
/// estimate `2 V_L` (V_L the loading velocity of Γ_D): the slider is a block of mass m on a
/// shear spring k (docs/spring-block.md, with inertia) that starts at rest while the load
/// point moves at V_L. Once the spring force reaches the friction force F, the block slides
/// against a friction force that stays near F (rate-and-state friction changes by
/// `aσ̄_n ln(V/V*)`, small against F), so `m ẍ = k(V_L t − x) − F` with `ẋ(0) = 0` gives
/// `ẋ = V_L (1 − cos ωt)`, whose peak is 2 V_L; a drop ΔF of the friction force adds
/// `ΔF/√(km)`. Measured peaks are 1.9–14 V_L.
fn case(name: &'static str, what: &'static str, scene: SliderScene) -> Case {
    let v_l = scene.loading_velocity_m_per_s;
    Case {
        name,
        what,
        steps: scene.steps,
        scene,
        fault: Fault::Uniform,
        paper_relaxation: None,
        expect: Expect::Ok,
        peak: (0.2 * v_l, 20.0 * v_l),
    }
}

/// A case that stays stuck: every slip rate of the run stays below `10 V_m(α₀)`, the case's
/// own cutoff velocity (2.13). Below V_m friction vanishes, and a stuck node's slip rate is
/// `V_m e^{τ_s/(aσ̄_n)}` for a shear stress τ_s; staying within a factor 10 of V_m means the
/// shear stress on Γ_F stays below `aσ̄_n ln 10`, i.e. the load has not reached Γ_F
/// (τ ≤ 1e-5 s: 300 steps are shorter than a shear wave's transit) or is negligible against
/// σ̄_n (σ̄_n = 1e8 Pa). Measured: 0.03–1.0 V_m.
fn stuck(c: Case) -> Case {
    let p = c.scene.rate_state_params();
    let v_m = p.ln_cutoff_velocity(c.scene.alpha0).exp();
    Case {
        peak: (0.0, 10.0 * v_m),
        ..c
    }
}

/// With τ changed to `tau` keeping the number of steps.
fn with_tau(tau: f64) -> SliderScene {
    let b = base();
    SliderScene {
        end_time_s: tau * b.steps as f64,
        ..b
    }
}

/// `L = 1e-9 m`: slip increments `τV/L` up to ~6e4 per step.
fn tiny_l() -> SliderScene {
    SliderScene {
        l_m: 1e-9,
        ..base()
    }
}

/// The case list (table order).
pub fn cases() -> Vec<Case> {
    let b = base;
    let mut v = vec![
        case("base", "paper parameters, fast loading", b()),
        case(
            "rock",
            "E = 3e10 Pa, ρ = 2700 kg/m², same τ",
            SliderScene {
                youngs_modulus_pa: 3e10,
                density_kg_per_m2: 2700.0,
                ..b()
            },
        ),
        stuck(case("tau-1e-7", "τ = 1e-7 s", with_tau(1e-7))),
        stuck(case("tau-1e-5", "τ = 1e-5 s", with_tau(1e-5))),
        case("tau-1e-1", "τ = 0.1 s", with_tau(0.1)),
        case(
            "L-1e-9",
            "L = 1e-9 m (τV/L up to 6e4), default scheme",
            tiny_l(),
        ),
        Case {
            expect: Expect::FixedPointNotConverged,
            paper_relaxation: Some(0.5),
            ..case(
                "L-1e-9, paper",
                "L = 1e-9 m, the paper's iteration (ω = 0.5)",
                tiny_l(),
            )
        },
        Case {
            expect: Expect::FixedPointNotConverged,
            paper_relaxation: Some(0.5),
            ..case(
                "L-1e-9, paper, 1000 FPI",
                "L = 1e-9 m, the paper's iteration, budget 1000, ω = 0.5",
                SliderScene {
                    fixed_point_max_iterations: 1000,
                    ..tiny_l()
                },
            )
        },
        Case {
            paper_relaxation: Some(1.0),
            ..case(
                "L-1e-9, paper, ω=1, 1000 FPI",
                "L = 1e-9 m, the paper's iteration with ω ≡ 1, budget 1000",
                SliderScene {
                    fixed_point_max_iterations: 1000,
                    ..tiny_l()
                },
            )
        },
        case("L-1e-1", "L = 0.1 m", SliderScene { l_m: 1e-1, ..b() }),
    ];
    for (name, ratio) in [
        ("b/a-0.5", 0.5),
        ("b/a-1.5", 1.5),
        ("b/a-2.5", 2.5),
        ("b/a-5", 5.0),
    ] {
        v.push(case(
            name,
            "b/a with a = 0.01",
            SliderScene {
                b: 0.01 * ratio,
                ..b()
            },
        ));
    }
    v.extend([
        case(
            "alpha0--50",
            "α₀ = −50 (V_m ≈ 0.1 m/s)",
            SliderScene {
                alpha0: -50.0,
                ..b()
            },
        ),
        case(
            "alpha0-+50",
            "α₀ = +50 (V_m ≈ 1e-63 m/s)",
            SliderScene {
                alpha0: 50.0,
                ..b()
            },
        ),
        case(
            "sigma-1e2",
            "σ̄_n = 1e2 Pa",
            SliderScene {
                sigma_n_pa: 1e2,
                ..b()
            },
        ),
        stuck(case(
            "sigma-1e8",
            "σ̄_n = 1e8 Pa",
            SliderScene {
                sigma_n_pa: 1e8,
                ..b()
            },
        )),
        Case {
            expect: Expect::InvalidParameter,
            ..case(
                "sigma-0",
                "σ̄_n = 0 (invalid)",
                SliderScene {
                    sigma_n_pa: 0.0,
                    ..b()
                },
            )
        },
        Case {
            peak: (0.5, 10.0),
            ..case(
                "fast-slip",
                "loading 1 m/s: slip event to V ~ 1 m/s",
                SliderScene {
                    loading_velocity_m_per_s: 1.0,
                    ..b()
                },
            )
        },
        Case {
            peak: (0.5, 10.0),
            ..case(
                "ruina-fast-slip",
                "as fast-slip, Ruina's law",
                SliderScene {
                    loading_velocity_m_per_s: 1.0,
                    state_law: rsf::StateLawKind::Slip,
                    ..b()
                },
            )
        },
        Case {
            fault: Fault::Patch { half_width: 1.0 },
            ..case(
                "patch",
                "VW patch 1.5 ≤ x ≤ 3.5 m, VS surround (a ↔ b)",
                b(),
            )
        },
    ]);
    v
}

fn build(c: &Case) -> rsf::Result<SceneSimulation<2>> {
    let s = &c.scene;
    let base = s.rate_state_params();
    let law = |x: &[f64; 2]| {
        let x = x[0];
        let params = match c.fault {
            Fault::Uniform => base,
            Fault::Patch { half_width } if (x - 2.5).abs() <= half_width => base,
            Fault::Patch { .. } => RateStateParams {
                a: base.b,
                b: base.a,
                ..base
            },
        };
        DieterichRuina::new(params)
    };
    let scheme = match c.paper_relaxation {
        Some(relaxation) => FixedPointOptions {
            acceleration: rsf::method::Acceleration::Relaxation { relaxation },
            ..FixedPointOptions::paper()
        },
        None => FixedPointOptions::default(),
    };
    let fp = FixedPointOptions {
        tolerance: s.fixed_point_tolerance,
        max_iterations: s.fixed_point_max_iterations,
        ..scheme
    };
    // The scene's model, state law, α₀, τ, solver and state update; the case's friction
    // along Γ_F and fixed point options.
    s.simulation_builder()?
        .friction_at(law)
        .integrator(Integrator::Newmark)
        .fixed_point(fp)
        .build()
}

fn all_finite(x: &[f64]) -> bool {
    x.iter().all(|v| v.is_finite())
}

/// Runs a case to its end or its first error.
pub fn run_case(c: &Case) -> Outcome {
    let start = Instant::now();
    let mut out = Outcome {
        steps_done: 0,
        fpi_mean: 0.0,
        fpi_max: 0,
        solver_per_solve: 0.0,
        solver_max: 0,
        relaxed_steps: 0,
        max_slip_rate: 0.0,
        max_correction: 0.0,
        min_slip_rate_end: 0.0,
        alpha_range: (0.0, 0.0),
        finite: true,
        seconds: 0.0,
        error: None,
    };
    let mut sim = match build(c) {
        Ok(s) => s,
        Err(e) => {
            out.error = Some(e);
            return out;
        }
    };
    let (mut fpi, mut solver) = (0usize, 0usize);
    for _ in 0..c.steps {
        match sim.step() {
            Ok(r) => {
                out.steps_done += 1;
                fpi += r.fixed_point_iterations;
                solver += r.solver_iterations;
                out.fpi_max = out.fpi_max.max(r.fixed_point_iterations);
                out.solver_max = out.solver_max.max(r.solver_iterations);
                out.relaxed_steps += usize::from(r.relaxed_iterations > 0);
                out.max_slip_rate = out.max_slip_rate.max(r.max_slip_rate);
                out.max_correction = out.max_correction.max(r.fixed_point_error);
                out.finite &= r.correction.is_finite() && r.max_slip_rate.is_finite();
            }
            Err(e) => {
                out.error = Some(e);
                break;
            }
        }
        let k = sim.kinematics();
        out.finite &= all_finite(&k.u) && all_finite(&k.v) && all_finite(&k.a);
        out.finite &= all_finite(sim.alpha());
        if !out.finite {
            break;
        }
    }
    if let Some(Error::FixedPointNotConverged { history, .. }) = &out.error {
        out.finite &= all_finite(history);
    }
    let alpha = sim.alpha();
    out.alpha_range = (
        alpha.iter().copied().fold(f64::INFINITY, f64::min),
        alpha.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let v = &sim.kinematics().v;
    out.min_slip_rate_end = sim
        .model()
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| v[2 * p].hypot(v[2 * p + 1]))
        .fold(f64::INFINITY, f64::min);
    if out.steps_done > 0 {
        out.fpi_mean = fpi as f64 / out.steps_done as f64;
        out.solver_per_solve = solver as f64 / fpi.max(1) as f64;
    }
    out.seconds = start.elapsed().as_secs_f64();
    out
}

/// Runs the named case and asserts its expected outcome.
#[cfg(test)]
fn check(name: &str) {
    let c = cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no case {name}"));
    check_case(&c);
}

/// The physics of a case that ended in `Ok`: every step done, the peak slip rate in the
/// case's range, every step's fixed point error within the tolerance.
#[cfg(test)]
fn check_ok_physics(c: &Case, o: &Outcome) {
    let name = c.name;
    assert_eq!(o.steps_done, c.steps, "{name}");
    assert!(
        o.max_slip_rate >= c.peak.0 && o.max_slip_rate <= c.peak.1,
        "{name}: peak slip rate {:e} outside {:?}",
        o.max_slip_rate,
        c.peak
    );
    assert!(
        o.max_correction <= c.scene.fixed_point_tolerance,
        "{name}: a step ended with the fixed point error {:e} above the tolerance",
        o.max_correction
    );
}

/// The case list with `change` applied to every scene.
#[cfg(test)]
fn cases_with(change: impl Fn(&mut SliderScene)) -> Vec<Case> {
    cases()
        .into_iter()
        .map(|mut c| {
            change(&mut c.scene);
            c
        })
        .collect()
}

/// Runs a case and asserts its expected outcome.
#[cfg(test)]
fn check_case(c: &Case) {
    let name = c.name;
    let o = run_case(c);
    eprintln!("{name} ({}): {o:?}", c.what);
    assert!(o.finite, "{name}: non-finite values");
    assert!(
        o.as_expected(c.expect),
        "{name}: expected {:?}, got {:?} after {} steps",
        c.expect,
        o.error,
        o.steps_done
    );
    match c.expect {
        Expect::Ok => check_ok_physics(c, &o),
        Expect::FixedPointNotConverged => {
            let Some(Error::FixedPointNotConverged {
                history,
                iterations,
                ..
            }) = &o.error
            else {
                unreachable!("checked by as_expected")
            };
            assert_eq!(*iterations, c.scene.fixed_point_max_iterations);
            assert_eq!(history.len(), *iterations);
            assert!(history.iter().all(|h| h.is_finite() && *h >= 0.0));
            assert!(*history.last().unwrap() > c.scene.fixed_point_tolerance);
            assert!(o.steps_done > 0, "{name}: fails in the first step");
        }
        Expect::InvalidParameter => {}
    }
}

macro_rules! stability_tests {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                check($name);
            }
        )*

        /// The same cases with TNNMG, the paper's solver (the scene's default, `auto`,
        /// resolves to the direct solver at level 2): the same outcomes and physics.
        #[test]
        fn every_case_with_tnnmg() {
            for c in cases_with(|s| s.solver = rsf::SolverKind::Tnnmg) {
                check_case(&c);
            }
        }

        /// The same cases with the exact state update at constant slip rate (beyond the
        /// paper; docs/friction-state.md): finite values and a typed outcome in every case —
        /// the cases' expected outcomes are those of backward Euler, so a case may now end
        /// in `Ok` where backward Euler's fixed point fails, or the other way round; an `Ok`
        /// run must still meet the case's physics (peak slip rate, fixed point tolerance).
        #[test]
        fn every_case_with_the_constant_slip_rate_update() {
            for c in cases_with(|s| s.state_integrator = rsf::method::StateIntegrator::ConstantSlipRate) {
                let o = run_case(&c);
                let name = c.name;
                eprintln!("{name} (constant slip rate): {o:?}");
                assert!(o.finite, "{name}: non-finite values");
                match &o.error {
                    None => check_ok_physics(&c, &o),
                    Some(Error::FixedPointNotConverged { history, .. }) => {
                        assert!(history.iter().all(|h| h.is_finite()), "{name}");
                    }
                    Some(e) => assert!(
                        c.expect == Expect::InvalidParameter,
                        "{name}: unexpected error {e}"
                    ),
                }
            }
        }

        /// Every case of the list has a test, and names are unique.
        #[test]
        fn every_case_is_tested() {
            let tested = [$($name),*];
            let names: Vec<_> = cases().iter().map(|c| c.name).collect();
            for n in &names {
                assert!(tested.contains(n), "case {n} has no test");
            }
            let mut sorted = names.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), names.len(), "duplicate case names");
        }
    };
}

stability_tests! {
    base_case => "base",
    rock_stiffness => "rock",
    tau_1e_7 => "tau-1e-7",
    tau_1e_5 => "tau-1e-5",
    tau_1e_1 => "tau-1e-1",
    l_1e_9 => "L-1e-9",
    l_1e_9_paper_fixed_point_limit => "L-1e-9, paper",
    l_1e_9_paper_damped_1000 => "L-1e-9, paper, 1000 FPI",
    l_1e_9_paper_undamped_1000 => "L-1e-9, paper, ω=1, 1000 FPI",
    l_1e_1 => "L-1e-1",
    b_over_a_0_5 => "b/a-0.5",
    b_over_a_1_5 => "b/a-1.5",
    b_over_a_2_5 => "b/a-2.5",
    b_over_a_5 => "b/a-5",
    alpha0_minus_50 => "alpha0--50",
    alpha0_plus_50 => "alpha0-+50",
    sigma_1e2 => "sigma-1e2",
    sigma_1e8 => "sigma-1e8",
    sigma_0_invalid => "sigma-0",
    fast_slip_to_1_m_per_s => "fast-slip",
    ruina_fast_slip => "ruina-fast-slip",
    heterogeneous_patch => "patch",
}
