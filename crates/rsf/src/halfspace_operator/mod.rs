//! A boundary-element fault operator behind [`FaultOperator`]: Okada's half-space
//! stiffness of a planar rectangular fault ([`rsf_halfspace::RectangularFault`]) on the
//! slip unknowns of a 3-D finite-element model's internal fault, so that the same fault
//! problem runs with either kernel (docs/math.md §12, "The fault operator";
//! docs/three-d.md, "Finite elements against boundary elements (issue 55)").
//!
//! Feature `halfspace`.

use std::time::Instant;

use faer::Mat;
use rsf_halfspace::{Medium, Rectangle, RectangularFault};
use rsf_hmatrix::{HOptions, RowPart};
use rsf_linalg::Parallelism;

use crate::error::Result;
use crate::fault_kernel::Kernel;
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport, RowSplit};
use crate::model::Model;
use nodes::{alone_nodes, internal_fault_nodes, Node};
use rsf_ranks::RankGroup;

mod bttb;
mod elements;
mod error;
mod grid;
mod grid_fft;
mod nodes;
mod parts;

pub use elements::{fault_alone_model, ElementOperator, ElementOptions, CENTRE_TOLERANCE};
pub use error::HalfSpaceOperatorError;
pub use grid_fft::{WholeSpaceGrid, MAX_GRID_CELLS};

/// Relative tolerance (times the grid's spacing) of "at an element centre" and "in the
/// fault's plane".
pub const GRID_TOLERANCE: f64 = 1e-6;

/// How a [`HalfSpaceOperator`] places the half-space and stores its stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfSpaceOptions {
    /// The free surface `z = surface` of the half-space in the model's coordinates (m),
    /// the model's `z` axis pointing up (Okada's `z`): the fault must lie below it. For a
    /// buried fault in a box whose every face is held (a full space truncated), put it far
    /// above the fault: the surface's effect on the stiffness decays as `(a/d)³` (`a` the
    /// fault's size, `d` its depth).
    pub surface: f64,
    /// The elastic medium (the model's λ, μ).
    pub medium: Medium,
    /// Above this many unknowns (`2 ×` elements) the stiffness is an ℋ-matrix of
    /// accuracy [`epsilon`](Self::epsilon) ([`RectangularFault::hmatrix`]), at or below
    /// it dense ([`RectangularFault::dense`]). Default 4 096 (128 MB dense).
    pub dense_max: usize,
    /// Relative accuracy ε of the ℋ-matrix, in `(0, `[`MAX_KERNEL_EPSILON`](crate::fault_operator::MAX_KERNEL_EPSILON)`]`
    /// (default 1e-6).
    pub epsilon: f64,
    /// Largest leaf cluster of the ℋ-matrix (default rsf-hmatrix's, 48).
    pub leaf_size: usize,
}

impl HalfSpaceOptions {
    /// A dense operator up to 4 096 unknowns, an ℋ-matrix at ε = 1e-6 beyond.
    pub fn new(surface: f64, medium: Medium) -> Self {
        Self {
            surface,
            medium,
            dense_max: 4096,
            epsilon: 1e-6,
            leaf_size: HOptions::default().leaf_size,
        }
    }
}

/// The half-space geometry of the fault: Okada's frame in the model's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OkadaFrame {
    /// Model point of Okada's `(0, 0, 0)` (m; on the free surface).
    pub origin: [f64; 3],
    /// Okada's `x` (strike `e_s`), `y` and `z` (up) axes in model coordinates.
    pub axes: [[f64; 3]; 3],
    /// The fault's up-dip unit vector `e_d` in model coordinates.
    pub up_dip: [f64; 3],
    /// Okada's fault normal `n = e_s × e_d` (into the hanging wall) in model coordinates.
    pub normal: [f64; 3],
    /// The dip δ (degrees, in `[0, 90]`).
    pub dip_deg: f64,
    /// `+1` if the model's plus side (where the polygon's right-hand normal points) is
    /// Okada's hanging wall, else `−1`: the model's jump `u⁺ − u⁻` is `sign ×` Okada's
    /// dislocation `U`.
    pub plus_is_hanging_wall: f64,
}

impl OkadaFrame {
    /// Okada coordinates (m) of the model point `x`.
    pub fn to_okada(&self, x: [f64; 3]) -> [f64; 3] {
        let d = [0, 1, 2].map(|i| x[i] - self.origin[i]);
        self.axes.map(|a| dot(&a, &d))
    }

    /// Model components of a vector `v` given in Okada's frame.
    pub fn to_model(&self, v: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|a| self.axes[a][i] * v[a]).sum())
    }
}

/// The checks of [`HalfSpaceOptions`].
fn check_options(options: &HalfSpaceOptions) -> std::result::Result<(), HalfSpaceOperatorError> {
    use HalfSpaceOperatorError as E;
    nodes::check_kernel(options.epsilon, options.leaf_size)?;
    if !options.surface.is_finite() {
        return Err(E::Options {
            name: "surface",
            value: options.surface,
            expected: "finite",
        });
    }
    Ok(())
}

fn kernel_error(e: rsf_halfspace::Error) -> crate::Error {
    crate::error::invalid("half_space", e.to_string())
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(&a, &a).sqrt();
    a.map(|x| x / l)
}

/// The boundary-element operator `S_bem` of a planar rectangular fault in a half-space on
/// the slip unknowns of a 3-D finite-element model's internal fault — a
/// [`FaultOperator`], for
/// [`SimulationBuilder::build_fault_ode_with_operator`](crate::SimulationBuilder::build_fault_ode_with_operator).
///
/// **Geometry.** The frictional nodes (the split pairs' minus vertices; the rim's tips
/// do not slip) must lie in one plane on a regular grid of spacings `h_s × h_d` along
/// strike and dip — e.g. a buried polygon of
/// [`ModelBuilder::internal_fault_polygon`](crate::ModelBuilder::internal_fault_polygon)
/// on a mesh of uniform spacing `h` on the fault, whose `(n − 1) × (n − 1)` interior
/// nodes are the centres of `h × h` cells offset by `h/2` from the rim. Each node is the
/// centre of one constant-slip element of a [`RectangularFault`]; every element has one
/// node (checked by coordinates to [`GRID_TOLERANCE`] `× h`).
///
/// **Unknowns and scaling.** With `j_k = (j₁, j₂)` node `k`'s slip in its pair frame
/// (`t₁`, `t₂`: the model's unknowns, `Model::internal_fault`'s `transform.frames`) and
/// `s_e = (U₁, U₂)` Okada's strike and up-dip slip of its element `e`,
/// `s_e = σ A_k j_k`, `A_k[c][a] = e_c · t_a` (`e_c` strike, up dip; `σ = ±1`
/// [`OkadaFrame::plus_is_hanging_wall`]), and
///
/// ```text
/// S_bem = Pᵀ W K P,     (S_bem)_{k,l} = w_k A_kᵀ K_{e(k), e(l)} A_l
/// ```
///
/// (`K` the half-space stiffness, Pa/m, `Δτ = −K s`; `W` the nodes' weights
/// `model.frictional_boundary.weights`, m², `= h_s h_d` on the regular grid), so that
/// `S_bem` maps slip (m) to forces (N) like the condensed finite-element `S`. `σ` cancels
/// (`σ² = 1`): both the slip and the traction change sign with the side.
///
/// **Not supported** (typed errors, [`HalfSpaceOperatorError`]): non-planar faults, nodes
/// off a regular grid or not filling a rectangle, a fault on the model's boundary, and a
/// fault breaking the free surface — its split nodes on the surface would be centres of
/// half cells that [`RectangularFault`] (square cells centred on the nodes) cannot
/// represent.
pub struct HalfSpaceOperator {
    kernel: Kernel,
    /// Per frictional node: its element and `σ A_k` (row c = strike, dip).
    element: Vec<usize>,
    map: Vec<[[f64; 2]; 2]>,
    weights: Vec<f64>,
    frame: OkadaFrame,
    fault: RectangularFault,
    s: Vec<f64>,
    y: Vec<f64>,
    report: KernelReport,
    /// The split of [`FaultOperator::split_rows`], if any.
    rows: Option<parts::ElementRows>,
    /// The ranks that hold the rows, one part each, if the kernel holds only this rank's
    /// ([`fault_alone_on_ranks`](Self::fault_alone_on_ranks)).
    on_ranks: Option<parts::OnRanks>,
}

impl std::fmt::Debug for HalfSpaceOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HalfSpaceOperator")
            .field("n_strike", &self.fault.n_strike())
            .field("n_dip", &self.fault.n_dip())
            .field("frame", &self.frame)
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

impl HalfSpaceOperator {
    /// The operator of `model`'s internal fault in the half-space of `options`.
    ///
    /// # Errors
    /// [`HalfSpaceOperatorError`]: no internal fault, a frictional node not a pair or
    /// without exactly its two tangential components free, a non-planar fault, nodes
    /// off a regular grid or not filling a rectangle, a cell above the free surface
    /// (surface-breaking faults), invalid options, and the kernels' errors.
    pub fn new(
        model: &Model<3, 3>,
        options: &HalfSpaceOptions,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        check_options(options)?;
        let clock = Instant::now();
        let nodes = internal_fault_nodes(model)?;
        let fb = &model.frictional_boundary;
        Self::from_nodes(&nodes, &fb.nodes, &fb.weights, options, clock, None)
    }

    /// The operator of a fault alone ([`Model::fault_only`]: one vertex per cell, no
    /// volume) in the half-space of `options`, for
    /// [`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone):
    /// each frictional node's two free components are its slip along those Cartesian
    /// axes (`t₁`, `t₂` in increasing axis order), its fixed component the normal `n`
    /// (`+` that axis: the plus side is where it points). The cells must be the
    /// centres of a regular grid filling a rectangle below the surface, as for
    /// [`new`](Self::new) — here a fault may reach the free surface (the cells' tops on it).
    ///
    /// # Errors
    /// As [`new`](Self::new) ([`HalfSpaceOperatorError::Components`] for a node without
    /// exactly one fixed component); [`HalfSpaceOperatorError::NotAlone`] for a model
    /// with a stiffness, a fault inside the body or nodal frames.
    pub fn fault_alone(
        model: &Model<3, 3>,
        options: &HalfSpaceOptions,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        Self::fault_alone_part(model, options, None)
    }

    /// [`fault_alone`](Self::fault_alone) shared by `ranks`, each holding only its part of
    /// the rows (docs/scaling.md, "The fault ODE on MPI ranks"): with an ℋ-matrix kernel
    /// (more than [`HalfSpaceOptions::dense_max`] unknowns) every rank builds and keeps
    /// only the blocks of its part's rows ([`rsf_hmatrix::HMatrix::from_entries_part`]:
    /// memory and set-up about `1/ranks` of the whole, the table of distinct pairs
    /// excepted), and the whole product
    /// ([`subtract_product`](FaultOperator::subtract_product)) is each rank's rows and one
    /// all-gather — collective: every rank calls it with the same `x`, as every rank of a
    /// shared fault ODE does. Every row has the bits of [`fault_alone`](Self::fault_alone)'s
    /// product. [`split_rows`](FaultOperator::split_rows) gives the parts the ranks hold
    /// (and refuses another number of parts), so that
    /// [`FaultOde::share_evaluations`](crate::FaultOde::share_evaluations) with the same
    /// ranks uses them. A dense kernel (or one rank) is held whole, as by
    /// [`fault_alone`](Self::fault_alone). The [report](FaultOperator::report) is this
    /// rank's part's ([`KernelReport::part`]).
    ///
    /// # Errors
    /// As [`fault_alone`](Self::fault_alone); [`HalfSpaceOperatorError::Ranks`] if the
    /// rows give fewer parts than ranks.
    pub fn fault_alone_on_ranks(
        model: &Model<3, 3>,
        options: &HalfSpaceOptions,
        ranks: Box<dyn RankGroup + Send>,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        Self::fault_alone_part(model, options, Some(ranks))
    }

    /// [`fault_alone`](Self::fault_alone), whole or on ranks.
    fn fault_alone_part(
        model: &Model<3, 3>,
        options: &HalfSpaceOptions,
        ranks: Option<Box<dyn RankGroup + Send>>,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        check_options(options)?;
        let clock = Instant::now();
        let nodes = alone_nodes(model)?;
        let fb = &model.frictional_boundary;
        let ranks = ranks.filter(|r| r.size() > 1 && 2 * nodes.len() > options.dense_max);
        let row_part = ranks.as_ref().map(|r| RowPart {
            parts: r.size(),
            part: r.rank(),
        });
        let mut op = Self::from_nodes(&nodes, &fb.nodes, &fb.weights, options, clock, row_part)?;
        if let Some(group) = ranks {
            op.share_rows(group)?;
        }
        Ok(op)
    }

    /// The operator on `nodes` (position, `t₁`, `t₂`, normal into the plus side) of the
    /// frictional vertices `vertices` with weights `weights`: Okada's axes from the
    /// normal ([`grid::PlaneAxes`]), the grid the nodes are the centres of
    /// ([`grid::NodeGrid`]), the rectangle and its elements, every node checked at its
    /// element's centre in Okada's frame, and the kernel ([`Self::kernel_of`]).
    fn from_nodes(
        nodes: &[Node],
        vertices: &[usize],
        weights: &[f64],
        options: &HalfSpaceOptions,
        clock: Instant,
        row_part: Option<RowPart>,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        use HalfSpaceOperatorError as E;
        if nodes.len() < 2 {
            return Err(E::TooFewNodes { nodes: nodes.len() });
        }
        let (x0, _, _, n_fe) = nodes[0];
        let axes = grid::PlaneAxes::of_normal(n_fe);
        let grid = grid::NodeGrid::of_nodes(nodes, vertices, &axes)?;
        let (hs, hd, tol) = (grid.hs, grid.hd, grid.tol);
        // The origin: on the surface above node 0 along Okada's z.
        let depth = options.surface - x0[2];
        let origin = [x0[0], x0[1], options.surface];
        grid.check_below(nodes, vertices, options.surface, axes.up_dip[2])?;
        let rect = Rectangle::new(
            depth,
            axes.dip_deg,
            [
                grid.xi0 - 0.5 * hs,
                grid.xi0 + (grid.n_strike as f64 - 0.5) * hs,
            ],
            [
                grid.eta1 - (grid.n_dip as f64 - 0.5) * hd,
                grid.eta1 + 0.5 * hd,
            ],
        )?;
        let bem =
            RectangularFault::from_rectangle(options.medium, rect, grid.n_strike, grid.n_dip)?;
        let frame = OkadaFrame {
            origin,
            axes: [axes.strike, axes.axis_y, [0.0, 0.0, 1.0]],
            up_dip: axes.up_dip,
            normal: axes.normal,
            dip_deg: axes.dip_deg,
            plus_is_hanging_wall: axes.sign,
        };
        // Every node at its element's centre, in Okada's frame.
        for (k, (x, ..)) in nodes.iter().enumerate() {
            let c = bem.centres()[grid.element[k]];
            let o = frame.to_okada(*x);
            let offset = (0..3).map(|i| (c[i] - o[i]).powi(2)).sum::<f64>().sqrt();
            if offset > tol {
                return Err(E::NotAtCentre {
                    node: k,
                    vertex: vertices[k],
                    position: *x,
                    spacing: [hs, hd],
                    offset,
                });
            }
        }
        let sign = axes.sign;
        let map = nodes
            .iter()
            .map(|(_, t1, t2, _)| {
                [axes.strike, axes.up_dip].map(|e| [sign * dot(&e, t1), sign * dot(&e, t2)])
            })
            .collect();
        let len = bem.len();
        let (kernel, report) = Self::kernel_of(&bem, options, row_part, &grid, clock)?;
        Ok(Self {
            kernel,
            element: grid.element,
            map,
            weights: weights.to_vec(),
            frame,
            fault: bem,
            s: vec![0.0; len],
            y: vec![0.0; len],
            report,
            rows: None,
            on_ranks: None,
        })
    }

    /// The kernel of the elements `bem` on `grid` (dense up to
    /// [`HalfSpaceOptions::dense_max`] unknowns, an ℋ-matrix beyond, of this rank's
    /// `row_part` if given) and its report, the set-up timed from `clock`.
    ///
    /// # Errors
    /// The kernel's assembly or compression.
    fn kernel_of(
        bem: &RectangularFault,
        options: &HalfSpaceOptions,
        row_part: Option<RowPart>,
        grid: &grid::NodeGrid,
        clock: Instant,
    ) -> std::result::Result<(Kernel, KernelReport), HalfSpaceOperatorError> {
        let len = bem.len();
        let (kernel, kind, relative_error, error_samples, stored, blocks) =
            if len <= options.dense_max {
                let k = bem.dense()?;
                (
                    Kernel::Dense(k),
                    FaultKernel::Dense,
                    0.0,
                    0,
                    len * len,
                    (1, 0, 0),
                )
            } else {
                let h_options = HOptions {
                    epsilon: options.epsilon,
                    leaf_size: options.leaf_size,
                    ..HOptions::default()
                };
                let h = match row_part {
                    Some(p) => bem.hmatrix_part(&h_options, p)?,
                    None => bem.hmatrix(&h_options)?,
                };
                let r = h.report().clone();
                let samples = match r.error_measure {
                    rsf_hmatrix::ErrorMeasure::Sampled { samples } => samples,
                    _ => 0,
                };
                (
                    Kernel::Hierarchical(Box::new(h)),
                    FaultKernel::Hierarchical {
                        epsilon: options.epsilon,
                        leaf_size: options.leaf_size,
                    },
                    r.relative_error,
                    samples,
                    r.stored_entries,
                    (r.dense_blocks, r.low_rank_blocks, r.max_rank),
                )
            };
        let (n_strike, n_dip) = (grid.n_strike, grid.n_dip);
        let report = KernelReport {
            kernel: kind,
            dim: grid.element.len() * 2,
            relative_error,
            error_samples,
            // The dense K, or the table of distinct source–receiver pairs (48 bytes each)
            // the ℋ-matrix is compressed from, if it has one (at most
            // `rsf_halfspace::TABLE_MAX_PAIRS` pairs).
            setup_bytes: if blocks.1 == 0 && kind == FaultKernel::Dense {
                8 * stored
            } else {
                let pairs = (2 * n_strike - 1).saturating_mul(n_dip.saturating_mul(n_dip));
                if pairs <= rsf_halfspace::TABLE_MAX_PAIRS {
                    48 * pairs
                } else {
                    0
                }
            },
            stored_entries: stored,
            dense_blocks: blocks.0,
            low_rank_blocks: blocks.1,
            max_rank: blocks.2,
            setup_seconds: clock.elapsed().as_secs_f64(),
            part: match &kernel {
                Kernel::Hierarchical(h) => h.held_part(),
                Kernel::Dense(_) => None,
            },
        };
        Ok((kernel, report))
    }

    /// The boundary-element fault (Okada's frame: [`frame`](Self::frame)).
    pub fn fault(&self) -> &RectangularFault {
        &self.fault
    }

    /// Okada's frame in the model's coordinates, the dip and the side convention.
    pub fn frame(&self) -> &OkadaFrame {
        &self.frame
    }

    /// The element (`i_dip · n_strike + i_strike` of [`fault`](Self::fault)) of every
    /// frictional node, by fault index.
    pub fn elements(&self) -> &[usize] {
        &self.element
    }

    /// `σ A_k` of every frictional node (rows: strike, up dip; columns: `t₁`, `t₂`):
    /// Okada's slip of its element is `σ A_k j_k`.
    pub fn component_maps(&self) -> &[[[f64; 2]; 2]] {
        &self.map
    }

    /// Okada's slip `[U₁, U₂]` of every element (element-major, length
    /// `2 n_strike n_dip`, m) from the model's slip unknowns `x` (length
    /// [`dim`](FaultOperator::dim), m).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] named `x` for a length other than `dim`.
    pub fn okada_slip(&self, x: &[f64]) -> Result<Vec<f64>> {
        if x.len() != 2 * self.element.len() {
            return Err(crate::error::invalid(
                "x",
                format!(
                    "has {} entries, the operator {}",
                    x.len(),
                    2 * self.element.len()
                ),
            ));
        }
        let mut s = vec![0.0; self.fault.len()];
        self.scatter(x, &mut s);
        Ok(s)
    }

    fn scatter(&self, x: &[f64], s: &mut [f64]) {
        nodes::scatter(&self.element, &self.map, x, s);
    }

    /// The displacement at `points` (model coordinates, in the half-space, off the
    /// fault; m) per unit slip of every slip unknown (Okada's `DC3D` of each element):
    /// `out[p][c · dim + j]` is component `c` (the model's Cartesian axes) at point `p` of
    /// unit slip (1 m) of unknown `j`, so that the displacement at `p` of a slip `x` is
    /// `Σ_j out[p][c · dim + j] x_j` — the half-space's elastic part; a fault alone
    /// loaded by back slip adds each side's rigid plate motion (docs/seas-bp5.md).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] named `points` for a point above the free
    /// surface or a non-finite one; the kernels' errors (e.g. a point on an element's
    /// edge), named `half_space`.
    pub fn displacement_columns(&self, points: &[[f64; 3]]) -> Result<Vec<Vec<f64>>> {
        let m = self.dim();
        let alpha = self.fault.medium().alpha();
        let mut out = Vec::with_capacity(points.len());
        for (p, x) in points.iter().enumerate() {
            let o = self.frame.to_okada(*x);
            if !(o.iter().all(|c| c.is_finite()) && o[2] <= 0.0) {
                return Err(crate::error::invalid(
                    "points",
                    format!("point {p} at {x:?} is not finite or above the free surface"),
                ));
            }
            let mut row = vec![0.0; 3 * m];
            for (k, (&e, a)) in self.element.iter().zip(&self.map).enumerate() {
                let unit = |d: [f64; 3]| -> Result<[f64; 3]> {
                    let rect = *self.fault.element(e).map_err(kernel_error)?;
                    let u = rsf_halfspace::okada::dc3d(alpha, o, rect, d)
                        .map_err(kernel_error)?
                        .u;
                    Ok(self.frame.to_model(u))
                };
                let (strike, dip) = (unit([1.0, 0.0, 0.0])?, unit([0.0, 1.0, 0.0])?);
                for t in 0..2 {
                    for c in 0..3 {
                        row[c * m + 2 * k + t] = a[0][t] * strike[c] + a[1][t] * dip[c];
                    }
                }
            }
            out.push(row);
        }
        Ok(out)
    }

    /// The dense `S_bem` (`m × m`, N/m, rows and columns the model's slip unknowns).
    ///
    /// # Errors
    /// Those of the product.
    pub fn dense(&mut self) -> Result<Mat<f64>> {
        nodes::dense_of(self)
    }
}

impl FaultOperator for HalfSpaceOperator {
    fn dim(&self) -> usize {
        2 * self.element.len()
    }

    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()> {
        if self.on_ranks.is_some() {
            return self.subtract_product_on_ranks(x, r);
        }
        let mut s = std::mem::take(&mut self.s);
        self.scatter(x, &mut s);
        self.y.fill(0.0);
        let result = self.kernel.subtract_product(&s, &mut self.y, par);
        self.s = s;
        result?;
        // y = −K s: r_k += w_k (σ A_k)ᵀ y_e.
        nodes::gather(&self.element, &self.map, &self.weights, &self.y, r);
        Ok(())
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn operator_origin(&self) -> crate::fault_operator::OperatorOrigin {
        crate::fault_operator::OperatorOrigin::OkadaGrid
    }

    /// From the kernel's 2 × 2 element blocks (on ranks, whose kernel is split: one
    /// product per unknown).
    fn diagonal(&mut self, out: &mut [f64]) -> Result<()> {
        if self.on_ranks.is_some() {
            return crate::fault_operator::diagonal_by_products(self, out);
        }
        nodes::diagonal_of(&self.kernel, &self.element, &self.map, &self.weights, out)
    }

    /// `K`'s rows split by its kernel, by element (docs/scaling.md, "The fault ODE on MPI
    /// ranks"; `parts.rs`).
    fn split_rows(&mut self, parts: usize, work_per_row: f64) -> Result<RowSplit> {
        if let Some(on) = &self.on_ranks {
            return on.split_for(parts);
        }
        self.split_element_rows(parts, work_per_row)
    }

    fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> Result<()> {
        self.element_part_subtract(x, part, r)
    }
}
