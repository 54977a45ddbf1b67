//! The lumped friction functional `Φ_h(v, α) = Σ_p w_p ϕ(|v_p|, α_p)` (docs/math.md §3) as a
//! block nonlinearity for the velocity solvers.

use rsf_friction::{ConvexPotential, FrictionLaw};
use rsf_tnnmg::{BlockNonlinearity, Linearization};

/// Friction on the frictional boundary's nodes, frozen at a state `α` (one per node).
///
/// Blocks are the mesh nodes `nodes[k]` (strictly increasing); `weights[k] = w_p` the
/// lumped boundary weight (m in 2D). The potential of node `k` is `ϕ_k(·) =
/// laws[k].potential(α_k)`, evaluated once per [`set_state`](Self::set_state).
///
/// The friction acts on the Euclidean norm of the whole block `v_p`; components fixed by
/// a constraint (the normal component under bilateral contact) are expected to be 0, so
/// that `|v_p|` is the slip rate.
#[derive(Debug, Clone)]
pub struct FrictionBlocks<L: FrictionLaw> {
    nodes: Vec<usize>,
    weights: Vec<f64>,
    laws: Vec<L>,
    potentials: Vec<L::Potential>,
}

impl<L: FrictionLaw> FrictionBlocks<L> {
    /// Friction on `nodes` (strictly increasing) with weights and one law per node, at
    /// state `alpha`.
    ///
    /// # Panics
    /// If the lengths differ or the nodes are not strictly increasing (internal invariant:
    /// the simulation builds these from a validated boundary).
    pub fn new(nodes: Vec<usize>, weights: Vec<f64>, laws: Vec<L>, alpha: &[f64]) -> Self {
        assert!(
            nodes.len() == weights.len() && nodes.len() == laws.len() && nodes.len() == alpha.len()
        );
        assert!(
            nodes.windows(2).all(|w| w[0] < w[1]),
            "frictional nodes must be increasing"
        );
        let potentials = laws
            .iter()
            .zip(alpha)
            .map(|(l, &a)| l.potential(a))
            .collect();
        Self {
            nodes,
            weights,
            laws,
            potentials,
        }
    }

    /// Re-evaluates the potentials at a new state (one `α` per node, node order).
    ///
    /// # Panics
    /// If `alpha.len()` differs from the number of nodes.
    pub fn set_state(&mut self, alpha: &[f64]) {
        assert_eq!(alpha.len(), self.laws.len());
        for ((p, l), &a) in self.potentials.iter_mut().zip(&self.laws).zip(alpha) {
            *p = l.potential(a);
        }
    }

    /// The frictional nodes.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// The lumped weights `w_p`.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The laws, one per node.
    pub fn laws(&self) -> &[L] {
        &self.laws
    }

    /// Whether the friction depends on the state at all.
    pub fn uses_state(&self) -> bool {
        self.laws.iter().any(|l| l.uses_state())
    }
}

/// Euclidean norm of a block; squares directly unless that over- or underflows.
#[inline]
pub(crate) fn norm<const D: usize>(v: &[f64; D]) -> f64 {
    let q: f64 = v.iter().map(|x| x * x).sum();
    if q.is_finite() && q > 1e-280 {
        q.sqrt()
    } else {
        v.iter().fold(0.0f64, |acc, &x| acc.hypot(x))
    }
}

impl<const D: usize, L: FrictionLaw> BlockNonlinearity<D> for FrictionBlocks<L> {
    fn active_blocks(&self) -> &[usize] {
        &self.nodes
    }

    fn value(&self, k: usize, v: &[f64; D]) -> f64 {
        self.weights[k] * self.potentials[k].value(norm(v))
    }

    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; D]; D],
        r: &[f64; D],
        free: &[bool; D],
        v: &mut [f64; D],
    ) {
        let w = self.weights[k];
        let phi = &self.potentials[k];
        // Right-hand side of the free components (fixed ones move to the right).
        let mut rf = [0.0; D];
        let mut idx = [0usize; D];
        let mut m = 0;
        for c in 0..D {
            if free[c] {
                let mut s = r[c];
                for c2 in 0..D {
                    if !free[c2] {
                        s -= a[c][c2] * v[c2];
                    }
                }
                rf[m] = s;
                idx[m] = c;
                m += 1;
            }
        }
        match m {
            0 => {}
            1 => {
                let (c, r1) = (idx[0], rf[0]);
                let s = phi.minimize(a[c][c], r1.abs(), w);
                v[c] = if r1 < 0.0 { -s } else { s };
            }
            _ => {
                let mut b = [[0.0; D]; D];
                for i in 0..m {
                    for j in 0..m {
                        b[i][j] = a[idx[i]][idx[j]];
                    }
                }
                let x = minimize_anisotropic(&b, &rf, m, w, phi);
                for i in 0..m {
                    v[idx[i]] = x[i];
                }
            }
        }
    }

    fn linearize(&self, k: usize, v: &[f64; D]) -> Linearization<D> {
        let w = self.weights[k];
        let phi = &self.potentials[k];
        let s = norm(v);
        let Some(curv) = phi.curvature(s) else {
            return Linearization::Truncate;
        };
        let mut gradient = [0.0; D];
        let mut hessian = [[0.0; D]; D];
        if s == 0.0 {
            if phi.slope(0.0) > 0.0 {
                return Linearization::Truncate;
            }
            for c in 0..D {
                hessian[c][c] = w * curv;
            }
        } else {
            let slope = phi.slope(s);
            let tangential = slope / s;
            for i in 0..D {
                let ui = v[i] / s;
                gradient[i] = w * slope * ui;
                for j in 0..D {
                    let uj = v[j] / s;
                    let id = if i == j { 1.0 } else { 0.0 };
                    hessian[i][j] = w * (curv * ui * uj + tangential * (id - ui * uj));
                }
            }
        }
        Linearization::Smooth { gradient, hessian }
    }

    fn kink_at_zero(&self, k: usize) -> bool {
        self.potentials[k].slope(0.0) > 0.0
    }

    fn directional_derivatives(&self, k: usize, v: &[f64; D], d: &[f64; D]) -> (f64, f64) {
        let w = self.weights[k];
        let phi = &self.potentials[k];
        let s = norm(v);
        if s == 0.0 {
            let g = w * phi.slope(0.0) * norm(d);
            (-g, g)
        } else {
            let dot: f64 = v.iter().zip(d).map(|(a, b)| a * b).sum();
            let g = w * phi.slope(s) * dot / s;
            (g, g)
        }
    }
}

/// Exact minimiser of `½ xᵀBx − rᵀx + w ϕ(|x|)` over `x ∈ R^m` (`m ≤ D`, B SPD) for
/// anisotropic blocks: with `x(μ) = (B + μI)⁻¹ r`, the function
/// `h(μ) = μ|x(μ)| − w ϕ'(|x(μ)|)` is increasing, and the minimiser is `x(μ*)` at its
/// root (or 0 when `|r| ≤ w ϕ'(0+)`). Bisection in `ln μ`.
fn minimize_anisotropic<const D: usize, P: ConvexPotential>(
    b: &[[f64; D]; D],
    r: &[f64; D],
    m: usize,
    w: f64,
    phi: &P,
) -> [f64; D] {
    let rn = r[..m].iter().fold(0.0f64, |acc, &x| acc.hypot(x));
    if rn <= w * phi.slope(0.0) || rn == 0.0 {
        return [0.0; D];
    }
    let solve = |mu: f64| -> [f64; D] {
        let mut a = *b;
        for i in 0..m {
            a[i][i] += mu;
        }
        let mut x = [0.0; D];
        let free = {
            let mut f = [false; D];
            f[..m].fill(true);
            f
        };
        let ok = rsf_tnnmg::solve_spd_masked(&a, r, &free, &mut x);
        debug_assert!(ok);
        x
    };
    let h = |mu: f64| {
        let x = solve(mu);
        let xn = x[..m].iter().fold(0.0f64, |acc, &v| acc.hypot(v));
        mu * xn - w * phi.slope(xn)
    };
    if h(0.0) >= 0.0 {
        return solve(0.0);
    }
    let scale: f64 = (0..m).map(|i| b[i][i]).fold(0.0, f64::max).max(1e-300);
    let (mut lo, mut hi) = ((scale * 1e-30).ln(), scale.ln());
    while h(hi.exp()) < 0.0 && hi < 700.0 {
        hi += 10.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if h(mid.exp()) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-15 * hi.abs().max(1.0) {
            break;
        }
    }
    solve(hi.exp())
}
