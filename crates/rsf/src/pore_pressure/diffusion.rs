//! The injection's diffusion along the fault solved numerically: cell-centred finite
//! volumes on a uniform grid between two no-flux ends, integrated exactly in time
//! (docs/seas-bp6.md, "The numerical diffusion").

use std::sync::Mutex;

use super::{Injection, PorePressure};
use crate::error::{invalid, Result};

/// Largest number of cells of a [`FaultDiffusion`]: every evaluation at a new time costs
/// `cells²` multiply-adds.
pub const MAX_DIFFUSION_CELLS: usize = 20_000;

/// `∂p/∂t = α ∂²p/∂s² + q(t) δ(s)/(βφ)` on `s ∈ [s₀, s₁]` with no flux through the ends
/// (`∂p/∂s = 0`) and `p(s, 0) = 0` (BP6 description eqs. 20–21, 25), `s = (x − source)·direction`
/// the distance along the fault from the injection point (m).
///
/// Space: `cells` finite volumes of width `h = (s₁ − s₀)/cells`, the second difference
/// `α (p_{i+1} − 2p_i + p_{i−1})/h²` with mirrored ghost cells at the ends (the no-flux
/// condition; the total `βφ h Σ p_i` is the volume injected so far, to round-off), the point
/// source spread over the two cells whose centres bracket it (linear weights, summing to
/// `1/h`). Time: exact — the semi-discrete system is diagonal in the cosine modes
/// `cos(πk(i + ½)/N)` with rates `λ_k = (4α/h²) sin²(πk/(2N))`, so each mode's amplitude
/// under the piecewise-constant injection is a closed form (`expm1` for its small
/// rates). `p(x, t)` is therefore a function of `t` alone, whatever times a method asks
/// for (Runge–Kutta stages, rejected steps), and a checkpoint needs none of its state.
/// Between cell centres `p` is interpolated linearly (constant beyond the outer centres);
/// the Darcy velocity `−(k/η_f) ∂p/∂s` is the difference of the two centres around the
/// point.
///
/// Cost: at each new time, one exponential per mode and `N²` multiply-adds (Clenshaw's
/// sum of the cosine series at every cell); the last time's cells are kept.
#[derive(Debug)]
pub struct FaultDiffusion<const D: usize> {
    injection: Injection,
    diffusivity: f64,
    mobility: f64,
    source: [f64; D],
    direction: [f64; D],
    ends: [f64; 2],
    h: f64,
    /// `λ_k` (1/s).
    rates: Vec<f64>,
    /// The amplitude of mode `k` per unit injected rate and time (Pa·s/m … per m/s).
    weights: Vec<f64>,
    /// The cells at the last time asked for: `(t, p_i)`.
    cache: Mutex<(f64, Vec<f64>, Vec<f64>)>,
}

impl<const D: usize> Clone for FaultDiffusion<D> {
    fn clone(&self) -> Self {
        let cells = self.rates.len();
        Self {
            injection: self.injection,
            diffusivity: self.diffusivity,
            mobility: self.mobility,
            source: self.source,
            direction: self.direction,
            ends: self.ends,
            h: self.h,
            rates: self.rates.clone(),
            weights: self.weights.clone(),
            cache: Mutex::new((f64::NAN, vec![0.0; cells], vec![0.0; cells])),
        }
    }
}

impl<const D: usize> FaultDiffusion<D> {
    /// The diffusion of `injection` at `source` (m) along the unit vector `direction`,
    /// storage `βφ` (1/Pa), diffusivity `α` (m²/s), mobility `k/η_f` (m²/(Pa·s), for the
    /// Darcy velocity), between the no-flux ends `ends = [s₀, s₁]` (m along the fault from
    /// the source) on `cells` cells.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `injection.*`,
    /// `storage`, `diffusivity`, `mobility` (positive and finite), `source`, `direction`,
    /// `ends` (finite, `s₀ < 0 < s₁`: the source inside) or `cells` (2 to
    /// [`MAX_DIFFUSION_CELLS`]).
    pub fn new(
        injection: Injection,
        (storage, diffusivity, mobility): (f64, f64, f64),
        source: [f64; D],
        direction: [f64; D],
        ends: [f64; 2],
        cells: usize,
    ) -> Result<Self> {
        // The closed form's checks of the shared parameters.
        super::InjectionPressure::new(injection, storage, diffusivity, source, direction)?;
        if !(mobility > 0.0 && mobility.is_finite()) {
            return Err(invalid(
                "mobility",
                format!("{mobility} must be positive and finite"),
            ));
        }
        if !(ends[0] < 0.0 && ends[1] > 0.0 && ends[0].is_finite() && ends[1].is_finite()) {
            return Err(invalid(
                "ends",
                format!("{ends:?} m must be finite with the source inside (s0 < 0 < s1)"),
            ));
        }
        if !(2..=MAX_DIFFUSION_CELLS).contains(&cells) {
            return Err(invalid(
                "cells",
                format!("{cells} must be in 2..={MAX_DIFFUSION_CELLS}"),
            ));
        }
        let n = cells;
        let h = (ends[1] - ends[0]) / n as f64;
        let pi = std::f64::consts::PI;
        let rates: Vec<f64> = (0..n)
            .map(|k| {
                let s = (pi * k as f64 / (2.0 * n as f64)).sin();
                4.0 * diffusivity / (h * h) * s * s
            })
            .collect();
        // The source's cells: linear weights between the two centres around it, summing
        // to 1/h (the centres c_i = s₀ + (i + ½) h; a source within half a cell of an end
        // goes to the end cell).
        let (i0, f) = between_centres((0.0 - ends[0]) / h - 0.5, n);
        let source_cells = [(i0, (1.0 - f) / h), (i0 + 1, f / h)];
        let weights = (0..n)
            .map(|k| {
                let norm = if k == 0 { n as f64 } else { 0.5 * n as f64 };
                let proj: f64 = source_cells
                    .iter()
                    .map(|&(i, w)| w * (pi * k as f64 * (i as f64 + 0.5) / n as f64).cos())
                    .sum();
                proj / (storage * norm)
            })
            .collect();
        Ok(Self {
            injection,
            diffusivity,
            mobility,
            source,
            direction,
            ends,
            h,
            rates,
            weights,
            cache: Mutex::new((f64::NAN, vec![0.0; n], vec![0.0; n])),
        })
    }

    /// The cell width `h` (m).
    pub fn cell_width(&self) -> f64 {
        self.h
    }

    /// The diffusivity `α` (m²/s).
    pub fn diffusivity(&self) -> f64 {
        self.diffusivity
    }

    /// The distance along the fault from the source (m).
    pub fn along(&self, x: &[f64; D]) -> f64 {
        (0..D)
            .map(|i| (x[i] - self.source[i]) * self.direction[i])
            .sum()
    }

    /// The cells' pressures `p_i(t)` (Pa), cell `i` centred at `s₀ + (i + ½) h`.
    pub fn cells(&self, t: f64) -> Vec<f64> {
        self.with_cells(t, |p| p.to_vec())
    }

    /// Runs `f` on the cells' pressures at `t` (computed if `t` is not the last time).
    fn with_cells<R>(&self, t: f64, f: impl FnOnce(&[f64]) -> R) -> R {
        let mut guard = self
            .cache
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let (last, amplitudes, cells) = &mut *guard;
        if last.to_bits() != t.to_bits() {
            self.amplitudes(t, amplitudes);
            clenshaw_cosines(amplitudes, cells);
            *last = t;
        }
        f(cells)
    }

    /// The modes' amplitudes at `t`: `w_k ∫₀ᵗ q(s) e^{−λ_k (t − s)} ds` for the injection's
    /// constant rate on `[0, t_off)`.
    fn amplitudes(&self, t: f64, out: &mut [f64]) {
        let end = t.min(self.injection.shut_in).max(0.0);
        let after = (t - end).max(0.0);
        let q = self.injection.rate;
        for ((a, &lambda), &w) in out.iter_mut().zip(&self.rates).zip(&self.weights) {
            let integral = if lambda == 0.0 {
                end
            } else {
                -(-lambda * end).exp_m1() / lambda * (-lambda * after).exp()
            };
            *a = w * q * integral;
        }
    }

    /// `(i, f)`: the point at `s` lies a fraction `f` of the way from centre `i` to `i + 1`.
    fn locate(&self, s: f64) -> (usize, f64) {
        between_centres((s - self.ends[0]) / self.h - 0.5, self.rates.len())
    }
}

/// `(i, f)`: the point `u` cell widths past the first of `n` cell centres lies a fraction
/// `f` of the way from centre `i` to `i + 1` (`(0, 0)` before the first, NaN included;
/// `(n − 2, 1)` after the last).
fn between_centres(u: f64, n: usize) -> (usize, f64) {
    if !(u > 0.0) {
        (0, 0.0)
    } else if u >= (n - 1) as f64 {
        (n - 2, 1.0)
    } else {
        let i = u.floor() as usize;
        (i, u - i as f64)
    }
}

/// `cells[i] = Σ_k a_k cos(k θ_i)`, `θ_i = π(i + ½)/N`, by Clenshaw's recurrence.
fn clenshaw_cosines(a: &[f64], cells: &mut [f64]) {
    let n = a.len();
    for (i, c) in cells.iter_mut().enumerate() {
        let x = (std::f64::consts::PI * (i as f64 + 0.5) / n as f64).cos();
        let (mut b1, mut b2) = (0.0, 0.0);
        for &ak in a[1..].iter().rev() {
            let b0 = ak + 2.0 * x * b1 - b2;
            b2 = b1;
            b1 = b0;
        }
        *c = a[0] + x * b1 - b2;
    }
}

impl<const D: usize> PorePressure<D> for FaultDiffusion<D> {
    fn pressure(&self, x: &[f64; D], t: f64) -> f64 {
        let (i, f) = self.locate(self.along(x));
        self.with_cells(t, |p| (1.0 - f) * p[i] + f * p[i + 1])
    }
    fn pressures(&self, t: f64, points: &[[f64; D]], out: &mut [f64]) {
        self.with_cells(t, |p| {
            for (o, x) in out.iter_mut().zip(points) {
                let (i, f) = self.locate(self.along(x));
                *o = (1.0 - f) * p[i] + f * p[i + 1];
            }
        });
    }
    fn darcy_velocity(&self, x: &[f64; D], t: f64) -> Option<f64> {
        let s = self.along(x);
        let n = self.rates.len();
        let u = (s - self.ends[0]) / self.h - 0.5;
        if !(u > 0.0) || u >= (n - 1) as f64 {
            // Beyond the outer centres: the no-flux ends.
            return Some(0.0);
        }
        let (i, _) = self.locate(s);
        Some(self.with_cells(t, |p| -self.mobility * (p[i + 1] - p[i]) / self.h))
    }
    fn darcy_velocity_vector(&self, x: &[f64; D], t: f64) -> Option<[f64; D]> {
        let q = self.darcy_velocity(x, t)?;
        Some(self.direction.map(|d| q * d))
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.injection.shut_in]
    }
}
