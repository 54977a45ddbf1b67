//! The linear algebra of implicit steps without a matrix (docs/math.md §12, "Implicit
//! steps"): a block-diagonal approximation of the Jacobian that the system gives
//! ([`JacobianBlocks`], [`OdeSystem::local_jacobian`](crate::OdeSystem::local_jacobian)),
//! its factors for `I − hγ J` (the preconditioner), and restarted GMRES (Saad & Schultz
//! 1986) with right preconditioning, whose operator is applied by the caller (a
//! finite difference of the rate function). Sequential arithmetic in a fixed order: the
//! same inputs give the same bits.

use crate::{Error, Result};

/// An approximation of the Jacobian `∂f/∂y` by independent dense blocks: block `b` couples
/// the components [`components(b)`](Self::components) (distinct, each in at most one
/// block), its entries `∂f_i/∂y_j` row-major over them ([`block_mut`](Self::block_mut)).
/// Components in no block are taken as uncoupled with `∂f_i/∂y_i = 0`. The system sets
/// the structure once ([`push_block`](Self::push_block), on the first call of
/// [`OdeSystem::local_jacobian`](crate::OdeSystem::local_jacobian), when
/// [`is_empty`](Self::is_empty)) and the entries at every call.
#[derive(Debug, Clone, Default)]
pub struct JacobianBlocks {
    /// Block `b`'s components: `index[start[b]..start[b + 1]]`.
    start: Vec<usize>,
    index: Vec<usize>,
    /// Block `b`'s entries from `offset[b]` (`k²`, row-major).
    offset: Vec<usize>,
    values: Vec<f64>,
}

impl JacobianBlocks {
    /// No blocks.
    pub fn new() -> Self {
        Self {
            start: vec![0],
            index: Vec::new(),
            offset: vec![0],
            values: Vec::new(),
        }
    }

    /// Whether no block has been set.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Appends a block over `components` (its entries zero).
    pub fn push_block(&mut self, components: &[usize]) {
        if self.start.is_empty() {
            *self = Self::new();
        }
        self.index.extend_from_slice(components);
        self.start.push(self.index.len());
        let k = components.len();
        self.values.resize(self.values.len() + k * k, 0.0);
        self.offset.push(self.values.len());
    }

    /// The components of block `b`.
    ///
    /// # Panics
    /// If `b >= len()`.
    pub fn components(&self, b: usize) -> &[usize] {
        &self.index[self.start[b]..self.start[b + 1]]
    }

    /// The entries of block `b`, row-major `k × k` (`k` its components): entry `(i, j)`
    /// is `∂f_{c_i}/∂y_{c_j}`.
    ///
    /// # Panics
    /// If `b >= len()`.
    pub fn block_mut(&mut self, b: usize) -> &mut [f64] {
        &mut self.values[self.offset[b]..self.offset[b + 1]]
    }

    /// Checks the structure for a system of dimension `n`: components below `n`, none in
    /// two blocks.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `jacobian_blocks`.
    pub fn validate(&self, n: usize) -> Result<()> {
        let mut seen = vec![false; n];
        for &i in &self.index {
            if i >= n || seen[i] {
                return Err(Error::InvalidParameter {
                    name: "jacobian_blocks",
                    value: i as f64,
                    requirement: "components below the system's dimension, each in at most \
                                  one block",
                });
            }
            seen[i] = true;
        }
        Ok(())
    }
}

/// The LU factors (partial pivoting) of `I − hγ J_b` for every block of a
/// [`JacobianBlocks`]: the preconditioner of an implicit stage's linear system.
#[derive(Debug, Clone, Default)]
pub(crate) struct BlockFactors {
    lu: Vec<f64>,
    pivots: Vec<usize>,
}

impl BlockFactors {
    /// Factors `I − hγ J_b` of every block. A block whose factor has a zero or
    /// non-finite pivot is replaced by the identity (that block goes unpreconditioned).
    pub(crate) fn factor(&mut self, blocks: &JacobianBlocks, h_gamma: f64) {
        self.lu.clear();
        self.lu.extend_from_slice(&blocks.values);
        self.pivots.clear();
        self.pivots.resize(blocks.index.len(), 0);
        for b in 0..blocks.len() {
            let k = blocks.start[b + 1] - blocks.start[b];
            let a = &mut self.lu[blocks.offset[b]..blocks.offset[b + 1]];
            for (e, x) in a.iter_mut().enumerate() {
                *x = if e / k == e % k { 1.0 } else { 0.0 } - h_gamma * *x;
            }
            let piv = &mut self.pivots[blocks.start[b]..blocks.start[b + 1]];
            if !lu_in_place(a, k, piv) {
                for (e, x) in a.iter_mut().enumerate() {
                    *x = if e / k == e % k { 1.0 } else { 0.0 };
                }
                for (i, p) in piv.iter_mut().enumerate() {
                    *p = i;
                }
            }
        }
    }

    /// `x ← P⁻¹ x` on the blocks' components (the others unchanged).
    pub(crate) fn solve(&self, blocks: &JacobianBlocks, x: &mut [f64]) {
        let mut local = [0.0; 8];
        for b in 0..blocks.len() {
            let comps = blocks.components(b);
            let k = comps.len();
            let a = &self.lu[blocks.offset[b]..blocks.offset[b + 1]];
            let piv = &self.pivots[blocks.start[b]..blocks.start[b + 1]];
            if k <= local.len() {
                let z = &mut local[..k];
                for (zi, &c) in z.iter_mut().zip(comps) {
                    *zi = x[c];
                }
                lu_solve(a, k, piv, z);
                for (&zi, &c) in z.iter().zip(comps) {
                    x[c] = zi;
                }
            } else {
                let mut z: Vec<f64> = comps.iter().map(|&c| x[c]).collect();
                lu_solve(a, k, piv, &mut z);
                for (&zi, &c) in z.iter().zip(comps) {
                    x[c] = zi;
                }
            }
        }
    }
}

/// LU with partial pivoting of the row-major `k × k` matrix `a` in place; `false` for a
/// zero or non-finite pivot.
fn lu_in_place(a: &mut [f64], k: usize, piv: &mut [usize]) -> bool {
    for (i, p) in piv.iter_mut().enumerate() {
        *p = i;
    }
    for col in 0..k {
        let mut best = col;
        for row in col + 1..k {
            if a[row * k + col].abs() > a[best * k + col].abs() {
                best = row;
            }
        }
        if best != col {
            for j in 0..k {
                a.swap(col * k + j, best * k + j);
            }
            piv.swap(col, best);
        }
        let d = a[col * k + col];
        if !(d != 0.0 && d.is_finite()) {
            return false;
        }
        for row in col + 1..k {
            let l = a[row * k + col] / d;
            a[row * k + col] = l;
            for j in col + 1..k {
                a[row * k + j] -= l * a[col * k + j];
            }
        }
    }
    true
}

/// Solves `A z = b` in place (`z` holds `b`) from [`lu_in_place`]'s factors.
fn lu_solve(a: &[f64], k: usize, piv: &[usize], z: &mut [f64]) {
    let mut buf = [0.0; 8];
    let mut heap = Vec::new();
    let p: &mut [f64] = if k <= buf.len() {
        &mut buf[..k]
    } else {
        heap.resize(k, 0.0);
        &mut heap
    };
    for (pi, &from) in p.iter_mut().zip(piv) {
        *pi = z[from];
    }
    for i in 0..k {
        let mut s = p[i];
        for j in 0..i {
            s -= a[i * k + j] * p[j];
        }
        p[i] = s;
    }
    for i in (0..k).rev() {
        let mut s = p[i];
        for j in i + 1..k {
            s -= a[i * k + j] * p[j];
        }
        p[i] = s / a[i * k + i];
    }
    z.copy_from_slice(p);
}

/// How a GMRES solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GmresOutcome {
    /// Whether the residual reached the tolerance.
    pub converged: bool,
    /// Operator applications (the first residual's and the restarts' included).
    pub applications: usize,
    /// Arnoldi iterations.
    pub iterations: usize,
    /// The last residual norm (Euclidean; ∞ if not finite).
    pub residual: f64,
}

/// The workspace of restarted GMRES on vectors of length `n`, allocated once.
#[derive(Debug, Clone)]
pub(crate) struct Gmres {
    restart: usize,
    basis: Vec<Vec<f64>>,
    hessenberg: Vec<f64>,
    cs: Vec<f64>,
    sn: Vec<f64>,
    g: Vec<f64>,
    w: Vec<f64>,
    t: Vec<f64>,
}

/// The operator and the preconditioner of a GMRES solve: `out ← A v`, `v ← M⁻¹ v`.
pub(crate) trait LinearOperator {
    /// The error of an application.
    type Error;
    /// `out ← A v`.
    fn apply(&mut self, v: &[f64], out: &mut [f64]) -> std::result::Result<(), Self::Error>;
    /// `v ← M⁻¹ v` (right preconditioning).
    fn precondition(&self, v: &mut [f64]);
}

impl Gmres {
    pub(crate) fn new(n: usize, restart: usize) -> Self {
        let restart = restart.max(1);
        Self {
            restart,
            basis: vec![vec![0.0; n]; restart + 1],
            hessenberg: vec![0.0; (restart + 1) * restart],
            cs: vec![0.0; restart],
            sn: vec![0.0; restart],
            g: vec![0.0; restart + 1],
            w: vec![0.0; n],
            t: vec![0.0; n],
        }
    }

    /// Solves `A x = b` from `x = 0` with right preconditioning until `‖b − A x‖₂ ≤ tol`
    /// or `max_iterations` Arnoldi iterations; `x` holds the last iterate either way.
    pub(crate) fn solve<O: LinearOperator>(
        &mut self,
        op: &mut O,
        b: &[f64],
        x: &mut [f64],
        (tol, max_iterations): (f64, usize),
    ) -> std::result::Result<GmresOutcome, O::Error> {
        let m = self.restart;
        x.fill(0.0);
        let mut outcome = GmresOutcome {
            converged: false,
            applications: 0,
            iterations: 0,
            residual: f64::INFINITY,
        };
        // The residual of x = 0 is b.
        self.basis[0].copy_from_slice(b);
        loop {
            let beta = norm2(&self.basis[0]);
            outcome.residual = if beta.is_finite() {
                beta
            } else {
                f64::INFINITY
            };
            if !beta.is_finite() {
                return Ok(outcome);
            }
            if beta <= tol {
                outcome.converged = true;
                return Ok(outcome);
            }
            if outcome.iterations >= max_iterations {
                return Ok(outcome);
            }
            for v in &mut self.basis[0] {
                *v /= beta;
            }
            self.g.fill(0.0);
            self.g[0] = beta;
            let mut k = 0;
            while k < m && outcome.iterations < max_iterations {
                self.t.copy_from_slice(&self.basis[k]);
                op.precondition(&mut self.t);
                op.apply(&self.t, &mut self.w)?;
                outcome.applications += 1;
                outcome.iterations += 1;
                // Modified Gram–Schmidt.
                for i in 0..=k {
                    let h = dot(&self.w, &self.basis[i]);
                    self.hessenberg[i * m + k] = h;
                    for (w, &v) in self.w.iter_mut().zip(&self.basis[i]) {
                        *w -= h * v;
                    }
                }
                let h_next = norm2(&self.w);
                self.hessenberg[(k + 1) * m + k] = h_next;
                // The earlier rotations on column k, then a new one.
                for i in 0..k {
                    let (a, b) = (self.hessenberg[i * m + k], self.hessenberg[(i + 1) * m + k]);
                    self.hessenberg[i * m + k] = self.cs[i] * a + self.sn[i] * b;
                    self.hessenberg[(i + 1) * m + k] = -self.sn[i] * a + self.cs[i] * b;
                }
                let (a, b) = (self.hessenberg[k * m + k], h_next);
                let r = a.hypot(b);
                if !(r.is_finite()) {
                    outcome.residual = f64::INFINITY;
                    return Ok(outcome);
                }
                let (c, s) = if r > 0.0 { (a / r, b / r) } else { (1.0, 0.0) };
                self.cs[k] = c;
                self.sn[k] = s;
                self.hessenberg[k * m + k] = r;
                self.hessenberg[(k + 1) * m + k] = 0.0;
                self.g[k + 1] = -s * self.g[k];
                self.g[k] *= c;
                k += 1;
                outcome.residual = self.g[k].abs();
                if h_next > 0.0 {
                    for (v, &w) in self.basis[k].iter_mut().zip(&self.w) {
                        *v = w / h_next;
                    }
                }
                if outcome.residual <= tol || h_next == 0.0 {
                    break;
                }
            }
            // y from the triangular system, x += M⁻¹ V y.
            for i in (0..k).rev() {
                let mut s = self.g[i];
                for j in i + 1..k {
                    s -= self.hessenberg[i * m + j] * self.g[j];
                }
                self.g[i] = s / self.hessenberg[i * m + i];
            }
            self.t.fill(0.0);
            for i in 0..k {
                let yi = self.g[i];
                for (t, &v) in self.t.iter_mut().zip(&self.basis[i]) {
                    *t += yi * v;
                }
            }
            op.precondition(&mut self.t);
            for (xi, &t) in x.iter_mut().zip(&self.t) {
                *xi += t;
            }
            if outcome.residual <= tol {
                outcome.converged = true;
                return Ok(outcome);
            }
            if outcome.iterations >= max_iterations || !outcome.residual.is_finite() {
                return Ok(outcome);
            }
            // Restart from the true residual.
            op.apply(x, &mut self.w)?;
            outcome.applications += 1;
            for ((r, &bi), &ax) in self.basis[0].iter_mut().zip(b).zip(&self.w) {
                *r = bi - ax;
            }
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm2(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Dense {
        a: Vec<Vec<f64>>,
        diag_precond: bool,
    }

    impl LinearOperator for Dense {
        type Error = ();
        fn apply(&mut self, v: &[f64], out: &mut [f64]) -> std::result::Result<(), ()> {
            for (o, row) in out.iter_mut().zip(&self.a) {
                *o = dot(row, v);
            }
            Ok(())
        }
        fn precondition(&self, v: &mut [f64]) {
            if self.diag_precond {
                for (i, x) in v.iter_mut().enumerate() {
                    *x /= self.a[i][i];
                }
            }
        }
    }

    /// GMRES solves a nonsymmetric system (with restarts) to its tolerance, and a
    /// diagonal preconditioner cuts the iterations of a badly scaled one.
    #[test]
    fn gmres_solves_to_its_tolerance_and_preconditioning_helps() {
        let n = 40;
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let d = if i == j {
                            2.0 + 100.0 * (i % 7) as f64
                        } else {
                            0.0
                        };
                        d + if j + 1 == i { -1.0 } else { 0.0 }
                            + if j == i + 1 { -0.5 } else { 0.0 }
                            + 0.01 * ((i * 3 + j * 5) % 11) as f64
                    })
                    .collect()
            })
            .collect();
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut iterations = Vec::new();
        for diag_precond in [false, true] {
            let mut op = Dense {
                a: a.clone(),
                diag_precond,
            };
            let mut g = Gmres::new(n, 10);
            let mut x = vec![0.0; n];
            let out = g.solve(&mut op, &b, &mut x, (1e-10, 500)).unwrap();
            assert!(out.converged, "{out:?}");
            let mut ax = vec![0.0; n];
            op.apply(&x, &mut ax).unwrap();
            let r: f64 = ax
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(r <= 1e-9, "true residual {r}");
            iterations.push(out.iterations);
        }
        assert!(iterations[1] < iterations[0], "{iterations:?}");
    }

    /// The block factors solve `I − hγ J_b` exactly, blocks of mixed sizes, a component
    /// outside every block untouched.
    #[test]
    fn block_factors_invert_each_block() {
        let mut blocks = JacobianBlocks::new();
        blocks.push_block(&[3, 0]);
        blocks.push_block(&[1]);
        blocks.push_block(&[5, 2, 4]);
        blocks.validate(7).unwrap();
        let entries: [&[f64]; 3] = [
            &[-3.0, 1.0, 0.5, -10.0],
            &[-7.0],
            &[-1.0, 2.0, 0.0, 0.3, -5.0, 1.0, 0.0, 4.0, -2.0],
        ];
        for (b, e) in entries.iter().enumerate() {
            blocks.block_mut(b).copy_from_slice(e);
        }
        let hg = 0.7;
        let mut f = BlockFactors::default();
        f.factor(&blocks, hg);
        let x0 = [1.0, -2.0, 0.5, 3.0, 0.25, -1.5, 9.0];
        let mut x = x0;
        f.solve(&blocks, &mut x);
        // (I − hγ J) x = x0 block by block.
        for (b, e) in entries.iter().enumerate() {
            let c = blocks.components(b);
            let k = c.len();
            for i in 0..k {
                let mut s = x[c[i]];
                for j in 0..k {
                    s -= hg * e[i * k + j] * x[c[j]];
                }
                assert!((s - x0[c[i]]).abs() < 1e-12, "block {b} row {i}: {s}");
            }
        }
        assert_eq!(x[6], 9.0);
        let mut bad = JacobianBlocks::new();
        bad.push_block(&[0, 0]);
        assert!(bad.validate(3).is_err());
    }
}
