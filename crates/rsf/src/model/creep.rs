//! The creeping section of a fault inside the body: split pairs whose slip rate is
//! prescribed (a vector in 3-D) instead of found by friction (docs/faults-inside.md
//! "Loading", docs/math.md "Slip as a vector").

use crate::error::{invalid, Result};

/// Largest normal part of a [`CreepRate::Cartesian`] slip rate, relative to its length:
/// a larger one would open or close the fault, whose normal jump is tied.
pub const MAX_CREEP_NORMAL_FRACTION: f64 = 1e-6;

/// Declares a prescribed jump of a split pair (`$amount` in `$unit`; errors name
/// `$parameter` and speak of a `$what`): the enum of its two forms, in the pair's frame
/// (`InFrame`) or Cartesian, with `rake` and `in_frame` (through [`Jump`]).
macro_rules! prescribed_jump {
    (
        $(#[$doc:meta])*
        pub enum $name:ident($amount:ident in $unit:literal, $parameter:literal, $what:literal) {
            $(#[$in_frame:meta])*
            InFrame,
            $(#[$cartesian:meta])*
            Cartesian,
        }
    ) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum $name<const D: usize> {
            $(#[$in_frame])*
            InFrame([f64; 2]),
            $(#[$cartesian])*
            Cartesian([f64; D]),
        }

        impl<const D: usize> $name<D> {
            #[doc = concat!(
                "`", stringify!($amount), "` (", $unit, ") along the direction at ",
                "`rake_degrees` from `t₁` towards `t₂` (the seismological rake when `t₁` is ",
                "the strike and `t₂` the up-dip direction): `InFrame([", stringify!($amount),
                " cos r, ", stringify!($amount), " sin r])`."
            )]
            pub fn rake($amount: f64, rake_degrees: f64) -> Self {
                let r = rake_degrees.to_radians();
                Self::InFrame([$amount * r.cos(), $amount * r.sin()])
            }

            /// The prescribed components of the jump in the pair's frame: the first `C − 1`
            /// (vector field) or the one (scalar field) of the returned array; `frame` is the
            /// pair's (row-major, columns `(t₁, …, −n)`).
            ///
            /// # Errors
            #[doc = concat!(
                "[`Error::InvalidParameter`](crate::Error::InvalidParameter) named `",
                $parameter, "` for a non-finite ", $what, ", a second tangential component ",
                "in 2-D or for a scalar field, a Cartesian ", $what, " on a scalar field or ",
                "with a normal part, naming the position `x`."
            )]
            pub(crate) fn in_frame<const C: usize>(
                &self,
                frame: &[[f64; D]; D],
                x: &[f64; D],
            ) -> Result<[f64; C]> {
                let jump = match *self {
                    Self::InFrame(v) => Jump::InFrame(v),
                    Self::Cartesian(v) => Jump::Cartesian(v),
                };
                jump.in_frame(frame, x, ($parameter, $what, $unit))
            }
        }
    };
}

prescribed_jump! {
    /// The prescribed slip rate of a creeping split pair of a fault inside the body (m/s,
    /// times the loading history `g(t)`): the jump `v⁺ − v⁻` of the velocity, in the pair's
    /// frame `(t₁, t₂, −n)` (2-D: `(t, −n)`; the scalar field: the one component).
    ///
    /// Every tangential component of a creeping pair is fixed — in 3-D both, so slip on the
    /// creeping part is a vector of prescribed direction, never free along `t₂`.
    pub enum CreepRate(rate in "m/s", "internal_creep", "creep rate") {
        /// The components `(V₁, V₂)` along the pair's tangents `t₁`, `t₂` (m/s): in 2-D and
        /// for a scalar field `V₂` must be 0 (`V₁` along the fault's tangent `t`, or the
        /// scalar jump); in 3-D `t₁` is the projection of
        /// [`fault_tangent`](crate::ModelBuilder::fault_tangent) on the fault.
        InFrame,
        /// The Cartesian slip-rate vector `v⁺ − v⁻` (m/s) for a vector field: its tangential
        /// components in each pair's frame are prescribed. Its part along the pair's normal
        /// must be at most [`MAX_CREEP_NORMAL_FRACTION`] of its length (the fault does not
        /// open); not for a scalar field.
        Cartesian,
    }
}

prescribed_jump! {
    /// The prescribed slip of a split pair of a fault inside the body (m): the jump
    /// `u⁺ − u⁻` of the displacement, set by
    /// [`internal_slip_at`](crate::ModelBuilder::internal_slip_at) — a kinematic source (a
    /// dislocation), in the pair's frame `(t₁, t₂, −n)` (2-D: `(t, −n)`; the scalar field:
    /// the one component) or as a Cartesian vector tangent to the fault. Every tangential
    /// component of such a pair is fixed: in the static problem (the model's initial
    /// equilibrium, [`Model::initial_displacement`](crate::Model::initial_displacement)) its
    /// jump is the slip, and it does not slip further (its slip rate is 0, or a creep rate
    /// of [`internal_creep_at`](crate::ModelBuilder::internal_creep_at) at the same pair).
    pub enum PrescribedSlip(slip in "m", "internal_slip", "slip") {
        /// The components `(s₁, s₂)` along the pair's tangents `t₁`, `t₂` (m): in 2-D and for
        /// a scalar field `s₂` must be 0; in 3-D `t₁` is the projection of
        /// [`fault_tangent`](crate::ModelBuilder::fault_tangent) on the fault.
        InFrame,
        /// The Cartesian slip vector `u⁺ − u⁻` (m) for a vector field; its part along the
        /// pair's normal must be at most [`MAX_CREEP_NORMAL_FRACTION`] of its length (the
        /// fault does not open); not for a scalar field.
        Cartesian,
    }
}

/// A prescribed jump (a creep rate or a slip) before it is written in a pair's frame.
enum Jump<const D: usize> {
    InFrame([f64; 2]),
    Cartesian([f64; D]),
}

impl<const D: usize> Jump<D> {
    /// The jump's components in `frame` (the first `C − 1` of a vector field, the one of
    /// a scalar field); errors name `parameter` and speak of a `what` in `unit`.
    fn in_frame<const C: usize>(
        &self,
        frame: &[[f64; D]; D],
        x: &[f64; D],
        (parameter, what, unit): (&str, &str, &str),
    ) -> Result<[f64; C]> {
        let vector = C == D && C > 1;
        let tangential = if vector { C - 1 } else { 1 };
        let refuse = |why: String| Err(invalid(parameter, format!("the {what} at {x:?} m {why}")));
        let mut j = [0.0; C];
        match *self {
            Self::InFrame(v) => {
                if v.iter().any(|x| !x.is_finite()) {
                    return refuse(format!("{v:?} {unit} is not finite"));
                }
                if tangential < 2 && v[1] != 0.0 {
                    return refuse(format!(
                        "has a second tangential component {:e} {unit}, but the fault has \
                         one tangent",
                        v[1]
                    ));
                }
                j[..tangential].copy_from_slice(&v[..tangential]);
            }
            Self::Cartesian(v) => {
                if !vector {
                    return refuse(format!(
                        "is a Cartesian vector, but the field is scalar (give the {what} \
                         in the pair's frame, InFrame)"
                    ));
                }
                if v.iter().any(|x| !x.is_finite()) {
                    return refuse(format!("{v:?} {unit} is not finite"));
                }
                // j = Rᵀ v.
                let local: [f64; D] =
                    std::array::from_fn(|a| (0..D).map(|b| frame[b][a] * v[b]).sum());
                let length = v.iter().fold(0.0f64, |m, x| m.hypot(*x));
                if local[D - 1].abs() > MAX_CREEP_NORMAL_FRACTION * length {
                    return refuse(format!(
                        "{v:?} {unit} has the normal part {:e} {unit}: it would open or \
                         close the fault (give a vector tangent to the fault)",
                        -local[D - 1]
                    ));
                }
                j[..tangential].copy_from_slice(&local[..tangential]);
            }
        }
        Ok(j)
    }
}

/// Where and how much a fault inside the body's pairs are slipped by prescription: `None`
/// where the pair at position `x` (m) is not.
pub(crate) type SlipField<const D: usize> = Box<dyn Fn(&[f64; D]) -> Option<PrescribedSlip<D>>>;

/// Where and how fast the creeping section of an internal fault slips: `None` where the
/// pair at position `x` (m) slips by friction.
pub(crate) type CreepField<const D: usize> = Box<dyn Fn(&[f64; D]) -> Option<CreepRate<D>>>;

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame (rows: Cartesian components; columns t₁, t₂, −n) of the plane x = 0 with
    /// t₁ = e₂, t₂ = e₃, n = e₁.
    const FRAME: [[f64; 3]; 3] = [[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn a_cartesian_rate_is_its_tangential_components_and_a_normal_part_is_refused() {
        let x = [0.0, 1.0, 2.0];
        let j: [f64; 3] = CreepRate::Cartesian([0.0, 3.0, 4.0])
            .in_frame(&FRAME, &x)
            .unwrap();
        assert_eq!(j, [3.0, 4.0, 0.0]);
        let e = CreepRate::Cartesian([1e-3, 3.0, 4.0])
            .in_frame::<3>(&FRAME, &x)
            .unwrap_err();
        assert!(e.to_string().contains("normal part"), "{e}");
    }

    #[test]
    fn a_rake_splits_the_rate_between_the_tangents() {
        let j: [f64; 3] = CreepRate::rake(2.0, 30.0)
            .in_frame(&FRAME, &[0.0; 3])
            .unwrap();
        assert!((j[0] - 3f64.sqrt()).abs() < 1e-15 && (j[1] - 1.0).abs() < 1e-15);
        assert_eq!(j[2], 0.0);
    }

    #[test]
    fn two_tangential_components_need_a_3d_vector_field() {
        let frame = [[0.0, -1.0], [1.0, 0.0]];
        assert!(CreepRate::<2>::InFrame([1.0, 1.0])
            .in_frame::<2>(&frame, &[0.0; 2])
            .is_err());
        assert!(CreepRate::<2>::Cartesian([1.0, 0.0])
            .in_frame::<1>(&frame, &[0.0; 2])
            .is_err());
        assert!(CreepRate::<2>::InFrame([f64::NAN, 0.0])
            .in_frame::<2>(&frame, &[0.0; 2])
            .is_err());
        let j: [f64; 1] = CreepRate::<2>::InFrame([2.0, 0.0])
            .in_frame(&frame, &[0.0; 2])
            .unwrap();
        assert_eq!(j, [2.0]);
    }
}
