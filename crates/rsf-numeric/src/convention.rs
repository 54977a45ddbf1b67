//! The state-variable convention: what the state `α` of a law stands for.
//!
//! A state law (`rsf-state`) evolves a state `α` at every frictional node and a friction
//! law (`rsf-friction`) reads it; both must mean the same quantity. The rate-and-state laws
//! of Pipping, Sander & Kornhuber use `α = ln θ` ((2.15), (2.16)); the discontinuous law
//! (2.10), (2.17) uses `θ` itself. [`StateVariable`] names the two conventions so that a
//! simulation can check that a friction law and a state law agree.

/// What the state variable `α` of a law is.
///
/// Units (SI): `θ` in s for the aging and slip laws; for the discontinuous law `α = θ` is
/// in the paper's normalisation `ψ_dc = |αV − 1|`, i.e. in s/m.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StateVariable {
    /// `α = ln θ`, `θ` in s (aging law (2.15), slip law (2.16); what the rate-state friction
    /// laws (2.12)–(2.13) expect: `μ = μ0 + a ln(V/V0) + b(α + ln(V0/L))`).
    LogTheta,
    /// `α = θ` itself (discontinuous law (2.17)).
    Theta,
}
