//! Frictionless elastodynamics on the paper's slider mesh (Table 6.1 material):
//! energy conservation (Newmark), monotone dissipation (backward Euler) and the
//! measured order in τ against the exact solution of a single vibration mode.
use rsf_fem::*;
use rsf_time::*;

const RHO: f64 = 5e3;

struct Problem {
    m: SparseMatrix,
    k: SparseMatrix,
    fixed: Vec<bool>,
    mesh: TriangleMesh,
}

fn slider(level: usize) -> Problem {
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), level);
    let mesh = h.finest().clone();
    let asm = Assembler::new(&mesh).unwrap();
    let mat = LinearElasticity::plane_strain(5e7, 0.3).unwrap();
    let m = asm.mass(&mesh, RHO).unwrap();
    let k = asm.stiffness(&mesh, &mat).unwrap();
    let top = BoundarySegment::from_tag(&mesh, TAG_DIRICHLET).unwrap();
    let mut c = Constraints::<2>::new(mesh.num_vertices());
    c.fix_nodes(top.nodes(), &[0, 1], [0.0, 0.0]).unwrap();
    Problem {
        m,
        k,
        fixed: c.fixed().to_vec(),
        mesh,
    }
}

fn quad(a: &SparseMatrix, x: &[f64]) -> f64 {
    let mut y = vec![0.0; x.len()];
    spmv_add(a.as_ref(), 1.0, x, &mut y);
    x.iter().zip(&y).map(|(a, b)| a * b).sum()
}

/// `[½vᵀMv, ½uᵀKu]`: kinetic and elastic energy.
fn energies(p: &Problem, s: &Kinematics) -> [f64; 2] {
    [0.5 * quad(&p.m, &s.v), 0.5 * quad(&p.k, &s.u)]
}

/// Released from the gravity-loaded equilibrium (then gravity switched off):
/// u_0 solves K u = F_g, v_0 = 0, a_0 consistent (M a_0 = −K u_0 on free dofs).
fn released_state(p: &Problem) -> Kinematics {
    let n = p.fixed.len();
    let g = body_force_load(&p.mesh, |_| [0.0, -RHO * 9.81]).unwrap();
    let mut s = Kinematics::zeros(n);
    ConstrainedSystem::new(p.k.as_ref(), &p.fixed)
        .unwrap()
        .solve(&g, &mut s.u)
        .unwrap();
    let mut ku = vec![0.0; n];
    spmv_add(p.k.as_ref(), -1.0, &s.u, &mut ku);
    ConstrainedSystem::new(p.m.as_ref(), &p.fixed)
        .unwrap()
        .solve(&ku, &mut s.a)
        .unwrap();
    s
}

/// Runs `steps` frictionless steps with zero load, returning the kinetic and elastic
/// energies of every step (and the start).
fn run<I: VelocityIntegrator>(
    integ: &I,
    p: &Problem,
    mut s: Kinematics,
    tau: f64,
    steps: usize,
) -> (Vec<[f64; 2]>, Kinematics) {
    let n = p.fixed.len();
    let (cm, ck) = integ.coefficients(tau);
    let a = combine(cm, &p.m, ck, &p.k).unwrap();
    let mut sys = ConstrainedSystem::new(a.as_ref(), &p.fixed).unwrap();
    let load = vec![0.0; n];
    let mut rhs = vec![0.0; n];
    let mut v = vec![0.0; n];
    let mut next = Kinematics::zeros(n);
    let mut e = vec![energies(p, &s)];
    for _ in 0..steps {
        integ
            .right_hand_side(
                tau,
                SystemMatrices::new(Some(&p.m), &p.k),
                &load,
                &s,
                &mut rhs,
            )
            .unwrap();
        sys.solve(&rhs, &mut v).unwrap(); // fixed entries of v stay 0
        integ.advance(tau, &s, &v, &mut next);
        std::mem::swap(&mut s, &mut next);
        e.push(energies(p, &s));
    }
    (e, s)
}

#[test]
fn newmark_conserves_energy() {
    let p = slider(2);
    let s0 = released_state(&p);
    let (parts, s) = run(&Newmark, &p, s0.clone(), 1e-3, 1000);
    let e: Vec<f64> = parts.iter().map(|[k, el]| k + el).collect();
    let e0 = e[0];
    assert!(e0 > 0.0);
    let worst = e.iter().map(|x| ((x - e0) / e0).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-10, "relative energy drift {worst:e}");
    // ...and it really vibrates: released at rest (all energy elastic), the kinetic energy
    // takes a large share at some point (measured: 0.98).
    assert_eq!(parts[0][0], 0.0);
    let share = parts.iter().map(|[k, _]| k / e0).fold(0.0, f64::max);
    assert!(share > 0.5, "largest kinetic share {share}");
    let moved: f64 =
        s.u.iter()
            .zip(&s0.u)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
    assert!(moved > 1e-3 * s0.u.iter().fold(0.0f64, |a, b| a.max(b.abs())));
}

#[test]
fn backward_euler_dissipates_monotonically() {
    let p = slider(2);
    let s0 = released_state(&p);
    let (parts, _) = run(&BackwardEuler, &p, s0, 1e-3, 300);
    let e: Vec<f64> = parts.iter().map(|[k, el]| k + el).collect();
    for w in e.windows(2) {
        assert!(
            w[1] <= w[0] * (1.0 + 1e-13),
            "energy increased: {} -> {}",
            w[0],
            w[1]
        );
    }
    assert!(
        e[e.len() - 1] < 0.5 * e[0],
        "dissipation too weak: {} -> {}",
        e[0],
        e[e.len() - 1]
    );
}

/// Lowest generalised eigenpair (ω², φ) of K φ = ω² M φ on the free dofs, with a
/// generic dense solver: Cholesky M_ff = L Lᵀ, symmetric eigen of L⁻¹ K_ff L⁻ᵀ.
fn lowest_mode(p: &Problem) -> (f64, Vec<f64>) {
    let free: Vec<usize> = (0..p.fixed.len()).filter(|&i| !p.fixed[i]).collect();
    let nf = free.len();
    let mut pos = vec![usize::MAX; p.fixed.len()];
    for (k, &i) in free.iter().enumerate() {
        pos[i] = k;
    }
    let dense = |a: &SparseMatrix| {
        let mut d = nalgebra::DMatrix::<f64>::zeros(nf, nf);
        for j in 0..a.ncols() {
            for (&i, &v) in a.as_ref().row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                if pos[i] != usize::MAX && pos[j] != usize::MAX {
                    d[(pos[i], pos[j])] += v;
                }
            }
        }
        d
    };
    let (m, k) = (dense(&p.m), dense(&p.k));
    let l = nalgebra::Cholesky::new(m).expect("M_ff SPD").l();
    let linv = l.clone().try_inverse().unwrap();
    let c = &linv * k * linv.transpose();
    let c = 0.5 * (&c + c.transpose());
    let eig = c.symmetric_eigen();
    let (imin, &w2) = eig
        .eigenvalues
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.partial_cmp(b.1).unwrap())
        .unwrap();
    let y = eig.eigenvectors.column(imin).into_owned();
    let phi_f = linv.transpose() * y;
    let mut phi = vec![0.0; p.fixed.len()];
    for (k, &i) in free.iter().enumerate() {
        phi[i] = phi_f[k];
    }
    (w2, phi)
}

/// Error in (u, v) at t = one period, in the energy norm ½|e_v|²_M + ½|e_u|²_K (sqrt).
fn mode_error<I: VelocityIntegrator>(
    integ: &I,
    p: &Problem,
    w2: f64,
    phi: &[f64],
    steps: usize,
) -> f64 {
    let omega = w2.sqrt();
    let t_end = 2.0 * std::f64::consts::PI / omega;
    let tau = t_end / steps as f64;
    let mut s = Kinematics::zeros(phi.len());
    s.u.copy_from_slice(phi);
    for (a, f) in s.a.iter_mut().zip(phi) {
        *a = -w2 * f;
    }
    let (_, s) = run(integ, p, s, tau, steps);
    let eu: Vec<f64> =
        s.u.iter()
            .zip(phi)
            .map(|(u, f)| u - f * (omega * t_end).cos())
            .collect();
    let ev: Vec<f64> =
        s.v.iter()
            .zip(phi)
            .map(|(v, f)| v + omega * f * (omega * t_end).sin())
            .collect();
    (0.5 * quad(&p.m, &ev) + 0.5 * quad(&p.k, &eu)).sqrt()
}

#[test]
fn measured_orders_in_tau() {
    let p = slider(1);
    let (w2, phi) = lowest_mode(&p);
    // Check it is an eigenpair of the sparse operators: ‖Kφ − ω² Mφ‖ small.
    let (mut kp, mut mp) = (vec![0.0; phi.len()], vec![0.0; phi.len()]);
    spmv_add(p.k.as_ref(), 1.0, &phi, &mut kp);
    spmv_add(p.m.as_ref(), w2, &phi, &mut mp);
    let scale = kp.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for (i, (a, b)) in kp.iter().zip(&mp).enumerate() {
        if !p.fixed[i] {
            assert!((a - b).abs() < 1e-8 * scale);
        }
    }
    let order = |integ: &dyn Fn(usize) -> f64, ns: &[usize]| -> Vec<f64> {
        let e: Vec<f64> = ns.iter().map(|&n| integ(n)).collect();
        eprintln!("errors {e:?}");
        e.windows(2)
            .zip(ns.windows(2))
            .map(|(e, n)| (e[0] / e[1]).ln() / (n[1] as f64 / n[0] as f64).ln())
            .collect()
    };
    let newmark = |n| mode_error(&Newmark, &p, w2, &phi, n);
    let backward_euler = |n| mode_error(&BackwardEuler, &p, w2, &phi, n);
    for (name, integ, ns, expected) in [
        (
            "Newmark",
            &newmark as &dyn Fn(usize) -> f64,
            [50, 100, 200, 400],
            2.0,
        ),
        (
            "backward Euler",
            &backward_euler,
            [400, 800, 1600, 3200],
            1.0,
        ),
    ] {
        let orders = order(integ, &ns);
        eprintln!("{name} orders {orders:?}");
        for r in orders {
            assert!((r - expected).abs() <= 0.15, "{name} order {r}");
        }
    }
}

#[test]
fn quasistatic_never_needs_mass_and_reaches_equilibrium() {
    let p = slider(1);
    let n = p.fixed.len();
    let g = body_force_load(&p.mesh, |_| [0.0, -RHO * 9.81]).unwrap();
    let q = Quasistatic::new();
    assert_eq!(q.coefficients(0.1).0, 0.0);
    let (_, ck) = q.coefficients(0.1);
    let a = combine(0.0, &p.m, ck, &p.k).unwrap();
    let mut sys = ConstrainedSystem::new(a.as_ref(), &p.fixed).unwrap();
    let mut s = Kinematics::zeros(n);
    let mut rhs = vec![0.0; n];
    let mut v = vec![0.0; n];
    q.right_hand_side(0.1, SystemMatrices::new(None, &p.k), &g, &s, &mut rhs)
        .unwrap();
    sys.solve(&rhs, &mut v).unwrap();
    let mut next = Kinematics::zeros(n);
    q.advance(0.1, &s, &v, &mut next);
    s = next;
    // One quasistatic step without friction lands on the equilibrium K u = F.
    let mut r = g.clone();
    spmv_add(p.k.as_ref(), -1.0, &s.u, &mut r);
    let scale = g.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for (i, ri) in r.iter().enumerate() {
        if !p.fixed[i] {
            assert!(ri.abs() < 1e-9 * scale);
        }
    }
    assert!(matches!(
        Newmark.right_hand_side(0.1, SystemMatrices::new(None, &p.k), &g, &s, &mut rhs),
        Err(rsf_time::Error::MissingMass(_))
    ));
    assert!(matches!(
        Newmark.right_hand_side(
            -0.1,
            SystemMatrices::new(Some(&p.m), &p.k),
            &g,
            &s,
            &mut rhs
        ),
        Err(rsf_time::Error::InvalidTimeStep(_))
    ));
    assert!(matches!(
        BackwardEuler.right_hand_side(
            0.1,
            SystemMatrices::new(Some(&p.m), &p.k),
            &g[1..],
            &s,
            &mut rhs
        ),
        Err(rsf_time::Error::DimensionMismatch { .. })
    ));
    assert!(Quasistatic::with_radiation_damping(-1.0).is_err());
    assert_eq!(
        Quasistatic::with_radiation_damping(3.0)
            .unwrap()
            .radiation_damping(),
        3.0
    );
}
