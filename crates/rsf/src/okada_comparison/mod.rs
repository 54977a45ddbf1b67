//! The 3-D finite-element model against Okada's (1992) half-space as `rsf-halfspace`
//! evaluates it (docs/halfspace.md; checked against Okada's DC3D): a slip prescribed on a
//! fault inside the body ([`ModelBuilder::internal_slip_at`](crate::ModelBuilder::internal_slip_at),
//! every pair: no frictional node), the far faces held at Okada's displacement or at rest
//! ([`dirichlet_displacement`](crate::ModelBuilder::dirichlet_displacement)), the static
//! problem solved by the build (the direct solver, or multigrid on a refinement
//! hierarchy), and the surface displacement and the on-fault traction compared with
//! Okada's (docs/three-d.md "Against Okada's half-space (issue 55)", docs/faults-inside.md
//! "A prescribed slip"). Feature `halfspace`.
//!
//! The model's frame is Okada's: `x` along strike, `z` up, the free surface `z = 0`. A
//! vertical fault ([`Fault`]) is the plane `y = 0`, a 45° dipping one ([`DippingFault`])
//! the plane `y − z = depth` — the two dips a Kuhn grid of cubes resolves besides the
//! horizontal (its cells' faces lie on the planes `x_i = const` and `x_i − x_j = const`).
//!
//! **The rim.** A rim of the fault inside the body is a shared tip in the model (zero
//! jump at the rim node): the finite-element slip is `s` at the inner nodes and ramps
//! linearly to 0 over the last cell. The model's polygon is therefore Okada's rectangle
//! grown by half a cell on every inner edge (not along the free surface), or Okada's
//! rectangle the model's shrunk by half a cell: the ramp is then centred on Okada's edge,
//! the two slips have the same moment, and their difference (odd about the edge, zero
//! mean) acts at distance `r` as a line of dipoles of strength `O(h²)` — second order,
//! below the discretisation error measured.
//!
//! **Signs.** The polygon's corners go along strike first, then up dip, so its right-hand
//! normal is Okada's `n` (`−e_y` on a vertical fault): the model's plus side is Okada's
//! hanging wall, and the model's jump `u⁺ − u⁻` is Okada's `U1 e_s + U2 e_d`, checked on
//! the model's own displacements ([`Errors::jump`]).
//!
//! **Tractions.** At a pair `(p⁻, p⁺)` the residual of the prescribed jump components is
//! `f'_j = Rᵀ f⁺` (the plus copy's force; `f⁺ + f⁻ = 0` at equilibrium, whatever the
//! sharing of the jump), and `f⁺ = ∫ φ σ n⁺_out dS` with the plus side's outward normal
//! `−n` on the fault: `f⁺ / w ≈ σ (−n)`, `w` the node's lumped weight (a third of each
//! adjacent triangle's area). Compared with Okada's `σ (−n)` at the nodes at least a
//! quarter of the fault's width from its rim.

mod common;
mod dipping;
mod dislocation;
mod error;
mod measure;
mod modes;
mod vertical;

pub use common::{Errors, Solver, MU, MULTIGRID_TOLERANCE, NU, SLIP};
pub use dipping::{compare_dipping, DippingFault};
pub use error::{ComparisonError, Result};
pub use modes::{compare_modes, ModeComparison};
pub use vertical::{compare_held, compare_refined, compare_smooth, hierarchy_vertices, Fault};
