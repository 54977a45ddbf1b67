//! Where the elastic medium is: a half-space or the whole space.

/// Where the elastic medium is: a half-space `z ≤ 0` with its free surface `z = 0`, or
/// the whole space (no surface; SEAS BP7 and BP8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Space {
    /// `z ≤ 0`, traction-free at `z = 0` (Okada's DC3D; Nikkhoo & Walter's half-space
    /// triangles).
    #[default]
    HalfSpace,
    /// The unbounded medium (Okada's full-space term alone; Nikkhoo & Walter's full-space
    /// triangles).
    WholeSpace,
}

impl Space {
    /// `"half-space"` or `"whole space"`.
    pub fn name(&self) -> &'static str {
        match self {
            Space::HalfSpace => "half-space",
            Space::WholeSpace => "whole space",
        }
    }
}
