//! The builder's setters for the boundary conditions other than the fault's: Dirichlet
//! parts with prescribed velocities, Neumann parts with tractions, absorbing parts, and the
//! loading history of every prescribed velocity.

use super::part::Part;
use super::settings::{Absorbing, Dirichlet};
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
        mut self,
        part: impl Into<Part<D>>,
        components: &[usize],
        velocity: [f64; C],
    ) -> Self {
        self.boundary.dirichlet.push(Dirichlet {
            part: part.into(),
            components: components.to_vec(),
            velocity,
        });
        self
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
