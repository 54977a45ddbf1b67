//! A closed-form nonsmooth block nonlinearity for the tests and measurements of the
//! distributed solvers: isotropic Tresca friction on whole blocks, plus a quadratic.

use rsf_nonsmooth::{BlockNonlinearity, Linearization};

use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::solve_spd_masked;

/// `φ_k(x) = g_k |x| + ½ q_k |x|²` on the blocks `nodes[k]` (`|x|` the Euclidean norm of
/// the whole block): Tresca friction of bound `g_k ≥ 0` with a viscous term `q_k ≥ 0` —
/// nonsmooth at `x = 0` (truncated there, a kink at zero when `g_k > 0`), smooth elsewhere
/// with Hessian `g_k/|x| (I − u uᵀ) + q_k I`, `u = x/|x|`. Its block minimisation is exact
/// up to the last bits (a bisection on the multiplier, the same arithmetic everywhere), so
/// the solvers' results depend on nothing but their own arithmetic. The friction of the
/// physics (rate-and-state potentials of the slip rate) lives in `rsf`.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockTresca<const D: usize> {
    nodes: Vec<usize>,
    g: Vec<f64>,
    q: Vec<f64>,
}

impl<const D: usize> BlockTresca<D> {
    /// Friction on the blocks `nodes` (strictly increasing), with the bounds `g` and the
    /// quadratic weights `q` (one per node each, finite, ≥ 0).
    ///
    /// # Errors
    /// [`ProblemError::InvalidOption`](rsf_nonsmooth::ProblemError::InvalidOption) if the lengths
    /// differ, the nodes are not strictly increasing, or a weight is negative or not finite.
    pub fn new(nodes: Vec<usize>, g: Vec<f64>, q: Vec<f64>) -> crate::Result<Self> {
        let bad = |m: &str| {
            Err(crate::Error::Problem(ProblemError::InvalidOption(format!(
                "BlockTresca: {m}"
            ))))
        };
        if g.len() != nodes.len() || q.len() != nodes.len() {
            return bad("one g and one q per node");
        }
        if nodes.windows(2).any(|w| w[0] >= w[1]) {
            return bad("nodes must be strictly increasing");
        }
        if g.iter().chain(&q).any(|&x| !(x.is_finite() && x >= 0.0)) {
            return bad("g and q must be finite and >= 0");
        }
        Ok(Self { nodes, g, q })
    }
}

fn norm<const D: usize>(x: &[f64; D]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

impl<const D: usize> BlockNonlinearity<D> for BlockTresca<D> {
    fn active_blocks(&self) -> &[usize] {
        &self.nodes
    }

    fn value(&self, k: usize, v: &[f64; D]) -> f64 {
        let s = norm(v);
        self.g[k] * s + 0.5 * self.q[k] * s * s
    }

    /// On the free components `y` (the fixed ones `f` held): the minimiser solves
    /// `(A_yy + (q + λ) I) y = r'` with `λ = g / |x|` (`r'` the right-hand side less the
    /// fixed components' coupling); `λ² |x(λ)|²` increases with `λ`, so `λ` is found by
    /// bisection to the last bit. `y = 0` when the fixed part is zero and `|r'| ≤ g`
    /// (stick).
    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; D]; D],
        r: &[f64; D],
        free: &[bool; D],
        v: &mut [f64; D],
    ) {
        let (g, q) = (self.g[k], self.q[k]);
        let mut rr = *r;
        let mut fixed2 = 0.0;
        for j in (0..D).filter(|&j| !free[j]) {
            fixed2 += v[j] * v[j];
            for i in 0..D {
                rr[i] -= a[i][j] * v[j];
            }
        }
        let r_norm = (0..D)
            .filter(|&i| free[i])
            .map(|i| rr[i] * rr[i])
            .sum::<f64>()
            .sqrt();
        if fixed2 == 0.0 && r_norm <= g {
            for i in (0..D).filter(|&i| free[i]) {
                v[i] = 0.0;
            }
            return;
        }
        // y(λ) and F(λ) = λ² |x(λ)|² − g².
        let solve = |lambda: f64, y: &mut [f64; D]| {
            let mut b = *a;
            for (i, row) in b.iter_mut().enumerate() {
                row[i] += q + lambda;
            }
            solve_spd_masked(&b, &rr, free, y);
            let y2: f64 = (0..D).filter(|&i| free[i]).map(|i| y[i] * y[i]).sum();
            lambda * lambda * (y2 + fixed2) - g * g
        };
        let mut y = *v;
        let (mut lo, mut hi) = (0.0, g.max(1.0));
        let mut guard = 0;
        while solve(hi, &mut y) < 0.0 && guard < 2100 {
            lo = hi;
            hi *= 2.0;
            guard += 1;
        }
        loop {
            let mid = 0.5 * (lo + hi);
            if !(mid > lo && mid < hi) {
                break;
            }
            if solve(mid, &mut y) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        solve(hi, &mut y);
        for i in (0..D).filter(|&i| free[i]) {
            v[i] = y[i];
        }
    }

    fn linearize(&self, k: usize, v: &[f64; D]) -> Linearization<D> {
        let (g, q) = (self.g[k], self.q[k]);
        let s = norm(v);
        if s == 0.0 && g > 0.0 {
            return Linearization::Truncate;
        }
        let mut gradient = [0.0; D];
        let mut hessian = [[0.0; D]; D];
        for i in 0..D {
            hessian[i][i] = q;
            gradient[i] = q * v[i];
        }
        if s > 0.0 {
            for i in 0..D {
                let ui = v[i] / s;
                gradient[i] += g * ui;
                for j in 0..D {
                    let id = if i == j { 1.0 } else { 0.0 };
                    hessian[i][j] += g / s * (id - ui * v[j] / s);
                }
            }
        }
        Linearization::Smooth { gradient, hessian }
    }

    fn directional_derivatives(&self, k: usize, v: &[f64; D], d: &[f64; D]) -> (f64, f64) {
        let (g, q) = (self.g[k], self.q[k]);
        let s = norm(v);
        let vd: f64 = v.iter().zip(d).map(|(a, b)| a * b).sum();
        if s > 0.0 {
            let x = g * vd / s + q * vd;
            (x, x)
        } else {
            let kink = g * norm(d);
            (-kink, kink)
        }
    }

    fn kink_at_zero(&self, k: usize) -> bool {
        self.g[k] > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block minimisation against the optimality condition `A x − r + g x/|x| + q x ∈
    /// 0` (to round-off), sticking where `|r| ≤ g`, with and without a fixed component.
    #[test]
    fn block_minimisation_is_optimal() {
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 2.0]];
        let t = BlockTresca::<3>::new(vec![0], vec![1.5], vec![0.25]).unwrap();
        let mut v = [0.3, -0.2, 0.1];
        t.minimize_block(0, &a, &[0.5, 1.0, -0.3], &[true; 3], &mut v);
        assert_eq!(v, [0.0; 3], "|r| < g sticks");
        for (r, free) in [
            ([3.0, -2.0, 1.0], [true; 3]),
            ([3.0, -2.0, 1.0], [false, true, true]),
        ] {
            let mut v = [0.7, 0.0, 0.0];
            t.minimize_block(0, &a, &r, &free, &mut v);
            let s = norm(&v);
            for i in (0..3).filter(|&i| free[i]) {
                let ax: f64 = (0..3).map(|j| a[i][j] * v[j]).sum();
                let res = ax - r[i] + 1.5 * v[i] / s + 0.25 * v[i];
                assert!(res.abs() < 1e-12, "{free:?}: residual {res} at {i}");
            }
            assert_eq!(v[0], if free[0] { v[0] } else { 0.7 });
        }
    }
}
