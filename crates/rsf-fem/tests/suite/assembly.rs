use crate::common::{apply, check_frames, component_sums};
use rsf_fem::*;

fn slider(level: usize) -> (TriangleMesh, Assembler<2>) {
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), level);
    let m = h.finest().clone();
    let a = Assembler::new(&m).unwrap();
    (m, a)
}

fn dense(a: &SparseMatrix) -> Vec<Vec<f64>> {
    let mut d = vec![vec![0.0; a.ncols()]; a.nrows()];
    for j in 0..a.ncols() {
        for (&i, &v) in a.as_ref().row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            d[i][j] += v;
        }
    }
    d
}

#[test]
fn mass_and_weights_sum() {
    let rho = 5e3;
    for level in 0..3 {
        let (m, asm) = slider(level);
        let mm = asm.mass(&m, rho).unwrap();
        // Sum over one component's entries = ρ·area.
        let s = component_sums::<2>(&mm);
        for c in s {
            assert!((c - rho * 5.0).abs() < 1e-9 * rho * 5.0, "{c}");
        }
        for (tag, len) in [
            (TAG_FRICTIONAL, 5.0),
            (TAG_DIRICHLET, 5.0),
            (TAG_NEUMANN, 2.0),
        ] {
            let seg = BoundarySegment::from_tag(&m, tag).unwrap();
            let w = lumped_weights(&m, &seg);
            assert!((w.iter().sum::<f64>() - len).abs() < 1e-13);
            assert!(w.iter().all(|&x| x > 0.0));
        }
    }
}

#[test]
fn stiffness_symmetric_rigid_modes_and_spd_after_constraints() {
    let (m, asm) = slider(2);
    let mat = LinearElasticity::plane_strain(5e7, 0.3).unwrap();
    let k = asm.stiffness(&m, &mat).unwrap();
    let d = dense(&k);
    let scale = d.iter().flatten().fold(0.0f64, |a, &b| a.max(b.abs()));
    for i in 0..d.len() {
        for j in 0..d.len() {
            assert!((d[i][j] - d[j][i]).abs() <= 1e-14 * scale);
        }
    }
    let n = m.num_vertices();
    let modes: [Vec<f64>; 3] = [
        (0..n).flat_map(|_| [1.0, 0.0]).collect(),
        (0..n).flat_map(|_| [0.0, 1.0]).collect(),
        m.vertices().iter().flat_map(|x| [-x[1], x[0]]).collect(),
    ];
    for r in &modes {
        let kr = apply(&k, r);
        let nrm = kr.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
        assert!(nrm < 1e-12 * scale * 5.0, "rigid mode residual {nrm:e}");
    }
    // An indefinite matrix is reported as such.
    let mm = asm.mass(&m, 5e3).unwrap();
    let indefinite = combine(1.0, &mm, -1.0, &k).unwrap();
    assert!(matches!(
        ConstrainedSystem::new(indefinite.as_ref(), &vec![false; 2 * n]),
        Err(Error::NotPositiveDefinite { .. })
    ));
    // Dirichlet on top → SPD reduced system; check xᵀ K_ff x > 0 on random vectors too.
    let top = BoundarySegment::from_tag(&m, TAG_DIRICHLET).unwrap();
    let mut c = Constraints::<2>::new(n);
    c.fix_nodes(top.nodes(), &[0, 1], [0.0, 0.0]).unwrap();
    let sys = ConstrainedSystem::new(k.as_ref(), c.fixed()).unwrap();
    assert_eq!(sys.free_dofs().len(), c.num_free());
    let mut seed = 12345u64;
    for _ in 0..20 {
        let x: Vec<f64> = (0..2 * n)
            .map(|i| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                if c.fixed()[i] {
                    0.0
                } else {
                    (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
                }
            })
            .collect();
        let kx = apply(&k, &x);
        let q: f64 = x.iter().zip(&kx).map(|(a, b)| a * b).sum();
        assert!(q > 0.0);
    }
    // Only the bottom normal component fixed (bilateral contact) does not remove the
    // x-translation: restricted to the free dofs it stays in the kernel of K_ff (Rayleigh
    // quotient at round-off), while the top Dirichlet condition removes it (the same
    // quotient is 2.6 % of the largest entry of K).
    let bottom = BoundarySegment::from_tag(&m, TAG_FRICTIONAL).unwrap();
    let mut c2 = Constraints::<2>::new(n);
    c2.fix_nodes(bottom.nodes(), &[1], [0.0, 0.0]).unwrap();
    let rayleigh_on_free = |mode: &[f64], fixed: &[bool]| {
        let x: Vec<f64> = mode
            .iter()
            .zip(fixed)
            .map(|(&v, &f)| if f { 0.0 } else { v })
            .collect();
        let kx = apply(&k, &x);
        let free = |i: &usize| !fixed[*i];
        let num: f64 = (0..x.len()).filter(free).map(|i| x[i] * kx[i]).sum();
        num / x.iter().map(|v| v * v).sum::<f64>()
    };
    let bilateral = rayleigh_on_free(&modes[0], c2.fixed());
    let clamped = rayleigh_on_free(&modes[0], c.fixed());
    assert!(
        bilateral.abs() <= 1e-12 * scale,
        "x-translation not in the kernel of K_ff: {bilateral:e}"
    );
    assert!(
        clamped >= 1e-3 * scale,
        "top Dirichlet does not remove the x-translation: {clamped:e} of {scale:e}"
    );
    // ...but the energy matrix K + M is SPD without constraints.
    let e = asm.energy(&m, 5e3, &mat).unwrap();
    let s = combine(1.0, &k, 1.0, &mm).unwrap();
    for (a, b) in e.val().iter().zip(s.val()) {
        assert!((a - b).abs() <= 1e-12 * scale);
    }
    let mut ch = Cholesky::new(e.as_ref()).unwrap();
    let b: Vec<f64> = (0..2 * n).map(|i| (i as f64).sin()).collect();
    let x = ch.solve(&b).unwrap();
    let r = apply(&e, &x);
    for (ri, bi) in r.iter().zip(&b) {
        assert!((ri - bi).abs() < 1e-8);
    }
    // Refactorisation with new values on the same pattern.
    let a2 = combine(2.0, &mm, 0.5, &k).unwrap();
    ch.factorize(a2.as_ref()).unwrap();
    let x = ch.solve(&b).unwrap();
    let r = apply(&a2, &x);
    for (ri, bi) in r.iter().zip(&b) {
        assert!((ri - bi).abs() < 1e-8);
    }
    assert!(matches!(
        ch.solve(&b[1..]).map_err(Error::from),
        Err(Error::DimensionMismatch { .. })
    ));
}

/// Rectangle with its interior vertices perturbed (keeps positive orientation).
fn perturbed_square(n: usize) -> TriangleMesh {
    let r = rectangle([0.0, 0.0], [1.0, 1.0], n, n, Diagonal::Forward).unwrap();
    let h = 1.0 / (n - 1) as f64;
    let mut v = r.vertices().to_vec();
    for (i, x) in v.iter_mut().enumerate() {
        let (a, b) = (i % n, i / n);
        if a > 0 && a < n - 1 && b > 0 && b < n - 1 {
            x[0] += 0.2 * h * ((7 * i) as f64).sin();
            x[1] += 0.2 * h * ((3 * i) as f64).cos();
        }
    }
    TriangleMesh::new(v, r.cells().to_vec()).unwrap()
}

#[test]
fn patch_test_dirichlet_and_neumann() {
    let m = perturbed_square(6);
    let asm = Assembler::new(&m).unwrap();
    let mat = LinearElasticity::plane_strain(3.0, 0.25).unwrap();
    let k = asm.stiffness(&m, &mat).unwrap();
    // Affine field u = G x + c.
    let g = [[0.3, -0.7], [1.1, 0.4]];
    let u = |x: &[f64; 2]| {
        [
            0.1 + g[0][0] * x[0] + g[0][1] * x[1],
            -0.2 + g[1][0] * x[0] + g[1][1] * x[1],
        ]
    };
    let exact: Vec<f64> = m.vertices().iter().flat_map(u).collect();
    let n = m.num_vertices();
    // `K x = load` with the nodes of `fixed` held at `u`: `x` must be `u` everywhere.
    let solves_exactly = |fixed: &BoundarySegment<2>, load: &[f64]| {
        let mut c = Constraints::<2>::new(n);
        for &p in fixed.nodes() {
            let val = u(&m.vertices()[p]);
            c.fix_nodes(&[p], &[0, 1], val).unwrap();
        }
        let mut sys = ConstrainedSystem::new(k.as_ref(), c.fixed()).unwrap();
        let mut x = vec![0.0; 2 * n];
        c.apply(&mut x);
        sys.solve(load, &mut x).unwrap();
        for (a, b) in x.iter().zip(&exact) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
    };
    // (a) Dirichlet on the whole boundary, no load.
    let all = BoundarySegment::from_predicate(&m, "all", |_| true).unwrap();
    solves_exactly(&all, &vec![0.0; 2 * n]);
    // (b) Dirichlet on the left edge only, traction σ n on the other three edges.
    let eps = [
        [g[0][0], 0.5 * (g[0][1] + g[1][0])],
        [0.5 * (g[0][1] + g[1][0]), g[1][1]],
    ];
    let tr = eps[0][0] + eps[1][1];
    let sigma = [
        [
            mat.lambda * tr + 2.0 * mat.mu * eps[0][0],
            2.0 * mat.mu * eps[0][1],
        ],
        [
            2.0 * mat.mu * eps[1][0],
            mat.lambda * tr + 2.0 * mat.mu * eps[1][1],
        ],
    ];
    let mut load = vec![0.0; 2 * n];
    for (name, normal, pred) in [
        (
            "right",
            [1.0, 0.0],
            (|x: &[f64; 2]| x[0] > 1.0 - 1e-9) as fn(&[f64; 2]) -> bool,
        ),
        ("top", [0.0, 1.0], |x: &[f64; 2]| x[1] > 1.0 - 1e-9),
        ("bottom", [0.0, -1.0], |x: &[f64; 2]| x[1] < 1e-9),
    ] {
        let seg = BoundarySegment::from_predicate(&m, name, pred).unwrap();
        for nn in seg.normals(&m) {
            assert!((nn[0] - normal[0]).abs() < 1e-14 && (nn[1] - normal[1]).abs() < 1e-14);
        }
        let t = [
            sigma[0][0] * normal[0] + sigma[0][1] * normal[1],
            sigma[1][0] * normal[0] + sigma[1][1] * normal[1],
        ];
        let f = traction_load(&m, &seg, |_| t).unwrap();
        for (l, fi) in load.iter_mut().zip(f) {
            *l += fi;
        }
    }
    let left = BoundarySegment::from_predicate(&m, "left", |x| x[0] < 1e-9).unwrap();
    solves_exactly(&left, &load);
}

#[test]
fn body_force_and_traction_totals() {
    let (m, _) = slider(2);
    let f = body_force_load(&m, |_| [0.0, -5e3 * 9.81]).unwrap();
    let fy: f64 = f.iter().skip(1).step_by(2).sum();
    let fx: f64 = f.iter().step_by(2).sum();
    assert!((fy + 5e3 * 9.81 * 5.0).abs() < 1e-8);
    assert!(fx.abs() < 1e-10);
    let top = BoundarySegment::from_tag(&m, TAG_DIRICHLET).unwrap();
    // ∫ x ds on the top edge = 12.5
    let t = traction_load(&m, &top, |x| [x[0], 0.0]).unwrap();
    let tx: f64 = t.iter().step_by(2).sum();
    assert!((tx - 12.5).abs() < 1e-12);
    assert!(matches!(
        body_force_load(&m, |_| [f64::NAN, 0.0]),
        Err(Error::NonFiniteValue(_))
    ));
}

#[test]
fn nodal_frames_rotate_consistently() {
    // Slanted frictional boundary: a parallelogram with a bottom edge at 30°.
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let r = rectangle([0.0, 0.0], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
    let v: Vec<[f64; 2]> = r
        .vertices()
        .iter()
        .map(|x| [c * x[0] - s * x[1], s * x[0] + c * x[1]])
        .collect();
    let m = TriangleMesh::new(v, r.cells().to_vec()).unwrap();
    let asm = Assembler::new(&m).unwrap();
    let mat = LinearElasticity::plane_strain(1.0, 0.3).unwrap();
    let k = asm.stiffness(&m, &mat).unwrap();
    // Bottom edge in the rotated frame: points (c, s)·t.
    let bottom =
        BoundarySegment::from_predicate(&m, "bottom", |x| (s * x[0] - c * x[1]).abs() < 1e-9)
            .unwrap();
    let frames = bottom.frames(&m);
    for q in &frames.rotations {
        // tangent (c, s), inward normal (−s, c)
        assert!((q[0][0] - c).abs() < 1e-12 && (q[1][0] - s).abs() < 1e-12);
        assert!((q[0][1] + s).abs() < 1e-12 && (q[1][1] - c).abs() < 1e-12);
    }
    check_frames(&k, &frames);
    let n = 2 * m.num_vertices();
    let kt = frames.rotate_matrix(k.as_ref()).unwrap();
    // A rigid tangential sliding of the bottom has zero local normal components.
    let mut t: Vec<f64> = (0..m.num_vertices()).flat_map(|_| [c, s]).collect();
    frames.to_local(&mut t).unwrap();
    for &p in bottom.nodes() {
        assert!((t[2 * p] - 1.0).abs() < 1e-14 && t[2 * p + 1].abs() < 1e-14);
    }
    // Fixing the normal component in the local frame + one tangential dof gives SPD.
    let mut con = Constraints::<2>::new(m.num_vertices());
    con.fix_nodes(bottom.nodes(), &[1], [0.0, 0.0]).unwrap();
    con.fix(bottom.nodes()[0], 0, 0.0).unwrap();
    assert!(ConstrainedSystem::new(kt.as_ref(), con.fixed()).is_ok());
    // Rotating prolongation rows: P̃ = Rᵀ P maps coarse Cartesian → fine local.
    let h = MeshHierarchy::refine_uniformly(m.clone(), 1);
    let fine = h.finest();
    let fb =
        BoundarySegment::from_predicate(fine, "bottom", |x| (s * x[0] - c * x[1]).abs() < 1e-9)
            .unwrap();
    let ff = fb.frames(fine);
    let p = h.vector_prolongation(1);
    let pt = ff.rotate_rows(p.as_ref()).unwrap();
    let vc: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin()).collect();
    let mut vf = apply(p, &vc);
    ff.to_local(&mut vf).unwrap();
    let vf2 = apply(&pt, &vc);
    for (a, b) in vf.iter().zip(&vf2) {
        assert!((a - b).abs() < 1e-14);
    }
}
