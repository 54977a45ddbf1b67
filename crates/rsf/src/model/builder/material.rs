//! The builder's setters for the body: its medium, the forces acting inside it, inertia.

use super::ModelBuilder;
use crate::model::medium::Medium;

impl<const D: usize> ModelBuilder<D> {
    /// Gravitational acceleration `g` (m/s²): body force density `ρ g`.
    pub fn gravity(mut self, g: [f64; D]) -> Self {
        self.body.gravity = Some(g);
        self
    }
}

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    /// The material (required): a [`Material`](crate::model::Material) for elasticity
    /// (`C = D`), an [`AntiplaneMaterial`](crate::model::AntiplaneMaterial) for a scalar
    /// field (`C = 1`), or a user's [`Medium`].
    pub fn material(mut self, material: impl Medium<D, C> + 'static) -> Self {
        self.body.material = Some(Box::new(material));
        self
    }

    /// A body force density `f(x)` (N/m³; N/m² per unit thickness in 2D), added to gravity.
    pub fn body_force(mut self, f: impl Fn(&[f64; D]) -> [f64; C] + 'static) -> Self {
        self.body.body_force = Some(Box::new(f));
        self
    }

    /// No mass matrix (quasistatic problems); the energy norm is then `K`.
    pub fn without_mass(mut self) -> Self {
        self.body.with_mass = false;
        self
    }

    /// `u₀ = 0` (on the free dofs; the fixed ones at their held values): no initial
    /// equilibrium `K u₀ = F` is solved. For a model whose load a
    /// run carries in its own right-hand side, such as the fault ODE's condensed load of
    /// the SEAS scenes (docs/math.md §12): the equilibrium's solve — a sparse Cholesky
    /// factor of the whole `K` below
    /// [`EQUILIBRIUM_DIRECT_MAX_DOFS_3D`](crate::model::EQUILIBRIUM_DIRECT_MAX_DOFS_3D)
    /// dofs — is then never paid for (it was the peak of BP5's finite-element build,
    /// docs/three-d.md, "The build's memory"). [`build_columns`](Self::build_columns)
    /// takes its equilibrium from its caller and ignores this.
    pub fn without_initial_equilibrium(mut self) -> Self {
        self.body.equilibrium = false;
        self
    }

    /// How the initial equilibrium — the static problem `K u₀ = F` with the held values
    /// of Dirichlet parts and prescribed slips — is solved: the solver, multigrid's
    /// stopping test, and a [`SolveWatch`](crate::nonsmooth::SolveWatch) for progress
    /// reports and a time limit ([`StaticOptions`](crate::model::StaticOptions); default:
    /// Cholesky, or multigrid for a 3-D model of more than
    /// [`EQUILIBRIUM_DIRECT_MAX_DOFS_3D`](crate::model::EQUILIBRIUM_DIRECT_MAX_DOFS_3D)
    /// dofs with a hierarchy, unwatched, at most 500 iterations).
    ///
    /// # Errors (at `build`)
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `static_solver`
    /// for multigrid without a hierarchy; [`Error::Solver`](crate::Error::Solver) for
    /// multigrid stopped by its iteration cap or time limit (the iterations and the last
    /// correction).
    pub fn equilibrium_solver(mut self, options: crate::model::StaticOptions) -> Self {
        self.body.equilibrium_solver = options;
        self
    }
}
