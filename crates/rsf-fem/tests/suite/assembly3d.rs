//! 3D P1 vector elements: mass, stiffness (rigid-body modes, SPD after constraints), loads
//! and the patch test, against closed forms.
use crate::common::{apply, component_sums, dot};
use rsf_fem::element::tetrahedron_quadrature;
use rsf_fem::*;

/// A box with its interior vertices perturbed (orientation kept).
fn perturbed_box(n: usize) -> TetrahedronMesh {
    let b = cuboid([0.0; 3], [1.0, 1.2, 0.8], [n, n, n]).unwrap();
    let h = 0.8 / (n - 1) as f64;
    let inside = |x: &[f64; 3]| {
        x[0] > 1e-9
            && x[0] < 1.0 - 1e-9
            && x[1] > 1e-9
            && x[1] < 1.2 - 1e-9
            && x[2] > 1e-9
            && x[2] < 0.8 - 1e-9
    };
    let v: Vec<[f64; 3]> = b
        .vertices()
        .iter()
        .enumerate()
        .map(|(i, x)| {
            if inside(x) {
                let s = i as f64;
                [
                    x[0] + 0.15 * h * (7.0 * s).sin(),
                    x[1] + 0.15 * h * (3.0 * s).cos(),
                    x[2] + 0.15 * h * (5.0 * s).sin(),
                ]
            } else {
                *x
            }
        })
        .collect();
    TetrahedronMesh::new(v, b.cells().to_vec()).unwrap()
}

#[test]
fn isotropic_lame_parameters() {
    let m = LinearElasticity::isotropic(1.0, 0.25).unwrap();
    assert!((m.lambda - 0.4).abs() < 1e-15 && (m.mu - 0.4).abs() < 1e-15);
    assert_eq!(
        LinearElasticity::isotropic(1.0, 0.5),
        Err(Error::InvalidPoissonRatio(0.5))
    );
    assert_eq!(
        LinearElasticity::isotropic(f64::INFINITY, 0.3),
        Err(Error::InvalidYoungsModulus(f64::INFINITY))
    );
}

#[test]
fn mass_matches_quadrature_and_sums_to_rho_volume() {
    let m = perturbed_box(4);
    let rho = 2700.0;
    let asm = Assembler::new(&m).unwrap();
    let mm = asm.mass(&m, rho).unwrap();
    // Σ_ij over one component = ρ|Ω|, no coupling between components.
    let s = component_sums::<3>(&mm);
    let vol = 1.0 * 1.2 * 0.8;
    for c in s {
        assert!((c - rho * vol).abs() < 1e-10 * rho * vol, "{c}");
    }
    // uᵀ M u = ρ ∫ |u_h|² by the degree-5 rule, for a P1 field u_h.
    let u: Vec<f64> = (0..3 * m.num_vertices())
        .map(|i| (0.7 * i as f64).sin())
        .collect();
    let mut exact = 0.0;
    for c in 0..m.num_cells() {
        let v = m.cell(c);
        for (l, w) in tetrahedron_quadrature() {
            for r in 0..3 {
                let uh: f64 = (0..4).map(|a| l[a] * u[3 * v[a] + r]).sum();
                exact += rho * w * m.cell_measure(c) * uh * uh;
            }
        }
    }
    let q = dot(&u, &apply(&mm, &u));
    assert!((q - exact).abs() < 1e-12 * exact, "{q} vs {exact}");
}

#[test]
fn stiffness_rigid_modes_symmetry_and_spd() {
    let m = perturbed_box(4);
    let mat = LinearElasticity::isotropic(5e7, 0.3).unwrap();
    let asm = Assembler::new(&m).unwrap();
    let k = asm.stiffness(&m, &mat).unwrap();
    let n = m.num_vertices();
    let scale = k.val().iter().fold(0.0f64, |a, &b| a.max(b.abs()));
    // Symmetry: xᵀKy = yᵀKx.
    let x: Vec<f64> = (0..3 * n).map(|i| (0.37 * i as f64).sin()).collect();
    let y: Vec<f64> = (0..3 * n).map(|i| (0.11 * i as f64).cos()).collect();
    let (kxy, kyx) = (dot(&x, &apply(&k, &y)), dot(&y, &apply(&k, &x)));
    assert!((kxy - kyx).abs() < 1e-13 * scale * n as f64);
    // Three translations and three rotations in the kernel.
    let v = m.vertices();
    let modes: Vec<Vec<f64>> = vec![
        (0..n).flat_map(|_| [1.0, 0.0, 0.0]).collect(),
        (0..n).flat_map(|_| [0.0, 1.0, 0.0]).collect(),
        (0..n).flat_map(|_| [0.0, 0.0, 1.0]).collect(),
        v.iter().flat_map(|x| [-x[1], x[0], 0.0]).collect(),
        v.iter().flat_map(|x| [0.0, -x[2], x[1]]).collect(),
        v.iter().flat_map(|x| [x[2], 0.0, -x[0]]).collect(),
    ];
    for r in &modes {
        let kr = apply(&k, r);
        let nrm = kr.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
        assert!(nrm < 1e-12 * scale, "rigid mode residual {nrm:e}");
    }
    // A non-rigid field has positive energy.
    let stretch: Vec<f64> = v.iter().flat_map(|x| [x[0], 0.0, 0.0]).collect();
    assert!(dot(&stretch, &apply(&k, &stretch)) > 1e-3 * scale);
    // Dirichlet on the bottom face → SPD reduced system; Cholesky solves it.
    let bottom = BoundaryPart::from_predicate(&m, "bottom", |x| x[2] < 1e-9).unwrap();
    let mut c = Constraints::<3>::new(n);
    c.fix_nodes(bottom.nodes(), &[0, 1, 2], [0.0; 3]).unwrap();
    let mut sys = ConstrainedSystem::new(k.as_ref(), c.fixed()).unwrap();
    let b: Vec<f64> = (0..3 * n).map(|i| (i as f64).sin()).collect();
    let mut u = vec![0.0; 3 * n];
    sys.solve(&b, &mut u).unwrap();
    let r = apply(&k, &u);
    for i in (0..3 * n).filter(|&i| !c.fixed()[i]) {
        assert!((r[i] - b[i]).abs() < 1e-9, "{i}");
    }
    // Energy matrix = K + M; SPD without constraints.
    let e = asm.energy(&m, 2700.0, &mat).unwrap();
    let s = combine(1.0, &k, 1.0, &asm.mass(&m, 2700.0).unwrap()).unwrap();
    for (a, b) in e.val().iter().zip(s.val()) {
        assert!((a - b).abs() <= 1e-12 * scale);
    }
    assert!(Cholesky::new(e.as_ref()).is_ok());
    assert!(matches!(
        ConstrainedSystem::new(k.as_ref(), &vec![false; 3 * n]),
        Err(Error::NotPositiveDefinite { .. })
    ));
}

#[test]
fn loads_integrate_exactly() {
    let m = perturbed_box(3);
    // ∫ f over the box for f = (1, x, yz): volume, ∫x, ∫yz.
    let f = body_force_load(&m, |x| [1.0, x[0], x[1] * x[2]]).unwrap();
    let tot = |c: usize| f.iter().skip(c).step_by(3).sum::<f64>();
    let (lx, ly, lz) = (1.0, 1.2, 0.8);
    let vol = lx * ly * lz;
    assert!((tot(0) - vol).abs() < 1e-13);
    assert!((tot(1) - vol * lx / 2.0).abs() < 1e-13);
    assert!((tot(2) - vol * ly / 2.0 * lz / 2.0).abs() < 1e-13);
    // ∫_top x² ds on z = 0.8 (area 1.2): 1.2 · 1/3.
    let top = BoundaryPart::from_predicate(&m, "top", |x| x[2] > lz - 1e-9).unwrap();
    let t = traction_load(&m, &top, |x| [0.0, x[0] * x[0], 0.0]).unwrap();
    let ty: f64 = t.iter().skip(1).step_by(3).sum();
    assert!((ty - ly / 3.0).abs() < 1e-13);
    assert!(matches!(
        body_force_load(&m, |_| [0.0, f64::NAN, 0.0]),
        Err(Error::NonFiniteValue(_))
    ));
    assert!(matches!(
        traction_load(&m, &top, |_| [0.0, 0.0, f64::INFINITY]),
        Err(Error::NonFiniteValue(_))
    ));
    let other = cuboid([0.0; 3], [1.0; 3], [2, 2, 2]).unwrap();
    assert!(matches!(
        traction_load(&other, &top, |_| [0.0; 3]),
        Err(Error::DimensionMismatch { .. })
    ));
}

#[test]
fn patch_test_dirichlet_and_neumann() {
    let m = perturbed_box(4);
    let mat = LinearElasticity::isotropic(3.0, 0.25).unwrap();
    let k = Assembler::new(&m).unwrap().stiffness(&m, &mat).unwrap();
    let g = [[0.3, -0.7, 0.2], [1.1, 0.4, -0.5], [0.6, 0.1, -0.3]];
    let u = |x: &[f64; 3]| -> [f64; 3] {
        let mut v = [0.1, -0.2, 0.05];
        for r in 0..3 {
            for c in 0..3 {
                v[r] += g[r][c] * x[c];
            }
        }
        v
    };
    let exact: Vec<f64> = m.vertices().iter().flat_map(u).collect();
    let n = m.num_vertices();
    let solve = |part: &BoundaryPart<3>, load: &[f64]| {
        let mut c = Constraints::<3>::new(n);
        for &p in part.nodes() {
            c.fix_nodes(&[p], &[0, 1, 2], u(&m.vertices()[p])).unwrap();
        }
        let mut x = vec![0.0; 3 * n];
        c.apply(&mut x);
        ConstrainedSystem::new(k.as_ref(), c.fixed())
            .unwrap()
            .solve(load, &mut x)
            .unwrap();
        for (a, b) in x.iter().zip(&exact) {
            assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        }
    };
    // (a) Dirichlet on the whole boundary, no load.
    let all = BoundaryPart::from_predicate(&m, "all", |_| true).unwrap();
    solve(&all, &vec![0.0; 3 * n]);
    // (b) Dirichlet on x = 0, traction σn on the five other faces.
    let mut sigma = [[0.0; 3]; 3];
    let tr = g[0][0] + g[1][1] + g[2][2];
    for r in 0..3 {
        for c in 0..3 {
            sigma[r][c] = mat.mu * (g[r][c] + g[c][r]) + if r == c { mat.lambda * tr } else { 0.0 };
        }
    }
    let mut load = vec![0.0; 3 * n];
    let size = [1.0, 1.2, 0.8];
    for axis in 0..3 {
        for high in [false, true] {
            if axis == 0 && !high {
                continue;
            }
            let face = BoundaryPart::from_predicate(&m, "face", |x| {
                if high {
                    x[axis] > size[axis] - 1e-9
                } else {
                    x[axis] < 1e-9
                }
            })
            .unwrap();
            let mut normal = [0.0; 3];
            normal[axis] = if high { 1.0 } else { -1.0 };
            for nn in face.normals(&m).unwrap() {
                assert!((0..3).all(|r| (nn[r] - normal[r]).abs() < 1e-14));
            }
            let t: [f64; 3] =
                std::array::from_fn(|r| (0..3).map(|c| sigma[r][c] * normal[c]).sum());
            for (l, fi) in load
                .iter_mut()
                .zip(traction_load(&m, &face, |_| t).unwrap())
            {
                *l += fi;
            }
        }
    }
    let left = BoundaryPart::from_predicate(&m, "left", |x| x[0] < 1e-9).unwrap();
    solve(&left, &load);
}
