//! The lumped friction functional `Φ_h(v, α) = Σ_p w_p ϕ(|v_p|, α_p)` (docs/math.md §3) as a
//! block nonlinearity for the velocity solvers.

use rsf_friction::{ConvexPotential, FrictionLaw};
use rsf_nonsmooth::{BlockNonlinearity, Linearization};

use crate::model::fault::{norm, FrictionalBoundary};

/// Friction on the frictional boundary's nodes, frozen at a state `α` (one per node): the
/// lumped functional `Φ_h(v) = Σ_k w_k ϕ_k(|v_{p_k}|)` as a block nonlinearity for the
/// velocity solvers.
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
        let mut potentials = Vec::with_capacity(laws.len());
        evaluate_potentials(&laws, alpha, &mut potentials);
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
        evaluate_potentials(&self.laws, alpha, &mut self.potentials);
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

    fn view(&self) -> FrictionView<'_, L> {
        FrictionView {
            nodes: &self.nodes,
            weights: &self.weights,
            potentials: &self.potentials,
        }
    }
}

/// `potentials[k] = laws[k].potential(alpha[k])` (reusing the vector's storage).
///
/// # Panics
/// If `alpha` and `laws` differ in length (internal invariant).
pub(crate) fn evaluate_potentials<L: FrictionLaw>(
    laws: &[L],
    alpha: &[f64],
    potentials: &mut Vec<L::Potential>,
) {
    assert_eq!(alpha.len(), laws.len());
    if potentials.len() == laws.len() {
        for ((p, l), &a) in potentials.iter_mut().zip(laws).zip(alpha) {
            *p = l.potential(a);
        }
    } else {
        potentials.clear();
        potentials.extend(laws.iter().zip(alpha).map(|(l, &a)| l.potential(a)));
    }
}

/// The lumped friction functional over borrowed parts: what [`FrictionBlocks`] and a
/// simulation's step (which keeps the laws in its problem and the potentials in its
/// workspace) hand to the solvers.
#[derive(Debug)]
pub(crate) struct FrictionView<'a, L: FrictionLaw> {
    /// The frictional nodes, strictly increasing.
    pub nodes: &'a [usize],
    /// Their lumped weights.
    pub weights: &'a [f64],
    /// Their potentials at the frozen state.
    pub potentials: &'a [L::Potential],
}

impl<'a, L: FrictionLaw> FrictionView<'a, L> {
    /// The functional on `boundary` with `potentials` (one per node, node order).
    pub fn new(boundary: &'a FrictionalBoundary, potentials: &'a [L::Potential]) -> Self {
        Self {
            nodes: &boundary.nodes,
            weights: &boundary.weights,
            potentials,
        }
    }
}

impl<const D: usize, L: FrictionLaw> BlockNonlinearity<D> for FrictionBlocks<L> {
    fn active_blocks(&self) -> &[usize] {
        &self.nodes
    }
    fn value(&self, k: usize, v: &[f64; D]) -> f64 {
        BlockNonlinearity::<D>::value(&self.view(), k, v)
    }
    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; D]; D],
        r: &[f64; D],
        free: &[bool; D],
        v: &mut [f64; D],
    ) {
        self.view().minimize_block(k, a, r, free, v)
    }
    fn linearize(&self, k: usize, v: &[f64; D]) -> Linearization<D> {
        self.view().linearize(k, v)
    }
    fn kink_at_zero(&self, k: usize) -> bool {
        BlockNonlinearity::<D>::kink_at_zero(&self.view(), k)
    }
    fn directional_derivatives(&self, k: usize, v: &[f64; D], d: &[f64; D]) -> (f64, f64) {
        self.view().directional_derivatives(k, v, d)
    }
}

impl<const D: usize, L: FrictionLaw> BlockNonlinearity<D> for FrictionView<'_, L> {
    fn active_blocks(&self) -> &[usize] {
        self.nodes
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
        let (slope, curv) = phi.slope_and_curvature(s);
        let Some(curv) = curv else {
            return Linearization::Truncate;
        };
        let mut gradient = [0.0; D];
        let mut hessian = [[0.0; D]; D];
        if s == 0.0 {
            if slope > 0.0 {
                return Linearization::Truncate;
            }
            for c in 0..D {
                hessian[c][c] = w * curv;
            }
        } else {
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
    if !rn.is_finite() {
        // A non-finite traction is not stick: the NaN reaches the solver's checks.
        return [f64::NAN; D];
    }
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
        let ok = rsf_ranks::block::solve_spd_masked(&a, r, &free, &mut x);
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
    let (mut h_lo, mut h_hi) = (h(lo.exp()), h(hi.exp()));
    while h_hi < 0.0 && hi < 700.0 {
        lo = hi;
        h_lo = h_hi;
        hi += 10.0;
        h_hi = h(hi.exp());
    }
    if !(h_lo < 0.0) {
        // h is increasing and h(0) < 0: the root lies below the scanned range.
        return solve(lo.exp());
    }
    // Illinois regula falsi in ln μ on the monotone h (bisection every fourth step), to a
    // bracket of relative width 1e-15 or an exact zero.
    let mut side = 0i8;
    for it in 0..200 {
        if hi - lo < 1e-15 * hi.abs().max(1.0) {
            break;
        }
        let mut x = if it % 4 == 3 || !(h_hi - h_lo).is_finite() {
            0.5 * (lo + hi)
        } else {
            lo - h_lo * (hi - lo) / (h_hi - h_lo)
        };
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        let hx = h(x.exp());
        if hx == 0.0 {
            return solve(x.exp());
        }
        if hx < 0.0 {
            lo = x;
            h_lo = hx;
            if side == -1 {
                h_hi *= 0.5;
            }
            side = -1;
        } else {
            hi = x;
            h_hi = hx;
            if side == 1 {
                h_lo *= 0.5;
            }
            side = 1;
        }
    }
    solve(hi.exp())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_friction::{DieterichRuina, RateStateParams, Tresca};
    use rsf_nonsmooth::BlockNonlinearity;

    fn params() -> RateStateParams {
        RateStateParams {
            mu0: 0.6,
            a: 0.01,
            b: 0.015,
            v0: 1e-6,
            l: 1e-5,
            sigma_n: 49_050.0,
        }
    }

    /// The exact block minimiser of a 3-D block with a fixed normal component (two free
    /// tangential components, an anisotropic 2×2 block of A): the minimum satisfies
    /// `B x − r + w ϕ'(|x|) x/|x| = 0` (or `x = 0` with `|r| ≤ w ϕ'(0)`), checked to 1e-10 of
    /// `|r|` over states, loads from stuck to fast sliding and anisotropies up to 100.
    #[test]
    fn anisotropic_tangent_plane_minimiser_is_optimal() {
        let w = 0.05;
        for (alpha, r_scale) in [
            (-10.0, 1e2),
            (0.0, 1e3),
            (2.0, 3e3),
            (-2.0, 1e4),
            (5.0, 1e5),
        ] {
            for aniso in [1.0f64, 3.0, 100.0] {
                let law = DieterichRuina::new(params()).unwrap();
                let fb = FrictionBlocks::new(vec![0], vec![w], vec![law], &[alpha]);
                let phi = law.potential(alpha);
                // A = diag blocks: x, z free (components 0 and 2), y fixed at 0.
                let c = 0.3 * aniso.sqrt() * 1e4;
                let a = [[1e4, 5.0, c], [5.0, 2e4, 7.0], [c, 7.0, 1e4 * aniso]];
                let r = [r_scale * 0.8, 123.0, -r_scale * 0.6];
                let free = [true, false, true];
                let mut v = [0.0; 3];
                fb.minimize_block(0, &a, &r, &free, &mut v);
                assert_eq!(v[1], 0.0, "the fixed component stays");
                let s = v[0].hypot(v[2]);
                let rn = r[0].hypot(r[2]);
                if s == 0.0 {
                    assert!(rn <= w * phi.slope(0.0) * (1.0 + 1e-12));
                    continue;
                }
                let t = w * phi.slope(s) / s;
                let g0 = a[0][0] * v[0] + a[0][2] * v[2] - r[0] + t * v[0];
                let g2 = a[2][0] * v[0] + a[2][2] * v[2] - r[2] + t * v[2];
                assert!(
                    g0.hypot(g2) <= 1e-10 * rn,
                    "α {alpha}, |r| {rn}, anisotropy {aniso}: residual {} at |x| = {s:e}",
                    g0.hypot(g2)
                );
            }
        }
    }

    /// Tresca in the tangent plane: stick below the threshold, otherwise optimal.
    #[test]
    fn tresca_tangent_plane_stick_and_slip() {
        let law = Tresca::new(0.6, 1e5).unwrap();
        let w = 0.1;
        let fb = FrictionBlocks::new(vec![0], vec![w], vec![law], &[0.0]);
        let a = [[2e4, 0.0, 3e3], [0.0, 1e4, 0.0], [3e3, 0.0, 5e4]];
        let threshold = w * 0.6 * 1e5;
        for scale in [0.5, 2.0, 10.0] {
            let r = [scale * threshold * 0.6, 0.0, scale * threshold * 0.8];
            let mut v = [0.0; 3];
            fb.minimize_block(0, &a, &r, &[true, false, true], &mut v);
            let s = v[0].hypot(v[2]);
            if scale < 1.0 {
                assert_eq!(s, 0.0, "sticks below the threshold");
            } else {
                let t = threshold / s;
                let g0 = a[0][0] * v[0] + a[0][2] * v[2] - r[0] + t * v[0];
                let g2 = a[2][0] * v[0] + a[2][2] * v[2] - r[2] + t * v[2];
                assert!(g0.hypot(g2) <= 1e-10 * r[0].hypot(r[2]));
            }
        }
    }

    /// A NaN in the traction of a block is never "stuck": with one free component (the
    /// scalar minimiser) and with two (the anisotropic one) the block becomes NaN, which
    /// the velocity solvers' non-finite checks turn into an error (before: slip rate 0).
    #[test]
    fn a_nan_traction_gives_a_nan_block_not_stick() {
        let law = DieterichRuina::new(params()).unwrap();
        let fb = FrictionBlocks::new(vec![0], vec![0.05], vec![law], &[0.0]);
        let a = [[1e4, 0.0, 0.0], [0.0, 2e4, 0.0], [0.0, 0.0, 3e4]];
        for (free, r) in [
            ([true, false, false], [f64::NAN, 0.0, 0.0]),
            ([true, false, true], [f64::NAN, 0.0, 1.0]),
            ([true, false, true], [f64::INFINITY, 0.0, f64::NAN]),
        ] {
            let mut v = [0.0; 3];
            BlockNonlinearity::<3>::minimize_block(&fb, 0, &a, &r, &free, &mut v);
            for c in 0..3 {
                if free[c] {
                    assert!(v[c].is_nan(), "free {free:?}, r {r:?}: {v:?}");
                } else {
                    assert_eq!(v[c], 0.0);
                }
            }
        }
    }
}
