//! The frictional boundary Γ_F of a model: its nodes, lumped weights and order along the
//! boundary, and the slip rate of a node's velocity block.

use crate::error::{invalid, Result};

/// The frictional boundary Γ_F of the discrete model. Its entries are indexed by the
/// **fault index** `k` (a position on Γ_F); `nodes[k]` is the **vertex id** of that node
/// in the mesh ([`Model`](crate::Model), "Two index spaces").
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionalBoundary {
    /// Vertex ids of the nodes of Γ_F in increasing order (the solver's block order):
    /// `nodes[k]` is the vertex of fault index `k`.
    pub nodes: Vec<usize>,
    /// Lumped weights `w_p = ∫_Γ_F λ_p ds` (m in 2D), by fault index (same order as `nodes`).
    pub weights: Vec<f64>,
    /// Fault indices (positions into `nodes`) ordered along the boundary (for profiles and
    /// plots).
    pub along: Vec<usize>,
    /// Slip per unit of the model's field on Γ_F, `s` (default 1: a body sliding on a
    /// rigid surface). `2` when Γ_F is a plane of antisymmetry (a fault between two halves
    /// moving oppositely, slip `δ = 2u`): the builder's
    /// [`antisymmetric_fault`](crate::ModelBuilder::antisymmetric_fault) then scales the
    /// model's unknown to `s·u`, so that every block on Γ_F *is* the slip and its norm the
    /// slip rate (docs/seas-bp1.md); divide the model's field by `s` for the displacement
    /// of the half that is modelled.
    pub slip_factor: f64,
    /// The faults Γ_F is made of, by name: the frictional boundary's part, or every fault
    /// inside the body in the order the builder was given them
    /// ([`ModelBuilder::internal_fault`](crate::ModelBuilder::internal_fault), once per
    /// fault). One unnamed fault (`""`) for a boundary built with [`new`](Self::new) alone.
    pub fault_names: Vec<String>,
    /// The fault of every node, by fault index `k` (same order as `nodes`): an index into
    /// [`fault_names`](Self::fault_names).
    pub fault_of: Vec<usize>,
}

impl FrictionalBoundary {
    /// From the segment's nodes (ordered along the boundary) and weights in that order.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for an empty boundary,
    /// mismatched lengths or non-positive weights.
    pub fn new(nodes_along: &[usize], weights_along: &[f64]) -> Result<Self> {
        if nodes_along.is_empty() {
            return Err(invalid("frictional_boundary", "has no nodes"));
        }
        if nodes_along.len() != weights_along.len() {
            return Err(invalid(
                "frictional_boundary",
                "nodes and weights differ in length",
            ));
        }
        if weights_along.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(invalid(
                "frictional_boundary",
                "weights must be finite and positive",
            ));
        }
        let mut order: Vec<usize> = (0..nodes_along.len()).collect();
        order.sort_by_key(|&i| nodes_along[i]);
        if order
            .windows(2)
            .any(|w| nodes_along[w[0]] == nodes_along[w[1]])
        {
            return Err(invalid("frictional_boundary", "repeated node"));
        }
        let nodes = order.iter().map(|&i| nodes_along[i]).collect();
        let weights = order.iter().map(|&i| weights_along[i]).collect();
        let mut along = vec![0; order.len()];
        for (sorted_pos, &i) in order.iter().enumerate() {
            along[i] = sorted_pos;
        }
        let n = nodes_along.len();
        Ok(Self {
            nodes,
            weights,
            along,
            slip_factor: 1.0,
            fault_names: vec![String::new()],
            fault_of: vec![0; n],
        })
    }

    /// The same boundary with its nodes' faults: `names` of the faults, and the fault of
    /// every node in the order the nodes were given to [`new`](Self::new)
    /// (`faults_along[i]` for `nodes_along[i]`, an index into `names`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `frictional_boundary` for a length that differs from the nodes', a fault index out
    /// of range, no name or a name given twice.
    pub fn with_faults(mut self, names: Vec<String>, faults_along: &[usize]) -> Result<Self> {
        if faults_along.len() != self.nodes.len() {
            return Err(invalid(
                "frictional_boundary",
                "one fault per node is needed",
            ));
        }
        if names.is_empty() || faults_along.iter().any(|&f| f >= names.len()) {
            return Err(invalid(
                "frictional_boundary",
                "a node's fault is not one of the names",
            ));
        }
        if names
            .iter()
            .enumerate()
            .any(|(i, n)| names[..i].contains(n))
        {
            return Err(invalid(
                "frictional_boundary",
                "a fault name is given twice",
            ));
        }
        for (i, &f) in faults_along.iter().enumerate() {
            self.fault_of[self.along[i]] = f;
        }
        self.fault_names = names;
        Ok(self)
    }

    /// The index (into [`fault_names`](Self::fault_names)) of the fault named `name`.
    pub fn fault_named(&self, name: &str) -> Option<usize> {
        self.fault_names.iter().position(|n| n == name)
    }

    /// The fault indices `k` of fault `fault`'s nodes in order along it (the
    /// [`along`](Self::along) order restricted to the fault).
    pub fn along_fault(&self, fault: usize) -> Vec<usize> {
        self.along
            .iter()
            .copied()
            .filter(|&k| self.fault_of[k] == fault)
            .collect()
    }

    /// No frictional node: the frictional boundary of a model whose fault inside the body
    /// has every pair's slip prescribed (a kinematic source,
    /// [`ModelBuilder::internal_slip_at`](crate::ModelBuilder::internal_slip_at)). Such a
    /// model is a static problem; a simulation refuses it
    /// ([`Error::NoFrictionalNode`](crate::Error::NoFrictionalNode)).
    pub fn empty() -> Self {
        Self {
            nodes: Vec::new(),
            weights: Vec::new(),
            along: Vec::new(),
            slip_factor: 1.0,
            fault_names: vec![String::new()],
            fault_of: Vec::new(),
        }
    }

    /// The same boundary with slip factor `s` (see [`slip_factor`](Self::slip_factor)).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `slip_factor`
    /// unless `s` is finite and positive.
    pub fn with_slip_factor(mut self, s: f64) -> Result<Self> {
        if !(s.is_finite() && s > 0.0) {
            return Err(invalid(
                "slip_factor",
                format!("{s} must be finite and positive"),
            ));
        }
        self.slip_factor = s;
        Ok(self)
    }

    /// Number of frictional nodes (fault indices are `0..len()`).
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The fault index `k` (position in [`nodes`](Self::nodes)) of mesh vertex `vertex`,
    /// `None` if the vertex is not on Γ_F. `O(log n)`.
    pub fn fault_index(&self, vertex: usize) -> Option<usize> {
        self.nodes.binary_search(&vertex).ok()
    }

    /// Whether there are none: a model of a kinematic source only
    /// ([`empty`](Self::empty)), which no simulation accepts.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// `(Σ_p w_p x_p²)^{1/2}`, the lumped L²(Γ_F) norm (for the relaxation rule, docs/math.md §4).
    pub fn l2_norm(&self, x: &[f64]) -> f64 {
        self.weights
            .iter()
            .zip(x)
            .map(|(w, v)| w * v * v)
            .sum::<f64>()
            .sqrt()
    }
}

/// Euclidean norm of a block; squares directly unless that over- or underflows.
#[inline]
pub(crate) fn norm<const D: usize>(v: &[f64; D]) -> f64 {
    let q: f64 = v.iter().map(|x| x * x).sum();
    if q.is_finite() && q > 1e-280 {
        q.sqrt()
    } else {
        v.iter().fold(0.0f64, |acc, &x| acc.hypot(x))
    }
}

/// `|v_p|`, the Euclidean norm of node `p`'s block of the node-major vector `v` (as the
/// library computes a slip rate: squares directly unless that over- or underflows).
///
/// # Panics
/// If `v` has no block `p`.
#[inline]
pub fn block_norm<const D: usize>(v: &[f64], p: usize) -> f64 {
    let mut x = [0.0; D];
    x.copy_from_slice(&v[D * p..D * p + D]);
    norm(&x)
}
