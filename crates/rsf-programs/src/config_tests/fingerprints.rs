//! Every setting of each SEAS program's run configuration is in its fingerprint (none is
//! left out of it).

use rsf::fault_ode::{InteriorOrdering, OdeIntegrator};
use rsf_scenes::{
    Bp1Absorbing, Bp1DynamicIntegrator, Bp1Scheme, Bp5Condensation, Bp5Kernel, Bp5PairRun,
    Bp6BemProduct, Bp6Elastic, Bp6PressureChoice, Bp6Variant, Bp8OverpressureRule, Bp8Source,
    KernelChoice, RunConfig, SeasBp1Run, SeasBp3Run, SeasBp5Mesh, SeasBp5Run, SeasBp6Run,
    SeasBp8Run,
};

/// Asserts of each change of `base` — a setting `field = value`, or several separated by
/// commas, a change ending at `;` — that the run it gives has a fingerprint other than
/// `base`'s.
macro_rules! each_changes_the_fingerprint {
    ($base:expr => $($($field:ident = $value:expr),+;)+) => {{
        let base = &$base;
        $(
            let mut run = base.clone();
            $(run.$field = $value;)+
            assert_ne!(run.fingerprint(), base.fingerprint(), "{run:?}");
        )+
    }};
}

/// Every setting of BP1 changes the fingerprint: those of BP1-QD's run and the scene's on
/// its defaults, the fully dynamic run's on BP1-FD's.
#[test]
fn every_bp1_setting_is_in_the_fingerprint() {
    let qd = SeasBp1Run::default();
    each_changes_the_fingerprint! { qd =>
        end_years = 2.0; dz = 50.0; domain_km = 500.0; ratio = 1.1;
        inertia = true; event_quiet_time = Some(1.0); every_step = true;
        scheme = Bp1Scheme::Implicit; rk_tolerance = 1e-7;
        kernel = KernelChoice::Dense; kernel_epsilon = Some(1e-5);
        integrator = OdeIntegrator::Rkc;
        rho = 2700.0; c_s = 3500.0; sigma_n = 4e7;
        a0 = 0.011; a_max = 0.02; b0 = 0.016; d_c = 0.01;
        v_p = 2e-9; v_init = 2e-9; v0 = 2e-6; f0 = 0.5;
        h_top = 14e3; h_transition = 2e3; w_f = 30e3;
    }
    let implicit = SeasBp1Run {
        scheme: Bp1Scheme::Implicit,
        ..qd
    };
    each_changes_the_fingerprint! { implicit =>
        tolerance = 1e-4; state_change_cap = 0.0; fixed_point_tolerance = 1e-9;
        setup_per_time_step = true;
    }
    let fd = SeasBp1Run {
        inertia: true,
        ..qd
    };
    each_changes_the_fingerprint! { fd =>
        absorbing = Some(Bp1Absorbing::Dynamic);
        dynamic_integrator = Bp1DynamicIntegrator::BackwardEuler;
        dynamic_tau = Some(1e-3);
        switch_to_dynamic = Some(1e-1); switch_to_quasi_dynamic = Some(1e-4);
        dynamic_fixed_point_tolerance = 1e-7;
    }
    // A setting left unset and set to its resolved value are one run.
    assert_eq!(fd.fingerprint(), fd.resolved().fingerprint());
}

/// Every setting of the two strands changes the fingerprint; an ordering left unset is
/// the front end's default.
#[test]
fn every_bp5_pair_setting_is_in_the_fingerprint() {
    let base = Bp5PairRun::default();
    each_changes_the_fingerprint! { base =>
        kernel = Bp5Kernel::Fe; dx = 4000.0; separation_km = 16.0;
        domain_km = 500.0; ratio = 1.2; ordering = Some(InteriorOrdering::NestedDissection);
        end_years = 2.0; tolerance = 1e-7; integrator = OdeIntegrator::Rkc; epsilon = 1e-5;
    }
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
    each_changes_the_fingerprint! { SeasBp3Run::default() =>
        dip = 30.0; end_years = 2.0; dx = 250.0; domain_km = 800.0; ratio = 1.05;
        tolerance = 1e-8; kernel = KernelChoice::Dense; kernel_epsilon = Some(1e-6);
        integrator = OdeIntegrator::Rkc;
    }
}

/// Every setting of BP6 changes the fingerprint (those the run uses: the integrator of
/// A and S, the diffusion's cells with the diffusion).
#[test]
fn every_bp6_setting_is_in_the_fingerprint() {
    let diffusion = SeasBp6Run {
        pressure: Bp6PressureChoice::Diffusion,
        ..SeasBp6Run::default()
    };
    each_changes_the_fingerprint! { SeasBp6Run::default() =>
        variant = Bp6Variant::S; end_years = 1.0; dz = 20.0;
        elastic = Bp6Elastic::Fe; bem_product = Some(Bp6BemProduct::Stored);
        domain_km = 40.0; ratio = 1.1; tolerance = Some(1e-8);
        pressure = Bp6PressureChoice::Diffusion; station_interval = 60.0; profile_interval = 60.0;
        kernel = KernelChoice::Dense; kernel_epsilon = Some(1e-6);
        integrator = OdeIntegrator::Rkc;
    }
    each_changes_the_fingerprint! { diffusion => diffusion_cells = Some(400); }
}

/// Every setting of BP5 changes the fingerprint (the volume's with the finite-element
/// kernel), the friction among them.
#[test]
fn every_bp5_setting_is_in_the_fingerprint() {
    let base = SeasBp5Run::default();
    each_changes_the_fingerprint! { base =>
        kernel = Bp5Kernel::Fe; dx = 4000.0; end_years = 1.0; tolerance = 1e-7;
        integrator = OdeIntegrator::Rkc; epsilon = 1e-5;
        sigma_n = 30e6; a0 = 0.005; a_max = 0.03; b0 = 0.02;
        l = 0.1; l_nucleation = 0.1; f0 = 0.5;
        v0 = 1e-5; v_p = 2e-9; v_init = 2e-9; v_i = 0.01;
    }
    let fe = SeasBp5Run {
        kernel: Bp5Kernel::Fe,
        ..base
    };
    each_changes_the_fingerprint! { fe =>
        domain_km = Some(200.0); ratio = Some(1.1); mesh = Some(SeasBp5Mesh::Tensor);
        fault_zone_width_km = Some(4.0), fault_zone_rigidity = Some(0.5);
        condensation = Some(Bp5Condensation::Factor);
        ordering = Some(InteriorOrdering::NestedDissection);
    }
}

/// Every setting of BP8 changes the fingerprint (none is left out of it).
#[test]
fn every_setting_is_in_the_fingerprint() {
    each_changes_the_fingerprint! { SeasBp8Run::default() =>
        source = Bp8Source::Well; end_days = 2.0; dx = 20.0; tolerance = 1e-8;
        overpressure = Bp8OverpressureRule::Refuse; sigma_min = Some(2.0);
        station_interval = 60.0; profile_interval = 60.0;
        integrator = OdeIntegrator::Rkc;
    }
}
