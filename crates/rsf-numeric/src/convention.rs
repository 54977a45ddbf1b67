//! Conventions shared by the crates: what the state `α` of a law stands for
//! ([`StateVariable`]), and which component of a nodal frame is the normal
//! ([`normal_component`]).
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

/// The component of a block of `components` (per node: `C` unknowns, `C ≥ 1`) that a
/// nodal frame makes the **normal**: the last, `components − 1` (docs/math.md §10). A
/// frame's columns are its tangents then the inward normal, so in local coordinates the
/// normal velocity, the tied normal jump of a fault inside the body and the normal
/// reaction sit there, and the tangential slip is the components before it. Every crate
/// that means "the normal component" uses this function instead of writing `C − 1`.
///
/// ```
/// assert_eq!(rsf_numeric::normal_component(3), 2);
/// assert_eq!(rsf_numeric::normal_component(2), 1);
/// ```
///
/// # Panics
/// For `components = 0` (no component; in const contexts a compile error).
pub const fn normal_component(components: usize) -> usize {
    assert!(components > 0, "a block has at least one component");
    components - 1
}
