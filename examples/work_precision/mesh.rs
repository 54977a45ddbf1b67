//! The mesh studies: error against the refinement level, and the energy-norm error of a
//! frictionless shear mode.

use std::fmt::Write as _;

use rsf::SolverKind;
use rsf_scenes::SliderScene;

use crate::common::{base, log, window, Ctx, Res};
use crate::errors::{errors, opt, row, Errors, ROW_HEAD};
use crate::plot::{plot_panels, Line};
use crate::trace::trace;

/// Frictionless shear mode at `level` with `steps` per period, run for 1.25 periods; returns (discrete energy
/// error, interpolation error, both relative; CPU seconds; dofs).
fn energy_run(level: usize, steps: usize, solver: SolverKind) -> Res<(f64, f64, f64, usize)> {
    let cpu0 = rsf_programs::cpu_seconds();
    let probe = SliderScene::default();
    let mu = probe.youngs_modulus_pa / (2.0 * (1.0 + probe.poisson_ratio));
    let rho = probe.density_kg_per_m2;
    let omega = std::f64::consts::PI * (mu / rho).sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    let amp = 1e-4;
    // 1.25 periods: u is at its maximum (sin ωt = 1), so the H¹ part dominates the norm.
    let scene = SliderScene {
        level,
        steps: steps + steps / 4,
        end_time_s: 1.25 * period,
        solver,
        ..SliderScene::default()
    };
    let mut model = scene.build_model()?;
    model.load.fill(0.0);
    model.initial_displacement.fill(0.0);
    model.dirichlet = rsf::model::DirichletVelocity::none();
    let (x_lo, x_hi) = (0.0, 5.0);
    for (p, x) in model.vertices.iter().enumerate() {
        if x[1].abs() < 1e-12 {
            model.fixed[2 * p] = true;
            model.fixed[2 * p + 1] = true;
        }
        if (x[0] - x_lo).abs() < 1e-12 || (x[0] - x_hi).abs() < 1e-12 {
            model.fixed[2 * p + 1] = true;
        }
    }
    let vertices = model.vertices.clone();
    let mut sim = scene.build_with_model(model)?;
    let mut cp = sim.checkpoint();
    for (p, x) in vertices.iter().enumerate() {
        cp.state.kinematics.v[2 * p] = amp * omega * (std::f64::consts::PI * x[1]).sin();
        cp.state.kinematics.v[2 * p + 1] = 0.0;
    }
    cp.state.kinematics.u.fill(0.0);
    cp.state.kinematics.a.fill(0.0);
    sim.restore(&cp)?;
    for _ in 0..scene.steps {
        sim.step()?;
    }
    let t = sim.time();
    let (s, co) = (omega * t).sin_cos();
    let kin = sim.kinematics();
    let n = kin.u.len();
    let mut e = vec![0.0; n];
    let mut ed = vec![0.0; n];
    for (p, x) in vertices.iter().enumerate() {
        let f = (std::f64::consts::PI * x[1]).sin();
        e[2 * p] = kin.u[2 * p] - amp * f * s;
        e[2 * p + 1] = kin.u[2 * p + 1];
        ed[2 * p] = kin.v[2 * p] - amp * omega * f * co;
        ed[2 * p + 1] = kin.v[2 * p + 1];
    }
    let m = sim.model();
    let quad = |a: &rsf::fem::SparseMatrix, x: &[f64]| {
        let mut y = vec![0.0; x.len()];
        rsf::fem::spmv_add(a.as_ref(), 1.0, x, &mut y);
        x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>()
    };
    let mass = m.mass.as_ref().ok_or("no mass matrix")?;
    let err2 = quad(&m.stiffness, &e) + quad(mass, &ed);
    // Exact energy norm²: ∫ μ f'² + ρ ḟ² over [0,5]×[0,1] = 2.5 μ A² π² (constant in t).
    let pi = std::f64::consts::PI;
    let exact2 = 2.5 * mu * amp * amp * pi * pi;
    // Interpolation error of the y-only field on the 2^j horizontal strips (exact 1D
    // integrals by 5-point Gauss per strip).
    let cells = 1usize << level;
    let h = 1.0 / cells as f64;
    let gx = [
        0.0,
        -0.538_469_310_105_683,
        0.538_469_310_105_683,
        -0.906_179_845_938_664,
        0.906_179_845_938_664,
    ];
    let gw = [
        0.568_888_888_888_889,
        0.478_628_670_499_366,
        0.478_628_670_499_366,
        0.236_926_885_056_189,
        0.236_926_885_056_189,
    ];
    let mut interp2 = 0.0;
    for k in 0..cells {
        let (y0, y1) = (k as f64 * h, (k + 1) as f64 * h);
        let (f0, f1) = ((pi * y0).sin(), (pi * y1).sin());
        for (x, w) in gx.iter().zip(&gw) {
            let y = 0.5 * (y0 + y1) + 0.5 * h * x;
            let lin = f0 + (f1 - f0) * (y - y0) / h;
            let df = pi * (pi * y).cos() - (f1 - f0) / h;
            let d0 = (pi * y).sin() - lin;
            interp2 += 0.5
                * h
                * w
                * 5.0
                * (mu * (amp * s * df).powi(2) + rho * (amp * omega * co * d0).powi(2));
        }
    }
    Ok((
        (err2.max(0.0) / exact2).sqrt(),
        (interp2 / exact2).sqrt(),
        rsf_programs::cpu_seconds() - cpu0,
        n,
    ))
}

pub(crate) fn mesh_study(c: &Ctx) -> Res<()> {
    let levels: Vec<usize> = if c.big {
        (2..=6).collect()
    } else {
        (2..=5).collect()
    };
    let n = c.mesh_steps;
    let ref_level = *levels.last().expect("levels");
    let mut rs = base(ref_level, n);
    rs.solver = SolverKind::Direct;
    let (tmin, tmax) = window(&rs);
    log(&format!("mesh study: reference j = {ref_level}, N = {n}"));
    let reference = trace(&rs, tmin, tmax, true)?;
    log(&format!("  reference: {:.1} s", reference.seconds()));
    let mut csv = format!("level,solver,N,{ROW_HEAD}\n");
    let _ = writeln!(
        csv,
        "{ref_level},direct-reference,{n},{}",
        row(&reference, &Errors::default())
    );
    let mut points = Vec::new();
    for solver in [SolverKind::Tnnmg, SolverKind::Direct] {
        for &j in &levels[..levels.len() - 1] {
            let mut s = base(j, n);
            s.solver = solver;
            let tr = trace(&s, tmin, tmax, true)?;
            let e = errors(&tr, &reference, &s);
            log(&format!(
                "  j = {j} {}: {:.2} s, err a {} b {} c {}",
                solver.name(),
                tr.seconds(),
                opt(e.u),
                opt(e.ts),
                opt(e.lnv)
            ));
            let _ = writeln!(csv, "{j},{},{n},{}", solver.name(), row(&tr, &e));
            std::fs::write(c.out.join("mesh.csv"), &csv)?;
            points.push(e.point(format!("{} (j = 2…)", solver.name()), &tr));
        }
    }
    // Timing of the reference with TNNMG, for the TNNMG-vs-direct comparison at j_max.
    let mut rt = rs.clone();
    rt.solver = SolverKind::Tnnmg;
    if let Ok(tr) = trace(&rt, tmin, tmax, true) {
        let e = errors(&tr, &reference, &rt);
        log(&format!(
            "  j = {ref_level} tnnmg: {:.2} s, err a {} b {} c {}",
            tr.seconds(),
            opt(e.u),
            opt(e.ts),
            opt(e.lnv)
        ));
        let _ = writeln!(csv, "{ref_level},tnnmg,{n},{}", row(&tr, &e));
        std::fs::write(c.out.join("mesh.csv"), &csv)?;
    }
    let energy = energy_study(c)?;
    plot_panels(
        &c.figures.join("work_precision_mesh.png"),
        &format!(
            "Mesh: j = 2…{}, τ = T/{n}, error vs j = {ref_level}; (e) frictionless mode",
            ref_level - 1
        ),
        &points,
        Some(("(e) shear mode, energy norm", energy)),
    )?;
    Ok(())
}

/// Frictionless shear-mode study; returns plot series (seconds, error) per line.
pub(crate) fn energy_study(c: &Ctx) -> Res<Vec<Line>> {
    let levels: Vec<usize> = (2..=6).collect();
    let mut csv = String::from(
        "level,solver,steps_per_period,dofs,cpu_s,err_energy_discrete_rel,err_interp_rel\n",
    );
    let mut lines = vec![
        ("tnnmg discrete".to_string(), Vec::new()),
        ("direct discrete".to_string(), Vec::new()),
        ("interpolation".to_string(), Vec::new()),
    ];
    for &j in &levels {
        for (i, solver) in [SolverKind::Tnnmg, SolverKind::Direct]
            .into_iter()
            .enumerate()
        {
            for steps in [c.energy_steps, 2 * c.energy_steps] {
                if steps != c.energy_steps && j != 2 && j != 6 {
                    continue;
                }
                match energy_run(j, steps, solver) {
                    Ok((err, interp, secs, dofs)) => {
                        log(&format!(
                            "  energy j = {j} {} steps {steps}: {secs:.2} s, err {err:.3e}, \
                             interp {interp:.3e}",
                            solver.name()
                        ));
                        let _ = writeln!(
                            csv,
                            "{j},{},{steps},{dofs},{secs:.4},{err:.6e},{interp:.6e}",
                            solver.name()
                        );
                        std::fs::write(c.out.join("energy.csv"), &csv)?;
                        if steps == c.energy_steps {
                            lines[i].1.push((secs, err));
                            if i == 0 {
                                lines[2].1.push((secs, interp));
                            }
                        }
                    }
                    Err(e) => log(&format!("  energy j = {j} {}: {e}", solver.name())),
                }
            }
        }
    }
    Ok(lines)
}
