//! Normal stress that changes with slip on a fault inside the body (docs/faults-inside.md
//! "Normal stress", docs/math.md §15): the slip → normal-traction operator of the
//! condensed problem and the friction laws scaled by the current normal stress.

use std::time::Instant;

use faer::Mat;
use rayon::prelude::*;
use rsf_direct::Condensation;
use rsf_friction::FrictionLaw;
use rsf_hmatrix::{ErrorMeasure, HMatrix, HOptions, Points};
use rsf_linalg::Parallelism;
use rsf_numeric::normal_component;

use crate::error::{invalid, Error, Result};
use crate::fault_kernel::{compress, Kernel};
use crate::fault_operator::{FaultKernel, KernelReport};
use crate::model::Model;
use crate::observe::FaultTractions;

/// How a fault's normal stress `σ̄_n` (Pa, compressive positive) is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NormalStress {
    /// The laws' own `σ̄_n` ([`FrictionLaw::normal_stress`]), fixed in time: the paper's
    /// model and every boundary fault (the default).
    #[default]
    Fixed,
    /// On a fault inside the body (vector field): `σ̄_n = σ̄_n⁰ + Δσ_n`, `σ̄_n⁰` the laws'
    /// and `Δσ_n` the change of the normal traction since `t = 0` that the slip and the
    /// loading cause (the reaction that keeps the fault closed). The friction of node `k`
    /// is its law's potential scaled by `σ̄_n,k/σ̄_n⁰,k`: the law must be proportional to
    /// its normal stress ([`FrictionLaw::proportional_to_normal_stress`]).
    FromSlip,
}

/// The laws' normal stresses `σ̄_n⁰` for a normal stress from slip (`None` for
/// [`NormalStress::Fixed`]).
///
/// # Errors
/// [`Error::InvalidParameter`] named `normal_stress` without an internal fault, for a
/// scalar field, or for a law without a positive normal stress it is proportional to.
fn initial_normal_stress<const D: usize, const C: usize, L: FrictionLaw>(
    choice: NormalStress,
    model: &Model<D, C>,
    laws: &[L],
) -> Result<Option<Vec<f64>>> {
    if choice == NormalStress::Fixed {
        return Ok(None);
    }
    if model.internal_fault.is_none() || C != D || C == 1 {
        return Err(invalid(
            "normal_stress",
            "NormalStress::FromSlip needs a fault inside the body of a vector (plane \
             strain or 3-D) model (ModelBuilder::internal_fault, \
             internal_fault_polygon): a boundary fault's normal stress is prescribed, \
             an antiplane model has none",
        ));
    }
    laws.iter()
        .enumerate()
        .map(|(k, law)| match law.normal_stress() {
            Some(s) if law.proportional_to_normal_stress() && s > 0.0 && s.is_finite() => Ok(s),
            _ => Err(invalid(
                "normal_stress",
                format!(
                    "the law of frictional node {k} has no positive normal stress it is \
                     proportional to (FrictionLaw::normal_stress, \
                     FrictionLaw::proportional_to_normal_stress)"
                ),
            )),
        })
        .collect::<Result<Vec<f64>>>()
        .map(Some)
}

/// The normal stress of every frictional node as an affine function of the condensed
/// unknowns `u_F` and the integrated loading `G(t)`:
/// `σ̄_n,k = σ̄_n⁰,k − (G(t) a_k + (S_N (u_F − u_F⁰))_k)/w_k`, where `S_N` (`nodes × m`, N/m)
/// maps the condensed unknowns (m) to the reactions (N) at the tied normal jumps and `a`
/// (N per unit of `G`) is the reaction of a unit loading with the condensed unknowns held.
pub(crate) struct NormalCoupling {
    /// `S_N`, dense or compressed ([`compress`](Self::compress)).
    s_n: SlipToNormal,
    /// `u_F − u_F⁰` (scratch for the compressed product).
    du: Vec<f64>,
    loading: Vec<f64>,
    u_f0: Vec<f64>,
    g0: f64,
    sigma0: Vec<f64>,
    weights: Vec<f64>,
}

/// How `S_N` is stored.
enum SlipToNormal {
    /// `nodes × m`, column-major.
    Dense(Mat<f64>),
    /// An ℋ-matrix of `S_N` itself, its rows and columns on the same points (node `k`'s
    /// one free component is unknown `k`: a 2-D fault inside the body).
    Square(Box<HMatrix>),
    /// One ℋ-matrix per slip component (a 3-D fault).
    ByComponent(Vec<ComponentBlock>),
}

/// The columns of `S_N` of one slip component `c` (each node's `c`-th free component: the
/// strike or dip slip of a 3-D fault's node) as a square ℋ-matrix on the nodes that have
/// that component — row `j` (node `nodes[j]`'s reaction) and column `j` (its slip
/// `unknowns[j]`) at the same point, the node's coordinates — plus the dense rows of the
/// nodes without it (none where every node has the same free components). rsf-hmatrix's
/// ℋ-matrices are square with one point per row and column: this takes `S_N`'s
/// `nodes × m` entries as they are, without zero rows or padding.
struct ComponentBlock {
    h: HMatrix,
    /// The frictional nodes with a `c`-th free component (rows and points of `h`).
    nodes: Vec<usize>,
    /// Their `c`-th free components (condensed unknowns; the columns of `h`).
    unknowns: Vec<usize>,
    /// The other frictional nodes.
    rest_nodes: Vec<usize>,
    /// Their rows of `S_N` in the columns `unknowns` (`rest_nodes.len() × unknowns.len()`).
    rest: Mat<f64>,
    /// Scratch: `u_F − u_F⁰` at `unknowns`.
    x: Vec<f64>,
    /// Scratch: zeros, the reactions `h x` (length `nodes.len()`), then those of `rest`.
    y: Vec<f64>,
    y_rest: Vec<f64>,
}

impl ComponentBlock {
    /// `r ← r + S_N,c (u_F − u_F⁰)_c` on `par`'s threads (the same bits for every `par`);
    /// a non-finite slip gives NaN reactions.
    ///
    /// # Errors
    /// [`Error::HMatrix`] from the product (none for the lengths set up here).
    fn add_product(
        &mut self,
        u_f: &[f64],
        u_f0: &[f64],
        r: &mut [f64],
        par: Parallelism,
    ) -> Result<()> {
        for (x, &i) in self.x.iter_mut().zip(&self.unknowns) {
            *x = u_f[i] - u_f0[i];
        }
        self.y.fill(0.0);
        match self.h.apply_add(&self.x, &mut self.y, 1.0, par.faer()) {
            Err(rsf_hmatrix::Error::NonFiniteInput(_)) => self.y.fill(f64::NAN),
            other => other?,
        }
        for (y, &k) in self.y.iter().zip(&self.nodes) {
            r[k] += y;
        }
        if !self.rest_nodes.is_empty() {
            self.y_rest.fill(0.0);
            // Rows of nodes without this component: dense (`x` already holds the slips).
            add_dense_product(&self.rest, &self.x, &[], &mut self.y_rest, par);
            for (y, &k) in self.y_rest.iter().zip(&self.rest_nodes) {
                r[k] += y;
            }
        }
        Ok(())
    }
}

/// Entries of `S_N` below which its dense product stays on the calling thread: a rayon
/// task per part costs microseconds, the product of a few thousand entries about as much.
const MIN_PARALLEL_ENTRIES: usize = 1 << 12;

/// `r ← r + S_N (u_F − u_F⁰)` for the dense `S_N` (`r.len() × m`), the rows split into
/// contiguous parts on `par`'s threads. Each row's sum runs over the columns in order
/// (`r_k += S_N,ki (u_i − u⁰_i)`, `i = 0, 1, …`) whatever the split, so the bits are
/// those of the sequential column-by-column product at every thread count; within a part
/// each column's rows are contiguous. An empty `u_f0` is taken as zero (`u_f` is then
/// the difference itself).
fn add_dense_product(s_n: &Mat<f64>, u_f: &[f64], u_f0: &[f64], r: &mut [f64], par: Parallelism) {
    let part = |start: usize, r: &mut [f64]| {
        for (i, u) in u_f.iter().enumerate() {
            let du = match u_f0.get(i) {
                Some(u0) => u - u0,
                None => *u,
            };
            let col = &s_n.col_as_slice(i)[start..start + r.len()];
            for (s, c) in r.iter_mut().zip(col) {
                *s += c * du;
            }
        }
    };
    let rows = r.len();
    if !par.is_parallel() || rows < 2 || rows * u_f.len() < MIN_PARALLEL_ENTRIES {
        part(0, r);
        return;
    }
    let chunk = rows.div_ceil(par.threads());
    r.par_chunks_mut(chunk)
        .enumerate()
        .for_each(|(b, rb)| part(b * chunk, rb));
}

impl NormalCoupling {
    /// The coupling of `model`'s internal fault (`C = D` = 2 or 3) condensed by `cond` onto the
    /// frictional nodes' free components, with the laws' `σ̄_n⁰`; `None` for
    /// [`NormalStress::Fixed`].
    ///
    /// `velocity_factor`: the Dirichlet velocity factors (length `n`); `big_g0` = `G(0)`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `normal_stress` without an internal fault, for a
    /// scalar field, or for a law without a normal stress or not proportional to it;
    /// condensation errors.
    pub(crate) fn new<const D: usize, const C: usize, L: FrictionLaw>(
        choice: NormalStress,
        model: &Model<D, C>,
        cond: &mut Condensation<C>,
        laws: &[L],
        velocity_factor: &[f64],
        big_g0: f64,
    ) -> Result<Option<Self>> {
        let Some(sigma0) = initial_normal_stress(choice, model, laws)? else {
            return Ok(None);
        };
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let m = cond.dim();
        // The reaction at node k's tied normal jump of a field `x` is row k of `rows` applied
        // to `x`: (K x)_N, column N of the symmetric K (no load: the load's part is constant
        // and drops out of the change).
        let k = model.stiffness.as_ref();
        let rows: Vec<Vec<(usize, f64)>> = fb
            .nodes
            .iter()
            .map(|&p| {
                let dof = C * p + normal_component(C);
                k.row_idx_of_col(dof)
                    .zip(k.val_of_col(dof))
                    .map(|(i, &v)| (i, v))
                    .collect()
            })
            .collect();
        // S_N's columns: the reactions of the harmonic extensions of the unit interface
        // vectors, many extensions per sweep over the factor.
        let s_n = cond.extension_functionals(&rows)?;
        let zeros = vec![0.0; n];
        let mut g = vec![0.0; m];
        let mut x = vec![0.0; n];
        // A unit of integrated loading with the condensed unknowns held at 0.
        cond.condense(&zeros, velocity_factor, &mut g)?;
        x.copy_from_slice(velocity_factor);
        for &dof in cond.interface_dofs() {
            x[dof] = 0.0;
        }
        cond.extend(&mut x)?;
        let loading = rows
            .iter()
            .map(|row| row.iter().map(|&(i, v)| v * x[i]).sum())
            .collect();
        let u_f0 = cond
            .interface_dofs()
            .iter()
            .map(|&dof| model.initial_displacement[dof])
            .collect();
        Ok(Some(Self {
            s_n: SlipToNormal::Dense(s_n),
            du: vec![0.0; m],
            loading,
            u_f0,
            g0: big_g0,
            sigma0,
            weights: fb.weights.clone(),
        }))
    }

    /// `S_N` as the fault ODE's `kind` of kernel, with the same accuracy and leaf size as
    /// `S`: the report of the compression, `None` where `S_N` stays dense (a dense `kind`,
    /// or a 1-D or 2-D fault whose rows and columns are on different points).
    ///
    /// - Every frictional node with exactly one free component, condensed unknown `k` of
    ///   node `k` (a 2-D fault inside the body with its normal tied): `S_N` is square on
    ///   those nodes and compressed from its dense entries by truncated SVD, as `S` in
    ///   2-D (rsf-hmatrix's `from_dense`, the error over every entry).
    /// - A 3-D model (two tangential slip components per node): the columns of each slip
    ///   component form a square matrix on the nodes that have it (row and column `j` at
    ///   node `j`'s coordinates, m), each compressed by cross approximation from `S_N`'s
    ///   entries (rsf-hmatrix's `from_entries`, as `S` in 3-D, the error estimated on
    ///   sampled entries); the rows of nodes without that component stay dense. The
    ///   report sums the blocks' storage and weighs their errors by their Frobenius norms
    ///   (`‖S_N − S_N,H‖_F/‖S_N‖_F`); its `dim` is `m`, the dense `S_N` has `nodes × m`
    ///   entries (`m²/2` on a 3-D fault, half of the `m²` of
    ///   [`KernelReport::compression_ratio`]), and `setup_bytes` is that dense `S_N`
    ///   (`8 nodes m`), freed once compressed.
    ///
    /// # Errors
    /// The compression's errors ([`Error::HMatrix`]: a non-finite entry, invalid options).
    pub(crate) fn compress<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        cond: &Condensation<C>,
        kind: FaultKernel,
    ) -> Result<Option<KernelReport>> {
        let fb = &model.frictional_boundary;
        let same_points = cond.interface_dofs().len() == fb.len()
            && cond
                .interface_dofs()
                .iter()
                .zip(&fb.nodes)
                .all(|(&dof, &p)| dof / C == p);
        if matches!(kind, FaultKernel::Dense) || !(same_points || D == 3) {
            return Ok(None);
        }
        let SlipToNormal::Dense(dense) =
            std::mem::replace(&mut self.s_n, SlipToNormal::Dense(Mat::zeros(0, 0)))
        else {
            return Ok(None);
        };
        if same_points {
            let (kernel, report) = compress(dense, model, cond, kind)?;
            self.s_n = match kernel {
                Kernel::Dense(s) => SlipToNormal::Dense(s),
                Kernel::Hierarchical(h) => SlipToNormal::Square(h),
            };
            return Ok(Some(report));
        }
        let FaultKernel::Hierarchical { epsilon, leaf_size } = kind else {
            return Ok(None);
        };
        let clock = Instant::now();
        let m = cond.dim();
        let nodes = fb.len();
        // Each frictional node's free components as condensed unknowns (the condensation's
        // unknowns come node by node, each node's free components in order: `first` as
        // the fault ODE's).
        let interface = cond.interface_dofs();
        let mut first = Vec::with_capacity(nodes + 1);
        let mut i = 0;
        for &p in &fb.nodes {
            first.push(i);
            while i < m && interface[i] / C == p {
                i += 1;
            }
        }
        first.push(i);
        if i != m {
            // Not the order assumed: keep the exact dense operator.
            self.s_n = SlipToNormal::Dense(dense);
            return Ok(None);
        }
        let options = HOptions {
            epsilon,
            leaf_size,
            ..HOptions::default()
        };
        let (mut stored, mut dense_blocks, mut low_rank_blocks, mut max_rank) = (0, 0, 0, 0);
        let (mut samples, mut err2, mut norm2) = (0, 0.0, 0.0);
        let mut blocks = Vec::new();
        for c in 0..C {
            let (with, without): (Vec<usize>, Vec<usize>) =
                (0..nodes).partition(|&k| first[k] + c < first[k + 1]);
            if with.is_empty() {
                continue;
            }
            let unknowns: Vec<usize> = with.iter().map(|&k| first[k] + c).collect();
            let coords: Vec<[f64; D]> = with.iter().map(|&k| model.vertices[fb.nodes[k]]).collect();
            let h = HMatrix::from_entries(
                |a, b| dense[(with[a], unknowns[b])],
                &Points::from_array(&coords)?,
                &options,
            )?;
            let r = h.report();
            // ‖S_N,c‖_F² weighs the block's relative error in the whole's.
            let block_norm2: f64 = unknowns
                .iter()
                .flat_map(|&j| with.iter().map(move |&k| (k, j)))
                .map(|(k, j)| dense[(k, j)] * dense[(k, j)])
                .sum();
            err2 += r.relative_error * r.relative_error * block_norm2;
            norm2 += block_norm2;
            if let ErrorMeasure::Sampled { samples: s } = r.error_measure {
                samples += s;
            }
            stored += r.stored_entries + without.len() * unknowns.len();
            dense_blocks += r.dense_blocks + usize::from(!without.is_empty());
            low_rank_blocks += r.low_rank_blocks;
            max_rank = max_rank.max(r.max_rank);
            let rest = Mat::from_fn(without.len(), unknowns.len(), |a, b| {
                dense[(without[a], unknowns[b])]
            });
            blocks.push(ComponentBlock {
                h,
                x: vec![0.0; unknowns.len()],
                y: vec![0.0; with.len()],
                y_rest: vec![0.0; without.len()],
                nodes: with,
                unknowns,
                rest_nodes: without,
                rest,
            });
        }
        let report = KernelReport {
            kernel: kind,
            dim: m,
            relative_error: if norm2 > 0.0 {
                (err2 / norm2).sqrt()
            } else {
                0.0
            },
            error_samples: samples,
            setup_bytes: 8 * dense.nrows() * dense.ncols(),
            stored_entries: stored,
            dense_blocks,
            low_rank_blocks,
            max_rank,
            setup_seconds: clock.elapsed().as_secs_f64(),
        };
        drop(dense);
        self.s_n = SlipToNormal::ByComponent(blocks);
        Ok(Some(report))
    }

    /// The laws' normal stresses `σ̄_n⁰` (Pa).
    pub(crate) fn initial(&self) -> &[f64] {
        &self.sigma0
    }

    /// Writes `σ̄_n,k` (Pa) at integrated loading `big_g` and condensed unknowns `u_f`
    /// (m, length `m`) into `sigma` (one per frictional node), the product with `S_N` on
    /// `par`'s threads: the same bits at every thread count (a dense `S_N` also the bits
    /// of the sequential column-by-column product).
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] where the slip would open the fault
    /// (`σ̄_n ≤ 0`) or the value is not finite (a non-finite `u_f` gives NaN, refused so).
    pub(crate) fn evaluate(
        &mut self,
        time: f64,
        big_g: f64,
        u_f: &[f64],
        sigma: &mut [f64],
        par: Parallelism,
    ) -> Result<()> {
        let dg = big_g - self.g0;
        // The reactions r = dg a + S_N (u_F − u_F⁰) accumulated in `sigma`.
        for (s, a) in sigma.iter_mut().zip(&self.loading) {
            *s = dg * a;
        }
        match &mut self.s_n {
            SlipToNormal::Dense(s_n) => add_dense_product(s_n, u_f, &self.u_f0, sigma, par),
            SlipToNormal::Square(h) => {
                for ((d, u), u0) in self.du.iter_mut().zip(u_f).zip(&self.u_f0) {
                    *d = u - u0;
                }
                match h.apply_add(&self.du, sigma, 1.0, par.faer()) {
                    // A trial stage that blew up: NaN, refused below as for dense.
                    Err(rsf_hmatrix::Error::NonFiniteInput(_)) => sigma.fill(f64::NAN),
                    other => other.map_err(Error::from)?,
                }
            }
            SlipToNormal::ByComponent(blocks) => {
                for block in blocks {
                    block.add_product(u_f, &self.u_f0, sigma, par)?;
                }
            }
        }
        for (k, s) in sigma.iter_mut().enumerate() {
            let r = *s;
            *s = self.sigma0[k] - r / self.weights[k];
            if !(*s > 0.0 && s.is_finite()) {
                return Err(Error::NormalStressNotPositive {
                    node: k,
                    time,
                    sigma_n: *s,
                });
            }
        }
        Ok(())
    }
}

/// The tractions observers see with a changing normal stress: each law's scaled by
/// `σ̄_n/σ̄_n⁰` at the last accepted step.
#[derive(Debug, Clone)]
pub(crate) struct ScaledTractions<L> {
    pub(crate) laws: Vec<L>,
    pub(crate) sigma0: Vec<f64>,
    pub(crate) sigma: Vec<f64>,
}

impl<L: FrictionLaw> FaultTractions for ScaledTractions<L> {
    fn shear_traction(&self, k: usize, slip_rate: f64, alpha: f64) -> f64 {
        use rsf_friction::ConvexPotential;
        self.sigma[k] / self.sigma0[k] * self.laws[k].potential(alpha).slope(slip_rate)
    }
    fn normal_traction(&self, k: usize) -> Option<f64> {
        Some(self.sigma[k])
    }
}

/// The normal stress of the implicit scheme, from the whole field of an iterate:
/// `σ̄_n,k = σ̄_n⁰,k − (r_N,k − r_N,k(0))/w_k` with the reactions
/// `r_N = (M a + K u − F)_N` at the tied normal jumps (dashpots of absorbing parts are
/// not included: they act on the outer boundary, not on the fault's split nodes).
#[derive(Debug, Clone)]
pub(crate) struct NormalReactions {
    dofs: Vec<usize>,
    r0: Vec<f64>,
    sigma0: Vec<f64>,
    weights: Vec<f64>,
}

impl NormalReactions {
    /// The reactions of `model` with its `laws`, relative to the `initial` kinematics;
    /// `None` for [`NormalStress::Fixed`].
    ///
    /// # Errors
    /// As [`NormalCoupling::new`]'s checks.
    pub(crate) fn new<const D: usize, const C: usize, L: FrictionLaw>(
        choice: NormalStress,
        model: &Model<D, C>,
        laws: &[L],
        initial: &rsf_time::Kinematics,
    ) -> Result<Option<Self>> {
        let Some(sigma0) = initial_normal_stress(choice, model, laws)? else {
            return Ok(None);
        };
        let fb = &model.frictional_boundary;
        let mut this = Self {
            dofs: fb
                .nodes
                .iter()
                .map(|&p| C * p + normal_component(C))
                .collect(),
            r0: vec![0.0; fb.len()],
            sigma0,
            weights: fb.weights.clone(),
        };
        let mut r0 = vec![0.0; fb.len()];
        this.reactions(model, initial, &mut r0);
        this.r0 = r0;
        Ok(Some(this))
    }

    /// The laws' normal stresses `σ̄_n⁰` (Pa).
    pub(crate) fn initial(&self) -> &[f64] {
        &self.sigma0
    }

    fn reactions<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        kin: &rsf_time::Kinematics,
        out: &mut [f64],
    ) {
        let row = |a: &crate::fem::SparseMatrix, x: &[f64], dof: usize| -> f64 {
            a.row_idx_of_col(dof)
                .zip(a.val_of_col(dof))
                .map(|(i, v)| v * x[i])
                .sum()
        };
        for (o, &dof) in out.iter_mut().zip(&self.dofs) {
            let mut r = row(&model.stiffness, &kin.u, dof) - model.load[dof];
            if let Some(m) = &model.mass {
                r += row(m, &kin.a, dof);
            }
            *o = r;
        }
    }

    /// Writes `σ̄_n,k` (Pa) of the kinematics `kin` at `time` into `sigma` and the scaled
    /// weights `w_k σ̄_n,k/σ̄_n⁰,k` into `weights`.
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] where `σ̄_n ≤ 0` or not finite.
    pub(crate) fn evaluate<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        kin: &rsf_time::Kinematics,
        time: f64,
        sigma: &mut [f64],
        weights: &mut [f64],
    ) -> Result<()> {
        self.reactions(model, kin, sigma);
        for (k, s) in sigma.iter_mut().enumerate() {
            *s = self.sigma0[k] - (*s - self.r0[k]) / self.weights[k];
            if !(*s > 0.0 && s.is_finite()) {
                return Err(Error::NormalStressNotPositive {
                    node: k,
                    time,
                    sigma_n: *s,
                });
            }
            weights[k] = self.weights[k] * (*s / self.sigma0[k]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries of order 1 with all their bits used (a seeded scramble), so that a sum in
    /// another order rounds differently.
    fn scrambled(i: usize, seed: u64) -> f64 {
        let mut x = (i as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        x ^= x >> 29;
        x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 32;
        (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// The dense `S_N` product split by rows over 1, 2, 3 and 4 threads (explicit rayon
    /// pools) has the bits of the sequential column-by-column loop (the product before it
    /// was split: `r = dg a`, then `r_k += S_N,ki du_i` over `i` in order), row by row;
    /// rows summed in another order would differ in some rows (checked: the reversed
    /// column order differs).
    #[test]
    fn the_dense_product_has_the_bits_of_the_column_loop_at_every_thread_count() {
        let (rows, m) = (97, 190);
        assert!(rows * m >= MIN_PARALLEL_ENTRIES);
        let s_n = Mat::from_fn(rows, m, |i, j| scrambled(i * m + j, 1) * 1e9);
        let u: Vec<f64> = (0..m).map(|i| scrambled(i, 2) * 1e-3).collect();
        let u0: Vec<f64> = (0..m).map(|i| scrambled(i, 3) * 1e-4).collect();
        let start: Vec<f64> = (0..rows).map(|k| scrambled(k, 4) * 1e5).collect();
        let mut column_loop = start.clone();
        for (i, (u, u0)) in u.iter().zip(&u0).enumerate() {
            let du = u - u0;
            for (s, c) in column_loop.iter_mut().zip(s_n.col(i).iter()) {
                *s += c * du;
            }
        }
        let mut reversed = start.clone();
        for i in (0..m).rev() {
            let du = u[i] - u0[i];
            for (k, s) in reversed.iter_mut().enumerate() {
                *s += s_n[(k, i)] * du;
            }
        }
        assert!(
            reversed
                .iter()
                .zip(&column_loop)
                .any(|(a, b)| a.to_bits() != b.to_bits()),
            "the order of the sum shows in the bits"
        );
        for threads in [1, 2, 3, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let r = pool.install(|| {
                let mut r = start.clone();
                add_dense_product(&s_n, &u, &u0, &mut r, Parallelism::rayon(threads));
                r
            });
            for (k, (a, b)) in r.iter().zip(&column_loop).enumerate() {
                assert_eq!(a.to_bits(), b.to_bits(), "{threads} threads, row {k}");
            }
        }
        // An empty u⁰ is zero.
        let mut r = start.clone();
        add_dense_product(&s_n, &u, &[], &mut r, Parallelism::SEQ);
        let mut expected = start;
        for (i, u) in u.iter().enumerate() {
            for (s, c) in expected.iter_mut().zip(s_n.col(i).iter()) {
                *s += c * u;
            }
        }
        assert_eq!(r, expected);
    }

    /// CPU seconds of the calling thread from /proc (Linux; 0 elsewhere), at the kernel's
    /// 100 Hz tick.
    fn thread_cpu_seconds() -> f64 {
        std::fs::read_to_string("/proc/thread-self/stat")
            .ok()
            .and_then(|s| {
                // utime and stime: the 12th and 13th fields after the command name.
                let rest = &s[s.rfind(')')? + 2..];
                let f: Vec<&str> = rest.split(' ').collect();
                let t = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
                Some(t / 100.0)
            })
            .unwrap_or(0.0)
    }

    /// Measurement (docs/three-d.md, "The normal-stress operator S_N"): the CPU per
    /// evaluation and the memory of a 3-D dipping fault's `S_N`, dense and compressed. A
    /// fault dipping 45° (`x = z`, `|y| ≤ 0.5`, from the free surface `z = 0` to depth
    /// 0.5) in a box graded from the fault's spacing `h` (`RSF_SN_CELLS` cells per unit
    /// length, default 32) at ratio 1.5 to 2 on every side, the faces `x = ±2` pushed
    /// together; laws at σ̄_n⁰ = 5 MPa; ε = 1e-6 with the default leaf size.
    ///
    /// `cargo test --release -p rsf --lib -- --ignored --nocapture
    /// normal_stress::tests::measure_s_n_dense_and_compressed`
    #[test]
    #[ignore = "a measurement: minutes and GB"]
    fn measure_s_n_dense_and_compressed() {
        use crate::model::{Material, ModelBuilder, Part};
        use rsf_fem::{cuboid_from_coordinates, geometric_grading};
        use rsf_friction::{AsinhLaw, RateStateParams};
        let cells: f64 = std::env::var("RSF_SN_CELLS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(32.0);
        let (h, depth, far, ratio) = (1.0 / cells, 0.5, 2.0, 1.5);
        let margin = 4.0 * h;
        let neg = |c: Vec<f64>| -> Vec<f64> { c.iter().rev().map(|x| -x).collect() };
        let mut xs = neg(geometric_grading(h, depth + margin, ratio, far).unwrap());
        xs.extend_from_slice(&geometric_grading(h, margin, ratio, far).unwrap()[1..]);
        let mut ys = neg(geometric_grading(h, 0.5 + margin, ratio, far).unwrap());
        ys.extend_from_slice(&geometric_grading(h, 0.5 + margin, ratio, far).unwrap()[1..]);
        let zs = neg(geometric_grading(h, depth + margin, ratio, far).unwrap());
        let clock = Instant::now();
        let mesh = cuboid_from_coordinates(&xs, &ys, &zs).unwrap();
        let v = 1e-4;
        let model = ModelBuilder::new(mesh)
            .material(Material::new(1e10, 0.25, 2700.0))
            .without_mass()
            .dirichlet(
                Part::predicate("left", move |x| x[0] < -far + 1e-9),
                [v, 0.0, 0.0],
            )
            .dirichlet(
                Part::predicate("right", move |x| x[0] > far - 1e-9),
                [-v, 0.0, 0.0],
            )
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, -0.5, 0.0],
                    [-depth, -0.5, -depth],
                    [-depth, 0.5, -depth],
                    [0.0, 0.5, 0.0],
                ],
            )
            .build()
            .unwrap();
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let mut velocity_factor = vec![0.0; n];
        for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
            velocity_factor[dof] = f;
        }
        let mut cond =
            Condensation::<3>::new(model.stiffness.as_ref(), &model.fixed, &fb.nodes).unwrap();
        let m = cond.dim();
        let law = AsinhLaw::new(RateStateParams {
            mu0: 0.1,
            a: 0.015,
            b: 0.01,
            v0: 1e-6,
            l: 1e-4,
            sigma_n: 5e6,
        })
        .unwrap();
        let laws = vec![law; fb.len()];
        let s_n_clock = Instant::now();
        let mut coupling = NormalCoupling::new(
            NormalStress::FromSlip,
            &model,
            &mut cond,
            &laws,
            &velocity_factor,
            0.0,
        )
        .unwrap()
        .unwrap();
        let s_n_seconds = s_n_clock.elapsed().as_secs_f64();
        eprintln!(
            "h = 1/{cells}: {} vertices, {n} dofs, {} frictional nodes, m = {m}, factor \
             {:.3e} entries; model and condensation and S_N in {:.1} s (S_N's columns {:.1} s)",
            model.vertices.len(),
            fb.len(),
            cond.factor_nnz() as f64,
            clock.elapsed().as_secs_f64(),
            s_n_seconds
        );
        // Slips of up to 1 μm: σ̄_n changes by kPa, far from opening.
        let u: Vec<f64> = coupling
            .u_f0
            .iter()
            .enumerate()
            .map(|(i, u0)| u0 + 1e-6 * scrambled(i, 7))
            .collect();
        let mut sigma = vec![0.0; fb.len()];
        // Evaluations for about `seconds` of CPU; CPU and wall seconds per evaluation.
        let time = |c: &mut NormalCoupling, sigma: &mut [f64], par: Parallelism| {
            c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
            let probe = Instant::now();
            c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
            let reps = (2.0 / probe.elapsed().as_secs_f64().max(1e-7)).clamp(3.0, 1e6) as usize;
            let (cpu, wall) = (thread_cpu_seconds(), Instant::now());
            for _ in 0..reps {
                c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
            }
            (
                (thread_cpu_seconds() - cpu) / reps as f64,
                wall.elapsed().as_secs_f64() / reps as f64,
            )
        };
        let (dense_cpu, dense_wall) = time(&mut coupling, &mut sigma, Parallelism::SEQ);
        let dense_sigma = sigma.clone();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (_, dense_wall_2) =
            pool.install(|| time(&mut coupling, &mut sigma, Parallelism::rayon(2)));
        assert_eq!(sigma, dense_sigma, "the same bits on 2 threads");
        let dense_bytes = 8 * fb.len() * m;
        eprintln!(
            "dense S_N: {} × {m} = {} f64 ({:.1} MB); per evaluation {:.3} ms CPU, {:.3} ms \
             wall (1 thread), {:.3} ms wall (2 threads)",
            fb.len(),
            fb.len() * m,
            dense_bytes as f64 / 1e6,
            dense_cpu * 1e3,
            dense_wall * 1e3,
            dense_wall_2 * 1e3
        );
        let report = coupling
            .compress(&model, &cond, FaultKernel::hierarchical(1e-6))
            .unwrap()
            .expect("compressed");
        let (h_cpu, h_wall) = time(&mut coupling, &mut sigma, Parallelism::SEQ);
        let (_, h_wall_2) = pool.install(|| time(&mut coupling, &mut sigma, Parallelism::rayon(2)));
        let change: f64 = dense_sigma
            .iter()
            .map(|s| (s - 5e6).powi(2))
            .sum::<f64>()
            .sqrt();
        let diff: f64 = dense_sigma
            .iter()
            .zip(&sigma)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            .sqrt();
        eprintln!(
            "compressed S_N: {report}\n  {} f64 ({:.1} MB, {:.2}× fewer than the dense S_N); \
             per evaluation {:.3} ms CPU, {:.3} ms wall (1 thread), {:.3} ms wall (2 threads); \
             ‖Δσ_H − Δσ‖/‖Δσ‖ = {:.2e} at a random slip",
            report.stored_entries,
            report.bytes() as f64 / 1e6,
            (fb.len() * m) as f64 / report.stored_entries as f64,
            h_cpu * 1e3,
            h_wall * 1e3,
            h_wall_2 * 1e3,
            diff / change
        );
    }
}
