//! A synthetic test problem of the direct solver and TNNMG (rsf-tnnmg's tests include this
//! file): the P1 Laplacian on the unit square with Tresca-like friction on its bottom edge.

use faer::sparse::{SparseColMat, Triplet};
use rsf_nonsmooth::{BlockNonlinearity, Linearization};

pub type Mat = SparseColMat<usize, f64>;

pub fn from_triplets(nr: usize, nc: usize, t: &[Triplet<usize, usize, f64>]) -> Mat {
    SparseColMat::try_new_from_triplets(nr, nc, t).unwrap()
}

/// P1 on the unit square, (m+1)² nodes, triangles split along the (i,j)–(i+1,j+1) diagonal:
/// `A = K + c M_lumped` with K the P1 stiffness (5-point stencil).
pub fn square(m: usize, c: f64) -> Mat {
    let n1 = m + 1;
    let h = 1.0 / m as f64;
    let id = |i: usize, j: usize| j * n1 + i;
    let mut t = Vec::new();
    for j in 0..n1 {
        for i in 0..n1 {
            let mut diag = c * h * h;
            for (di, dj) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if a >= 0 && b >= 0 && a < n1 as i64 && b < n1 as i64 {
                    t.push(Triplet::new(id(i, j), id(a as usize, b as usize), -1.0));
                    diag += 1.0;
                }
            }
            t.push(Triplet::new(id(i, j), id(i, j), diag));
        }
    }
    from_triplets(n1 * n1, n1 * n1, &t)
}

/// `φ_k(v) = g_k |v|` (Tresca-like, nonsmooth at 0) on the listed nodes, block size 1.
pub struct Tresca1 {
    pub nodes: Vec<usize>,
    pub g: Vec<f64>,
}

impl BlockNonlinearity<1> for Tresca1 {
    fn active_blocks(&self) -> &[usize] {
        &self.nodes
    }
    fn value(&self, k: usize, v: &[f64; 1]) -> f64 {
        self.g[k] * v[0].abs()
    }
    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; 1]; 1],
        r: &[f64; 1],
        free: &[bool; 1],
        v: &mut [f64; 1],
    ) {
        if free[0] {
            let g = self.g[k];
            v[0] = r[0].signum() * (r[0].abs() - g).max(0.0) / a[0][0];
        }
    }
    fn linearize(&self, k: usize, v: &[f64; 1]) -> Linearization<1> {
        if v[0] == 0.0 {
            Linearization::Truncate
        } else {
            Linearization::Smooth {
                gradient: [self.g[k] * v[0].signum()],
                hessian: [[0.0]],
            }
        }
    }
    fn kink_at_zero(&self, _k: usize) -> bool {
        true
    }
    fn directional_derivatives(&self, k: usize, v: &[f64; 1], d: &[f64; 1]) -> (f64, f64) {
        let g = self.g[k];
        if v[0] == 0.0 {
            (-g * d[0].abs(), g * d[0].abs())
        } else {
            let s = g * v[0].signum() * d[0];
            (s, s)
        }
    }
}

/// Boundary mask of the square grid (fixed on x = 0).
pub fn left_edge_fixed(m: usize) -> Vec<bool> {
    let n1 = m + 1;
    (0..n1 * n1).map(|k| k % n1 == 0).collect()
}

/// Nodes on the bottom edge y = 0, except x = 0.
pub fn bottom_nodes(m: usize) -> Vec<usize> {
    (1..=m).collect()
}

/// The load of the stick–slip test problem on the unit square with `m` cells per side
/// (node-major, `(m + 1)²` entries).
pub fn stick_slip_load(m: usize) -> Vec<f64> {
    let n1 = m + 1;
    let h = 1.0 / m as f64;
    (0..n1 * n1)
        .map(|k| {
            let (i, j) = (k % n1, k / n1);
            let (x, y) = (i as f64 * h, j as f64 * h);
            h * h * 40.0 * (3.0 * x).sin() * (1.0 + y)
        })
        .collect()
}

/// Tresca friction on the bottom edge with a threshold varying along it, so that stick and
/// slip nodes coexist under [`stick_slip_load`].
pub fn stick_slip_tresca(m: usize) -> Tresca1 {
    let nodes = bottom_nodes(m);
    let h = 1.0 / m as f64;
    let g = nodes
        .iter()
        .map(|&i| h * 60.0 * (1.0 + (i as f64 * h * 7.0).cos()))
        .collect();
    Tresca1 { nodes, g }
}
