//! A Peaceman well with storage on the grid of a [`SurfaceDiffusion`](super::SurfaceDiffusion),
//! solved exactly in time: the well couples one node to the cosine modes, a rank-one change
//! of their diagonal system, diagonalised once (docs/pore-pressure.md, "The well").
//!
//! In the storage-weighted coordinates `y = S^{1/2} (p, p_w)` (`S` the nodes' storages
//! `φβL_fwid A_ij` and the well's `S_well`) the system is `ẏ = −(Λ ⊕ 0) y − WI v vᵀ y + f`,
//! `v = (ψ_m(e), −S_well^{−1/2})`, `ψ_m` the modes normalised in that inner product and `e`
//! the well's node, `f = Q(t) S_well^{−1/2} e_w`. The uniform pressure (the exact kernel,
//! orthogonal to `v`) carries the injected volume alone. The rest lives in a space of
//! dimension `D`: one direction per distinct eigenvalue among the modes that do not
//! vanish at the well (the part of `v` in that eigenspace) and the combination `z⊥` of the
//! uniform nodes and the well orthogonal to the uniform pressure, where the system is
//! `T = diag(λ_g, 0) + WI ṽṽᵀ`, symmetric positive definite, diagonalised once
//! (`T = U diag(μ) Uᵀ`, faer's self-adjoint eigensolver on one thread). Each time then
//! costs `D` exponentials and one product with `U`.

use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, MatMut, MatRef, Par};

use crate::error::{invalid, Result};

/// The well's part of the solution.
#[derive(Debug, Clone)]
pub(super) struct WellModes {
    /// Per direction `g` (in `starts[g]..starts[g + 1]`): the modes `(k, l)` and the
    /// factor from the direction's coefficient to the mode's amplitude (Pa per unit).
    members: Vec<(usize, usize, f64)>,
    starts: Vec<usize>,
    /// `U` (`D × D`) and `μ` (1/s).
    vectors: Mat<f64>,
    values: Vec<f64>,
    /// `Uᵀ g` per unit rate: `g` the forcing's part in the `D` space.
    drive: Vec<f64>,
    /// The pressure of the uniform nodes, and of the well, per unit coefficient of `z⊥`.
    z_nodes: f64,
    z_well: f64,
}

/// What [`WellModes::add`] works in, per evaluation.
#[derive(Debug, Clone)]
pub(super) struct WellScratch {
    weighted: Col<f64>,
    coefficients: Col<f64>,
}

/// The well's geometry on the grid: what the modes are.
pub(super) struct WellSetup<'a> {
    /// `cos(πki/N)` per axis, `(k, i)`.
    pub basis: [MatRef<'a, f64>; 2],
    /// The modes' rates `λ_kl` (1/s).
    pub rates: MatRef<'a, f64>,
    /// `φβL_fwid h_u h_v` (m³/Pa).
    pub cell_storage: f64,
    /// The well's node `(i, j)`.
    pub node: [usize; 2],
    /// The well index `WI` (m³/(Pa·s)).
    pub index: f64,
    /// `S_well` (m³/Pa), positive.
    pub storage: f64,
    /// The largest `D` allowed.
    pub max_modes: usize,
}

impl WellModes {
    /// The well's modes.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `grid` where `D`
    /// exceeds `max_modes`; [`Error::IllConditioned`](crate::Error::IllConditioned) if
    /// the eigensolver does not converge.
    pub(super) fn new(s: &WellSetup<'_>) -> Result<Self> {
        let [nu, nv] = [s.basis[0].nrows(), s.basis[1].nrows()];
        let norm = |k: usize, n: usize| {
            if k == 0 || k == n - 1 {
                (n - 1) as f64
            } else {
                0.5 * (n - 1) as f64
            }
        };
        // ψ_m(e) of every mode but the uniform one, where it does not vanish, grouped by
        // equal rates (the basis' exact zeros and the rates' exact ties: see `cos_pi`).
        let mut coupled = Vec::new();
        for l in 0..nv {
            for k in 0..nu {
                let phi = s.basis[0][(k, s.node[0])] * s.basis[1][(l, s.node[1])];
                if (k, l) == (0, 0) || phi == 0.0 {
                    continue;
                }
                let scale = (s.cell_storage * norm(k, nu) * norm(l, nv)).sqrt();
                coupled.push((s.rates[(k, l)], k, l, phi / scale, scale));
            }
        }
        coupled.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        let (mut members, mut starts, mut diagonal, mut v) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut first = 0;
        while first < coupled.len() {
            let rate = coupled[first].0;
            let last = first + coupled[first..].partition_point(|c| c.0 == rate);
            let beta = coupled[first..last]
                .iter()
                .map(|c| c.3 * c.3)
                .sum::<f64>()
                .sqrt();
            starts.push(members.len());
            members.extend(
                coupled[first..last]
                    .iter()
                    .map(|&(_, k, l, b, scale)| (k, l, b / (beta * scale))),
            );
            diagonal.push(rate);
            v.push(beta);
            first = last;
        }
        starts.push(members.len());
        let d = diagonal.len() + 1;
        if d > s.max_modes {
            return Err(invalid(
                "grid",
                format!(
                    "the well couples {d} directions (above {}): a setup of D^3 and D^2 \
                     per evaluation; a coarser grid or a well at the grid's centre",
                    s.max_modes
                ),
            ));
        }
        let storage_nodes = s.cell_storage * ((nu - 1) * (nv - 1)) as f64;
        let storage_well = s.storage;
        let total = storage_nodes + storage_well;
        diagonal.push(0.0);
        v.push((1.0 / storage_nodes + 1.0 / storage_well).sqrt());
        let t = Mat::from_fn(d, d, |i, j| {
            let r = s.index * v[i] * v[j];
            if i == j {
                r + diagonal[i]
            } else {
                r
            }
        });
        let (values, vectors) = eigen(t.as_ref())?;
        // The forcing Q e_w S_well^{−1/2} on z⊥ = (√S_well e_00 − √S_nodes e_w)/√S_total.
        let g = -(storage_nodes / storage_well).sqrt() / total.sqrt();
        let drive = (0..d).map(|j| g * vectors[(d - 1, j)]).collect();
        Ok(Self {
            members,
            starts,
            vectors,
            values,
            drive,
            z_nodes: storage_well.sqrt() / (total.sqrt() * storage_nodes.sqrt()),
            z_well: -storage_nodes.sqrt() / (total.sqrt() * storage_well.sqrt()),
        })
    }

    /// `D`.
    pub(super) fn dimension(&self) -> usize {
        self.values.len()
    }

    /// Scratch for [`add`](Self::add).
    pub(super) fn scratch(&self) -> WellScratch {
        let d = self.values.len();
        WellScratch {
            weighted: Col::zeros(d),
            coefficients: Col::zeros(d),
        }
    }

    /// Adds the well's non-uniform part at `t` to the modes' `amplitudes` (Pa) for the
    /// constant rate `rate` on `[0, end)` seen `after` seconds later, and returns the
    /// well's pressure beyond the uniform one (Pa).
    pub(super) fn add(
        &self,
        (rate, end, after): (f64, f64, f64),
        scratch: &mut WellScratch,
        mut amplitudes: MatMut<'_, f64>,
    ) -> f64 {
        for ((w, &mu), &r) in scratch
            .weighted
            .iter_mut()
            .zip(&self.values)
            .zip(&self.drive)
        {
            *w = rate * r * super::surface::response(mu, end, after);
        }
        matmul(
            scratch.coefficients.as_mat_mut(),
            Accum::Replace,
            self.vectors.as_ref(),
            scratch.weighted.as_mat(),
            1.0,
            Par::Seq,
        );
        let c = &scratch.coefficients;
        for (g, w) in self.starts.windows(2).enumerate() {
            for &(k, l, f) in &self.members[w[0]..w[1]] {
                amplitudes[(k, l)] += c[g] * f;
            }
        }
        let z = c[self.values.len() - 1];
        amplitudes[(0, 0)] += z * self.z_nodes;
        z * self.z_well
    }
}

/// The eigenvalues (ascending, clamped at 0 from below) and eigenvectors of the symmetric
/// `t`, on one thread (the same bits whatever the pool).
fn eigen(t: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>)> {
    use faer::diag::Diag;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd;
    let n = t.nrows();
    let mut u = Mat::zeros(n, n);
    let mut s = Diag::zeros(n);
    let par = Par::Seq;
    let mut buffer = MemBuffer::new(evd::self_adjoint_evd_scratch::<f64>(
        n,
        evd::ComputeEigenvectors::Yes,
        par,
        Default::default(),
    ));
    evd::self_adjoint_evd(
        t,
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut buffer),
        Default::default(),
    )
    .map_err(|e| crate::Error::IllConditioned {
        fields: vec!["grid".into(), "well".into()],
        reason: format!("the well's {n} x {n} eigenproblem did not converge ({e:?})"),
    })?;
    let values = (0..n).map(|i| s[i].max(0.0)).collect();
    Ok((values, u))
}
