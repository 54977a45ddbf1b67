//! Manufactured-solution convergence for plane-strain elasticity. Errors are computed
//! with a degree-5 quadrature of the *exact* solution, not against the code's own output.
use rsf_fem::element::triangle_quadrature;
use rsf_fem::*;

use crate::common::{cell_geometry, observed_rates};

struct Exact {
    a: f64,
    b: f64,
    mat: LinearElasticity,
}

impl Exact {
    fn u(&self, x: &[f64; 2]) -> [f64; 2] {
        let (a, b) = (self.a, self.b);
        [
            (a * x[0]).sin() * (b * x[1]).sin(),
            (a * x[0]).cos() * (b * x[1]).cos(),
        ]
    }
    fn grad(&self, x: &[f64; 2]) -> [[f64; 2]; 2] {
        let (a, b) = (self.a, self.b);
        let (sx, cx, sy, cy) = (
            (a * x[0]).sin(),
            (a * x[0]).cos(),
            (b * x[1]).sin(),
            (b * x[1]).cos(),
        );
        [[a * cx * sy, b * sx * cy], [-a * sx * cy, -b * cx * sy]]
    }
    /// f = −div σ(u).
    fn f(&self, x: &[f64; 2]) -> [f64; 2] {
        let (a, b, l, m) = (self.a, self.b, self.mat.lambda, self.mat.mu);
        let s1 = (a * x[0]).sin() * (b * x[1]).sin();
        let s2 = (a * x[0]).cos() * (b * x[1]).cos();
        [
            -(l + m) * (-a * a * s1 + a * b * s1) + m * (a * a + b * b) * s1,
            -(l + m) * (a * b * s2 - b * b * s2) + m * (a * a + b * b) * s2,
        ]
    }
}

/// Returns (L² error, energy error) of the Galerkin solution on `m`.
fn solve_and_measure(m: &TriangleMesh, ex: &Exact) -> (f64, f64) {
    let asm = Assembler::new(m).unwrap();
    let k = asm.stiffness(m, &ex.mat).unwrap();
    let load = body_force_load(m, |x| ex.f(x)).unwrap();
    let all = BoundarySegment::from_predicate(m, "boundary", |_| true).unwrap();
    let mut c = Constraints::<2>::new(m.num_vertices());
    for &p in all.nodes() {
        c.fix_nodes(&[p], &[0, 1], ex.u(&m.vertices()[p])).unwrap();
    }
    let mut sys = ConstrainedSystem::new(k.as_ref(), c.fixed()).unwrap();
    let mut uh = vec![0.0; 2 * m.num_vertices()];
    c.apply(&mut uh);
    sys.solve(&load, &mut uh).unwrap();
    let q = triangle_quadrature();
    let (mut l2, mut en) = (0.0, 0.0);
    for cell in 0..m.num_cells() {
        let (v, x, area) = cell_geometry(m, cell);
        // P1 gradients by hand.
        let det =
            (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
        let g = [
            [(x[1][1] - x[2][1]) / det, (x[2][0] - x[1][0]) / det],
            [(x[2][1] - x[0][1]) / det, (x[0][0] - x[2][0]) / det],
            [(x[0][1] - x[1][1]) / det, (x[1][0] - x[0][0]) / det],
        ];
        let mut gh = [[0.0; 2]; 2];
        for a in 0..3 {
            for r in 0..2 {
                for d in 0..2 {
                    gh[r][d] += uh[2 * v[a] + r] * g[a][d];
                }
            }
        }
        for (lam, w) in &q {
            let p = [
                lam[0] * x[0][0] + lam[1] * x[1][0] + lam[2] * x[2][0],
                lam[0] * x[0][1] + lam[1] * x[1][1] + lam[2] * x[2][1],
            ];
            let ue = ex.u(&p);
            for r in 0..2 {
                let uhp: f64 = (0..3).map(|a| lam[a] * uh[2 * v[a] + r]).sum();
                l2 += w * area * (ue[r] - uhp).powi(2);
            }
            let ge = ex.grad(&p);
            let mut e = [[0.0; 2]; 2];
            for r in 0..2 {
                for d in 0..2 {
                    e[r][d] = 0.5 * ((ge[r][d] - gh[r][d]) + (ge[d][r] - gh[d][r]));
                }
            }
            en += w * area * 2.0 * ex.mat.energy_density(&e);
        }
    }
    (l2.sqrt(), en.sqrt())
}

fn rates(coarse: TriangleMesh, ex: &Exact, levels: usize) -> Vec<(f64, f64)> {
    let h = MeshHierarchy::refine_uniformly(coarse, levels);
    observed_rates(h.levels(), |m| solve_and_measure(m, ex))
}

fn check(r: &[(f64, f64)], take: usize) {
    for &(l2, en) in &r[r.len() - take..] {
        assert!((l2 - 2.0).abs() <= 0.15, "L2 rate {l2}");
        assert!((en - 1.0).abs() <= 0.15, "energy rate {en}");
    }
}

#[test]
fn manufactured_unit_square() {
    let ex = Exact {
        a: std::f64::consts::PI,
        b: 1.5 * std::f64::consts::PI,
        mat: LinearElasticity::plane_strain(1.0, 0.3).unwrap(),
    };
    let coarse = rectangle([0.0, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward).unwrap();
    // 6 levels 0..5; the last 3 rates span the finest 4 levels.
    check(&rates(coarse, &ex, 5), 3);
}

#[test]
fn manufactured_slider() {
    let ex = Exact {
        a: 0.6 * std::f64::consts::PI,
        b: 0.5 * std::f64::consts::PI,
        mat: LinearElasticity::plane_strain(5e7, 0.3).unwrap(),
    };
    check(&rates(pipping_slider_coarse(Diagonal::Forward), &ex, 5), 3);
}
