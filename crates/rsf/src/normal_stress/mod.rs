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

use crate::error::{check_normal_stress, invalid, Error, Result};
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
    let beside_a_boundary = model
        .internal_fault
        .as_ref()
        .is_some_and(|f| model.frictional_boundary.fault_names.len() > f.faults().len());
    if beside_a_boundary {
        return Err(invalid(
            "normal_stress",
            "NormalStress::FromSlip with a frictional boundary beside the faults inside the \
             body: the boundary fault's normal stress is prescribed; keep the faults alone",
        ));
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
    /// `S_N`'s rows split into one part per rank, if split ([`split_rows`](Self::split_rows)).
    rows: Option<parts::NormalRows>,
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
    let part = |start: usize, r: &mut [f64]| add_dense_rows(s_n, u_f, u_f0, start, r);
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

/// `r ← r + S_N (u_F − u_F⁰)` at rows `start..start + r.len()` of the dense `S_N`, each
/// row's sum over the columns in order: [`add_dense_product`]'s arithmetic for those rows.
fn add_dense_rows(s_n: &Mat<f64>, u_f: &[f64], u_f0: &[f64], start: usize, r: &mut [f64]) {
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
            rows: None,
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
            let (kernel, report) = compress(dense, model, cond.interface_dofs(), kind)?;
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
            part: None,
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
                // Split for ranks: every part in turn, the split kept for the ranks' shares
                // (the same bits as the whole product).
                let product = match &self.rows {
                    Some(rows) => rows.add_every_part(h, &self.du, sigma),
                    None => h.apply_add(&self.du, sigma, 1.0, par.faer()),
                };
                match product {
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
        self.finish(time, sigma)
    }

    /// The reactions `r` in `sigma` made into `σ̄_n,k = σ̄_n⁰,k − r_k/w_k`, checked in node
    /// order.
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] at the first node where `σ̄_n ≤ 0` or not finite.
    pub(crate) fn finish(&self, time: f64, sigma: &mut [f64]) -> Result<()> {
        for (k, s) in sigma.iter_mut().enumerate() {
            let r = *s;
            *s = self.sigma0[k] - r / self.weights[k];
            check_normal_stress(k, time, *s)?;
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
            check_normal_stress(k, time, *s)?;
            weights[k] = self.weights[k] * (*s / self.sigma0[k]);
        }
        Ok(())
    }
}

pub(crate) mod parts;
#[cfg(test)]
mod tests;
