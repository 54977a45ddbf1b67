//! Tests of the run configurations through the programs (docs/design.md, "One run
//! configuration"): random configurations round-trip through each program's command line
//! and through TOML; every setting is in the fingerprint; a `--config` file's keys, the
//! flags over them, the defaults under both; the refusals named as written. Apart from
//! `config.rs`, which the programs import.

use proptest::prelude::*;
use rsf::fault_ode::InteriorOrdering;
use rsf::fault_ode::OdeIntegrator;
use rsf_scenes::{
    Bp1Absorbing, Bp1DynamicIntegrator, Bp1Scheme, Bp5Condensation, Bp5Kernel, Bp5PairPatch,
    Bp5PairRun, Bp6BemProduct, Bp6Elastic, Bp6PressureChoice, Bp6Variant, Bp7Law,
    Bp8OverpressureRule, Bp8Source, KernelChoice, RunConfig, SeasBp1Run, SeasBp3Run, SeasBp5Mesh,
    SeasBp5Run, SeasBp6Run, SeasBp7Run, SeasBp8Run, SquareKernel, StepoverRun,
};

use crate::config_round_trip::{round_trip, round_trip_with};
use crate::guard::{parse_from, Program};

/// The kernel and its accuracy: dense, hierarchical at the tolerance's accuracy or at a
/// given one.
fn kernel() -> impl Strategy<Value = (KernelChoice, Option<f64>)> {
    prop_oneof![
        Just((KernelChoice::Dense, None)),
        Just((KernelChoice::Hierarchical, None)),
        (1e-14f64..1e-2).prop_map(|e| (KernelChoice::Hierarchical, Some(e))),
    ]
}

/// A folder of its own with the file `name` holding `text`.
fn file(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("rsf-config-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A square's kernel and, with `fe`, its box's settings (each set or left to its default).
fn square_kernel() -> impl Strategy<Value = (SquareKernel, Option<f64>, Option<f64>)> {
    prop_oneof![
        Just((SquareKernel::Bem, None, None)),
        (
            proptest::option::of(0.8f64..1000.0),
            proptest::option::of(1.01f64..2.0)
        )
            .prop_map(|(d, r)| (SquareKernel::Fe, d, r)),
    ]
}

fn bp7_run() -> impl Strategy<Value = SeasBp7Run> {
    (
        square_kernel(),
        prop_oneof![Just(Bp7Law::Aging), Just(Bp7Law::Slip)],
        1e-9f64..1000.0,
        prop_oneof![Just(5.0), Just(10.0), Just(20.0), Just(80.0), Just(400.0)],
        0.01f64..100.0,
        1e-12f64..0.1,
        0.0f64..1e7,
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    )
        .prop_map(
            |(
                (kernel, domain_km, ratio),
                law,
                end_years,
                dx,
                d_rs,
                tolerance,
                station_interval,
                integrator,
            )| SeasBp7Run {
                kernel,
                domain_km,
                ratio,
                law,
                end_years,
                dx,
                d_rs,
                tolerance,
                station_interval,
                integrator,
            },
        )
}

fn bp8_run() -> impl Strategy<Value = SeasBp8Run> {
    (
        square_kernel(),
        prop_oneof![Just(Bp8Source::Gaussian), Just(Bp8Source::Well)],
        1e-6f64..3650.0,
        prop_oneof![Just(5.0), Just(10.0), Just(40.0)],
        1e-12f64..0.1,
        prop_oneof![
            Just((Bp8OverpressureRule::Refuse, None)),
            Just((Bp8OverpressureRule::Floor, None)),
            (1e-3f64..12.5).prop_map(|s| (Bp8OverpressureRule::Floor, Some(s))),
        ],
        (0.0f64..1e7, 60.0f64..1e7),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    )
        .prop_map(
            |(
                (kernel, domain_km, ratio),
                source,
                end_days,
                dx,
                tolerance,
                (overpressure, sigma_min),
                (si, pi),
                integrator,
            )| {
                SeasBp8Run {
                    kernel,
                    domain_km,
                    ratio,
                    source,
                    end_days,
                    dx,
                    tolerance,
                    overpressure,
                    sigma_min,
                    station_interval: si,
                    profile_interval: pi,
                    integrator,
                }
            },
        )
}

fn stepover_run() -> impl Strategy<Value = StepoverRun> {
    (
        (
            1e-9f64..1e5,
            prop_oneof![Just(25.0), Just(50.0), Just(250.0)],
        ),
        (
            prop_oneof![Just(1.0), Just(4.0)],
            prop_oneof![Just(-2.0), Just(0.0), Just(2.0)],
        ),
        (25.0f64..1e5, 1.0f64..2.0, any::<bool>()),
        1e-10f64..0.1,
        kernel(),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    )
        .prop_map(
            |(
                (end_years, dx),
                (gap_km, overlap_km),
                (domain_km, ratio, nsfs),
                tolerance,
                (kernel, kernel_epsilon),
                integrator,
            )| {
                StepoverRun {
                    end_years,
                    dx,
                    gap_km,
                    overlap_km,
                    strand_km: 25.0,
                    domain_km,
                    ratio,
                    normal_stress_from_slip: nsfs,
                    tolerance,
                    kernel,
                    kernel_epsilon,
                    integrator,
                }
            },
        )
}

fn bp3_run() -> impl Strategy<Value = SeasBp3Run> {
    (
        (1.0f64..90.0, 1e-9f64..1e5),
        (1e-3f64..1e4, 60.00006f64..1e5, 1.0f64..2.0),
        1e-10f64..0.1,
        kernel(),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    )
        .prop_map(
            |(
                (dip, end_years),
                (dx, domain_km, ratio),
                tolerance,
                (kernel, kernel_epsilon),
                integrator,
            )| SeasBp3Run {
                dip,
                end_years,
                dx,
                domain_km,
                ratio,
                tolerance,
                kernel,
                kernel_epsilon,
                integrator,
            },
        )
}

fn bp6_run() -> impl Strategy<Value = SeasBp6Run> {
    (
        (
            prop_oneof![
                Just(Bp6Variant::A),
                Just(Bp6Variant::S),
                Just(Bp6Variant::C)
            ],
            1e-9f64..100.0,
            prop_oneof![Just(2.0), Just(10.0), Just(50.0), Just(1000.0), Just(1e4)],
        ),
        (
            prop_oneof![Just(Bp6Elastic::Bem), Just(Bp6Elastic::Fe)],
            prop_oneof![
                Just(None),
                Just(Some(Bp6BemProduct::Fft)),
                Just(Some(Bp6BemProduct::Stored))
            ],
            kernel(),
        ),
        (
            30.0f64..1e5,
            1.0f64..2.0,
            proptest::option::of(1e-12f64..0.1),
        ),
        prop_oneof![
            Just((Bp6PressureChoice::ClosedForm, None)),
            Just((Bp6PressureChoice::Diffusion, None)),
            (2usize..20_000).prop_map(|n| (Bp6PressureChoice::Diffusion, Some(n))),
        ],
        (0.0f64..1e7, 60.0f64..1e7),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    )
        .prop_map(
            |(
                (variant, end_years, dz),
                (elastic, bem_product, (kernel, kernel_epsilon)),
                (domain_km, ratio, tolerance),
                (pressure, diffusion_cells),
                (station_interval, profile_interval),
                integrator,
            )| {
                // The settings the run would ignore left unset (they are refused).
                let bem_product = bem_product.filter(|_| elastic == Bp6Elastic::Bem);
                let stored =
                    elastic == Bp6Elastic::Fe || bem_product == Some(Bp6BemProduct::Stored);
                let (kernel, kernel_epsilon) = if stored {
                    (kernel, kernel_epsilon)
                } else {
                    (KernelChoice::Hierarchical, None)
                };
                SeasBp6Run {
                    variant,
                    end_years,
                    dz,
                    elastic,
                    bem_product,
                    domain_km,
                    ratio,
                    tolerance,
                    pressure,
                    station_interval,
                    profile_interval,
                    diffusion_cells,
                    kernel,
                    kernel_epsilon,
                    integrator,
                }
            },
        )
}

fn bp5_run() -> impl Strategy<Value = SeasBp5Run> {
    let volume = (
        proptest::option::of(75.0f64..1e4),
        proptest::option::of(1.0f64..2.0),
        proptest::option::of(proptest::sample::select(vec![
            SeasBp5Mesh::Graded,
            SeasBp5Mesh::Tensor,
            SeasBp5Mesh::TensorMirrored,
        ])),
        proptest::option::of((0.1f64..10.0, 0.01f64..1.0)),
        proptest::option::of(prop_oneof![
            Just(Bp5Condensation::SchurOnly),
            Just(Bp5Condensation::Factor)
        ]),
        proptest::option::of(prop_oneof![
            Just(InteriorOrdering::Amd),
            Just(InteriorOrdering::NestedDissection)
        ]),
    );
    let friction = (
        (1e3f64..1e10, 1e-5f64..1.0, 1e-5f64..1.0, 1e-5f64..1.0),
        (1e-6f64..1e3, 1e-6f64..1e3, 0.0f64..10.0, 1e-15f64..1e3),
        (1e-15f64..1.0, 1e-20f64..10.0, 1e-20f64..10.0),
    );
    (
        prop_oneof![Just(Bp5Kernel::Okada), Just(Bp5Kernel::Fe)],
        prop_oneof![Just(2000.0), Just(4000.0), Just(5000.0), Just(2e4)],
        volume,
        (1e-9f64..1e5, 1e-10f64..0.1, 1e-14f64..1e-2),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
        friction,
    )
        .prop_map(
            |(
                kernel,
                dx,
                (domain_km, ratio, mesh, zone, condensation, ordering),
                (end_years, tolerance, epsilon),
                integrator,
                ((sigma_n, a0, a_max, b0), (l, l_nucleation, f0, v0), (v_p, v_init, v_i)),
            )| {
                // The volume's settings only with the finite-element kernel (refused with
                // Okada's).
                let fe = kernel == Bp5Kernel::Fe;
                let zone = zone.filter(|_| fe);
                SeasBp5Run {
                    kernel,
                    dx,
                    domain_km: domain_km.filter(|_| fe),
                    ratio: ratio.filter(|_| fe),
                    mesh: mesh.filter(|_| fe),
                    fault_zone_width_km: zone.map(|z| z.0),
                    fault_zone_rigidity: zone.map(|z| z.1),
                    condensation: condensation.filter(|_| fe),
                    ordering: ordering.filter(|_| fe),
                    end_years,
                    tolerance,
                    integrator,
                    epsilon,
                    sigma_n,
                    a0,
                    a_max,
                    b0,
                    l,
                    l_nucleation,
                    f0,
                    v0,
                    v_p,
                    v_init,
                    v_i,
                }
            },
        )
}

fn bp1_run() -> impl Strategy<Value = SeasBp1Run> {
    let scene = (
        (1e3f64..1e4, 1e3f64..1e4, 1e3f64..1e10, 1e-5f64..1.0),
        (1e-5f64..1.0, 1e-5f64..1.0, 1e-6f64..1e3, 1e-15f64..1.0),
        (1e-20f64..10.0, 1e-15f64..1e3, 0.0f64..10.0),
        (
            1.0f64..1e6,
            1.0f64..1e6,
            prop_oneof![Just(20e3), Just(40e3)],
        ),
    );
    let method = prop_oneof![
        Just((Bp1Scheme::RungeKutta, false)),
        Just((Bp1Scheme::RungeKutta, true)),
        Just((Bp1Scheme::Implicit, false)),
        Just((Bp1Scheme::Implicit, true)),
    ];
    // The implicit scheme's: tolerance, state change cap, fixed point tolerance, set-up.
    let implicit = (1e-8f64..0.1, 0.0f64..1e3, 1e-14f64..1.0, any::<bool>());
    // The fully dynamic run's: far boundary, integrator, step (a fraction of the
    // crossing time), thresholds, fixed point tolerance.
    let dynamic = (
        proptest::option::of(prop_oneof![
            Just(Bp1Absorbing::None),
            Just(Bp1Absorbing::Dynamic),
            Just(Bp1Absorbing::All)
        ]),
        prop_oneof![
            Just(Bp1DynamicIntegrator::Newmark),
            Just(Bp1DynamicIntegrator::BackwardEuler)
        ],
        proptest::option::of(2e-3f64..0.99),
        proptest::option::of((1e-12f64..1e2, 1e-12f64..1e2)),
        1e-12f64..1.0,
    );
    let grid = (
        1e-9f64..1e5,
        prop_oneof![Just(25.0), Just(100.0), Just(1000.0)],
        50.0f64..1e3,
        1.0f64..2.0,
    );
    let fault_ode = (
        proptest::option::of(0.0f64..1e9),
        any::<bool>(),
        1e-10f64..0.1,
        kernel(),
        proptest::sample::select(OdeIntegrator::ALL.to_vec()),
    );
    (scene, method, implicit, dynamic, grid, fault_ode).prop_map(
        |(
            (
                (rho, c_s, sigma_n, a0),
                (a_max, b0, d_c, v_p),
                (v_init, v0, f0),
                (h_top, h_transition, w_f),
            ),
            (scheme, inertia),
            (tolerance, state_change_cap, fixed_point_tolerance, setup_per_time_step),
            (absorbing, dynamic_integrator, tau, thresholds, dynamic_fixed_point_tolerance),
            (end_years, dz, domain_km, ratio),
            (event_quiet_time, every_step, rk_tolerance, (kernel, kernel_epsilon), integrator),
        )| {
            let mut run = SeasBp1Run {
                end_years,
                dz,
                domain_km,
                ratio,
                tolerance,
                inertia,
                absorbing,
                dynamic_integrator,
                dynamic_tau: tau.map(|f| f * dz / c_s),
                switch_to_dynamic: thresholds.map(|t| t.0),
                event_quiet_time,
                switch_to_quasi_dynamic: thresholds.map(|t| t.1),
                dynamic_fixed_point_tolerance,
                every_step,
                state_change_cap,
                fixed_point_tolerance,
                setup_per_time_step,
                scheme,
                rk_tolerance,
                kernel,
                kernel_epsilon,
                integrator,
                rho,
                c_s,
                sigma_n,
                a0,
                a_max,
                b0,
                d_c,
                v_p,
                v_init,
                v0,
                f0,
                h_top,
                h_transition,
                w_f,
            };
            // The settings the chosen method would ignore left at their defaults (they
            // are refused).
            let d = SeasBp1Run::default();
            if scheme == Bp1Scheme::RungeKutta && !inertia {
                run.tolerance = d.tolerance;
                run.state_change_cap = d.state_change_cap;
                run.fixed_point_tolerance = d.fixed_point_tolerance;
                run.setup_per_time_step = d.setup_per_time_step;
            }
            if !inertia {
                run.absorbing = absorbing.filter(|a| *a == Bp1Absorbing::None);
                run.dynamic_integrator = d.dynamic_integrator;
                run.dynamic_tau = None;
                run.switch_to_dynamic = None;
                run.switch_to_quasi_dynamic = None;
                run.dynamic_fixed_point_tolerance = d.dynamic_fixed_point_tolerance;
            }
            if scheme == Bp1Scheme::Implicit && run.absorbing == Some(Bp1Absorbing::Dynamic) {
                run.absorbing = Some(Bp1Absorbing::All);
            }
            run
        },
    )
}

fn bp5_pair_run() -> impl Strategy<Value = Bp5PairRun> {
    (
        prop_oneof![Just(Bp5Kernel::Okada), Just(Bp5Kernel::Fe)],
        prop_oneof![Just(1000.0), Just(2000.0), Just(4000.0), Just(20e3)],
        // The separation: half of it a whole number of cells (needed by `fe`).
        1u32..5,
        (75.0f64..1e4, 1.0f64..2.0),
        proptest::option::of(prop_oneof![
            Just(InteriorOrdering::Amd),
            Just(InteriorOrdering::NestedDissection)
        ]),
        (1e-9f64..1e5, 1e-10f64..0.1, 1e-14f64..1e-2),
        (
            proptest::sample::select(OdeIntegrator::ALL.to_vec()),
            prop_oneof![Just(Bp5PairPatch::Both), Just(Bp5PairPatch::West)],
        ),
    )
        .prop_map(
            |(
                kernel,
                dx,
                half_cells,
                (domain_km, ratio),
                ordering,
                (end_years, tolerance, epsilon),
                (integrator, patch),
            )| Bp5PairRun {
                kernel,
                dx,
                separation_km: 2.0 * f64::from(half_cells) * dx / 1e3,
                domain_km,
                ratio,
                ordering,
                end_years,
                tolerance,
                integrator,
                epsilon,
                patch,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn bp5_pair_settings_round_trip(run in bp5_pair_run()) {
        round_trip(&run, |p: crate::bp5_pair::Args| p.settings)?;
    }

    #[test]
    fn bp1_settings_round_trip(run in bp1_run()) {
        round_trip_with(&["--out", "out/seas_bp1"], &run, |p: crate::seas_bp1::Args| p.settings)?;
    }

    /// A configuration → its command line → the configuration the program parses: the
    /// same value; and through TOML: the same value and the same fingerprint.
    #[test]
    fn stepover_settings_round_trip(run in stepover_run()) {
        round_trip(&run, |p: crate::stepover::Args| p.settings)?;
    }

    #[test]
    fn bp7_settings_round_trip(run in bp7_run()) {
        round_trip(&run, |p: crate::seas_bp7::Args| p.settings)?;
    }

    #[test]
    fn bp8_settings_round_trip(run in bp8_run()) {
        round_trip(&run, |p: crate::seas_bp8::Args| p.settings)?;
    }

    #[test]
    fn bp3_settings_round_trip(run in bp3_run()) {
        round_trip(&run, |p: crate::seas_bp3::Args| p.settings)?;
    }

    #[test]
    fn bp5_settings_round_trip(run in bp5_run()) {
        round_trip(&run, |p: crate::seas_bp5::Args| p.settings)?;
    }

    #[test]
    fn bp6_settings_round_trip(run in bp6_run()) {
        round_trip(&run, |p: crate::seas_bp6::Args| p.settings)?;
    }
}

/// Each of `changed` (the base with one setting changed) has a fingerprint other than
/// `base`'s.
fn each_changes_the_fingerprint<C: RunConfig + std::fmt::Debug>(base: &C, changed: &[C]) {
    for run in changed {
        assert_ne!(run.fingerprint(), base.fingerprint(), "{run:?}");
    }
}

/// Every setting of BP1 changes the fingerprint: those of BP1-QD's run and the scene's on
/// its defaults, the fully dynamic run's on BP1-FD's.
#[test]
fn every_bp1_setting_is_in_the_fingerprint() {
    let qd = SeasBp1Run::default();
    let changed = |base: SeasBp1Run, changes: &[fn(&mut SeasBp1Run)]| -> Vec<SeasBp1Run> {
        changes
            .iter()
            .map(|change| {
                let mut run = base;
                change(&mut run);
                run
            })
            .collect()
    };
    each_changes_the_fingerprint(
        &qd,
        &changed(
            qd,
            &[
                |r| r.end_years = 2.0,
                |r| r.dz = 50.0,
                |r| r.domain_km = 500.0,
                |r| r.ratio = 1.1,
                |r| r.inertia = true,
                |r| r.event_quiet_time = Some(1.0),
                |r| r.every_step = true,
                |r| r.scheme = Bp1Scheme::Implicit,
                |r| r.rk_tolerance = 1e-7,
                |r| r.kernel = KernelChoice::Dense,
                |r| r.kernel_epsilon = Some(1e-5),
                |r| r.integrator = OdeIntegrator::Rkc,
                |r| r.rho = 2700.0,
                |r| r.c_s = 3500.0,
                |r| r.sigma_n = 4e7,
                |r| r.a0 = 0.011,
                |r| r.a_max = 0.02,
                |r| r.b0 = 0.016,
                |r| r.d_c = 0.01,
                |r| r.v_p = 2e-9,
                |r| r.v_init = 2e-9,
                |r| r.v0 = 2e-6,
                |r| r.f0 = 0.5,
                |r| r.h_top = 14e3,
                |r| r.h_transition = 2e3,
                |r| r.w_f = 30e3,
            ],
        ),
    );
    let implicit = SeasBp1Run {
        scheme: Bp1Scheme::Implicit,
        ..qd
    };
    each_changes_the_fingerprint(
        &implicit,
        &changed(
            implicit,
            &[
                |r| r.tolerance = 1e-4,
                |r| r.state_change_cap = 0.0,
                |r| r.fixed_point_tolerance = 1e-9,
                |r| r.setup_per_time_step = true,
            ],
        ),
    );
    let fd = SeasBp1Run {
        inertia: true,
        ..qd
    };
    each_changes_the_fingerprint(
        &fd,
        &changed(
            fd,
            &[
                |r| r.absorbing = Some(Bp1Absorbing::Dynamic),
                |r| r.dynamic_integrator = Bp1DynamicIntegrator::BackwardEuler,
                |r| r.dynamic_tau = Some(1e-3),
                |r| r.switch_to_dynamic = Some(1e-1),
                |r| r.switch_to_quasi_dynamic = Some(1e-4),
                |r| r.dynamic_fixed_point_tolerance = 1e-7,
            ],
        ),
    );
    // A setting left unset and set to its resolved value are one run.
    assert_eq!(fd.fingerprint(), fd.resolved().fingerprint());
}

/// Every setting of the two strands changes the fingerprint; an ordering left unset is
/// the front end's default.
#[test]
fn every_bp5_pair_setting_is_in_the_fingerprint() {
    let base = Bp5PairRun::default();
    each_changes_the_fingerprint(
        &base,
        &[
            Bp5PairRun {
                kernel: Bp5Kernel::Fe,
                ..base
            },
            Bp5PairRun { dx: 4000.0, ..base },
            Bp5PairRun {
                separation_km: 16.0,
                ..base
            },
            Bp5PairRun {
                domain_km: 500.0,
                ..base
            },
            Bp5PairRun { ratio: 1.2, ..base },
            Bp5PairRun {
                ordering: Some(InteriorOrdering::NestedDissection),
                ..base
            },
            Bp5PairRun {
                end_years: 2.0,
                ..base
            },
            Bp5PairRun {
                tolerance: 1e-7,
                ..base
            },
            Bp5PairRun {
                integrator: OdeIntegrator::Rkc,
                ..base
            },
            Bp5PairRun {
                epsilon: 1e-5,
                ..base
            },
        ],
    );
    let nd = InteriorOrdering::NestedDissection;
    assert_eq!(
        base.fingerprint_with(nd),
        Bp5PairRun {
            ordering: Some(nd),
            ..base
        }
        .fingerprint()
    );
}

/// Every setting of BP3 changes the fingerprint.
#[test]
fn every_bp3_setting_is_in_the_fingerprint() {
    let base = SeasBp3Run::default();
    each_changes_the_fingerprint(
        &base,
        &[
            SeasBp3Run { dip: 30.0, ..base },
            SeasBp3Run {
                end_years: 2.0,
                ..base
            },
            SeasBp3Run { dx: 250.0, ..base },
            SeasBp3Run {
                domain_km: 800.0,
                ..base
            },
            SeasBp3Run {
                ratio: 1.05,
                ..base
            },
            SeasBp3Run {
                tolerance: 1e-8,
                ..base
            },
            SeasBp3Run {
                kernel: KernelChoice::Dense,
                ..base
            },
            SeasBp3Run {
                kernel_epsilon: Some(1e-6),
                ..base
            },
            SeasBp3Run {
                integrator: OdeIntegrator::Rkc,
                ..base
            },
        ],
    );
}

/// Every setting of BP6 changes the fingerprint (those the run uses: the integrator of
/// A and S, the diffusion's cells with the diffusion).
#[test]
fn every_bp6_setting_is_in_the_fingerprint() {
    let base = SeasBp6Run::default();
    let diffusion = SeasBp6Run {
        pressure: Bp6PressureChoice::Diffusion,
        ..base
    };
    each_changes_the_fingerprint(
        &base,
        &[
            SeasBp6Run {
                variant: Bp6Variant::S,
                ..base
            },
            SeasBp6Run {
                end_years: 1.0,
                ..base
            },
            SeasBp6Run { dz: 20.0, ..base },
            SeasBp6Run {
                elastic: Bp6Elastic::Fe,
                ..base
            },
            SeasBp6Run {
                bem_product: Some(Bp6BemProduct::Stored),
                ..base
            },
            SeasBp6Run {
                domain_km: 40.0,
                ..base
            },
            SeasBp6Run { ratio: 1.1, ..base },
            SeasBp6Run {
                tolerance: Some(1e-8),
                ..base
            },
            diffusion,
            SeasBp6Run {
                station_interval: 60.0,
                ..base
            },
            SeasBp6Run {
                profile_interval: 60.0,
                ..base
            },
            SeasBp6Run {
                kernel: KernelChoice::Dense,
                ..base
            },
            SeasBp6Run {
                kernel_epsilon: Some(1e-6),
                ..base
            },
            SeasBp6Run {
                integrator: OdeIntegrator::Rkc,
                ..base
            },
        ],
    );
    each_changes_the_fingerprint(
        &diffusion,
        &[SeasBp6Run {
            diffusion_cells: Some(400),
            ..diffusion
        }],
    );
}

/// Every setting of BP5 changes the fingerprint (the volume's with the finite-element
/// kernel), the friction among them.
#[test]
fn every_bp5_setting_is_in_the_fingerprint() {
    let base = SeasBp5Run::default();
    let fe = SeasBp5Run {
        kernel: Bp5Kernel::Fe,
        ..base
    };
    each_changes_the_fingerprint(
        &base,
        &[
            fe,
            SeasBp5Run { dx: 4000.0, ..base },
            SeasBp5Run {
                end_years: 1.0,
                ..base
            },
            SeasBp5Run {
                tolerance: 1e-7,
                ..base
            },
            SeasBp5Run {
                integrator: OdeIntegrator::Rkc,
                ..base
            },
            SeasBp5Run {
                epsilon: 1e-5,
                ..base
            },
            SeasBp5Run {
                sigma_n: 30e6,
                ..base
            },
            SeasBp5Run { a0: 0.005, ..base },
            SeasBp5Run {
                a_max: 0.03,
                ..base
            },
            SeasBp5Run { b0: 0.02, ..base },
            SeasBp5Run { l: 0.1, ..base },
            SeasBp5Run {
                l_nucleation: 0.1,
                ..base
            },
            SeasBp5Run { f0: 0.5, ..base },
            SeasBp5Run { v0: 1e-5, ..base },
            SeasBp5Run { v_p: 2e-9, ..base },
            SeasBp5Run {
                v_init: 2e-9,
                ..base
            },
            SeasBp5Run { v_i: 0.01, ..base },
        ],
    );
    each_changes_the_fingerprint(
        &fe,
        &[
            SeasBp5Run {
                domain_km: Some(200.0),
                ..fe
            },
            SeasBp5Run {
                ratio: Some(1.1),
                ..fe
            },
            SeasBp5Run {
                mesh: Some(SeasBp5Mesh::Tensor),
                ..fe
            },
            SeasBp5Run {
                fault_zone_width_km: Some(4.0),
                fault_zone_rigidity: Some(0.5),
                ..fe
            },
            SeasBp5Run {
                condensation: Some(Bp5Condensation::Factor),
                ..fe
            },
            SeasBp5Run {
                ordering: Some(InteriorOrdering::NestedDissection),
                ..fe
            },
        ],
    );
}

/// Every setting changes the fingerprint (none is left out of it).
#[test]
fn every_setting_is_in_the_fingerprint() {
    let base = SeasBp8Run::default();
    let changed = [
        SeasBp8Run {
            source: Bp8Source::Well,
            ..base
        },
        SeasBp8Run {
            end_days: 2.0,
            ..base
        },
        SeasBp8Run { dx: 20.0, ..base },
        SeasBp8Run {
            tolerance: 1e-8,
            ..base
        },
        SeasBp8Run {
            overpressure: Bp8OverpressureRule::Refuse,
            ..base
        },
        SeasBp8Run {
            sigma_min: Some(2.0),
            ..base
        },
        SeasBp8Run {
            station_interval: 60.0,
            ..base
        },
        SeasBp8Run {
            profile_interval: 60.0,
            ..base
        },
        SeasBp8Run {
            integrator: OdeIntegrator::Rkc,
            ..base
        },
    ];
    each_changes_the_fingerprint(&base, &changed);
}

/// `--config`: the file's keys over the defaults, a flag given over the file's key; an
/// unknown key, a mistyped value and a refused value named as written.
#[test]
fn a_config_file_sets_what_no_flag_gives() {
    let path = file("bp7.toml", "law = \"slip\"\ndx = 20\nend_years = 2.5\n");
    let p = path.to_str().unwrap();
    let (args, _) =
        parse_from::<crate::seas_bp7::Args, _, _>(["seas_bp7", "--config", p, "--dx", "40"])
            .unwrap();
    let run = args.settings;
    assert_eq!(run.law, Bp7Law::Slip);
    assert_eq!(run.dx, 40.0, "the flag wins");
    assert_eq!(run.end_years, 2.5, "the file's key");
    assert_eq!(run.d_rs, SeasBp7Run::default().d_rs, "the default");
    args.plan().unwrap();

    let unknown = file("unknown.toml", "dx = 20\nd_c = 1\n");
    let e = parse_from::<crate::seas_bp7::Args, _, _>([
        "seas_bp7",
        "--config",
        unknown.to_str().unwrap(),
    ])
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("d_c") && e.contains("--config"), "{e}");

    let typed = file("typed.toml", "dx = \"ten\"\n");
    let e = parse_from::<crate::seas_bp7::Args, _, _>([
        "seas_bp7",
        "--config",
        typed.to_str().unwrap(),
    ])
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("dx") && e.contains("typed.toml"), "{e}");

    let refused = file("refused.toml", "dx = 30\n");
    let (args, _) = parse_from::<crate::seas_bp7::Args, _, _>([
        "seas_bp7",
        "--config",
        refused.to_str().unwrap(),
    ])
    .unwrap();
    let e = args.plan().err().unwrap().to_string();
    assert!(
        e.contains("refused.toml: key `dx` = 30: must divide"),
        "{e}"
    );
    let (args, _) = parse_from::<crate::seas_bp7::Args, _, _>([
        "seas_bp7",
        "--config",
        refused.to_str().unwrap(),
        "--dx",
        "3",
    ])
    .unwrap();
    let e = args.plan().err().unwrap().to_string();
    assert!(e.starts_with("--dx 3: must be in [5, 400]"), "{e}");
    for f in [path, unknown, typed, refused] {
        let _ = std::fs::remove_dir_all(f.parent().unwrap());
    }
}
