//! A 3-D test problem: P1 linear elasticity on a box of Kuhn tetrahedra (each cube of a
//! uniform grid cut into six tetrahedra around its main diagonal), assembled straight
//! into its compressed-column pattern (no triplets: the measurement's boxes have a few
//! hundred thousand dofs). Shared by the test suite and the `schur_only_box` example.
//!
//! Node `(i, j, k)` (`0 ≤ i ≤ nx`, …) is `i + (nx + 1) (j + (ny + 1) k)`, its dofs
//! `3 node + c` (`c` = x, y, z). The element stiffness is
//! `K_(a,i),(b,j) = V (λ ∂_i φ_a ∂_j φ_b + μ ∂_j φ_a ∂_i φ_b + μ δ_ij ∇φ_a·∇φ_b)`.

#![allow(dead_code)]

use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// A box of `nx × ny × nz` cubes of side `h` (m), Lamé parameters `lambda`, `mu` (Pa).
#[derive(Debug, Clone, Copy)]
pub struct ElasticityBox {
    pub nx: usize,
    pub ny: usize,
    pub nz: usize,
    pub h: f64,
    pub lambda: f64,
    pub mu: f64,
}

/// The six Kuhn tetrahedra of the unit cube as corner offsets: from the corner 0 along
/// the axes in the order of each permutation.
fn kuhn_tets() -> [[[usize; 3]; 4]; 6] {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut tets = [[[0; 3]; 4]; 6];
    for (t, p) in perms.iter().enumerate() {
        let mut c = [0usize; 3];
        for (v, &axis) in p.iter().enumerate() {
            c[axis] = 1;
            tets[t][v + 1] = c;
        }
    }
    tets
}

/// The element matrix of a tetrahedron with vertices `x`: `k[a][b][i][j]`.
fn element(x: [[f64; 3]; 4], lambda: f64, mu: f64) -> [[[[f64; 3]; 3]; 4]; 4] {
    let m = |r: usize, c: usize| x[c + 1][r] - x[0][r];
    let det = m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1))
        - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
        + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0));
    // Rows of M⁻¹ are the gradients of the barycentric coordinates 1..3.
    let cof = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m(r1, c1) * m(r2, c2) - m(r1, c2) * m(r2, c1)
    };
    let mut g = [[0.0; 3]; 4];
    for a in 1..4 {
        for i in 0..3 {
            // (M⁻¹)_{a-1, i} = cof(i, a-1) / det.
            g[a][i] = cof(i, a - 1) / det;
        }
    }
    for i in 0..3 {
        g[0][i] = -(g[1][i] + g[2][i] + g[3][i]);
    }
    let v = det.abs() / 6.0;
    let mut k = [[[[0.0; 3]; 3]; 4]; 4];
    for a in 0..4 {
        for b in 0..4 {
            let dot = (0..3).map(|i| g[a][i] * g[b][i]).sum::<f64>();
            for i in 0..3 {
                for j in 0..3 {
                    k[a][b][i][j] = v
                        * (lambda * g[a][i] * g[b][j]
                            + mu * g[a][j] * g[b][i]
                            + if i == j { mu * dot } else { 0.0 });
                }
            }
        }
    }
    k
}

impl ElasticityBox {
    /// A box of `nx × ny × nz` unit cubes, λ = μ = 1.
    pub fn new(nx: usize, ny: usize, nz: usize) -> Self {
        Self {
            nx,
            ny,
            nz,
            h: 1.0,
            lambda: 1.0,
            mu: 1.0,
        }
    }

    pub fn nodes(&self) -> usize {
        (self.nx + 1) * (self.ny + 1) * (self.nz + 1)
    }

    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        i + (self.nx + 1) * (j + (self.ny + 1) * k)
    }

    /// `(i, j, k)` of a node.
    pub fn coords(&self, p: usize) -> (usize, usize, usize) {
        let (a, b) = (self.nx + 1, self.ny + 1);
        (p % a, (p / a) % b, p / (a * b))
    }

    /// The stiffness matrix (`3 nodes × 3 nodes`, both triangles, rows sorted).
    pub fn stiffness(&self) -> SparseColMat<usize, f64> {
        let tets = kuhn_tets();
        let elems: Vec<_> = tets
            .iter()
            .map(|t| {
                let x = t.map(|c| c.map(|v| v as f64 * self.h));
                element(x, self.lambda, self.mu)
            })
            .collect();
        let n = 3 * self.nodes();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(45 * n);
        let mut val = Vec::with_capacity(45 * n);
        col_ptr.push(0);
        let (nx, ny, nz) = (self.nx as isize, self.ny as isize, self.nz as isize);
        for q in 0..self.nodes() {
            let (i, j, k) = self.coords(q);
            let (i, j, k) = (i as isize, j as isize, k as isize);
            // acc[slot][ci][cj]: slot = neighbour offset (dk, dj, di) ∈ {−1, 0, 1}³ in
            // increasing node order.
            let mut acc = [[[0.0f64; 3]; 3]; 27];
            let mut used = [false; 27];
            for corner in 0..8usize {
                let cq = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
                let cube = [i - cq[0] as isize, j - cq[1] as isize, k - cq[2] as isize];
                if cube[0] < 0
                    || cube[1] < 0
                    || cube[2] < 0
                    || cube[0] >= nx
                    || cube[1] >= ny
                    || cube[2] >= nz
                {
                    continue;
                }
                for (t, tet) in tets.iter().enumerate() {
                    let Some(b) = tet.iter().position(|c| *c == cq) else {
                        continue;
                    };
                    for (a, ca) in tet.iter().enumerate() {
                        let d = [
                            ca[0] as isize - cq[0] as isize,
                            ca[1] as isize - cq[1] as isize,
                            ca[2] as isize - cq[2] as isize,
                        ];
                        let slot = ((d[2] + 1) * 9 + (d[1] + 1) * 3 + (d[0] + 1)) as usize;
                        used[slot] = true;
                        for ci in 0..3 {
                            for cj in 0..3 {
                                acc[slot][ci][cj] += elems[t][a][b][ci][cj];
                            }
                        }
                    }
                }
            }
            for cj in 0..3 {
                for slot in (0..27).filter(|&s| used[s]) {
                    let d = [
                        (slot % 3) as isize - 1,
                        ((slot / 3) % 3) as isize - 1,
                        (slot / 9) as isize - 1,
                    ];
                    let p = self.node(
                        (i + d[0]) as usize,
                        (j + d[1]) as usize,
                        (k + d[2]) as usize,
                    );
                    for ci in 0..3 {
                        row_idx.push(3 * p + ci);
                        val.push(acc[slot][ci][cj]);
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        SparseColMat::new(symbolic, val)
    }
}
