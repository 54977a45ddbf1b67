//! Synthetic test problems: P1 Laplacians on uniform grids with their own hierarchies, and
//! simple closed-form block nonlinearities (independent of the friction crates).
#![allow(dead_code)]

use faer::sparse::Triplet;
use rsf_nonsmooth::{BlockNonlinearity, Linearization, NonsmoothSolver};

// The square's Laplacian and its stick–slip problem, the same as the direct solver's tests
// (one file, included by both suites).
#[path = "../../../../rsf-direct/tests/suite/common.rs"]
mod square_problem;
pub use square_problem::*;

/// Prolongation from the (m/2)-grid to the m-grid of [`square`] (nodal interpolation).
pub fn square_prolongation(m: usize) -> Mat {
    let (nf, nc) = (m + 1, m / 2 + 1);
    let mut t = Vec::new();
    for j in 0..nf {
        for i in 0..nf {
            let row = j * nf + i;
            let (ci, cj) = (i / 2, j / 2);
            match (i % 2, j % 2) {
                (0, 0) => t.push(Triplet::new(row, cj * nc + ci, 1.0)),
                (1, 0) => {
                    t.push(Triplet::new(row, cj * nc + ci, 0.5));
                    t.push(Triplet::new(row, cj * nc + ci + 1, 0.5));
                }
                (0, 1) => {
                    t.push(Triplet::new(row, cj * nc + ci, 0.5));
                    t.push(Triplet::new(row, (cj + 1) * nc + ci, 0.5));
                }
                _ => {
                    // midpoint of the diagonal edge (ci, cj)–(ci+1, cj+1)
                    t.push(Triplet::new(row, cj * nc + ci, 0.5));
                    t.push(Triplet::new(row, (cj + 1) * nc + ci + 1, 0.5));
                }
            }
        }
    }
    from_triplets(nf * nf, nc * nc, &t)
}

/// Hierarchy for `square(2^level * m0)`: prolongations coarse to fine.
pub fn square_hierarchy(m0: usize, level: usize) -> Vec<Mat> {
    (1..=level).map(|l| square_prolongation(m0 << l)).collect()
}

/// Smooth, strongly curved nonlinearity `φ(v) = w (cosh(v/ε) − 1) ε²` (curvature w at 0,
/// growing exponentially), a stand-in for stiff rate-and-state potentials.
pub struct Cosh1 {
    pub nodes: Vec<usize>,
    pub w: f64,
    pub eps: f64,
}

impl Cosh1 {
    fn d1(&self, x: f64) -> f64 {
        self.w * self.eps * (x / self.eps).sinh()
    }
}

impl BlockNonlinearity<1> for Cosh1 {
    fn active_blocks(&self) -> &[usize] {
        &self.nodes
    }
    fn value(&self, _: usize, v: &[f64; 1]) -> f64 {
        self.w * self.eps * self.eps * ((v[0] / self.eps).cosh() - 1.0)
    }
    fn minimize_block(
        &self,
        _: usize,
        a: &[[f64; 1]; 1],
        r: &[f64; 1],
        free: &[bool; 1],
        v: &mut [f64; 1],
    ) {
        if !free[0] {
            return;
        }
        // Monotone scalar equation a x + φ'(x) = r: bisection on a bracket.
        let f = |x: f64| a[0][0] * x + self.d1(x) - r[0];
        let mut lo = -r[0].abs() / a[0][0] - 1.0;
        let mut hi = r[0].abs() / a[0][0] + 1.0;
        debug_assert!(f(lo) <= 0.0 && f(hi) >= 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break;
            }
            if f(mid) > 0.0 {
                hi = mid
            } else {
                lo = mid
            }
        }
        v[0] = 0.5 * (lo + hi);
    }
    fn linearize(&self, _: usize, v: &[f64; 1]) -> Linearization<1> {
        Linearization::Smooth {
            gradient: [self.d1(v[0])],
            hessian: [[self.w * (v[0] / self.eps).cosh()]],
        }
    }
    fn directional_derivatives(&self, _: usize, v: &[f64; 1], d: &[f64; 1]) -> (f64, f64) {
        let s = self.d1(v[0]) * d[0];
        (s, s)
    }
}

pub fn energy_norm(a: &Mat, x: &[f64]) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            s += x[i] * v * x[j];
        }
    }
    s.sqrt()
}

/// The stick–slip test problem on the unit square with `m` cells per side: the P1
/// matrix [`square`]`(m, 10)`, fixed on x = 0, the load [`stick_slip_load`] and Tresca
/// friction [`stick_slip_tresca`] on the bottom edge.
pub struct StickSlip {
    pub a: Mat,
    pub fixed: Vec<bool>,
    pub b: Vec<f64>,
    pub nl: Tresca1,
}

/// [`StickSlip`] with `m` cells per side.
pub fn stick_slip(m: usize) -> StickSlip {
    stick_slip_with(m, 10.0)
}

/// [`StickSlip`] with `m` cells per side and the matrix [`square`]`(m, c)`.
pub fn stick_slip_with(m: usize, c: f64) -> StickSlip {
    StickSlip {
        a: square(m, c),
        fixed: left_edge_fixed(m),
        b: stick_slip_load(m),
        nl: stick_slip_tresca(m),
    }
}

/// The [`StickSlip`] problems of the square hierarchies of `m0 = 2` at levels 2–4:
/// `(m0, level, problem)`, the problem with `m0 << level` cells per side.
pub fn stick_slip_levels() -> impl Iterator<Item = (usize, usize, StickSlip)> {
    let m0 = 2;
    (2..=4).map(move |level| (m0, level, stick_slip(m0 << level)))
}

/// The direct solver's minimiser (default options, from zero) of `J` with the matrix `a`,
/// the fixed dofs `fixed`, the load `b` and the nonlinearity `nl`.
pub fn direct_minimiser(
    a: &Mat,
    fixed: &[bool],
    b: &[f64],
    nl: &impl BlockNonlinearity<1>,
) -> Vec<f64> {
    let mut v = vec![0.0; b.len()];
    rsf_direct::DirectSolver::<1>::new(a.as_ref(), fixed, rsf_direct::DirectOptions::default())
        .unwrap()
        .solve(b, nl, &mut v)
        .unwrap();
    v
}

/// `‖x − y‖_A / ‖reference‖_A`.
pub fn relative_energy_distance(a: &Mat, x: &[f64], y: &[f64], reference: &[f64]) -> f64 {
    let d: Vec<f64> = x.iter().zip(y).map(|(a, b)| a - b).collect();
    energy_norm(a, &d) / energy_norm(a, reference)
}
