//! The builder's setters for the boundary conditions other than the fault's: Dirichlet
//! parts with prescribed velocities, Neumann parts with tractions, absorbing parts, and the
//! loading history of every prescribed velocity.

use super::part::Part;
use super::settings::{Absorbing, Dirichlet, VectorField};
use super::ModelBuilder;
use crate::model::loading::TimeFunction;

impl<const D: usize, const C: usize> ModelBuilder<D, C> {
    /// A Dirichlet part whose nodes move with velocity `velocity · g(t)` (m/s; `g` the
    /// [`loading`](Self::loading) history), all components fixed. `[0.0; C]` clamps.
    pub fn dirichlet(self, part: impl Into<Part<D>>, velocity: [f64; C]) -> Self {
        self.dirichlet_components(part, &(0..C).collect::<Vec<_>>(), velocity)
    }

    /// A Dirichlet part fixing only the listed components (e.g. a roller: the normal
    /// component only); component `c` moves with `velocity[c] · g(t)`.
    pub fn dirichlet_components(
        self,
        part: impl Into<Part<D>>,
        components: &[usize],
        velocity: [f64; C],
    ) -> Self {
        self.with_dirichlet(part.into(), components.to_vec(), velocity, None)
    }

    /// Adds the Dirichlet part `part` fixing `components`, moving with `velocity · g(t)`
    /// (m/s) or held at `displacement(x)` (m) in the initial equilibrium.
    fn with_dirichlet(
        mut self,
        part: Part<D>,
        components: Vec<usize>,
        velocity: [f64; C],
        displacement: Option<VectorField<D, C>>,
    ) -> Self {
        self.boundary.dirichlet.push(Dirichlet {
            part,
            components,
            velocity,
            displacement,
        });
        self
    }

    /// A Dirichlet part whose nodes are held at the displacement `u(x)` (m, Cartesian, all
    /// components fixed, velocity 0): the data of the static problem the builder solves as
    /// the initial equilibrium (`K u₀ = F` on the free dofs, `u₀ = u(x)` here; e.g. the far
    /// faces of a box held at a half-space's field, docs/faults-inside.md "A prescribed
    /// slip"). A node also in a [`dirichlet`](Self::dirichlet) part must have velocity 0
    /// there; two displacement parts must agree where they meet. At a split pair of a
    /// fault inside the body both sides must be held (their displacements give its mean
    /// and jump, as clamped velocities do).
    ///
    /// ```
    /// use rsf::fem::cuboid;
    /// use rsf::model::PrescribedSlip;
    /// use rsf::{Material, ModelBuilder, Part};
    /// // A unit cube, its bottom clamped, its top shifted by 1 mm along x: simple shear.
    /// let model = ModelBuilder::new(cuboid([0.0; 3], [1.0; 3], [5, 5, 5])?)
    ///     .material(Material::new(1e10, 0.25, 2700.0))
    ///     .without_mass()
    ///     .dirichlet(Part::predicate("bottom", |x| x[2] < 1e-9), [0.0; 3])
    ///     .dirichlet_displacement(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), |_| {
    ///         [1e-3, 0.0, 0.0]
    ///     })
    ///     // A model needs a fault: a buried square with zero slip (the displacement stays
    ///     // continuous across it).
    ///     .internal_fault_polygon(
    ///         "fault",
    ///         &[[0.5, 0.25, 0.25], [0.5, 0.75, 0.25], [0.5, 0.75, 0.75], [0.5, 0.25, 0.75]],
    ///     )
    ///     .internal_slip_at(|_| Some(PrescribedSlip::InFrame([0.0, 0.0])))
    ///     .build()?;
    /// let u = &model.initial_displacement;
    /// let top = model.nearest_node(&[0.5, 0.5, 1.0])?;
    /// assert_eq!(u[3 * top], 1e-3);
    /// // The middle layer moves, by about half as much.
    /// let middle = model.nearest_node(&[0.25, 0.5, 0.5])?;
    /// assert!((u[3 * middle] - 5e-4).abs() < 2e-4);
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors (at `build`)
    /// As [`dirichlet`](Self::dirichlet); [`Error::InvalidParameter`](crate::Error::InvalidParameter)
    /// named `dirichlet` for a non-finite displacement or two parts holding a node at
    /// different displacements, named `dirichlet_displacement` in
    /// [`build_columns`](Self::build_columns) (its equilibrium starts from zero data).
    pub fn dirichlet_displacement(
        self,
        part: impl Into<Part<D>>,
        displacement: impl Fn(&[f64; D]) -> [f64; C] + 'static,
    ) -> Self {
        let held = Some(Box::new(displacement) as VectorField<D, C>);
        self.with_dirichlet(part.into(), (0..C).collect(), [0.0; C], held)
    }

    /// A Neumann part with traction `t(x)` (Pa; N/m per unit thickness in 2D). Parts
    /// without any condition are traction-free.
    pub fn neumann(
        mut self,
        part: impl Into<Part<D>>,
        traction: impl Fn(&[f64; D]) -> [f64; C] + 'static,
    ) -> Self {
        self.boundary
            .neumann
            .push((part.into(), Box::new(traction)));
        self
    }

    /// An absorbing part Γ_A (a truncation boundary of a dynamic model): Lysmer–Kuhlemeyer
    /// dashpots with the medium's impedances
    /// ([`Medium::impedances`](crate::model::Medium::impedances)), the far field at rest
    /// ([`AbsorbingBoundary`](crate::model::AbsorbingBoundary), docs/math.md "Absorbing
    /// boundaries"). May be called for several parts; a part's dofs that are also Dirichlet
    /// dofs stay prescribed (the dashpot does nothing there).
    pub fn absorbing_boundary(self, part: impl Into<Part<D>>) -> Self {
        self.absorbing_boundary_moving(part, [0.0; C])
    }

    /// An absorbing part whose far field moves with velocity `velocity · g(t)` (m/s, of
    /// the field `u` as Dirichlet velocities are given; `g` the [`loading`](Self::loading)
    /// history): the dashpots act on `v − velocity · g(t)`, so a body translating with the
    /// far field feels no force (e.g. SEAS BP1's half-space moving at `V_p/2`).
    pub fn absorbing_boundary_moving(
        mut self,
        part: impl Into<Part<D>>,
        velocity: [f64; C],
    ) -> Self {
        self.boundary.absorbing.push(Absorbing {
            part: part.into(),
            velocity,
        });
        self
    }

    /// The loading history `g(t)` scaling every Dirichlet velocity (default `g ≡ 1`).
    pub fn loading(mut self, history: TimeFunction) -> Self {
        self.boundary.loading = history;
        self
    }
}
