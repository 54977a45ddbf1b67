//! The nonsmooth part of the functional: a sum of convex functions of node blocks.

/// Second-order information of one block nonlinearity at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Linearization<const D: usize> {
    /// φ_p is twice differentiable here: its gradient and Hessian (symmetric, PSD).
    Smooth {
        /// ∇φ_p(v_p).
        gradient: [f64; D],
        /// ∇²φ_p(v_p).
        hessian: [[f64; D]; D],
    },
    /// φ_p is not twice differentiable here (e.g. Tresca friction in stick, v_p = 0):
    /// the block is **truncated** — the linear correction leaves it unchanged.
    Truncate,
}

/// A block-separable convex function `Φ(v) = Σ_k φ_k(v_{p_k})` over node blocks
/// `v_p ∈ R^D` (dofs `D p .. D p + D`, node-major).
///
/// Only the blocks listed by [`active_blocks`](Self::active_blocks) carry a nonlinearity;
/// all other blocks contribute zero. Every method takes `k`, the position of the block in
/// that list, and the block's current value `v` (all `D` components, fixed ones included).
///
/// Contract: every φ_k is convex, finite and continuous on `R^D`. Implementations are the
/// seam between the solvers and the physics (the friction potentials live elsewhere).
/// `Sync`: the multi-colour smoother minimises the blocks of one colour on several threads.
pub trait BlockNonlinearity<const D: usize>: Sync {
    /// Node indices `p_k` of the blocks with a nonlinearity, strictly increasing.
    fn active_blocks(&self) -> &[usize];

    /// φ_k(v).
    fn value(&self, k: usize, v: &[f64; D]) -> f64;

    /// Exact block minimisation: overwrite the `free` components of `v` with the minimiser of
    /// `½ xᵀ A x − rᵀ x + φ_k(x)` over the free components, the others held at their values
    /// in `v`. `a` is the (symmetric positive definite on the free components) diagonal block
    /// of the matrix and `r` the block right-hand side including all off-block coupling.
    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; D]; D],
        r: &[f64; D],
        free: &[bool; D],
        v: &mut [f64; D],
    );

    /// Gradient and Hessian of φ_k at `v`, or [`Linearization::Truncate`] where φ_k is not
    /// twice differentiable.
    fn linearize(&self, k: usize, v: &[f64; D]) -> Linearization<D>;

    /// One-sided derivatives `(d⁻, d⁺)` at `s = 0` of the convex function
    /// `s ↦ φ_k(v + s d)`; `d⁻ ≤ d⁺`, equal where φ_k is differentiable.
    fn directional_derivatives(&self, k: usize, v: &[f64; D], d: &[f64; D]) -> (f64, f64);

    /// Whether φ_k has a kink at `v = 0` (a subdifferential with interior there, like
    /// Tresca friction). TNNMG then stops the Newton correction of a block that would pass
    /// through zero at zero, so that all blocks entering stick do so in one step (instead of
    /// one per iteration through the line search). Default `false`.
    fn kink_at_zero(&self, _k: usize) -> bool {
        false
    }
}

/// The zero nonlinearity: the problem is a plain quadratic (linear system).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoNonlinearity;

impl<const D: usize> BlockNonlinearity<D> for NoNonlinearity {
    fn active_blocks(&self) -> &[usize] {
        &[]
    }
    fn value(&self, _: usize, _: &[f64; D]) -> f64 {
        0.0
    }
    fn minimize_block(
        &self,
        _: usize,
        _: &[[f64; D]; D],
        _: &[f64; D],
        _: &[bool; D],
        _: &mut [f64; D],
    ) {
        unreachable!("NoNonlinearity has no active blocks")
    }
    fn linearize(&self, _: usize, _: &[f64; D]) -> Linearization<D> {
        unreachable!("NoNonlinearity has no active blocks")
    }
    fn directional_derivatives(&self, _: usize, _: &[f64; D], _: &[f64; D]) -> (f64, f64) {
        (0.0, 0.0)
    }
}

/// `ψ_k(x) = s (φ_k(x) + ½ q_k |x|²)`: a nonlinearity `φ` scaled by `s > 0`, plus a
/// quadratic of weight `q_k ≥ 0` on each of its blocks.
///
/// What for: a velocity problem `min ½vᵀ(cK + H)v − bᵀv + Φ(v)` with `H = diag(q_k)` on
/// the blocks (radiation damping `q_k = η w_k`) is, divided by `c > 0`,
/// `min ½vᵀKv − (b/c)ᵀv + Ψ(v)` with `Ψ = Scaled { s: 1/c, q }` of `Φ`: the same minimiser
/// with a matrix that does not depend on `c` (the quasistatic integrator's `c = τ`, so one
/// set-up of a solver serves every time step; docs/math.md §11).
#[derive(Debug, Clone, Copy)]
pub struct Scaled<'a, N> {
    /// The nonlinearity φ.
    pub inner: &'a N,
    /// The scale `s` (finite, > 0).
    pub scale: f64,
    /// `q_k` per active block (same order), or empty for none.
    pub quadratic: &'a [f64],
}

impl<N> Scaled<'_, N> {
    fn q(&self, k: usize) -> f64 {
        self.quadratic.get(k).copied().unwrap_or(0.0)
    }
}

impl<const D: usize, N: BlockNonlinearity<D>> BlockNonlinearity<D> for Scaled<'_, N> {
    fn active_blocks(&self) -> &[usize] {
        self.inner.active_blocks()
    }

    fn value(&self, k: usize, v: &[f64; D]) -> f64 {
        let q: f64 = v.iter().map(|x| x * x).sum();
        self.scale * (self.inner.value(k, v) + 0.5 * self.q(k) * q)
    }

    /// `min ½xᵀAx − rᵀx + s(φ(x) + ½q|x|²)` is `min ½xᵀ(A/s + qI)x − (r/s)ᵀx + φ(x)`.
    fn minimize_block(
        &self,
        k: usize,
        a: &[[f64; D]; D],
        r: &[f64; D],
        free: &[bool; D],
        v: &mut [f64; D],
    ) {
        let (s, q) = (self.scale, self.q(k));
        let mut b = *a;
        for (i, row) in b.iter_mut().enumerate() {
            for x in row.iter_mut() {
                *x /= s;
            }
            row[i] += q;
        }
        let r = r.map(|x| x / s);
        self.inner.minimize_block(k, &b, &r, free, v);
    }

    fn linearize(&self, k: usize, v: &[f64; D]) -> Linearization<D> {
        let (s, q) = (self.scale, self.q(k));
        match self.inner.linearize(k, v) {
            Linearization::Smooth { gradient, hessian } => {
                let mut h = hessian;
                for (i, row) in h.iter_mut().enumerate() {
                    row[i] += q;
                    for x in row.iter_mut() {
                        *x *= s;
                    }
                }
                Linearization::Smooth {
                    gradient: std::array::from_fn(|i| s * (gradient[i] + q * v[i])),
                    hessian: h,
                }
            }
            Linearization::Truncate => Linearization::Truncate,
        }
    }

    fn directional_derivatives(&self, k: usize, v: &[f64; D], d: &[f64; D]) -> (f64, f64) {
        let (s, q) = (self.scale, self.q(k));
        let vd: f64 = v.iter().zip(d).map(|(a, b)| a * b).sum();
        let (lo, hi) = self.inner.directional_derivatives(k, v, d);
        (s * (lo + q * vd), s * (hi + q * vd))
    }

    fn kink_at_zero(&self, k: usize) -> bool {
        self.inner.kink_at_zero(k)
    }
}
