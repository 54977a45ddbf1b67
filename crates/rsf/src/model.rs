//! The assembled, discretised mechanical model a simulation runs on.

use std::sync::Arc;

use rsf_fem::SparseMatrix;

use crate::error::{invalid, Error, Result};

/// A dimensionless loading history `g(t)` that scales the prescribed Dirichlet
/// velocities: `v_i(t) = factor_i · g(t)` (see [`DirichletVelocity`]).
#[derive(Clone)]
pub enum TimeFunction {
    /// `g(t) = c` for all t.
    Constant(f64),
    /// The paper's ramp (docs/math.md §6): `g(t) = min(t / duration, 1)`; `duration = 0`
    /// is a step to 1 at t = 0.
    Ramp {
        /// Ramp duration (s), finite and ≥ 0.
        duration: f64,
    },
    /// Linear interpolation between `(t_k, g_k)` (s, dimensionless), constant before the
    /// first and after the last point. Times strictly increasing, values finite.
    PiecewiseLinear(Vec<(f64, f64)>),
    /// Any function of time (s). It must return finite values; a non-finite value makes
    /// the step fail (the velocity problem gets non-finite data).
    Custom(Arc<dyn Fn(f64) -> f64 + Send + Sync>),
}

impl TimeFunction {
    /// `g(t) = min(t / duration, 1)`.
    pub fn ramp(duration: f64) -> Self {
        TimeFunction::Ramp { duration }
    }

    /// A user function of time (s).
    pub fn custom(f: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        TimeFunction::Custom(Arc::new(f))
    }

    /// `g(t)` (dimensionless).
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(c) => *c,
            TimeFunction::Ramp { duration } => {
                if *duration > 0.0 && t < *duration {
                    t / duration
                } else {
                    1.0
                }
            }
            TimeFunction::PiecewiseLinear(points) => piecewise_linear(points, t),
            TimeFunction::Custom(f) => f(t),
        }
    }

    /// The first time strictly after `t` (s) at which `g` is not smooth, if `g` says so:
    /// the end of a ramp, the points of a piecewise-linear history (none for a constant or
    /// a custom function). Adaptive time steps end there instead of stepping over it
    /// (docs/math.md §9): an error estimate sees only smooth behaviour, and a step across a
    /// kink of the loading makes an error it cannot see.
    pub fn next_breakpoint(&self, t: f64) -> Option<f64> {
        match self {
            TimeFunction::Ramp { duration } => (*duration > t).then_some(*duration),
            TimeFunction::PiecewiseLinear(points) => points.iter().map(|p| p.0).find(|&tk| tk > t),
            TimeFunction::Constant(_) | TimeFunction::Custom(_) => None,
        }
    }

    /// Checks the parameters (finite constant, finite `duration ≥ 0`, strictly increasing
    /// finite times with finite values) and, for a custom function, that `g(0)` is finite.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `loading`.
    pub fn validate(&self) -> Result<()> {
        let ok = match self {
            TimeFunction::Constant(c) => c.is_finite(),
            TimeFunction::Ramp { duration } => duration.is_finite() && *duration >= 0.0,
            TimeFunction::PiecewiseLinear(p) => {
                !p.is_empty()
                    && p.iter().all(|(t, g)| t.is_finite() && g.is_finite())
                    && p.windows(2).all(|w| w[0].0 < w[1].0)
            }
            TimeFunction::Custom(f) => f(0.0).is_finite(),
        };
        if ok {
            Ok(())
        } else {
            Err(invalid(
                "loading",
                format!(
                    "{self:?} is not admissible (finite values; ramp duration ≥ 0; \
                     piecewise-linear times strictly increasing, at least one point)"
                ),
            ))
        }
    }
}

fn piecewise_linear(points: &[(f64, f64)], t: f64) -> f64 {
    let k = points.partition_point(|p| p.0 <= t);
    match (k.checked_sub(1).map(|i| points[i]), points.get(k)) {
        (None, Some(first)) => first.1,
        (Some(last), None) => last.1,
        (Some((t0, g0)), Some((t1, g1))) => g0 + (g1 - g0) * ((t - t0) / (t1 - t0)),
        (None, None) => 0.0,
    }
}

impl std::fmt::Debug for TimeFunction {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TimeFunction::Constant(c) => write!(f, "Constant({c})"),
            TimeFunction::Ramp { duration } => write!(f, "Ramp {{ duration: {duration} }}"),
            TimeFunction::PiecewiseLinear(p) => write!(f, "PiecewiseLinear({p:?})"),
            TimeFunction::Custom(_) => write!(f, "Custom(..)"),
        }
    }
}

impl PartialEq for TimeFunction {
    /// Equal parameters; custom functions are equal only if they are the same `Arc`.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (TimeFunction::Constant(a), TimeFunction::Constant(b)) => a == b,
            (TimeFunction::Ramp { duration: a }, TimeFunction::Ramp { duration: b }) => a == b,
            (TimeFunction::PiecewiseLinear(a), TimeFunction::PiecewiseLinear(b)) => a == b,
            (TimeFunction::Custom(a), TimeFunction::Custom(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Time-dependent Dirichlet velocity `v_i(t) = factor_i · g(t)` on the listed dofs, with a
/// dimensionless loading history `g` (the paper's ramp, docs/math.md §6, or any
/// [`TimeFunction`]). The factors carry the velocity (m/s): a Dirichlet part moving with
/// velocity `w` (a vector) gives factor `w_c` to component `c` of each of its nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct DirichletVelocity {
    /// Dofs with a prescribed non-zero velocity (a subset of the fixed dofs; all other
    /// fixed dofs have velocity 0).
    pub dofs: Vec<usize>,
    /// Velocity per dof at `g = 1` (m/s), same order as `dofs`.
    pub factors: Vec<f64>,
    /// The loading history `g(t)`.
    pub history: TimeFunction,
}

impl DirichletVelocity {
    /// No prescribed velocity: every fixed dof is at rest.
    pub fn none() -> Self {
        Self {
            dofs: Vec::new(),
            factors: Vec::new(),
            history: TimeFunction::Constant(0.0),
        }
    }

    /// The loading history `g(t)` (dimensionless); the velocity of dof `dofs[k]` is
    /// `factors[k] · g(t)`.
    pub fn speed(&self, t: f64) -> f64 {
        self.history.value(t)
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
/// Vectors are node-major with `D` components per node (`n = D · nodes`). Build one with
/// [`ModelBuilder`](crate::ModelBuilder) from a mesh, a material and boundary parts, or
/// fill the public fields yourself (e.g. a lumped spring–block system without a mesh);
/// [`Model::validate`] checks them, and every simulation validates its model.
///
/// ```
/// use rsf::fem::cuboid;
/// use rsf::{Material, ModelBuilder, Part};
///
/// // A 2 m × 1 m × 1 m block (not the paper's problem): its top moves in x at 0.1 mm/s,
/// // its bottom face slides with friction (bilateral contact: z velocity fixed).
/// let model = ModelBuilder::refined(cuboid([0.0; 3], [2.0, 1.0, 1.0], [3, 2, 2])?, 1)?
///     .material(Material::new(1e8, 0.25, 2.7e3))
///     .gravity([0.0, 0.0, -9.81])
///     .dirichlet(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), [1e-4, 0.0, 0.0])
///     .frictional(Part::predicate("bottom", |x| x[2] < 1e-9))
///     .build()?;
/// assert_eq!((model.num_nodes(), model.frictional.len()), (45, 15));
/// assert!(model.frictional.nodes.iter().all(|&p| model.fixed[3 * p + 2]));
/// // u0 is the gravity equilibrium: the middle layer sags, fixed dofs stay at 0.
/// let u0 = &model.initial_displacement;
/// assert!((0..45).all(|p| model.vertices[p][2] != 0.5 || u0[3 * p + 2] < 0.0));
/// assert!(u0.iter().zip(&model.fixed).all(|(u, &f)| !f || *u == 0.0));
/// # Ok::<(), rsf::Error>(())
/// ```
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

    /// Number of nodes (vertices).
    pub fn num_nodes(&self) -> usize {
        self.vertices.len()
    }

    /// `f(x_p)` for every frictional node `p`, in `frictional.nodes` order (the order of
    /// per-node laws and states): how a heterogeneous fault is described by position.
    pub fn on_frictional_nodes<T>(&self, mut f: impl FnMut(&[f64; D]) -> T) -> Vec<T> {
        self.frictional
            .nodes
            .iter()
            .map(|&p| f(&self.vertices[p]))
            .collect()
    }

    /// Checks that `node` is a node of the model.
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`] naming `what` the node is for.
    pub fn check_node(&self, what: &'static str, node: usize) -> Result<()> {
        if node < self.vertices.len() {
            Ok(())
        } else {
            Err(Error::NodeOutOfRange {
                what,
                node,
                nodes: self.vertices.len(),
            })
        }
    }

    /// The node nearest to `x` (m), by Euclidean distance; the first on ties.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a model without nodes or a non-finite `x`.
    pub fn nearest_node(&self, x: &[f64; D]) -> Result<usize> {
        crate::slider::nearest_vertex(&self.vertices, x)
    }

    /// Checks the shapes of all parts against each other, the Dirichlet data, and that
    /// every frictional node has a fixed component (the normal velocity under bilateral
    /// contact; `D ≥ 2`).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the mismatch; [`Error::NodeOutOfRange`] for a
    /// frictional node outside the mesh; [`Error::FreeNormal`] for a frictional node
    /// without a fixed component.
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
        if self.dirichlet.factors.iter().any(|f| !f.is_finite()) {
            return Err(invalid("dirichlet", "factors must be finite"));
        }
        self.dirichlet.history.validate()?;
        if let Some(&p) = self
            .frictional
            .nodes
            .iter()
            .find(|&&p| p >= self.vertices.len())
        {
            return Err(Error::NodeOutOfRange {
                what: "frictional boundary",
                node: p,
                nodes: self.vertices.len(),
            });
        }
        if self.frictional.weights.len() != self.frictional.nodes.len()
            || self.frictional.along.len() != self.frictional.nodes.len()
        {
            return Err(invalid(
                "frictional_boundary",
                "nodes, weights and along differ in length",
            ));
        }
        // Bilateral contact: the friction acts on the whole block v_p, so the normal
        // component must be fixed (docs/math.md §3); in 1D there is no normal.
        if D >= 2 {
            if let Some(&p) = self
                .frictional
                .nodes
                .iter()
                .find(|&&p| (0..D).all(|c| !self.fixed[D * p + c]))
            {
                return Err(Error::FreeNormal { node: p });
            }
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

#[cfg(test)]
mod tests {
    use super::TimeFunction;

    #[test]
    fn breakpoints_are_the_kinks_after_the_given_time() {
        let ramp = TimeFunction::ramp(2.0);
        assert_eq!(ramp.next_breakpoint(0.0), Some(2.0));
        assert_eq!(ramp.next_breakpoint(2.0), None);
        assert_eq!(TimeFunction::ramp(0.0).next_breakpoint(0.0), None);
        let pl = TimeFunction::PiecewiseLinear(vec![(-1.0, 0.0), (1.0, 1.0), (3.0, 0.5)]);
        assert_eq!(pl.next_breakpoint(-2.0), Some(-1.0));
        assert_eq!(pl.next_breakpoint(0.0), Some(1.0));
        assert_eq!(pl.next_breakpoint(1.0), Some(3.0));
        assert_eq!(pl.next_breakpoint(3.0), None);
        assert_eq!(TimeFunction::Constant(1.0).next_breakpoint(0.0), None);
        assert_eq!(TimeFunction::custom(|t| t).next_breakpoint(0.0), None);
    }
}
