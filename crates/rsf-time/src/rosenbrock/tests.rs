use super::*;
use crate::test_systems::{
    assert_halving_order, dormand_prince_run, error_at, Heat, SpringSlider, StiffLinear,
};

/// The tableau's order conditions up to order 3 (Hairer & Wanner §IV.7, Table 7.1,
/// with `βᵢⱼ = αᵢⱼ + γᵢⱼ`), the embedded solution's up to 2, and those of a W-method
/// up to 3 (any approximation of `J`: Rang & Angermann's conditions with `αᵢⱼ` and
/// `γᵢⱼ` apart); and the transformed coefficients reproduce `b` through `Γ`.
#[test]
fn the_coefficients_satisfy_the_order_conditions() {
    use ros34pw2::*;
    let (al, g, b, bh) = (ALPHA, GAMMA_IJ, B, B_HAT);
    let alpha: Vec<f64> = al.iter().map(|r| r.iter().sum()).collect();
    let beta = |i: usize, j: usize| al[i][j] + if j < i { g[i][j] } else { 0.0 };
    let beta_p: Vec<f64> = (0..4).map(|i| (0..i).map(|j| beta(i, j)).sum()).collect();
    let gp: Vec<f64> = (0..4).map(|i| (0..i).map(|j| g[i][j]).sum()).collect();
    let ap: Vec<f64> = alpha.clone();
    let sum = |f: &dyn Fn(usize) -> f64| (0..4).map(f).sum::<f64>();
    let gm = GAMMA;
    let close = |x: f64, y: f64, what: &str| assert!((x - y).abs() < 1e-14, "{what}: {x} vs {y}");
    for (w, name) in [(b, "b"), (bh, "b̂")] {
        close(sum(&|i| w[i]), 1.0, name);
        close(sum(&|i| w[i] * beta_p[i]), 0.5 - gm, name);
    }
    close(sum(&|i| b[i] * alpha[i] * alpha[i]), 1.0 / 3.0, "b α²");
    let bbb = sum(&|i| b[i] * (0..i).map(|j| beta(i, j) * beta_p[j]).sum::<f64>());
    close(bbb, 1.0 / 6.0 - gm + gm * gm, "b β β'");
    // W-method conditions of order 2 and 3 (J arbitrary): α and γ enter apart.
    close(sum(&|i| b[i] * ap[i]), 0.5, "W: b α");
    close(sum(&|i| b[i] * gp[i]), -gm, "W: b γ'");
    let w3: [(f64, f64); 4] = [
        (
            sum(&|i| b[i] * (0..i).map(|j| al[i][j] * ap[j]).sum::<f64>()),
            1.0 / 6.0,
        ),
        (
            sum(&|i| b[i] * (0..i).map(|j| al[i][j] * gp[j]).sum::<f64>()),
            -gm / 2.0,
        ),
        (
            sum(&|i| b[i] * (0..i).map(|j| g[i][j] * ap[j]).sum::<f64>()),
            -gm / 2.0,
        ),
        (
            sum(&|i| b[i] * (0..i).map(|j| g[i][j] * gp[j]).sum::<f64>()),
            gm * gm,
        ),
    ];
    for (k, (x, y)) in w3.iter().enumerate() {
        close(*x, *y, &format!("W order 3, condition {k}"));
    }
    // m = b Γ⁻¹: Σ mᵢ uᵢ with uᵢ = Σ γᵢⱼ kⱼ is Σ bⱼ kⱼ.
    let t = Transformed::ros34pw2();
    for j in 0..4 {
        let bj: f64 = (j..4).map(|i| t.m[i] * g[i][j]).sum();
        close(bj, b[j], "m Γ = b");
    }
}

fn fixed_options(h: f64) -> (RungeKuttaOptions, RosenbrockOptions) {
    (
        RungeKuttaOptions {
            dt_max: h,
            ..RungeKuttaOptions::default()
        },
        RosenbrockOptions {
            krylov_tolerance: 1e-6,
            max_krylov_iterations: 400,
            ..RosenbrockOptions::default()
        },
    )
}

/// Third order on a stiff linear system with a known solution whose Jacobian is not
/// diagonal (the heat equation `y' = −c L y`, eigenvalues 2.2 to 400, from its two
/// smoothest sine modes and the stiffest; Jacobi-preconditioned GMRES): at fixed steps
/// h = 0.2, 0.1, 0.05 (`dt_max`, `h λ_max` = 80 to 20; tolerance 1 and solves to
/// 1e-10 absolute: no step fails, the solves' error is below the method's) the error at t = 2 falls by 8 per halving. (With
/// a source whose solution is `v cos t` — the Prothero–Robinson form — the measured
/// order is 2.5: Rosenbrock methods' order reduction on stiff problems with
/// time-dependent data, which the fault ODE's loading, linear in `t`, does not have.)
#[test]
fn third_order_on_a_stiff_linear_system() {
    let mut errors = Vec::new();
    for h in [0.2, 0.1, 0.05] {
        let mut sys = Heat {
            c: 100.0,
            n: 20,
            tol: 1.0,
            forced: false,
        };
        let (o, mut r) = fixed_options(h);
        r.krylov_tolerance = 1e-10;
        let mut ros = Rosenbrock::new(o, r, 20, h).unwrap();
        let (mut t, mut y) = (0.0, sys.modal(0.0));
        let (mut steps, mut krylov) = (0, 0);
        while t < 2.0 {
            let s = ros.step(&mut sys, &mut t, &mut y, Some(2.0)).unwrap();
            assert_eq!(s.step.rejected, 0);
            assert!(s.preconditioned);
            steps += 1;
            krylov += s.krylov_iterations;
        }
        let exact = sys.modal(t);
        let e = y
            .iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        println!("h = {h}: error {e:e}, {steps} steps, {krylov} GMRES iterations");
        errors.push(e);
    }
    assert_halving_order(&errors, 3.0, 0.3);
}

/// Third order on the spring–slider (docs/spring-block.md, as RKC2's test): fixed steps
/// `h = 1.6, 0.8, 0.4 s` against Dormand–Prince 5(4) at tolerance 1e-12, the error in
/// slip (in `L`) and state at `t = 60 s` falls by 8 per halving. Without local
/// Jacobian: GMRES alone on the 2 × 2 system.
#[test]
fn third_order_on_the_spring_slider() {
    SpringSlider::assert_order([1.6, 0.8, 0.4], (3.0, 0.35), |h, t_end| {
        let (o, mut r) = fixed_options(h);
        r.krylov_tolerance = 1e-9;
        let mut ros = Rosenbrock::new(o, r, 2, h).unwrap();
        let mut sys = SpringSlider { tol: 1e-2 };
        let (mut t, mut y) = (0.0, SpringSlider::start());
        let mut steps = 0;
        while t < t_end {
            let s = ros.step(&mut sys, &mut t, &mut y, Some(t_end)).unwrap();
            assert_eq!(s.step.rejected, 0, "h = {h}");
            steps += 1;
        }
        (y, steps)
    });
}

fn ros_run(sys: &mut StiffLinear, t_end: f64) -> (f64, usize, usize) {
    let n = sys.lambda.len();
    let mut ros = Rosenbrock::new(
        RungeKuttaOptions::default(),
        RosenbrockOptions::default(),
        n,
        1e-3,
    )
    .unwrap();
    let (mut t, mut y) = (0.0, (0..n).map(StiffLinear::v).collect::<Vec<_>>());
    let (mut steps, mut krylov) = (0, 0);
    while t < t_end {
        let s = ros.step(sys, &mut t, &mut y, Some(t_end)).unwrap();
        steps += 1;
        krylov += s.krylov_iterations;
    }
    (error_at(&y, t), steps, krylov)
}

/// The stability test (as RKC2's): λ_max = 1e4 × 3.3/h with `h` the accuracy step on
/// the same problem with λ_max = 1 at tolerance 1e-6: ROS34PW2 takes the steps
/// accuracy sets (within 1.5× of the soft problem's count, with and without the
/// exact block Jacobian as preconditioner), the pair at least 100× more.
#[test]
fn a_stiff_problem_takes_the_steps_accuracy_sets() {
    let (tol, t_end) = (1e-6, 1.0);
    let mut soft = StiffLinear::new(8, 1.0, tol);
    let (e_soft, n_soft, _) = ros_run(&mut soft, t_end);
    let h_acc = t_end / n_soft as f64;
    let lambda_max = 1e4 * 3.3 / h_acc;
    let mut krylov_without = 0;
    for blocks in [false, true] {
        let mut stiff = StiffLinear::new(8, lambda_max, tol);
        stiff.blocks = blocks;
        let (e_stiff, n_stiff, krylov) = ros_run(&mut stiff, t_end);
        println!(
            "ROS34PW2: {n_soft} steps (error {e_soft:e}) at λ_max = 1, {n_stiff} steps \
             (error {e_stiff:e}, {krylov} GMRES iterations, {} evaluations) at λ_max = \
             {lambda_max:e}, blocks {blocks}",
            stiff.evaluations
        );
        assert!(lambda_max * h_acc / 3.3 >= 0.999e4);
        assert!(2 * n_stiff <= 3 * n_soft, "{n_stiff} against {n_soft}");
        assert!(e_stiff < 1e-4, "{e_stiff}");
        if blocks {
            // The exact Jacobian as preconditioner: a few iterations per solve (the
            // finite difference's round-off at h λ ≈ 1e4), far fewer than without.
            assert!(
                2 * krylov < krylov_without,
                "{krylov} against {krylov_without}"
            );
        } else {
            krylov_without = krylov;
        }
    }
    let (_, steps) = dormand_prince_run(&mut StiffLinear::new(8, lambda_max, tol), t_end);
    assert!(steps >= 100 * n_soft, "{steps} against {n_soft}");
}

/// A checkpoint's controller and rate continue the integration bit for bit.
#[test]
fn restore_continues_bit_for_bit() {
    let n = 20;
    let run = |split: Option<usize>| {
        let mut sys = Heat {
            c: 1e4,
            n,
            tol: 1e-6,
            forced: true,
        };
        let new = || {
            Rosenbrock::new(
                RungeKuttaOptions::default(),
                RosenbrockOptions::default(),
                n,
                1e-4,
            )
            .unwrap()
        };
        let mut ros = new();
        let (mut t, mut y) = (0.0, (0..n).map(StiffLinear::v).collect::<Vec<_>>());
        for k in 0..60 {
            if Some(k) == split {
                let (state, rate) = (ros.state(), ros.current_rate().unwrap().to_vec());
                ros = new();
                ros.set_state(RungeKuttaState {
                    dt: 1.0,
                    previous_error: 0.5,
                });
                ros.restore(state, &rate).unwrap();
            }
            ros.step(&mut sys, &mut t, &mut y, None).unwrap();
        }
        (
            t.to_bits(),
            y.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        )
    };
    assert_eq!(run(None), run(Some(23)));
}
