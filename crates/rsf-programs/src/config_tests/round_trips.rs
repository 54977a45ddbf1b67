//! Random configurations of each SEAS program round-trip through its command line and
//! through TOML (`crate::config_round_trip`).

use proptest::prelude::*;
use proptest::sample::select;
use rsf::fault_ode::{InteriorOrdering, OdeIntegrator};
use rsf_scenes::{
    Bp1Absorbing, Bp1DynamicIntegrator, Bp1Scheme, Bp5Condensation, Bp5Kernel, Bp5PairPatch,
    Bp5PairRun, Bp6BemProduct, Bp6Elastic, Bp6PressureChoice, Bp6Variant, Bp7Law,
    Bp8OverpressureRule, Bp8Source, KernelChoice, SeasBp1Run, SeasBp3Run, SeasBp5Mesh, SeasBp5Run,
    SeasBp6Run, SeasBp7Run, SeasBp8Run, SquareKernel, StepoverRun,
};

use crate::config_round_trip::round_trip_with;

/// The kernel and its accuracy: dense, hierarchical at the tolerance's accuracy or at a
/// given one.
fn kernel() -> impl Strategy<Value = (KernelChoice, Option<f64>)> {
    prop_oneof![
        Just((KernelChoice::Dense, None)),
        Just((KernelChoice::Hierarchical, None)),
        (1e-14f64..1e-2).prop_map(|e| (KernelChoice::Hierarchical, Some(e))),
    ]
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

prop_compose! {
    fn bp7_run()(
        (kernel, domain_km, ratio) in square_kernel(),
        law in select(vec![Bp7Law::Aging, Bp7Law::Slip]),
        end_years in 1e-9f64..1000.0,
        dx in select(vec![5.0, 10.0, 20.0, 80.0, 400.0]),
        d_rs in 0.01f64..100.0,
        tolerance in 1e-12f64..0.1,
        station_interval in 0.0f64..1e7,
        integrator in select(OdeIntegrator::ALL.to_vec()),
    ) -> SeasBp7Run {
        SeasBp7Run {
            kernel, domain_km, ratio, law, end_years, dx, d_rs, tolerance, station_interval,
            integrator,
        }
    }
}

prop_compose! {
    fn bp8_run()(
        (kernel, domain_km, ratio) in square_kernel(),
        source in select(vec![Bp8Source::Gaussian, Bp8Source::Well]),
        end_days in 1e-6f64..3650.0,
        dx in select(vec![5.0, 10.0, 40.0]),
        tolerance in 1e-12f64..0.1,
        (overpressure, sigma_min) in prop_oneof![
            Just((Bp8OverpressureRule::Refuse, None)),
            Just((Bp8OverpressureRule::Floor, None)),
            (1e-3f64..12.5).prop_map(|s| (Bp8OverpressureRule::Floor, Some(s))),
        ],
        station_interval in 0.0f64..1e7,
        profile_interval in 60.0f64..1e7,
        integrator in select(OdeIntegrator::ALL.to_vec()),
    ) -> SeasBp8Run {
        SeasBp8Run {
            kernel, domain_km, ratio, source, end_days, dx, tolerance, overpressure, sigma_min,
            station_interval, profile_interval, integrator,
        }
    }
}

fn stepover_run() -> impl Strategy<Value = StepoverRun> {
    (
        (1e-9f64..1e5, select(vec![25.0, 50.0, 250.0])),
        (select(vec![1.0, 4.0]), select(vec![-2.0, 0.0, 2.0])),
        (25.0f64..1e5, 1.0f64..2.0, any::<bool>()),
        1e-10f64..0.1,
        kernel(),
        select(OdeIntegrator::ALL.to_vec()),
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

prop_compose! {
    fn bp3_run()(
        dip in 1.0f64..90.0,
        end_years in 1e-9f64..1e5,
        (dx, domain_km, ratio) in (1e-3f64..1e4, 60.00006f64..1e5, 1.0f64..2.0),
        tolerance in 1e-10f64..0.1,
        (kernel, kernel_epsilon) in kernel(),
        integrator in select(OdeIntegrator::ALL.to_vec()),
    ) -> SeasBp3Run {
        SeasBp3Run {
            dip, end_years, dx, domain_km, ratio, tolerance, kernel, kernel_epsilon, integrator,
        }
    }
}

prop_compose! {
    fn bp6_run()(
        variant in select(vec![Bp6Variant::A, Bp6Variant::S, Bp6Variant::C]),
        end_years in 1e-9f64..100.0,
        dz in select(vec![2.0, 10.0, 50.0, 1000.0, 1e4]),
        elastic in select(vec![Bp6Elastic::Bem, Bp6Elastic::Fe]),
        bem_product in select(vec![None, Some(Bp6BemProduct::Fft), Some(Bp6BemProduct::Stored)]),
        (kernel, kernel_epsilon) in kernel(),
        domain_km in 30.0f64..1e5,
        ratio in 1.0f64..2.0,
        tolerance in proptest::option::of(1e-12f64..0.1),
        (pressure, diffusion_cells) in prop_oneof![
            Just((Bp6PressureChoice::ClosedForm, None)),
            Just((Bp6PressureChoice::Diffusion, None)),
            (2usize..20_000).prop_map(|n| (Bp6PressureChoice::Diffusion, Some(n))),
        ],
        station_interval in 0.0f64..1e7,
        profile_interval in 60.0f64..1e7,
        integrator in select(OdeIntegrator::ALL.to_vec()),
    ) -> SeasBp6Run {
        // The settings the run would ignore left unset (they are refused).
        let bem_product = bem_product.filter(|_| elastic == Bp6Elastic::Bem);
        let stored = elastic == Bp6Elastic::Fe || bem_product == Some(Bp6BemProduct::Stored);
        let (kernel, kernel_epsilon) = if stored {
            (kernel, kernel_epsilon)
        } else {
            (KernelChoice::Hierarchical, None)
        };
        SeasBp6Run {
            variant, end_years, dz, elastic, bem_product, domain_km, ratio, tolerance, pressure,
            station_interval, profile_interval, diffusion_cells, kernel, kernel_epsilon,
            integrator,
        }
    }
}

prop_compose! {
    fn bp5_run()(
        kernel in select(vec![Bp5Kernel::Okada, Bp5Kernel::Fe]),
        dx in select(vec![2000.0, 4000.0, 5000.0, 2e4]),
        // The volume's.
        domain_km in proptest::option::of(75.0f64..1e4),
        ratio in proptest::option::of(1.0f64..2.0),
        mesh in proptest::option::of(select(vec![
            SeasBp5Mesh::Graded,
            SeasBp5Mesh::Tensor,
            SeasBp5Mesh::TensorMirrored,
        ])),
        zone in proptest::option::of((0.1f64..10.0, 0.01f64..1.0)),
        condensation in proptest::option::of(select(vec![
            Bp5Condensation::SchurOnly,
            Bp5Condensation::Factor,
        ])),
        ordering in proptest::option::of(select(vec![
            InteriorOrdering::Amd,
            InteriorOrdering::NestedDissection,
        ])),
        (end_years, tolerance, epsilon) in (1e-9f64..1e5, 1e-10f64..0.1, 1e-14f64..1e-2),
        integrator in select(OdeIntegrator::ALL.to_vec()),
        // The friction.
        (sigma_n, a0, a_max, b0) in (1e3f64..1e10, 1e-5f64..1.0, 1e-5f64..1.0, 1e-5f64..1.0),
        (l, l_nucleation, f0, v0) in (1e-6f64..1e3, 1e-6f64..1e3, 0.0f64..10.0, 1e-15f64..1e3),
        (v_p, v_init, v_i) in (1e-15f64..1.0, 1e-20f64..10.0, 1e-20f64..10.0),
    ) -> SeasBp5Run {
        // The volume's settings only with the finite-element kernel (refused with Okada's).
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
            end_years, tolerance, integrator, epsilon,
            sigma_n, a0, a_max, b0, l, l_nucleation, f0, v0, v_p, v_init, v_i,
        }
    }
}

fn bp1_run() -> impl Strategy<Value = SeasBp1Run> {
    let scene = (
        (1e3f64..1e4, 1e3f64..1e4, 1e3f64..1e10, 1e-5f64..1.0),
        (1e-5f64..1.0, 1e-5f64..1.0, 1e-6f64..1e3, 1e-15f64..1.0),
        (1e-20f64..10.0, 1e-15f64..1e3, 0.0f64..10.0),
        (1.0f64..1e6, 1.0f64..1e6, select(vec![20e3, 40e3])),
    );
    let method = select(vec![
        (Bp1Scheme::RungeKutta, false),
        (Bp1Scheme::RungeKutta, true),
        (Bp1Scheme::Implicit, false),
        (Bp1Scheme::Implicit, true),
    ]);
    // The implicit scheme's: tolerance, state change cap, fixed point tolerance, set-up.
    let implicit = (1e-8f64..0.1, 0.0f64..1e3, 1e-14f64..1.0, any::<bool>());
    // The fully dynamic run's: far boundary, integrator, step (a fraction of the
    // crossing time), thresholds, fixed point tolerance.
    let dynamic = (
        proptest::option::of(select(vec![
            Bp1Absorbing::None,
            Bp1Absorbing::Dynamic,
            Bp1Absorbing::All,
        ])),
        select(vec![
            Bp1DynamicIntegrator::Newmark,
            Bp1DynamicIntegrator::BackwardEuler,
        ]),
        proptest::option::of(2e-3f64..0.99),
        proptest::option::of((1e-12f64..1e2, 1e-12f64..1e2)),
        1e-12f64..1.0,
    );
    let grid = (
        1e-9f64..1e5,
        select(vec![25.0, 100.0, 1000.0]),
        50.0f64..1e3,
        1.0f64..2.0,
    );
    let fault_ode = (
        proptest::option::of(0.0f64..1e9),
        any::<bool>(),
        1e-10f64..0.1,
        kernel(),
        select(OdeIntegrator::ALL.to_vec()),
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
        select(vec![Bp5Kernel::Okada, Bp5Kernel::Fe]),
        select(vec![1000.0, 2000.0, 4000.0, 20e3]),
        // The separation: half of it a whole number of cells (needed by `fe`).
        1u32..5,
        (75.0f64..1e4, 1.0f64..2.0),
        proptest::option::of(select(vec![
            InteriorOrdering::Amd,
            InteriorOrdering::NestedDissection,
        ])),
        (1e-9f64..1e5, 1e-10f64..0.1, 1e-14f64..1e-2),
        (
            select(OdeIntegrator::ALL.to_vec()),
            select(vec![Bp5PairPatch::Both, Bp5PairPatch::West]),
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

/// A proptest of each program: a configuration drawn by its strategy → its command line
/// (with the program's flags that are no settings after it) → the configuration the
/// program parses: the same value; and through TOML: the same value and the same
/// fingerprint.
macro_rules! round_trips {
    ($($test:ident: $run:ident() => $program:ty $(, $flag:literal)*;)*) => {
        proptest! {
            #![proptest_config(ProptestConfig::with_cases(64))]
            $(
                #[test]
                fn $test(run in $run()) {
                    round_trip_with(&[$($flag),*], &run, |p: $program| p.settings)?;
                }
            )*
        }
    };
}

round_trips! {
    bp5_pair_settings_round_trip: bp5_pair_run() => crate::bp5_pair::Args;
    bp1_settings_round_trip: bp1_run() => crate::seas_bp1::Args, "--out", "out/seas_bp1";
    stepover_settings_round_trip: stepover_run() => crate::stepover::Args;
    bp7_settings_round_trip: bp7_run() => crate::seas_bp7::Args;
    bp8_settings_round_trip: bp8_run() => crate::seas_bp8::Args;
    bp3_settings_round_trip: bp3_run() => crate::seas_bp3::Args;
    bp5_settings_round_trip: bp5_run() => crate::seas_bp5::Args;
    bp6_settings_round_trip: bp6_run() => crate::seas_bp6::Args;
}
