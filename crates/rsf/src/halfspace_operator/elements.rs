//! A boundary-element fault operator on any set of elements
//! ([`rsf_halfspace::ElementSet`]: rectangles of any strike, dip and position, or
//! triangles; several faults; a half-space or the whole space) behind [`FaultOperator`]:
//! for a fault alone (one frictional node per element, in element order) or on the
//! frictional nodes of a finite-element model's internal fault, each node matched to the
//! element centred on it (docs/halfspace.md §8).

use std::collections::HashMap;
use std::time::Instant;

use faer::Mat;
use rsf_halfspace::{Element, ElementSet};
use rsf_hmatrix::HOptions;
use rsf_linalg::Parallelism;

use super::error::HalfSpaceOperatorError;
use super::nodes::{
    alone_nodes, check_kernel, dense_of, gather, internal_fault_nodes, scatter, Node,
};
use crate::error::Result;
use crate::fault_kernel::Kernel;
use crate::fault_operator::{FaultKernel, FaultOperator, KernelReport};
use crate::model::{FrictionalBoundary, Model};

/// Relative tolerance (times an element's size, `√area`) of "at the element's centre";
/// a node's normal must be within `1e-6` rad of its element's (either sign).
pub const CENTRE_TOLERANCE: f64 = 1e-6;

/// How an [`ElementOperator`] stores its stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementOptions {
    /// Above this many element unknowns (`2 ×` elements) the stiffness is an ℋ-matrix of
    /// accuracy [`epsilon`](Self::epsilon), at or below it dense. Default 4 096 (128 MB
    /// dense).
    pub dense_max: usize,
    /// Relative accuracy ε of the ℋ-matrix, in `(0, `[`MAX_KERNEL_EPSILON`](crate::fault_operator::MAX_KERNEL_EPSILON)`]` (default
    /// 1e-6).
    pub epsilon: f64,
    /// Largest leaf cluster of the ℋ-matrix (default rsf-hmatrix's, 48).
    pub leaf_size: usize,
}

impl Default for ElementOptions {
    fn default() -> Self {
        Self {
            dense_max: 4096,
            epsilon: 1e-6,
            leaf_size: HOptions::default().leaf_size,
        }
    }
}

/// The fault alone of `set` ([`Model::fault_only`]): one vertex per element at its
/// centre, of weight its area, element order, the `z` component fixed. With
/// [`ElementOperator::fault_alone`] each vertex's two free components are its element's
/// strike and dip slip (whatever the element's orientation); the load (the prestress
/// times the area) is given in the same components.
///
/// # Errors
/// Those of [`Model::fault_only`].
pub fn fault_alone_model<E: Element>(set: &ElementSet<E>) -> Result<Model<3, 3>> {
    let areas: Vec<f64> = set.elements().iter().map(Element::area).collect();
    Model::fault_only(set.centres().to_vec(), &areas, 2)
}

/// The boundary-element operator `S = Pᵀ W K P` of an [`ElementSet`] on a model's
/// frictional nodes — a [`FaultOperator`] for the fault ODE
/// ([`SimulationBuilder::build_fault_ode_alone`](crate::SimulationBuilder::build_fault_ode_alone),
/// [`build_fault_ode_with_operator`](crate::SimulationBuilder::build_fault_ode_with_operator)).
///
/// Node `k` sits at the centre of element `e(k)`; its two slip unknowns `j_k` map to the
/// element's strike and dip slip by `s_e = A_k j_k` (`A_k[c][a] = σ_k e_c · t_a`, `e_c`
/// the element's strike and up-dip directions, `t_a` the node's slip directions, `σ_k =
/// ±1` as the node's plus side is the element's positive side or not), and
///
/// ```text
/// (S)_{k,l} = w_k A_kᵀ K_{e(k), e(l)} A_l
/// ```
///
/// with `K` the set's stiffness (Pa/m, `Δτ = −K s`) and `w_k` the node's weight (m²), so
/// that `S` maps slip (m) to forces (N) as the finite-element `S` does. For a planar
/// fault on a regular grid this is [`HalfSpaceOperator`](super::HalfSpaceOperator)'s
/// operator (checked to round-off), which stays the one BP5 uses (its table of strike
/// offsets, its bits); this one takes any set, several faults at once, in a half-space or
/// the whole space.
///
/// Not supported (yet): rows shared by ranks ([`FaultOperator::split_rows`] refuses).
pub struct ElementOperator {
    kernel: Kernel,
    /// Per node: its element and `A_k` (rows: strike, dip; columns: `t₁`, `t₂`).
    element: Vec<usize>,
    map: Vec<[[f64; 2]; 2]>,
    weights: Vec<f64>,
    s: Vec<f64>,
    y: Vec<f64>,
    report: KernelReport,
    /// A fault alone's unknowns' slip directions: each element's strike, then up dip
    /// (`None` on a model's fault, whose pair frames give them).
    directions: Option<Vec<[f64; 3]>>,
}

impl std::fmt::Debug for ElementOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ElementOperator")
            .field("nodes", &self.element.len())
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The start of a set-up on `model`: `options` checked, the clock started, the nodes (by
/// `nodes`: [`alone_nodes`] or [`internal_fault_nodes`]) and the frictional boundary.
fn start<'m>(
    model: &'m Model<3, 3>,
    options: &ElementOptions,
    nodes: fn(&Model<3, 3>) -> std::result::Result<Vec<Node>, HalfSpaceOperatorError>,
) -> std::result::Result<(Instant, Vec<Node>, &'m FrictionalBoundary), HalfSpaceOperatorError> {
    check_kernel(options.epsilon, options.leaf_size)?;
    let clock = Instant::now();
    Ok((clock, nodes(model)?, &model.frictional_boundary))
}

/// `A_k` of `node` on an element of frame `frame`, or the angle between their normals.
fn component_map(node: &Node, frame: &[[f64; 3]; 3]) -> std::result::Result<[[f64; 2]; 2], f64> {
    let (_, t1, t2, n) = node;
    let [es, ed, ne] = frame;
    let c = dot(n, ne);
    if c.abs() < 1.0 - 0.5e-12 {
        return Err(c.abs().clamp(-1.0, 1.0).acos());
    }
    let sign = c.signum();
    Ok([es, ed].map(|e| [sign * dot(e, t1), sign * dot(e, t2)]))
}

impl ElementOperator {
    /// The operator of a fault alone (`model` from [`fault_alone_model`]: node `k` at
    /// element `k`'s centre; or any [`Model::fault_only`] whose vertices are the centres in
    /// order): node `k`'s two free components are element `k`'s strike and dip slip (its
    /// Cartesian labels are not used), its weight the model's.
    ///
    /// # Errors
    /// [`HalfSpaceOperatorError::NotAlone`], [`HalfSpaceOperatorError::Components`] as
    /// [`HalfSpaceOperator::fault_alone`](super::HalfSpaceOperator::fault_alone);
    /// [`HalfSpaceOperatorError::ElementCount`] for another number of nodes than elements;
    /// [`HalfSpaceOperatorError::NotAtElement`] for a node away from its element's
    /// centre; invalid options; the kernel's errors.
    pub fn fault_alone<E: Element>(
        model: &Model<3, 3>,
        set: &ElementSet<E>,
        options: &ElementOptions,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        let (clock, nodes, fb) = start(model, options, alone_nodes)?;
        if nodes.len() != set.n_elements() {
            return Err(HalfSpaceOperatorError::ElementCount {
                nodes: nodes.len(),
                elements: set.n_elements(),
            });
        }
        for (k, node) in nodes.iter().enumerate() {
            let (c, x) = (set.centres()[k], node.0);
            let offset = (0..3).map(|i| (c[i] - x[i]).powi(2)).sum::<f64>().sqrt();
            if offset > CENTRE_TOLERANCE * set.elements()[k].area().sqrt() {
                return Err(HalfSpaceOperatorError::NotAtElement {
                    node: k,
                    vertex: fb.nodes[k],
                    position: x,
                    offset,
                });
            }
        }
        let element = (0..nodes.len()).collect();
        let map = vec![[[1.0, 0.0], [0.0, 1.0]]; nodes.len()];
        let mut op = Self::build(set, element, map, &fb.weights, options, clock)?;
        op.directions = Some(set.frames().iter().flat_map(|f| [f[0], f[1]]).collect());
        Ok(op)
    }

    /// The operator on the frictional nodes of `model`'s internal fault: every node at
    /// the centre of one element (to [`CENTRE_TOLERANCE`] of its size), every element with
    /// one node, each node's normal along its element's (either side: `σ_k`), the nodes'
    /// slip directions (the pair frames) mapped onto the elements' strike and dip.
    ///
    /// # Errors
    /// As [`HalfSpaceOperator::new`](super::HalfSpaceOperator::new) for the model's
    /// fault; [`HalfSpaceOperatorError::NotAtElement`] for a node at no element's centre
    /// (or at one that has a node already: `offset` 0),
    /// [`HalfSpaceOperatorError::NoNodeAt`] for an element without a node,
    /// [`HalfSpaceOperatorError::NotAligned`] for a node whose normal is not its
    /// element's; invalid options; the kernel's errors.
    pub fn new<E: Element>(
        model: &Model<3, 3>,
        set: &ElementSet<E>,
        options: &ElementOptions,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        use HalfSpaceOperatorError as E;
        let (clock, nodes, fb) = start(model, options, internal_fault_nodes)?;
        let finder = CentreFinder::new(set);
        let mut taken = vec![false; set.n_elements()];
        let mut element = Vec::with_capacity(nodes.len());
        let mut map = Vec::with_capacity(nodes.len());
        for (k, node) in nodes.iter().enumerate() {
            let not_at = |offset: f64| E::NotAtElement {
                node: k,
                vertex: fb.nodes[k],
                position: node.0,
                offset,
            };
            let (e, offset) = finder
                .nearest(node.0)
                .ok_or_else(|| not_at(f64::INFINITY))?;
            if offset > CENTRE_TOLERANCE * set.elements()[e].area().sqrt() {
                return Err(not_at(offset));
            }
            if std::mem::replace(&mut taken[e], true) {
                return Err(not_at(0.0));
            }
            let a = component_map(node, &set.frames()[e]).map_err(|angle| E::NotAligned {
                node: k,
                vertex: fb.nodes[k],
                element: e,
                angle,
            })?;
            element.push(e);
            map.push(a);
        }
        if let Some(e) = taken.iter().position(|t| !t) {
            return Err(E::NoNodeAt {
                element: e,
                centre: set.centres()[e],
            });
        }
        Self::build(set, element, map, &fb.weights, options, clock)
    }

    fn build<E: Element>(
        set: &ElementSet<E>,
        element: Vec<usize>,
        map: Vec<[[f64; 2]; 2]>,
        weights: &[f64],
        options: &ElementOptions,
        clock: Instant,
    ) -> std::result::Result<Self, HalfSpaceOperatorError> {
        let len = set.len();
        let (kernel, report) = if len <= options.dense_max {
            let mut report = KernelReport::dense(len);
            report.setup_seconds = clock.elapsed().as_secs_f64();
            (Kernel::Dense(set.dense()?), report)
        } else {
            let h = set.hmatrix(&HOptions {
                epsilon: options.epsilon,
                leaf_size: options.leaf_size,
                components: 2,
                ..HOptions::default()
            })?;
            let kind = FaultKernel::Hierarchical {
                epsilon: options.epsilon,
                leaf_size: options.leaf_size,
            };
            // Setup bytes 0: each block's own cache of source–receiver pairs, nothing n × n.
            let report = KernelReport::hierarchical(kind, 2 * element.len(), h.report(), 0, clock);
            (Kernel::Hierarchical(Box::new(h)), report)
        };
        let mut report = report;
        report.dim = 2 * element.len();
        report.setup_seconds = clock.elapsed().as_secs_f64();
        Ok(Self {
            kernel,
            element,
            map,
            weights: weights.to_vec(),
            s: vec![0.0; len],
            y: vec![0.0; len],
            report,
            directions: None,
        })
    }

    /// The element of every frictional node, by fault index.
    pub fn elements(&self) -> &[usize] {
        &self.element
    }

    /// `A_k` of every frictional node (rows: strike, up dip; columns: `t₁`, `t₂`).
    pub fn component_maps(&self) -> &[[[f64; 2]; 2]] {
        &self.map
    }

    /// The dense `S` (`m × m`, N/m), one product per column.
    ///
    /// # Errors
    /// Those of the product.
    pub fn dense(&mut self) -> Result<Mat<f64>> {
        dense_of(self)
    }
}

impl FaultOperator for ElementOperator {
    fn dim(&self) -> usize {
        2 * self.element.len()
    }

    fn subtract_product(&mut self, x: &[f64], r: &mut [f64], par: Parallelism) -> Result<()> {
        scatter(&self.element, &self.map, x, &mut self.s);
        self.y.fill(0.0);
        self.kernel.subtract_product(&self.s, &mut self.y, par)?;
        // y = −K s: r_k += w_k A_kᵀ y_e.
        gather(&self.element, &self.map, &self.weights, &self.y, r);
        Ok(())
    }

    fn report(&self) -> &KernelReport {
        &self.report
    }

    fn operator_origin(&self) -> crate::fault_operator::OperatorOrigin {
        crate::fault_operator::OperatorOrigin::BoundaryElements
    }

    fn slip_directions(&self) -> Option<&[[f64; 3]]> {
        self.directions.as_deref()
    }

    /// From the kernel's 2 × 2 element blocks.
    fn diagonal(&mut self, out: &mut [f64]) -> Result<()> {
        super::nodes::diagonal_of(&self.kernel, &self.element, &self.map, &self.weights, out)
    }
}

/// The element whose centre is nearest a point, on a hash grid of cells of the smallest
/// element's size.
struct CentreFinder<'a> {
    centres: &'a [[f64; 3]],
    cell: f64,
    grid: HashMap<[i64; 3], Vec<usize>>,
}

impl<'a> CentreFinder<'a> {
    fn new<E: Element>(set: &'a ElementSet<E>) -> Self {
        let cell = set
            .elements()
            .iter()
            .map(|e| e.area().sqrt())
            .fold(f64::INFINITY, f64::min);
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (e, c) in set.centres().iter().enumerate() {
            grid.entry(Self::key(c, cell)).or_default().push(e);
        }
        Self {
            centres: set.centres(),
            cell,
            grid,
        }
    }

    fn key(x: &[f64; 3], cell: f64) -> [i64; 3] {
        x.map(|v| (v / cell).floor() as i64)
    }

    /// The nearest centre among those in the point's and the neighbouring cells, and its
    /// distance.
    fn nearest(&self, x: [f64; 3]) -> Option<(usize, f64)> {
        let k = Self::key(&x, self.cell);
        let mut best: Option<(usize, f64)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(list) = self.grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) else {
                        continue;
                    };
                    for &e in list {
                        let c = self.centres[e];
                        let d = (0..3).map(|i| (c[i] - x[i]).powi(2)).sum::<f64>().sqrt();
                        if best.is_none_or(|(_, b)| d < b) {
                            best = Some((e, d));
                        }
                    }
                }
            }
        }
        best
    }
}
