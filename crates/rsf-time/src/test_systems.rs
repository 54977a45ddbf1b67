//! ODE systems with known solutions or independent references, shared by the tests of
//! the stiff integrators (RKC2, ROS34PW2).

use crate::runge_kutta::{EmbeddedRungeKutta, RungeKuttaOptions, DORMAND_PRINCE_54};
use crate::{Error, JacobianBlocks, OdeSystem, Result};

/// `y' = −D (y − v cos t) − v sin t` with `D = diag(λ_i)` and `y(0) = v`: the exact
/// solution `y = v cos t` whatever the stiffness; `λ_i` spread geometrically over
/// `[1, λ_max]`. Error: max |e_i| / tol.
pub(crate) struct StiffLinear {
    pub(crate) lambda: Vec<f64>,
    pub(crate) tol: f64,
    pub(crate) evaluations: usize,
    /// Whether it gives its (diagonal, exact) Jacobian as blocks.
    pub(crate) blocks: bool,
}

impl StiffLinear {
    pub(crate) fn new(n: usize, lambda_max: f64, tol: f64) -> Self {
        let lambda = (0..n)
            .map(|i| lambda_max.powf(i as f64 / (n - 1) as f64))
            .collect();
        Self {
            lambda,
            tol,
            evaluations: 0,
            blocks: false,
        }
    }
    pub(crate) fn v(i: usize) -> f64 {
        1.0 + 0.1 * i as f64
    }
}

impl OdeSystem for StiffLinear {
    type Error = Error;
    fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        self.evaluations += 1;
        for (i, (d, &yi)) in dy.iter_mut().zip(y).enumerate() {
            let v = Self::v(i);
            *d = -self.lambda[i] * (yi - v * t.cos()) - v * t.sin();
        }
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
        err.iter().fold(0.0_f64, |m, e| m.max(e.abs())) / self.tol
    }
    fn local_jacobian(
        &mut self,
        _t: f64,
        y: &[f64],
        _f: &[f64],
        blocks: &mut JacobianBlocks,
    ) -> Result<Option<usize>> {
        if !self.blocks {
            return Ok(None);
        }
        if blocks.is_empty() {
            for i in 0..y.len() {
                blocks.push_block(&[i]);
            }
        }
        for (i, l) in self.lambda.iter().enumerate() {
            blocks.block_mut(i)[0] = -l;
        }
        Ok(Some(0))
    }
}

/// The largest error of `y` against `v cos t` (the exact solution of [`StiffLinear`] and
/// [`Heat`]).
pub(crate) fn error_at(y: &[f64], t: f64) -> f64 {
    y.iter()
        .enumerate()
        .map(|(i, &yi)| (yi - StiffLinear::v(i) * t.cos()).abs())
        .fold(0.0, f64::max)
}

/// Dormand–Prince 5(4) on `sys` from `y = v` (its length) to `t_end`: the error at the
/// end ([`error_at`]) and the accepted steps.
pub(crate) fn dormand_prince_run(sys: &mut StiffLinear, t_end: f64) -> (f64, usize) {
    let n = sys.lambda.len();
    let mut rk =
        EmbeddedRungeKutta::new(DORMAND_PRINCE_54, RungeKuttaOptions::default(), n, 1e-3).unwrap();
    let (mut t, mut y) = (0.0, (0..n).map(StiffLinear::v).collect::<Vec<_>>());
    let mut steps = 0usize;
    while t < t_end {
        rk.step(sys, &mut t, &mut y, Some(t_end)).unwrap();
        steps += 1;
    }
    (error_at(&y, t), steps)
}

/// Asserts that `errors`, of step sizes halving from one to the next, fall at the rate
/// of `order`: the observed order of every halving within `tolerance` of it.
pub(crate) fn assert_halving_order(errors: &[f64], order: f64, tolerance: f64) {
    let expected = order;
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            (order - expected).abs() < tolerance,
            "observed order {order} ({errors:?})"
        );
    }
}

/// `y' = −c L y + g(t)` with `L` the 1-D Laplacian stencil `[−1, 2, −1]` on `n`
/// points (eigenvalues `4c sin²(kπ/(2(n + 1)))`, not diagonal in the unknowns) and `g`
/// such that `y = v cos t`.
pub(crate) struct Heat {
    pub(crate) c: f64,
    pub(crate) n: usize,
    /// The error tolerance (absolute).
    pub(crate) tol: f64,
    /// With the source `g(t)` (solution `v cos t`), or without (`y' = −c L y`, solution
    /// [`Heat::modal`] from [`Heat::modal`] at 0).
    pub(crate) forced: bool,
}

impl Heat {
    /// The solution of the unforced system from `s₁ + ½ s₂ + 0.1 s_n` (`s_k` the sine
    /// modes `sin(kπ(i + 1)/(n + 1))`, eigenvalues `λ_k = 4c sin²(kπ/(2(n + 1)))`): the
    /// two smoothest modes and the stiffest.
    pub(crate) fn modal(&self, t: f64) -> Vec<f64> {
        let n = self.n;
        let np1 = (n + 1) as f64;
        let mode =
            |k: usize, i: usize| (k as f64 * std::f64::consts::PI * (i + 1) as f64 / np1).sin();
        let lambda = |k: usize| {
            4.0 * self.c
                * (k as f64 * std::f64::consts::PI / (2.0 * np1))
                    .sin()
                    .powi(2)
        };
        (0..n)
            .map(|i| {
                [(1, 1.0), (2, 0.5), (n, 0.1)]
                    .iter()
                    .map(|&(k, a)| a * (-lambda(k) * t).exp() * mode(k, i))
                    .sum()
            })
            .collect()
    }
}

impl OdeSystem for Heat {
    type Error = Error;
    fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        let lap = |x: &dyn Fn(usize) -> f64, i: usize| {
            let left = if i > 0 { x(i - 1) } else { 0.0 };
            let right = if i + 1 < self.n { x(i + 1) } else { 0.0 };
            2.0 * x(i) - left - right
        };
        for i in 0..self.n {
            let ly = lap(&|j| y[j], i);
            dy[i] = if self.forced {
                let lv = lap(&|j| StiffLinear::v(j), i);
                -self.c * (ly - lv * t.cos()) - StiffLinear::v(i) * t.sin()
            } else {
                -self.c * ly
            };
        }
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
        err.iter().fold(0.0_f64, |m, e| m.max(e.abs())) / self.tol
    }
    /// The diagonal of `−c L` (a Jacobi preconditioner: `L` is not diagonal).
    fn local_jacobian(
        &mut self,
        _t: f64,
        y: &[f64],
        _f: &[f64],
        blocks: &mut JacobianBlocks,
    ) -> Result<Option<usize>> {
        if blocks.is_empty() {
            for i in 0..y.len() {
                blocks.push_block(&[i]);
            }
        }
        for i in 0..y.len() {
            blocks.block_mut(i)[0] = -2.0 * self.c;
        }
        Ok(Some(0))
    }
}

/// The quasi-static spring–slider of docs/spring-block.md without radiation damping:
/// `τ = k (V_L t − δ) + τ₀ = σ̄_n (μ₀ + a ln(V/V₀) + b ln(V₀θ/L))`, so
/// `V = V₀ exp((τ/σ̄_n − μ₀ − b ln(V₀θ/L))/a)`, `δ̇ = V`, `α̇ = e^{−α} − V/L` (aging,
/// `α = ln θ`); the docs' parameters, `V_L = 1e-6 m/s`, `k = 1.2 k_c` (a decaying
/// oscillation after a kick of the state by −0.5 from steady sliding).
pub(crate) struct SpringSlider {
    pub(crate) tol: f64,
}

impl SpringSlider {
    pub(crate) const SIGMA: f64 = 1e6;
    pub(crate) const A: f64 = 0.010;
    pub(crate) const B: f64 = 0.015;
    pub(crate) const L: f64 = 1e-5;
    pub(crate) const V0: f64 = 1e-6;
    pub(crate) const MU0: f64 = 0.6;
    pub(crate) const VL: f64 = 1e-6;
    pub(crate) fn k() -> f64 {
        1.2 * Self::SIGMA * (Self::B - Self::A) / Self::L
    }
    /// `τ₀` of steady sliding at `V_L` with `δ = 0` at `t = 0`.
    pub(crate) fn tau0() -> f64 {
        Self::SIGMA * Self::MU0
    }
    pub(crate) fn start() -> [f64; 2] {
        [0.0, (Self::L / Self::VL).ln() - 0.5]
    }
    /// The independent reference at `t_end`: Dormand–Prince 5(4) at tolerance 1e-12.
    pub(crate) fn reference(t_end: f64) -> [f64; 2] {
        let mut reference = SpringSlider { tol: 1e-12 };
        let mut rk =
            EmbeddedRungeKutta::new(DORMAND_PRINCE_54, RungeKuttaOptions::default(), 2, 1e-3)
                .unwrap();
        let (mut t, mut exact) = (0.0, SpringSlider::start());
        while t < t_end {
            rk.step(&mut reference, &mut t, &mut exact, Some(t_end))
                .unwrap();
        }
        exact
    }
    /// The error of `y` against `exact`: the larger of the slip's (in `L`) and the
    /// state's (in ln θ).
    pub(crate) fn error(y: &[f64], exact: &[f64]) -> f64 {
        ((y[0] - exact[0]) / Self::L)
            .abs()
            .max((y[1] - exact[1]).abs())
    }
    /// Asserts the order of a method at the fixed steps `hs` (s, halving): `run(h, t_end)`
    /// integrates from [`start`](Self::start) to `t_end = 60 s` (six `L/V_L`) with steps
    /// `h` and returns the end state and the steps it took; its [`error`](Self::error)
    /// against [`reference`](Self::reference) must fall at `order` within `tolerance`
    /// ([`assert_halving_order`]).
    pub(crate) fn assert_order(
        hs: [f64; 3],
        (order, tolerance): (f64, f64),
        mut run: impl FnMut(f64, f64) -> ([f64; 2], usize),
    ) {
        let t_end = 60.0;
        let exact = Self::reference(t_end);
        let mut errors = Vec::new();
        for h in hs {
            let (y, steps) = run(h, t_end);
            let e = Self::error(&y, &exact);
            println!("h = {h} s: {steps} steps, error {e:e} (slip in L, state in ln θ)");
            errors.push(e);
        }
        assert_halving_order(&errors, order, tolerance);
    }
}

impl OdeSystem for SpringSlider {
    type Error = Error;
    fn rate(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        let tau = Self::k() * (Self::VL * t - y[0]) + Self::tau0();
        let psi = Self::MU0 + Self::B * (Self::V0 * y[1].exp() / Self::L).ln();
        let v = Self::V0 * ((tau / Self::SIGMA - psi) / Self::A).exp();
        dy[0] = v;
        dy[1] = (-y[1]).exp() - v / Self::L;
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
        (err[0].abs() / (self.tol * Self::L)).max(err[1].abs() / self.tol)
    }
    fn error_weights(&self, _y: &[f64], w: &mut [f64]) -> bool {
        w[0] = 1.0 / (self.tol * Self::L);
        w[1] = 1.0 / self.tol;
        true
    }
}
