//! The injection's diffusion over a rectangle of a fault plane solved numerically:
//! vertex-centred finite volumes on a uniform grid with no-flux edges, exact in time
//! through the grid Laplacian's cosine modes (docs/pore-pressure.md).

use std::sync::Mutex;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

use super::surface::{
    response, FaultPlane, FaultZone, SurfaceGrid, SurfaceInjection, SurfaceSource,
};
use super::surface_well::{WellModes, WellScratch, WellSetup};
use super::PorePressure;
use crate::error::{invalid, Result};

/// Largest number of cells along each axis of a [`SurfaceDiffusion`]'s grid: an
/// evaluation at a new time costs `n_u n_v (n_u + n_v)` multiply-adds for `n` nodes
/// per axis.
pub const MAX_SURFACE_CELLS: usize = 1024;

/// Largest dimension `D` of a well's coupled system (docs/pore-pressure.md, "The well"):
/// its set-up costs `O(D³)`, each evaluation `D²` multiply-adds. A well at the centre
/// node of an `N × N` grid has `D ≈ N²/8`: 842 at BP8's 80 × 80 cells.
pub const MAX_WELL_MODES: usize = 4000;

/// `∂p/∂t = α ∇²p + Q(t) S(u, v)/(φβL_fwid)` on a rectangle of a fault plane with no flux
/// through its edges (`∂p/∂n = 0`) and `p = p₀` at `t = 0` (SEAS BP8 description eqs.
/// 17–25), `(u, v)` the plane's coordinates ([`FaultPlane`]), the fault zone's properties
/// uniform ([`FaultZone`]), `α = k/(φβη_f)`.
///
/// **Space**: vertex-centred finite volumes on the uniform grid [`SurfaceGrid`] (each node
/// owns the rectangle `h_u × h_v` around it, halved on the edges, quartered at the
/// corners: their areas sum to the rectangle's, as the late uniform pressure needs); the
/// flux between neighbours `−T Δp/h × face`, `T = kL_fwid/η_f`: the five-point Laplacian,
/// the same as P1 finite elements with lumped mass on the grid's right triangles. The
/// Gaussian is sampled at the nodes times their areas and scaled to sum to exactly 1; a
/// well sits on an interior node (Peaceman: the well index `WI = 2πT/ln(r_e/r_well)`,
/// its storage `S_well` an extra unknown `p_w` coupled to the node by `WI (p_w − p_e)`).
///
/// **Time**: exact. The semi-discrete operator is diagonal in the modes
/// `cos(πki/N_u) cos(πlj/N_v)` with rates `λ_kl = (4α/h_u²) sin²(πk/(2N_u)) +
/// (4α/h_v²) sin²(πl/(2N_v))`, so a mode's amplitude under the piecewise-constant
/// injection is a closed form (`expm1` for its small rates); the well's storage is a
/// rank-one change of that diagonal system, diagonalised once (module `surface_well`).
/// `p(x, t)` is therefore a function of `t` alone, whatever times a method asks for
/// (Runge–Kutta stages, rejected steps), stable at any step, and a checkpoint needs none
/// of its state; the uniform mode carries the injected volume, so
/// `Σ φβL_fwid A_ij (p_ij − p₀) + S_well (p_w − p₀)` is `Q₀ min(t, t_off)` to round-off.
///
/// **Evaluation**: the nodes' pressures at the last time asked for are kept (an
/// evaluation at a new time: `n_u n_v` exponentials, two products with the cosine tables,
/// `n_u n_v (n_u + n_v)` multiply-adds, and with a well `D` exponentials and `D²`
/// multiply-adds; nothing allocated). A point `x` of the model is projected onto the
/// plane; its pressure is the bilinear interpolant of the four nodes around it (the edge
/// values beyond the rectangle), its Darcy velocity `−(k/η_f)∇p` the bilinear
/// interpolant of the nodes' central differences (one-sided zero normal to the edges).
///
/// ```
/// use rsf::pore_pressure::*;
/// // SEAS BP8-QD-GS at 10 m: Q₀ = 3e-3 m³/s for 100 h through a Gaussian of 50 m at the
/// // centre of Ω_f = (−400, 400)², on the fault x₁ = 0 with (u, v) = (x₂, x₃).
/// let zone = FaultZone {
///     thickness: 1.0,
///     permeability: 5e-14,
///     porosity: 0.1,
///     compressibility: 1e-8,
///     viscosity: 1e-3,
/// };
/// let injection = SurfaceInjection {
///     injection: Injection { rate: 3e-3, shut_in: 3.6e5 },
///     source: SurfaceSource::Gaussian { width: 50.0 },
///     position: [0.0, 0.0],
/// };
/// let plane = FaultPlane {
///     origin: [0.0; 3],
///     axis_u: [0.0, 1.0, 0.0],
///     axis_v: [0.0, 0.0, 1.0],
/// };
/// let grid = SurfaceGrid { lower: [-400.0; 2], upper: [400.0; 2], cells: [80, 80] };
/// let p = SurfaceDiffusion::new(zone, injection, plane, grid)?;
/// // At the shut-in the centre is at 13.06 MPa (the restatement's 5 m solve; 10 m is within
/// // 0.02 MPa of it); a month later the whole fault is near
/// // the injected volume over its storage, 1080 m³ / (φβL_fwid |Ω_f|) = 1.6875 MPa.
/// assert!((p.pressure(&[0.0; 3], 3.6e5) / 1e6 - 13.06).abs() < 0.02);
/// assert!((p.pressure(&[0.0, 200.0, -200.0], 2.592e6) / 1e6 - 1.688).abs() < 0.002);
/// # Ok::<(), rsf::Error>(())
/// ```
#[derive(Debug)]
pub struct SurfaceDiffusion {
    zone: FaultZone,
    injection: SurfaceInjection,
    plane: FaultPlane,
    grid: SurfaceGrid,
    initial: f64,
    /// `(h_u, h_v)` (m).
    spacing: [f64; 2],
    /// `cos(πki/N)` per axis: `(k, i)`.
    basis: [Mat<f64>; 2],
    /// `λ_k` per axis and `λ_kl`, their sums (1/s).
    axis_rates: [Vec<f64>; 2],
    rates: Mat<f64>,
    /// The modes' amplitudes per unit rate and unit response (Pa per m³/s per s) of a
    /// source on the nodes; zero with a well that stores.
    weights: Mat<f64>,
    /// The well's node, index `WI` (m³/(Pa·s)), and its modes when it stores.
    well: Option<([usize; 2], f64, Option<WellModes>)>,
    /// The storage of the whole rectangle and the well (m³/Pa).
    total_storage: f64,
    cache: Mutex<Cache>,
}

/// The nodes' pressures at the last time asked for.
#[derive(Debug, Clone)]
struct Cache {
    /// The bits of the time, `None` before the first evaluation.
    time: Option<u64>,
    amplitudes: Mat<f64>,
    half: Mat<f64>,
    nodes: Mat<f64>,
    /// `p_ij − p₀` (Pa) at `i + n_u j`.
    values: Vec<f64>,
    /// `e^{−λ_k end}` and `e^{−λ_k after}` per axis.
    decay_end: [Vec<f64>; 2],
    decay_after: [Vec<f64>; 2],
    /// `p_w − p₀` (Pa).
    well: f64,
    scratch: Option<WellScratch>,
}

impl Clone for SurfaceDiffusion {
    fn clone(&self) -> Self {
        Self {
            zone: self.zone,
            injection: self.injection,
            plane: self.plane,
            grid: self.grid,
            initial: self.initial,
            spacing: self.spacing,
            basis: self.basis.clone(),
            axis_rates: self.axis_rates.clone(),
            rates: self.rates.clone(),
            weights: self.weights.clone(),
            well: self.well.clone(),
            total_storage: self.total_storage,
            cache: Mutex::new(self.fresh_cache()),
        }
    }
}

/// `cos(πm/n)` with exact zeros, signs and symmetries (`m` reduced in integers).
fn cos_pi(m: usize, n: usize) -> f64 {
    let mut r = m % (2 * n);
    if r > n {
        r = 2 * n - r;
    }
    // r ∈ [0, n]: cos(πr/n) = −cos(π(n − r)/n).
    match (2 * r).cmp(&n) {
        std::cmp::Ordering::Equal => 0.0,
        std::cmp::Ordering::Less => (std::f64::consts::PI * r as f64 / n as f64).cos(),
        std::cmp::Ordering::Greater => -(std::f64::consts::PI * (n - r) as f64 / n as f64).cos(),
    }
}

impl SurfaceDiffusion {
    /// The diffusion of `injection` in the fault zone `zone` over the grid `grid` of
    /// `plane`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) as
    /// [`FaultZone::validate`], [`SurfaceInjection::validate`] and
    /// [`FaultPlane::validate`]; named `grid` (corners finite with `lower < upper`, 1 to
    /// [`MAX_SURFACE_CELLS`] cells per axis; a well's system within
    /// [`MAX_WELL_MODES`]), `source.position` (a Gaussian's centre inside the
    /// rectangle; a well on an interior node, to 1e-6 of a cell) or
    /// `well.equivalent_radius` (Peaceman's `r_e` not above the well's radius).
    pub fn new(
        zone: FaultZone,
        injection: SurfaceInjection,
        plane: FaultPlane,
        grid: SurfaceGrid,
    ) -> Result<Self> {
        zone.validate()?;
        injection.validate()?;
        plane.validate()?;
        validate_grid(&grid)?;
        let [nu, nv] = grid.nodes();
        let h = grid.spacing();
        let alpha = zone.diffusivity();
        let basis = [0, 1].map(|a| {
            let n = grid.cells[a];
            Mat::from_fn(n + 1, n + 1, |k, i| cos_pi(k * i, n))
        });
        let axis_rates = [0, 1].map(|a| {
            let n = grid.cells[a];
            (0..=n)
                .map(|k| {
                    let s = (std::f64::consts::PI * k as f64 / (2 * n) as f64).sin();
                    4.0 * alpha / (h[a] * h[a]) * s * s
                })
                .collect::<Vec<f64>>()
        });
        let rates = Mat::from_fn(nu, nv, |k, l| axis_rates[0][k] + axis_rates[1][l]);
        let cell_storage = zone.storage() * h[0] * h[1];
        let p = injection.position;
        let (sources, well) = match injection.source {
            SurfaceSource::Gaussian { width } => {
                let inside = (0..2).all(|a| p[a] >= grid.lower[a] && p[a] <= grid.upper[a]);
                if !inside {
                    return Err(invalid(
                        "source.position",
                        format!("{p:?} m must lie on the grid's rectangle"),
                    ));
                }
                (gaussian_weights(&grid, p, width), None)
            }
            SurfaceSource::Well(w) => {
                let node = well_node(&grid, p)?;
                let r_e = w
                    .equivalent_radius
                    .unwrap_or(0.14 * (h[0] * h[0] + h[1] * h[1]).sqrt());
                if !(r_e > w.radius) {
                    return Err(invalid(
                        "well.equivalent_radius",
                        format!(
                            "Peaceman's r_e = {r_e} m must be above the well's radius {} m",
                            w.radius
                        ),
                    ));
                }
                let transmissivity = zone.mobility() * zone.thickness;
                let index = 2.0 * std::f64::consts::PI * transmissivity / (r_e / w.radius).ln();
                let modes = if w.storage > 0.0 {
                    Some(WellModes::new(&WellSetup {
                        basis: [basis[0].as_ref(), basis[1].as_ref()],
                        rates: rates.as_ref(),
                        cell_storage,
                        node,
                        index,
                        storage: w.storage,
                        max_modes: MAX_WELL_MODES,
                    })?)
                } else {
                    None
                };
                let mut weights = Mat::zeros(nu, nv);
                if modes.is_none() {
                    weights[(node[0], node[1])] = 1.0;
                }
                (weights, Some((node, index, modes)))
            }
        };
        // The modes' amplitudes per unit rate: Σ_ij W_ij φ_kl(ij)/(φβL h_u h_v n_k n_l).
        let mut half = Mat::zeros(nu, nv);
        matmul(
            half.as_mut(),
            Accum::Replace,
            basis[0].as_ref(),
            sources.as_ref(),
            1.0,
            Par::Seq,
        );
        let mut weights = Mat::zeros(nu, nv);
        matmul(
            weights.as_mut(),
            Accum::Replace,
            half.as_ref(),
            basis[1].transpose(),
            1.0,
            Par::Seq,
        );
        let norm = |k: usize, n: usize| {
            if k == 0 || k == n {
                n as f64
            } else {
                0.5 * n as f64
            }
        };
        for l in 0..nv {
            for k in 0..nu {
                weights[(k, l)] /= cell_storage * norm(k, grid.cells[0]) * norm(l, grid.cells[1]);
            }
        }
        let total_storage = cell_storage * (grid.cells[0] * grid.cells[1]) as f64
            + match injection.source {
                SurfaceSource::Well(w) => w.storage,
                SurfaceSource::Gaussian { .. } => 0.0,
            };
        let mut field = Self {
            zone,
            injection,
            plane,
            grid,
            initial: 0.0,
            spacing: h,
            basis,
            axis_rates,
            rates,
            weights,
            well,
            total_storage,
            cache: Mutex::new(Cache {
                time: None,
                amplitudes: Mat::zeros(0, 0),
                half: Mat::zeros(0, 0),
                nodes: Mat::zeros(0, 0),
                values: Vec::new(),
                decay_end: [Vec::new(), Vec::new()],
                decay_after: [Vec::new(), Vec::new()],
                well: 0.0,
                scratch: None,
            }),
        };
        field.cache = Mutex::new(field.fresh_cache());
        Ok(field)
    }

    /// The same field from a uniform pressure `p₀` (Pa) at `t = 0` (the well's too).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `initial_pressure` if `p₀` is not finite.
    pub fn with_initial_pressure(mut self, p0: f64) -> Result<Self> {
        if !p0.is_finite() {
            return Err(invalid(
                "initial_pressure",
                format!("{p0} Pa must be finite"),
            ));
        }
        self.initial = p0;
        Ok(self)
    }

    fn fresh_cache(&self) -> Cache {
        let [nu, nv] = self.grid.nodes();
        Cache {
            time: None,
            amplitudes: Mat::zeros(nu, nv),
            half: Mat::zeros(nu, nv),
            nodes: Mat::zeros(nu, nv),
            values: vec![0.0; nu * nv],
            decay_end: [vec![0.0; nu], vec![0.0; nv]],
            decay_after: [vec![0.0; nu], vec![0.0; nv]],
            well: 0.0,
            scratch: self
                .well
                .as_ref()
                .and_then(|w| w.2.as_ref())
                .map(WellModes::scratch),
        }
    }

    /// The grid.
    pub fn grid(&self) -> &SurfaceGrid {
        &self.grid
    }

    /// The plane.
    pub fn plane(&self) -> &FaultPlane {
        &self.plane
    }

    /// The fault zone.
    pub fn zone(&self) -> &FaultZone {
        &self.zone
    }

    /// The well index `WI` (m³/(Pa·s)), with a well.
    pub fn well_index(&self) -> Option<f64> {
        self.well.as_ref().map(|w| w.1)
    }

    /// The dimension `D` of a storing well's coupled system (docs/pore-pressure.md, "The
    /// well"): its set-up costs `O(D³)`, each evaluation `D²` multiply-adds.
    pub fn well_dimension(&self) -> Option<usize> {
        self.well
            .as_ref()
            .and_then(|w| w.2.as_ref())
            .map(WellModes::dimension)
    }

    /// The storage `φβL_fwid |rectangle| + S_well` (m³/Pa): the injected volume per unit
    /// of the late uniform pressure.
    pub fn total_storage(&self) -> f64 {
        self.total_storage
    }

    /// The nodes' pressures `p_ij(t)` (Pa), node `(i, j)` at index `i + n_u j` (`n_u =
    /// cells[0] + 1`; positions [`SurfaceGrid::node`]).
    pub fn nodes(&self, t: f64) -> Vec<f64> {
        self.with_nodes(t, |c| c.values.iter().map(|p| self.initial + p).collect())
    }

    /// The well's pressure `p_w(t)` (Pa), with a well: with storage the extra unknown;
    /// without, `p_e + Q(t)/WI` (the well node's pressure and the rate at `t`).
    pub fn well_pressure(&self, t: f64) -> Option<f64> {
        let (node, index, modes) = self.well.as_ref()?;
        Some(self.with_nodes(t, |c| {
            let rise = if modes.is_some() {
                c.well
            } else {
                c.values[node[0] + (self.grid.cells[0] + 1) * node[1]]
                    + self.injection.injection.rate_at(t) / index
            };
            self.initial + rise
        }))
    }

    /// `p(u, v, t)` (Pa) at the plane's coordinates `uv` (m).
    pub fn at(&self, uv: [f64; 2], t: f64) -> f64 {
        self.with_nodes(t, |c| self.initial + self.interpolate(&c.values, uv))
    }

    /// The Darcy velocity `(q_u, q_v)` (m/s) at `uv` (m).
    pub fn darcy_at(&self, uv: [f64; 2], t: f64) -> [f64; 2] {
        self.with_nodes(t, |c| {
            let (i, fu) = self.locate(0, uv[0]);
            let (j, fv) = self.locate(1, uv[1]);
            let g = |a, b| self.node_gradient(&c.values, a, b);
            let (g00, g10, g01, g11) = (g(i, j), g(i + 1, j), g(i, j + 1), g(i + 1, j + 1));
            let m = self.zone.mobility();
            [0, 1].map(|d| -m * bilinear([g00[d], g10[d], g01[d], g11[d]], fu, fv))
        })
    }

    /// `∇p` at node `(i, j)` (Pa/m): central differences, zero normal to an edge.
    fn node_gradient(&self, p: &[f64], i: usize, j: usize) -> [f64; 2] {
        let h = self.spacing;
        let [cu, cv] = self.grid.cells;
        let nu = cu + 1;
        let at = |i: usize, j: usize| p[i + nu * j];
        let du = if i == 0 || i == cu {
            0.0
        } else {
            (at(i + 1, j) - at(i - 1, j)) / (2.0 * h[0])
        };
        let dv = if j == 0 || j == cv {
            0.0
        } else {
            (at(i, j + 1) - at(i, j - 1)) / (2.0 * h[1])
        };
        [du, dv]
    }

    /// `(i, f)`: coordinate `x` along axis `a` lies a fraction `f ∈ [0, 1]` of the way
    /// from node `i` to node `i + 1` (clamped to the grid).
    fn locate(&self, a: usize, x: f64) -> (usize, f64) {
        let n = self.grid.cells[a];
        let s = (x - self.grid.lower[a]) / self.spacing[a];
        if !(s > 0.0) {
            (0, 0.0)
        } else if s >= n as f64 {
            (n - 1, 1.0)
        } else {
            let i = (s as usize).min(n - 1);
            (i, s - i as f64)
        }
    }

    fn interpolate(&self, p: &[f64], uv: [f64; 2]) -> f64 {
        let (i, fu) = self.locate(0, uv[0]);
        let (j, fv) = self.locate(1, uv[1]);
        let k = i + (self.grid.cells[0] + 1) * j;
        let up = k + self.grid.cells[0] + 1;
        bilinear([p[k], p[k + 1], p[up], p[up + 1]], fu, fv)
    }

    /// Runs `f` on the nodes at `t` (computed if `t` is not the last time).
    fn with_nodes<R>(&self, t: f64, f: impl FnOnce(&Cache) -> R) -> R {
        let mut guard = self
            .cache
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if guard.time != Some(t.to_bits()) {
            self.evaluate(t, &mut guard);
            guard.time = Some(t.to_bits());
        }
        f(&guard)
    }

    /// The nodes' `p − p₀` at `t` into `c`.
    fn evaluate(&self, t: f64, c: &mut Cache) {
        let inj = self.injection.injection;
        let end = t.min(inj.shut_in).max(0.0);
        let after = (t - end).max(0.0);
        let q = inj.rate;
        let [nu, nv] = self.grid.nodes();
        // e^{−λ_kl s} = e^{−λ_k s} e^{−λ_l s}: per-axis exponentials, and `expm1` where
        // λ_kl end is small (below 1/4; above, 1 − e^{−x} from the product of two
        // exponentials is within 8 ulps).
        for a in 0..2 {
            for (k, &lambda) in self.axis_rates[a].iter().enumerate() {
                c.decay_end[a][k] = (-lambda * end).exp();
                c.decay_after[a][k] = (-lambda * after).exp();
            }
        }
        for l in 0..nv {
            for k in 0..nu {
                let w = self.weights[(k, l)];
                let mu = self.rates[(k, l)];
                c.amplitudes[(k, l)] = if w == 0.0 {
                    0.0
                } else if mu * end >= 0.25 {
                    let kept = c.decay_after[0][k] * c.decay_after[1][l];
                    w * q * ((1.0 - c.decay_end[0][k] * c.decay_end[1][l]) / mu * kept)
                } else {
                    w * q * response(mu, end, after)
                };
            }
        }
        c.well = 0.0;
        if let (Some((_, _, Some(modes))), Some(scratch)) = (&self.well, &mut c.scratch) {
            // The uniform pressure of the volume injected, then the rest.
            let uniform = q * end / self.total_storage;
            c.amplitudes[(0, 0)] += uniform;
            c.well = uniform + modes.add((q, end, after), scratch, c.amplitudes.as_mut());
        }
        matmul(
            c.half.as_mut(),
            Accum::Replace,
            self.basis[0].transpose(),
            c.amplitudes.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(
            c.nodes.as_mut(),
            Accum::Replace,
            c.half.as_ref(),
            self.basis[1].as_ref(),
            1.0,
            Par::Seq,
        );
        for j in 0..nv {
            for i in 0..nu {
                c.values[i + nu * j] = c.nodes[(i, j)];
            }
        }
    }
}

/// The bilinear interpolant of `[p00, p10, p01, p11]` at `(fu, fv) ∈ [0, 1]²`, in a form
/// exact for equal values.
fn bilinear(p: [f64; 4], fu: f64, fv: f64) -> f64 {
    p[0] + fu * (p[1] - p[0]) + fv * (p[2] - p[0]) + fu * fv * (p[0] - p[1] - p[2] + p[3])
}

fn validate_grid(grid: &SurfaceGrid) -> Result<()> {
    for a in 0..2 {
        let (lo, hi) = (grid.lower[a], grid.upper[a]);
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(invalid(
                "grid",
                format!(
                    "corners {:?}, {:?} m must be finite with lower < upper",
                    grid.lower, grid.upper
                ),
            ));
        }
        if !(1..=MAX_SURFACE_CELLS).contains(&grid.cells[a]) {
            return Err(invalid(
                "grid",
                format!(
                    "{:?} cells: each must be in 1..={MAX_SURFACE_CELLS}",
                    grid.cells
                ),
            ));
        }
    }
    Ok(())
}

/// The Gaussian at the nodes times their areas, summing to 1 (relative to the nearest
/// node, so that a narrow one never underflows to nothing).
fn gaussian_weights(grid: &SurfaceGrid, p: [f64; 2], width: f64) -> Mat<f64> {
    let [nu, nv] = grid.nodes();
    let r2 = |i: usize, j: usize| {
        let x = grid.node(i, j);
        (x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2)
    };
    let mut nearest = f64::INFINITY;
    for j in 0..nv {
        for i in 0..nu {
            nearest = nearest.min(r2(i, j));
        }
    }
    let edge = |i: usize, n: usize| if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
    let mut w = Mat::from_fn(nu, nv, |i, j| {
        edge(i, nu) * edge(j, nv) * (-(r2(i, j) - nearest) / (2.0 * width * width)).exp()
    });
    let mut sum = 0.0;
    for j in 0..nv {
        for i in 0..nu {
            sum += w[(i, j)];
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            w[(i, j)] /= sum;
        }
    }
    w
}

/// The interior node at `p` (to 1e-6 of a cell).
fn well_node(grid: &SurfaceGrid, p: [f64; 2]) -> Result<[usize; 2]> {
    let h = grid.spacing();
    let mut node = [0; 2];
    for a in 0..2 {
        let s = (p[a] - grid.lower[a]) / h[a];
        let i = s.round();
        if !((s - i).abs() <= 1e-6 && i >= 1.0 && i <= (grid.cells[a] - 1) as f64) {
            return Err(invalid(
                "source.position",
                format!("a well at {p:?} m must sit on an interior node of the grid"),
            ));
        }
        node[a] = i as usize;
    }
    Ok(node)
}

impl PorePressure<3> for SurfaceDiffusion {
    fn pressure(&self, x: &[f64; 3], t: f64) -> f64 {
        self.at(self.plane.coordinates(x), t)
    }
    fn pressures(&self, t: f64, points: &[[f64; 3]], out: &mut [f64]) {
        self.with_nodes(t, |c| {
            for (o, x) in out.iter_mut().zip(points) {
                *o = self.initial + self.interpolate(&c.values, self.plane.coordinates(x));
            }
        });
    }
    fn darcy_velocity_vector(&self, x: &[f64; 3], t: f64) -> Option<[f64; 3]> {
        Some(self.plane.vector_at(x, |uv| self.darcy_at(uv, t)))
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.injection.injection.shut_in]
    }
}
