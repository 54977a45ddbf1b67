//! The Green's functions of a model's faults as a product: the fault operator `S`
//! ([`FaultOperator`]: slip on every slip unknown of every fault → the force on every
//! one) with what a user of its entries needs — the unknowns' faults, positions, weights
//! and slip directions, the operator's origin (finite-element volume or boundary
//! elements) and accuracy, the units — for inversions and other cycle codes
//! (docs/fault-networks.md, "Green's functions").
//!
//! [`GreensFunctions`] is the description; the operator stays where it lives (a
//! [`FaultOde`](crate::FaultOde)'s, [`FaultOde::greens_functions`](crate::FaultOde::greens_functions)
//! and [`FaultOde::fault_operator_mut`](crate::FaultOde::fault_operator_mut), or one a
//! program built) and is applied matrix-free ([`GreensFunctions::apply`]) or written out
//! by columns ([`GreensFunctions::dense`], `m` products, behind a size limit).
//!
//! Two faults 2 m apart in a 4 m box:
//!
//! ```rust
//! use rsf::fault_ode::FaultOdeOptions;
//! use rsf::fem::{rectangle, Diagonal};
//! use rsf::friction::{AsinhLaw, RateStateParams};
//! use rsf::greens::asymmetry;
//! use rsf::state::Aging;
//! use rsf::time::Quasistatic;
//! use rsf::{Material, ModelBuilder, Part, SimulationBuilder};
//! let mesh = rectangle([-2.0, -2.0], [4.0, 4.0], 33, 33, Diagonal::Forward)?;
//! let model = ModelBuilder::new(mesh)
//!     .material(Material::new(3e10, 0.25, 2700.0))
//!     .without_mass()
//!     .dirichlet(Part::predicate("top", |x| x[1] > 2.0 - 1e-9), [1e-9, 0.0])
//!     .dirichlet(Part::predicate("bottom", |x| x[1] < -2.0 + 1e-9), [-1e-9, 0.0])
//!     .internal_fault("west", [-1.0, -0.5], [-1.0, 0.5])
//!     .internal_fault("east", [1.0, -0.5], [1.0, 0.5])
//!     .build()?;
//! let p = RateStateParams { mu0: 0.6, a: 0.015, b: 0.01, v0: 1e-6, l: 1e-4, sigma_n: 5e6 };
//! let mut ode = SimulationBuilder::new(model)
//!     .friction(AsinhLaw::new(p)?)
//!     .state_law(Aging::new(p.l)?)
//!     .initial_state((p.l / 1e-9f64).ln())
//!     .integrator(Quasistatic::new())
//!     .radiation_damping(5e6)
//!     .time_step(1.0)
//!     .build_fault_ode(FaultOdeOptions::default())?;
//! let greens = ode.greens_functions()?;
//! let m = greens.dim();
//! // 1 mm of slip on the west fault, matrix-free: the traction change on the east one (Pa).
//! let mut x = vec![0.0; m];
//! for j in greens.unknowns_of("west") {
//!     x[j] = 1e-3;
//! }
//! let force = greens.apply(ode.fault_operator_mut(), &x)?;
//! let east: Vec<f64> = greens.unknowns_of("east").iter()
//!     .map(|&i| -force[i] / greens.weights[i])
//!     .collect();
//! assert!(east.iter().any(|t| *t != 0.0));
//! // The dense S (m products), symmetric to its accuracy; into HDF5 with rsf_hdf5::write_greens.
//! let s = greens.dense(ode.fault_operator_mut(), 2_000)?;
//! assert!(asymmetry(&s, m) <= greens.accuracy.tolerance());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::error::{check_len, invalid, Error, Result};
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport, OperatorOrigin};
use crate::model::Model;
use rsf_linalg::Parallelism;

/// The version of this crate (what a file of Green's functions records).
pub const RSF_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Units of `S` in a 3-D model: slip (m) → force (N).
pub const UNITS_S_3D: &str = "N/m";
/// Units of `S` in a 2-D model (forces per unit thickness): slip (m) → force (N/m).
pub const UNITS_S_2D: &str = "N/m^2";

/// How accurate the operator is: the [`KernelReport`] fields that say so, kept as plain
/// numbers (what a file stores and reads back).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GreensAccuracy {
    /// The kernel: dense (exact to round-off) or an ℋ-matrix of relative block accuracy ε.
    pub kernel: FaultKernel,
    /// `‖S − S_H‖_F / ‖S‖_F` measured at set-up (0 for a dense kernel).
    pub relative_error: f64,
    /// 0 if `relative_error` is over every entry, else the entries it was estimated on.
    pub error_samples: usize,
    /// f64 the operator stores.
    pub stored_entries: usize,
    /// Blocks stored dense.
    pub dense_blocks: usize,
    /// Blocks stored low-rank.
    pub low_rank_blocks: usize,
    /// Largest rank of a low-rank block (0 if none).
    pub max_rank: usize,
}

impl From<&KernelReport> for GreensAccuracy {
    fn from(r: &KernelReport) -> Self {
        Self {
            kernel: r.kernel,
            relative_error: r.relative_error,
            error_samples: r.error_samples,
            stored_entries: r.stored_entries,
            dense_blocks: r.dense_blocks,
            low_rank_blocks: r.low_rank_blocks,
            max_rank: r.max_rank,
        }
    }
}

impl GreensAccuracy {
    /// The relative accuracy to which `S` is known: the measured `‖S − S_H‖_F/‖S‖_F` of an
    /// ℋ-matrix (or its ε where larger, for a sampled estimate), `f64::EPSILON` for a
    /// dense kernel (round-off).
    pub fn tolerance(&self) -> f64 {
        match self.kernel {
            FaultKernel::Dense => f64::EPSILON,
            FaultKernel::Hierarchical { epsilon, .. } if self.error_samples > 0 => {
                epsilon.max(self.relative_error)
            }
            FaultKernel::Hierarchical { .. } => self.relative_error.max(f64::EPSILON),
        }
    }
}

/// The Green's functions of a model's faults: the description of the `m` slip unknowns of
/// its fault operator `S` (rows and columns), its origin and accuracy.
///
/// `S` maps slip (m) on the unknowns to the force (N in 3-D, N/m per unit thickness in
/// 2-D) on them: a slip `x` changes the traction on unknown `i` by
/// `Δτ_i = −(S x)_i / weights[i]` (Pa), the sign of the fault ODE's balance
/// `g(t) − S u_F = w τ` (docs/math.md §12). `S` is symmetric positive semi-definite: to
/// round-off for a dense kernel, to the [`accuracy`](Self::accuracy) of an ℋ-matrix. The
/// traction Green's function of unknown `j` on unknown `i` — the traction at `i` from unit
/// slip at `j` — is `−S_ij / weights[i]`.
///
/// Unknown `j` is component `component[j]` of the frictional node `node[j]` (a fault index
/// into `frictional_boundary.nodes`), on fault `fault_names[fault[j]]`: the nodes in the
/// frictional boundary's order, each node's free components in its frame's order (the
/// fault ODE's order). Per unknown `j`, row `j` of `positions` and `directions` (3 numbers
/// each; 2-D models have `z = 0`): the node's position (m) and the unit vector (Cartesian)
/// of the slip the unknown measures — the node's frame axis `component[j]` (for an
/// internal fault the jump across it, plus side minus minus side); the antiplane
/// component of a scalar model is `(0, 0, 1)`. A fault alone (a
/// [`Model::fault_only`]) whose operator defines its own components takes them from the
/// operator ([`FaultOperator::slip_directions`]: the element operator's, each element's
/// strike, then up dip); [`with_directions`](Self::with_directions) replaces them for an
/// operator of one's own that does not say.
#[derive(Debug, Clone, PartialEq)]
pub struct GreensFunctions {
    /// The model's spatial dimension (2 or 3).
    pub dimension: usize,
    /// The faults' names (the model's `frictional_boundary.fault_names`).
    pub fault_names: Vec<String>,
    /// Per unknown: its fault, an index into `fault_names`.
    pub fault: Vec<usize>,
    /// Per unknown: its node's fault index (into the model's `frictional_boundary.nodes`).
    pub node: Vec<usize>,
    /// Per unknown: its component in the node's frame.
    pub component: Vec<usize>,
    /// Per unknown: its node's position (m), `x, y, z`.
    pub positions: Vec<[f64; 3]>,
    /// Per unknown: its node's weight (m² in 3-D, m in 2-D): force = traction × weight.
    pub weights: Vec<f64>,
    /// Per unknown: the unit slip direction it measures (Cartesian).
    pub directions: Vec<[f64; 3]>,
    /// What the operator is the operator of.
    pub origin: OperatorOrigin,
    /// How accurate it is.
    pub accuracy: GreensAccuracy,
}

impl GreensFunctions {
    /// The description of `operator` on `model`'s frictional nodes (their free
    /// components, node by node: the fault ODE's slip unknowns).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `greens` for an operator of another dimension
    /// than the model's slip unknowns, one that holds only some of its rows (a rank's
    /// share) or a model whose components are neither its dimension nor one; named
    /// `directions` for an operator's [`FaultOperator::slip_directions`] that are not one
    /// unit vector per unknown.
    pub fn new<const D: usize, const C: usize>(
        model: &Model<D, C>,
        operator: &dyn FaultOperator,
    ) -> Result<Self> {
        if C != D && C != 1 {
            return Err(invalid(
                "greens",
                format!("{C} components per node in {D} dimensions"),
            ));
        }
        let report = operator.report();
        if let Some((p, n)) = report.part {
            return Err(invalid(
                "greens",
                format!("the operator holds only part {p} of {n} of its rows (one rank's)"),
            ));
        }
        let fb = &model.frictional_boundary;
        let mut g = Self {
            dimension: D,
            fault_names: fb.fault_names.clone(),
            fault: Vec::new(),
            node: Vec::new(),
            component: Vec::new(),
            positions: Vec::new(),
            weights: Vec::new(),
            directions: Vec::new(),
            origin: operator.operator_origin(),
            accuracy: GreensAccuracy::from(report),
        };
        for (k, &p) in fb.nodes.iter().enumerate() {
            for c in (0..C).filter(|&c| !model.fixed[C * p + c]) {
                g.fault.push(fb.fault_of[k]);
                g.node.push(k);
                g.component.push(c);
                g.positions.push(pad(&model.vertices[p]));
                g.weights.push(fb.weights[k]);
                g.directions.push(if C == 1 {
                    [0.0, 0.0, 1.0]
                } else {
                    let mut e = [0.0; C];
                    e[c] = 1.0;
                    pad(&model.to_global(p, e))
                });
            }
        }
        check_len("greens", operator.dim(), g.dim(), |len, expected| {
            format!("an operator of {len} unknowns for a model of {expected} slip unknowns")
        })?;
        match operator.slip_directions() {
            Some(directions) => g.with_directions(directions.to_vec()),
            None => Ok(g),
        }
    }

    /// The same with the slip directions given (one unit vector per unknown, Cartesian):
    /// a fault alone's operator components.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `directions` for another number than
    /// [`dim`](Self::dim) or a vector whose length is not 1 (to 1e-9) or not finite.
    pub fn with_directions(mut self, directions: Vec<[f64; 3]>) -> Result<Self> {
        if directions.len() != self.dim() {
            return Err(invalid(
                "directions",
                format!("{} for {} unknowns", directions.len(), self.dim()),
            ));
        }
        if let Some(j) = directions
            .iter()
            .position(|d| !((d.iter().map(|v| v * v).sum::<f64>() - 1.0).abs() <= 1e-9))
        {
            return Err(invalid(
                "directions",
                format!("unknown {j}'s {:?} is not a unit vector", directions[j]),
            ));
        }
        self.directions = directions;
        Ok(self)
    }

    /// Number `m` of slip unknowns (rows and columns of `S`).
    pub fn dim(&self) -> usize {
        self.weights.len()
    }

    /// The units of `S`: [`UNITS_S_3D`] or [`UNITS_S_2D`].
    pub fn units_s(&self) -> &'static str {
        if self.dimension == 2 {
            UNITS_S_2D
        } else {
            UNITS_S_3D
        }
    }

    /// The units of the weights: `m^2` in 3-D, `m` in 2-D.
    pub fn units_weights(&self) -> &'static str {
        if self.dimension == 2 {
            "m"
        } else {
            "m^2"
        }
    }

    /// The unknowns of the fault `name`, in order (empty for a name the model has not).
    pub fn unknowns_of(&self, name: &str) -> Vec<usize> {
        match self.fault_names.iter().position(|n| n == name) {
            Some(f) => (0..self.dim()).filter(|&j| self.fault[j] == f).collect(),
            None => Vec::new(),
        }
    }

    /// Checks the description: every per-unknown array of length [`dim`](Self::dim),
    /// every fault index a name's, positions and weights finite (weights positive).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `greens`.
    pub fn validate(&self) -> Result<()> {
        let m = self.dim();
        let lengths = [
            self.fault.len(),
            self.node.len(),
            self.component.len(),
            self.positions.len(),
            self.directions.len(),
        ];
        if lengths.iter().any(|&l| l != m) {
            return Err(invalid(
                "greens",
                format!("per-unknown arrays of lengths {lengths:?} for {m} weights"),
            ));
        }
        if self.fault.iter().any(|&f| f >= self.fault_names.len()) {
            return Err(invalid("greens", "a fault index without a name"));
        }
        let finite = self.positions.iter().flatten().all(|v| v.is_finite());
        if !finite || self.weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(invalid(
                "greens",
                "positions must be finite and weights finite and positive",
            ));
        }
        Ok(())
    }

    /// `S x` (length [`dim`](Self::dim); N or N/m) with `operator` (the one this
    /// describes): one product, matrix-free, on rayon's current pool (bit-identical for
    /// every thread count).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `x` for another length or a non-finite entry,
    /// `operator` for an operator of another dimension; the product's errors.
    pub fn apply(&self, operator: &mut dyn FaultOperator, x: &[f64]) -> Result<Vec<f64>> {
        let m = self.dim();
        if operator.dim() != m {
            return Err(invalid(
                "operator",
                format!("{} unknowns, the Green's functions {m}", operator.dim()),
            ));
        }
        if x.len() != m {
            return Err(invalid(
                "x",
                format!("{} entries for {m} unknowns", x.len()),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(invalid("x", format!("entry {i} is {}", x[i])));
        }
        let mut r = vec![0.0; m];
        operator.subtract_product(x, &mut r, Parallelism::default())?;
        r.iter_mut().for_each(|v| *v = -*v);
        Ok(r)
    }

    /// The dense `S` (`m × m`, row-major: entry `i·m + j` is `S_ij`), column `j` as the
    /// product `S e_j`: `m` products with `operator` — `m³` multiply-adds for a dense
    /// kernel, about `k m² log m` for an ℋ-matrix — and `8 m²` bytes. The columns are the
    /// operator's own products, so the matrix has the operator's accuracy (an ℋ-matrix's
    /// `S_H`, symmetric to about its accuracy).
    ///
    /// # Errors
    /// [`Error::GreensTooLarge`] for `m > max_unknowns` (before any product); the errors
    /// of [`apply`](Self::apply).
    pub fn dense(&self, operator: &mut dyn FaultOperator, max_unknowns: usize) -> Result<Vec<f64>> {
        let all: Vec<usize> = (0..self.dim()).collect();
        self.columns(operator, &all, &all, max_unknowns)
    }

    /// The block of `S` from the slip of the fault `source` to the forces on the fault
    /// `receiver` (row-major, `m_r × m_s`: entry `i·m_s + j` is `S` at the `i`-th unknown
    /// of [`unknowns_of`](Self::unknowns_of)`(receiver)` and the `j`-th of `source`'s):
    /// `m_s` products with `operator`, `8 m_r m_s` bytes — the interaction of two faults
    /// of a network (docs/fault-networks.md, "Green's functions"), without the whole
    /// `m × m` matrix. Each column is the operator's product, so the block equals the
    /// corresponding entries of [`dense`](Self::dense) bit for bit.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `receiver` or `source` for a name the model's
    /// faults do not have (the names listed); [`Error::GreensTooLarge`] for `m_s >
    /// max_unknowns` (before any product); the errors of [`apply`](Self::apply).
    pub fn block(
        &self,
        operator: &mut dyn FaultOperator,
        (receiver, source): (&str, &str),
        max_unknowns: usize,
    ) -> Result<Vec<f64>> {
        let unknowns = |which: &str, name: &str| {
            let u = self.unknowns_of(name);
            if u.is_empty() {
                Err(invalid(
                    which,
                    format!(
                        "`{}` is none of the faults {:?}",
                        rsf_numeric::excerpt(name),
                        self.fault_names
                    ),
                ))
            } else {
                Ok(u)
            }
        };
        let rows = unknowns("receiver", receiver)?;
        let cols = unknowns("source", source)?;
        self.columns(operator, &rows, &cols, max_unknowns)
    }

    /// The entries `S[rows, cols]` (row-major), column `j` as the rows of `S e_j`.
    fn columns(
        &self,
        operator: &mut dyn FaultOperator,
        rows: &[usize],
        cols: &[usize],
        max_unknowns: usize,
    ) -> Result<Vec<f64>> {
        let (m, n) = (self.dim(), cols.len());
        if n > max_unknowns {
            return Err(Error::GreensTooLarge {
                unknowns: n,
                limit: max_unknowns,
                bytes: 8.0 * (rows.len() as f64) * (n as f64),
            });
        }
        let mut s = vec![0.0; rows.len() * n];
        let mut e = vec![0.0; m];
        for (jj, &j) in cols.iter().enumerate() {
            e[j] = 1.0;
            let column = self.apply(operator, &e)?;
            e[j] = 0.0;
            for (ii, &i) in rows.iter().enumerate() {
                s[ii * n + jj] = column[i];
            }
        }
        Ok(s)
    }
}

/// `‖S − Sᵀ‖_F / ‖S‖_F` of a row-major `m × m` matrix (0 for a zero matrix).
///
/// # Panics
/// If `s` does not hold `m²` entries.
pub fn asymmetry(s: &[f64], m: usize) -> f64 {
    assert_eq!(s.len(), m * m, "asymmetry: {} entries for m = {m}", s.len());
    let (mut diff, mut norm) = (0.0f64, 0.0f64);
    for i in 0..m {
        for j in 0..m {
            diff += (s[i * m + j] - s[j * m + i]).powi(2);
            norm += s[i * m + j].powi(2);
        }
    }
    if norm == 0.0 {
        0.0
    } else {
        (diff / norm).sqrt()
    }
}

/// A position or vector of `N ≤ 3` components as three (zeros after).
fn pad<const N: usize>(x: &[f64; N]) -> [f64; 3] {
    let mut out = [0.0; 3];
    out[..N.min(3)].copy_from_slice(&x[..N.min(3)]);
    out
}
