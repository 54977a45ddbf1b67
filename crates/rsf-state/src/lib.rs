//! State laws of rate-and-state friction and their backward Euler update.
//!
//! Pipping, Sander & Kornhuber write the state evolution as a subdifferential inclusion
//! (2.4) `−α̇ ∈ ∂_α ψ(α, V)` with `ψ(·, V)` convex. Backward Euler (3.5) turns one time
//! step into a proximal problem, solved pointwise at every frictional node:
//!
//! ```text
//! α_n = argmin_β ½ |β − α_{n−1}|² + τ ψ(β, V)   ⇔   β − α_{n−1} + τ ∂_α ψ(β, V) ∋ 0.
//! ```
//!
//! * [`StateLaw`] — the trait. A user law implements only
//!   [`dpsi_dalpha`](StateLaw::dpsi_dalpha); the default [`update`](StateLaw::update)
//!   ([`generic_update`]) solves the implicit equation by safeguarded Newton/bisection.
//! * Built-in laws with closed-form updates: [`Aging`] (Dieterich, (2.15), (5.5), via the
//!   Wright omega function, overflow-safe), [`Slip`] (Ruina, (2.16)) and
//!   [`Discontinuous`] ((2.10), (2.17); here `α = θ`, not `ln θ`, see [`StateVariable`]).
//! * Beyond the paper: [`StateLaw::constant_rate_update`], the exact solution of the state
//!   equation over a step at constant slip rate, where a law has one in closed form (all
//!   three built-in laws; in stick it integrates healing exactly, which backward Euler in
//!   `α = ln θ` does not).
//!
//! # Units (SI)
//! Slip rate `V` in m/s, time step `τ` in s, `L` in m. For the aging and slip laws
//! `α = ln θ` with `θ` in s; for the discontinuous law `α = θ` in the paper's normalisation
//! `ψ_dc = |αV − 1|`, i.e. `α` in s/m.
//!
//! # Example: a user law through the trait
//! The "aging law without healing" `θ̇ = −θV/L` (i.e. `α̇ = −V/L`, `ψ = (V/L) α`) needs only
//! `∂ψ/∂α`; the generic update then integrates it:
//! ```
//! use rsf_state::{Aging, StateLaw};
//!
//! #[derive(Clone)]
//! struct NoHealing { l: f64 }
//! impl StateLaw for NoHealing {
//!     fn dpsi_dalpha(&self, _alpha: f64, v: f64) -> f64 { v / self.l }
//! }
//!
//! let law = NoHealing { l: 1e-5 };
//! let alpha = law.update(2.0, 1e-6, 1.0)?;      // α − τV/L exactly
//! assert!((alpha - (2.0 - 0.1)).abs() < 1e-12);
//! // The closed-form aging law and the generic solver agree:
//! let aging = Aging::new(1e-5)?;
//! let closed = aging.update(-10.0, 2e-4, 1e-3)?;
//! let generic = rsf_state::generic_update(&aging, -10.0, 2e-4, 1e-3)?;
//! assert!((closed - generic).abs() < 1e-10);
//! # Ok::<(), rsf_state::Error>(())
//! ```
#![warn(missing_docs)]

mod error;
mod generic;
mod kind;
mod law;
mod laws;
mod probe;

pub use error::{check_update_inputs, Error, Result};
pub use kind::{BuiltinStateLaw, StateLawKind};
pub use law::{generic_update, probe_monotonicity, StateLaw};
pub use laws::{Aging, Discontinuous, Slip};
pub use probe::{PROBE_ALPHA_MAX, PROBE_ALPHA_MIN, PROBE_ALPHA_POINTS, PROBE_SLIP_RATES};
pub use rsf_numeric::{wright_omega, wright_omega_ln, StateVariable};
