//! Elastic half-space kernels, independent of the finite-element model: a test anchor for
//! it and a boundary-element fault operator.
//!
//! - [`okada`]: Okada (1992) DC3D — displacement and its nine derivatives at any point of
//!   the half-space `z ≤ 0` for uniform strike-slip, dip-slip and tensile dislocation on
//!   a finite rectangle (Y. Okada, "Internal deformation due to shear and tensile faults
//!   in a half-space", BSSA 82(2), 1018–1040, 1992, §3). Checked against Okada's own
//!   FORTRAN routine on 972 fixture values (`tests/suite/okada_fixture.rs`).
//! - [`Medium`], [`traction`]: Hooke's law from the displacement gradient.
//! - [`two_d`]: the 2-D antiplane screw dislocation (vertical strike-slip segment:
//!   displacement and stress) and the plane-strain edge dislocation (dipping dip-slip
//!   segment: surface displacement, and stress anywhere) in a half-space, in closed form.
//! - [`RectangularFault`]: a planar rectangular fault meshed into `n_strike × n_dip`
//!   constant-slip rectangles, and its boundary-element operators: the stiffness `K`
//!   (`Δτ = −K s`) and the slip-to-normal-traction operator `K_N`, dense (on rayon) or as
//!   an ℋ-matrix ([`rsf_hmatrix`]).
//! - [`triangle`]: the triangular dislocation of Nikkhoo & Walter (2015, GJI 201,
//!   1119–1141, "Triangular dislocation: an analytical, artefact-free solution"):
//!   displacement and gradient of a [`Triangle`] of constant slip in a full space or a
//!   half-space.
//! - [`Space`]: a half-space or the whole space (Okada's part A alone,
//!   [`Okada::unit_responses_in`]; the triangle without image and harmonic terms).
//! - [`ElementSet`]: the same operators for any set of [`Element`]s — rectangles of any
//!   strike, dip and position ([`RectangleElement`]) or triangles — several faults or a
//!   non-planar one, in either space.
//!
//! Units are SI (m, Pa) throughout; the kernels are linear, so any consistent units work.
//! The conventions — Okada's frame, the hanging wall and the signs of slip and traction,
//! the unknown order and how to map other frames such as SEAS BP5's — are written out in
//! docs/halfspace.md.
//!
//! # Errors and panics
//! Every public function on user input returns [`Result`] with [`Error`] (invalid
//! parameters, points above the surface or on a dislocation's edge, results that
//! overflow); none panics on user input.
//!
//! # Example
//! ```
//! use rsf_halfspace::{okada::dc3d, Medium, Rectangle};
//! let medium = Medium::from_shear_poisson(32.04e9, 0.25).unwrap();
//! // 1 m of reverse slip on a 45° fault, stress 1 km above its centre.
//! let fault = Rectangle::new(3e3, 45.0, [-2e3, 2e3], [-1e3, 1e3]).unwrap();
//! let d = dc3d(medium.alpha(), [0.0, 0.0, -1e3], fault, [0.0, 1.0, 0.0]).unwrap();
//! let sigma = medium.stress(&d.grad);
//! assert!(sigma[0][1] == sigma[1][0]);
//!
//! use rsf_halfspace::RectangularFault;
//! // A vertical strike-slip fault 4 km long, from the surface to 2 km, in 500 m cells.
//! let plane = Rectangle::new(0.0, 90.0, [-2e3, 2e3], [-2e3, 0.0]).unwrap();
//! let fault = RectangularFault::new(medium, plane, 500.0).unwrap();
//! assert_eq!(fault.len(), 2 * 8 * 4);
//! let k = fault.dense().unwrap();
//! // Slip on an element lowers the shear traction there: K's diagonal is positive.
//! assert!(k[(0, 0)] > 0.0 && k[(1, 1)] > 0.0);
//!
//! use rsf_halfspace::{ElementSet, RectangleElement, Space, Triangle};
//! // Two faults in the whole space: a vertical one of 4 squares striking along y, a
//! // dipping triangle beside it.
//! let squares = RectangleElement::grid([0.0, 0.0, 0.0], 90.0, 90.0, [2e3, 2e3], [2, 2]).unwrap();
//! let set = ElementSet::new(medium, Space::WholeSpace, squares).unwrap();
//! assert_eq!(set.len(), 8);
//! assert!(set.dense().unwrap()[(0, 0)] > 0.0);
//! let tri = Triangle::new([[3e3, 0.0, 0.0], [4e3, 0.0, 0.0], [3.5e3, 500.0, 800.0]]).unwrap();
//! let d = tri.unit_responses(0.25, [0.0, 0.0, 0.0], Space::WholeSpace).unwrap();
//! assert!(d[0].u.iter().all(|u| u.is_finite()));
//! ```

#![warn(missing_docs)]

mod bem;
mod dual;
mod element_set;
mod elements;
mod error;
pub mod okada;
mod space;
mod stress;
pub mod triangle;
pub mod two_d;

pub use bem::{Component, RectangularFault, TABLE_MAX_PAIRS};
pub use element_set::{ElementSet, MAX_ELEMENTS};
pub use elements::{Element, RectangleElement};
pub use error::Error;
pub use okada::{Deformation, Okada, Rectangle};
pub use space::Space;
pub use stress::{traction, Medium};
pub use triangle::Triangle;
