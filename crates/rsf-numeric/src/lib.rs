//! Scalar numerics shared by the rsf crates, at the bottom of the workspace (it depends on
//! none of them):
//!
//! * [`wright_omega`] and [`wright_omega_ln`] — the Wright omega function `ω(x) = W₀(eˣ)`,
//!   overflow-safe for all real `x` (the closed-form aging-law update of `rsf-state` and
//!   the exact local solves of `rsf-friction`).
//! * [`safeguarded_newton`] and its one-closure forms [`solve_increasing`] and
//!   [`solve_increasing_from`] — roots of
//!   increasing scalar functions by Newton's method safeguarded with bisection (the
//!   generic state update of `rsf-state`, the local solves of `rsf-friction`).
//! * [`StateVariable`] — the convention for what the state `α` of a law is (`ln θ` or `θ`),
//!   shared by the state laws and the friction laws ([`convention`]).
//! * [`normal_component`] — the convention for which component of a nodal frame is the
//!   normal (the last), shared by the meshes' frames and the models built on them.
//! * [`excerpt`] — what an error message quotes of a user's value (at most 100
//!   characters); [`written`] — a user's number as written (up to notation).
//!
//! No function here can fail on its own: they return NaN only for NaN input, and the
//! root finder passes on the errors of the function it is given.
#![warn(missing_docs)]

pub mod convention;
mod message;
mod omega;
mod root;

pub use convention::{normal_component, StateVariable};
pub use message::{excerpt, number, parse_name, written, UnknownName, EXCERPT_CHARS};
pub use omega::{wright_omega, wright_omega_ln};
pub use root::{
    safeguarded_newton, solve_increasing, solve_increasing_from, solve_increasing_from_upper_end,
    Bracket, IncreasingFunction, RootOutcome, Start, Stopping,
};
