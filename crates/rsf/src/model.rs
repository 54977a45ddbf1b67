//! The assembled, discretised mechanical model a simulation runs on.

use rsf_fem::SparseMatrix;

use crate::error::{invalid, Result};

/// Time-dependent Dirichlet velocity `v_i(t) = factor_i · V_D(t)` on the listed dofs, with
/// the paper's ramp `V_D(t) = v_max · min(t / t_ramp, 1)` (docs/math.md §6).
#[derive(Debug, Clone, PartialEq)]
pub struct DirichletVelocity {
    /// Dofs with a prescribed velocity (a subset of the fixed dofs).
    pub dofs: Vec<usize>,
    /// Factor per dof (direction component of the prescribed velocity).
    pub factors: Vec<f64>,
    /// Final velocity `v_max` (m/s).
    pub v_max: f64,
    /// Ramp duration (s); 0 means a step to `v_max` at t = 0.
    pub t_ramp: f64,
}

impl DirichletVelocity {
    /// `V_D(t)` (m/s).
    pub fn speed(&self, t: f64) -> f64 {
        if self.t_ramp > 0.0 && t < self.t_ramp {
            self.v_max * (t / self.t_ramp)
        } else {
            self.v_max
        }
    }
}

/// The frictional boundary Γ_F of the discrete model.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionalBoundary {
    /// Mesh nodes of Γ_F in increasing index order (the solver's block order).
    pub nodes: Vec<usize>,
    /// Lumped weights `w_p = ∫_Γ_F λ_p ds` (m in 2D), same order as `nodes`.
    pub weights: Vec<f64>,
    /// Positions into `nodes` ordered along the boundary (for profiles and plots).
    pub along: Vec<usize>,
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
        Ok(Self {
            nodes,
            weights,
            along,
        })
    }

    /// Number of frictional nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether there are none (never true for a validated boundary).
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

/// An assembled model: matrices, loads, constraints, hierarchy and frictional boundary,
/// independent of the friction law, state law, time integrator and solver.
///
/// Vectors are node-major with `D` components per node (`n = D · nodes`).
#[derive(Debug, Clone)]
pub struct Model<const D: usize> {
    /// Node coordinates (m) of the finest mesh (or of the lumped points).
    pub vertices: Vec<[f64; D]>,
    /// Mass matrix `M` (kg per unit thickness in 2D); `None` for quasistatic scenes.
    pub mass: Option<SparseMatrix>,
    /// Stiffness matrix `K` (N/m per unit thickness in 2D).
    pub stiffness: SparseMatrix,
    /// Matrix of the energy norm used in all stopping tests: `K + M` (docs/math.md §3), or `K`
    /// without mass.
    pub energy_norm: SparseMatrix,
    /// Load vector `F` (body force + Neumann tractions), constant in time (N).
    pub load: Vec<f64>,
    /// Constrained dofs (Dirichlet on Γ_D, normal component on Γ_F).
    pub fixed: Vec<bool>,
    /// Prescribed velocities on the Dirichlet dofs; other fixed dofs have velocity 0.
    pub dirichlet: DirichletVelocity,
    /// Node-major prolongations of the refinement hierarchy, coarse to fine (may be empty).
    pub prolongations: Vec<SparseMatrix>,
    /// The frictional boundary.
    pub frictional: FrictionalBoundary,
    /// Initial displacement `u_0` (m).
    pub initial_displacement: Vec<f64>,
    /// Mesh cells as vertex indices with stride `D + 1` (for output such as VTU frames);
    /// empty for models without a mesh (e.g. a spring–block).
    pub cells: Vec<usize>,
}

impl<const D: usize> Model<D> {
    /// Number of dofs.
    pub fn num_dofs(&self) -> usize {
        self.load.len()
    }

    /// Checks the shapes of all parts against each other.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming the mismatch.
    pub fn validate(&self) -> Result<()> {
        let n = D * self.vertices.len();
        let sq = |name: &str, m: &SparseMatrix| {
            if m.nrows() != n || m.ncols() != n {
                Err(invalid(
                    name,
                    format!("is {}x{}, expected {n}x{n}", m.nrows(), m.ncols()),
                ))
            } else {
                Ok(())
            }
        };
        sq("stiffness", &self.stiffness)?;
        sq("energy_norm", &self.energy_norm)?;
        if let Some(m) = &self.mass {
            sq("mass", m)?;
        }
        for (name, len) in [
            ("load", self.load.len()),
            ("fixed", self.fixed.len()),
            ("initial_displacement", self.initial_displacement.len()),
        ] {
            if len != n {
                return Err(invalid(name, format!("has length {len}, expected {n}")));
            }
        }
        if self.dirichlet.dofs.len() != self.dirichlet.factors.len()
            || self
                .dirichlet
                .dofs
                .iter()
                .any(|&d| d >= n || !self.fixed[d])
        {
            return Err(invalid(
                "dirichlet",
                "dofs must be fixed dofs with one factor each",
            ));
        }
        if !(self.dirichlet.v_max.is_finite()
            && self.dirichlet.t_ramp >= 0.0
            && self.dirichlet.t_ramp.is_finite())
        {
            return Err(invalid(
                "dirichlet",
                "v_max and t_ramp must be finite, t_ramp >= 0",
            ));
        }
        if self
            .frictional
            .nodes
            .iter()
            .any(|&p| p >= self.vertices.len())
        {
            return Err(invalid("frictional_boundary", "node index out of range"));
        }
        if self.cells.len() % (D + 1) != 0 || self.cells.iter().any(|&c| c >= self.vertices.len()) {
            return Err(invalid(
                "cells",
                "need stride D + 1 and vertex indices in range",
            ));
        }
        if let Some(p) = self.prolongations.last() {
            if p.nrows() != n {
                return Err(invalid(
                    "prolongations",
                    "finest prolongation does not match the dofs",
                ));
            }
        }
        Ok(())
    }
}
