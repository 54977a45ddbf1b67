//! The pressure diffusing over a fault surface (`rsf::pore_pressure::SurfaceDiffusion`,
//! docs/pore-pressure.md) through the `PorePressure` seam of a 3-D model: a uniform
//! pressure `p₀` of the field is the laws at `σ̄_n − p₀` bit for bit — a fault alone
//! (BP5's cells and Okada's operator) and BP5's finite-element volume with its internal
//! fault, both by the fault ODE, and the volume by the implicit scheme — and the fault
//! ODE ends a step at the injection's shut-in.

use std::sync::Arc;

use rsf::pore_pressure::{
    FaultPlane, FaultZone, Injection, PorePressure, SurfaceDiffusion, SurfaceGrid,
    SurfaceInjection, SurfaceSource,
};
use rsf::{Stepping, Until};
use rsf_scenes::SeasBp5;

use crate::{bp5_zone_grid, StepTimes};

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// BP5's fault plane `x = 0`, `(u, v) = (x₂, depth)`.
fn bp5_plane() -> FaultPlane {
    FaultPlane {
        origin: [0.0; 3],
        axis_u: [0.0, 1.0, 0.0],
        axis_v: [0.0, 0.0, -1.0],
    }
}

/// A fault zone 10 m thick, k = 1e-13 m², φ = 0.1, β = 1e-8 /Pa, η_f = 1e-3 Pa·s
/// (α = 0.1 m²/s, BP6's).
fn zone() -> FaultZone {
    FaultZone {
        thickness: 10.0,
        permeability: 1e-13,
        porosity: 0.1,
        compressibility: 1e-8,
        viscosity: 1e-3,
    }
}

/// The field on BP5's fault (±50 km along strike, 0–40 km deep, 5 km cells) from `rate`
/// (m³/s) through a well at 10 km depth until `shut_in`, from the uniform `p0`.
fn field(rate: f64, shut_in: f64, p0: f64) -> Arc<SurfaceDiffusion> {
    let injection = SurfaceInjection {
        injection: Injection { rate, shut_in },
        source: SurfaceSource::Gaussian { width: 5e3 },
        position: [0.0, 10e3],
    };
    let grid = SurfaceGrid {
        lower: [-50e3, 0.0],
        upper: [50e3, 40e3],
        cells: [20, 8],
    };
    Arc::new(
        SurfaceDiffusion::new(zone(), injection, bp5_plane(), grid)
            .unwrap()
            .with_initial_pressure(p0)
            .unwrap(),
    )
}

/// BP5's fault alone on 10 km cells (Okada's operator, two slip components) with the laws
/// of `laws` and the pore pressure `pressure`, on one thread.
pub(crate) fn bp5_fault_alone(
    laws: SeasBp5,
    pressure: Option<Arc<dyn PorePressure<3>>>,
) -> rsf_scenes::SeasBp5FaultOde {
    let bp5 = SeasBp5::default();
    let model = bp5.model(10e3).unwrap();
    let half_space = bp5.half_space(1e-6).unwrap();
    let operator =
        rsf::halfspace_operator::HalfSpaceOperator::fault_alone(&model, &half_space).unwrap();
    let cells = model.vertices.len();
    let alone = rsf::fault_alone::FaultAlone {
        operator: Box::new(operator),
        plate_velocity: (0..cells).flat_map(|_| [bp5.v_p, 0.0]).collect(),
    };
    let mut o = bp5.fault_ode_options(1e-6).unwrap();
    o.parallelism = rsf::Parallelism::SEQ;
    let b = laws.problem_builder(model);
    let b = match pressure {
        Some(p) => b.pore_pressure(p),
        None => b,
    };
    b.build_fault_ode_alone(o, alone).unwrap()
}

/// 60 steps of [`bp5_fault_alone`]: the slip's and the state's bits, and the time.
pub(crate) fn fault_alone(
    laws: SeasBp5,
    pressure: Option<Arc<dyn PorePressure<3>>>,
) -> (Vec<u64>, Vec<u64>, f64) {
    let mut ode = bp5_fault_alone(laws, pressure);
    ode.run_until(Until::Steps(60), &mut []).unwrap();
    (
        bits(&ode.state().kinematics.u),
        bits(&ode.state().alpha),
        ode.state().time,
    )
}

#[test]
fn a_uniform_surface_pressure_is_the_lowered_normal_stress_on_a_fault_alone() {
    let bp5 = SeasBp5::default();
    let p0 = 3e6;
    let with_p = fault_alone(bp5, Some(field(0.0, 1e9, p0)));
    let plain = fault_alone(
        SeasBp5 {
            sigma_n: bp5.sigma_n - p0,
            ..bp5
        },
        None,
    );
    assert!(with_p.2 > 0.0);
    assert_eq!(with_p, plain);
}

#[test]
fn a_uniform_surface_pressure_is_the_lowered_normal_stress_in_a_volume_on_both_engines() {
    let bp5 = SeasBp5::default();
    let p0 = 3e6;
    let lowered = SeasBp5 {
        sigma_n: bp5.sigma_n - p0,
        ..bp5
    };
    let model = bp5.fe_model(&bp5_zone_grid()).unwrap();
    // The fault ODE, 40 steps.
    let ode = |laws: &SeasBp5, pressure: Option<Arc<dyn PorePressure<3>>>| {
        let mut o = bp5.fault_ode_options(1e-6).unwrap();
        o.parallelism = rsf::Parallelism::SEQ;
        let b = laws.problem_builder(model.clone());
        let b = match pressure {
            Some(p) => b.pore_pressure(p),
            None => b,
        };
        let mut ode = b.build_fault_ode(o).unwrap();
        ode.run_until(Until::Steps(40), &mut []).unwrap();
        (bits(&ode.state().kinematics.u), bits(&ode.state().alpha))
    };
    assert_eq!(ode(&bp5, Some(field(0.0, 1e9, p0))), ode(&lowered, None));
    // The implicit scheme, 5 steps of 1 s. The fixed point's tolerance is absolute (in the
    // energy norm); on this model its corrections fall from 2e6 to a round-off floor near
    // 1e-8 (5e-15 of the first), which the default 1e-10 sits below: 1e-6 ends every step
    // above the floor. The test asks for the same bits of two runs, not for convergence.
    let fixed_point = rsf::method::FixedPointOptions {
        tolerance: 1e-6,
        ..rsf::method::FixedPointOptions::default()
    };
    let implicit = |laws: &SeasBp5, pressure: Option<Arc<dyn PorePressure<3>>>| {
        let b = laws
            .problem_builder(model.clone())
            .solver(rsf::SolverKind::Direct)
            .fixed_point(fixed_point)
            .time_step(1.0);
        let b = match pressure {
            Some(p) => b.pore_pressure(p),
            None => b,
        };
        let mut sim = b.build().unwrap();
        sim.run_until(Until::Steps(5), &mut []).unwrap();
        (bits(&sim.state().kinematics.u), bits(&sim.state().alpha))
    };
    let (a, b) = (
        implicit(&bp5, Some(field(0.0, 1e9, p0))),
        implicit(&lowered, None),
    );
    assert!(a.0.iter().any(|&u| u != 0));
    assert_eq!(a, b);
}

#[test]
fn the_fault_ode_ends_a_step_at_the_shut_in() {
    // Fluid injected for 1000 s into BP5's fault alone (1 m³/s: the pressure it adds, some
    // 100 Pa, changes the run): some step ends at 1000 s exactly.
    let bp5 = SeasBp5::default();
    let pressure = field(1.0, 1000.0, 0.0);
    let mut ode = bp5_fault_alone(bp5, Some(pressure.clone()));
    let mut times = StepTimes(Vec::new());
    ode.run_until(
        Until::TimeWithin {
            time: 2000.0,
            max_steps: 100_000,
        },
        &mut [&mut times],
    )
    .unwrap();
    assert!(
        times.0.iter().any(|&t| t.to_bits() == 1000f64.to_bits()),
        "no step ends at the shut-in"
    );
    // The observers' normal stress is σ̄_n − p at the cells' centres: at the cell nearest
    // the source (x₂ = 0, 10 km deep).
    let vertices = &ode.model().vertices;
    let distance = |x: &[f64; 3]| x[1].hypot(x[2] + 10e3);
    let k = (0..vertices.len())
        .min_by(|&a, &b| distance(&vertices[a]).total_cmp(&distance(&vertices[b])))
        .unwrap();
    let x = vertices[k];
    let t = ode.state().time;
    let want = bp5.sigma_n - pressure.pressure(&x, t);
    assert!(want < bp5.sigma_n);
    assert_eq!(ode.fault_tractions().normal_traction(k), Some(want));
}

/// BP8-GS's pressure as the scene builds it (the Gaussian source of Table 1 diffusing over
/// the square with no-flux edges, 10 m cells) against the benchmark's derived check values
/// of the bounded fault (written in the test from the restatement of the description; a
/// finite-volume solve at 5 m, agreeing with 10 m to 0.02 MPa), at the source, 200 m along
/// strike and on the diagonal, from 10 h to 300 h (across the shut-in at 100 h): within
/// 0.05 MPa, so that the scene's L_gauss, k, φ, β, η_f, L_fwid, Q₀ and t_off are the
/// description's (the Gaussian twice as wide gives 1.5 MPa at the source after 10 h against
/// 4.26, the permeability 10 % higher 0.8 MPa less there at the shut-in).
#[test]
fn bp8_gs_pressure_is_the_descriptions_at_its_check_values() {
    let bp8 = rsf_scenes::SeasBp8::default();
    let field = bp8.pressure(rsf_scenes::Bp8Source::Gaussian, 10.0).unwrap();
    // (t in hours, p at (0, 0), (200, 0), (200, 200) m in MPa).
    let check: [(f64, [f64; 3]); 6] = [
        (10.0, [4.263, 0.044, 0.001]),
        (50.0, [10.052, 1.091, 0.250]),
        (100.0, [13.062, 2.571, 0.990]),
        (150.0, [4.851, 2.716, 1.573]),
        (200.0, [3.203, 2.306, 1.675]),
        (300.0, [2.125, 1.892, 1.687]),
    ];
    let points = [[0.0, 0.0, 0.0], [0.0, 200.0, 0.0], [0.0, 200.0, 200.0]];
    let mut worst: f64 = 0.0;
    for (hours, want) in check {
        for (x, w) in points.iter().zip(want) {
            let p = field.pressure(x, hours * 3600.0) / 1e6;
            worst = worst.max((p - w).abs());
        }
    }
    eprintln!("BP8-GS against the bounded check values: worst {worst:.4} MPa");
    assert!(worst <= 0.05, "{worst} MPa");
}

/// BP8-PW's field keeps the description's volume (its exact mass check, restated in
/// `../shared/benchmarks/seas-bp8.md`, "Exact mass checks"): with no flux across the
/// square's edges, the fluid stored in the fault zone, `φβL_fwid Σ A_ij p_ij`, and in the
/// well, `S_well p_w`, is the injected `Q₀ min(t, t_off)` — every value written here from
/// Table 1 (`φ = 0.1`, `β = 1e-8 /Pa`, `L_fwid = 1 m`, `S_well = 1e-7 m³/Pa`, `Q₀ = 3e-3
/// m³/s`, `t_off = 100 h`, `l_f = 400 m`), the nodes' areas (half cells on the edges,
/// quarter cells at the corners) recomputed here. The well's storage holds 6 % of the
/// volume after 10 h (`S_well p_w`, with `p_w` ≈ 65 MPa): a scene whose well stored twice
/// as much (issue 87's surviving mutant) or whose zone another volume breaks the balance by
/// far more than its round-off.
#[test]
fn bp8_pw_stores_the_descriptions_injected_volume_in_the_zone_and_the_well() {
    let bp8 = rsf_scenes::SeasBp8::default();
    let dx = 10.0;
    let field = bp8.pressure(rsf_scenes::Bp8Source::Well, dx).unwrap();
    let g = *field.grid();
    let [nu, nv] = g.nodes();
    // The description's square, at the description's spacing.
    assert_eq!([nu, nv], [81, 81]);
    let (phi, beta, l_fwid, s_well) = (0.1, 1e-8, 1.0, 1e-7);
    let (q0, t_off) = (3e-3, 100.0 * 3600.0);
    let area = |i: usize, n: usize| if i == 0 || i == n - 1 { dx / 2.0 } else { dx };
    let mut worst: f64 = 0.0;
    let mut well_share: f64 = 0.0;
    for hours in [0.1, 1.0, 10.0, 50.0, 100.0, 150.0, 300.0] {
        let t = hours * 3600.0;
        let p = field.nodes(t);
        let mut zone = 0.0;
        for j in 0..nv {
            for i in 0..nu {
                zone += phi * beta * l_fwid * area(i, nu) * area(j, nv) * p[i + nu * j];
            }
        }
        let well = s_well * field.well_pressure(t).expect("PW has a well");
        let injected = q0 * t.min(t_off);
        worst = worst.max(((zone + well) - injected).abs() / injected);
        if hours == 10.0 {
            well_share = well / injected;
        }
    }
    eprintln!(
        "BP8-PW: |stored − injected| / injected ≤ {worst:.1e}; the well holds {:.1} % at 10 h",
        100.0 * well_share
    );
    // Round-off of 6 562 unknowns, each a sum over the field's modes (the library's own
    // balance test finds 1e-12 and less on this grid).
    assert!(worst < 1e-10, "{worst}");
    // The check bites: the well's share is far above the round-off.
    assert!(well_share > 1e-2, "{well_share}");
    // The well's coupling is the description's well index `WI = 2π k L_fwid / (η_f
    // ln(r_e/r_well))` with `r_e = 0.198 Δx` (Peaceman's for the five-point Laplacian on
    // squares, §2.1.2), `k = 5e-14 m²`, `η_f = 1e-3 Pa s`, `r_well = 0.05 m`: 8.5e-11 m³/(Pa s).
    // (Peaceman's `0.14 √2 Δx` is 0.19799 Δx: 1.4e-5 apart in WI.)
    let (k, eta_f, r_well) = (5e-14, 1e-3, 0.05);
    let wi = 2.0 * std::f64::consts::PI * k * l_fwid / (eta_f * (0.198 * dx / r_well).ln());
    let scene = field.well_index().expect("PW has a well");
    assert!((scene - wi).abs() < 1e-4 * wi, "{scene} against {wi}");
}
