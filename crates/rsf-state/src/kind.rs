//! The built-in state laws as one run-time choice: [`StateLawKind`] names a law (scene files,
//! command lines), [`BuiltinStateLaw`] is the law with its parameter, dispatching to
//! [`Aging`], [`Slip`] or [`Discontinuous`] (so a simulation whose law is chosen at run time
//! is one type, not one per law).

use crate::{Aging, Discontinuous, Error, Result, Slip, StateLaw, StateVariable};

/// Which built-in state law (the name a user writes).
///
/// Names (`name`, `FromStr`, serde, clap): `aging` (alias `dieterich`), `slip` (alias
/// `ruina`), `discontinuous`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum StateLawKind {
    /// The aging law (Dieterich), paper (2.15): `θ̇ = 1 − Vθ/L`.
    #[cfg_attr(feature = "serde", serde(alias = "dieterich"))]
    #[cfg_attr(feature = "clap", value(alias = "dieterich"))]
    Aging,
    /// The slip law (Ruina), paper (2.16): `θ̇ = −(Vθ/L) ln(Vθ/L)`.
    #[cfg_attr(feature = "serde", serde(alias = "ruina"))]
    #[cfg_attr(feature = "clap", value(alias = "ruina"))]
    Slip,
    /// The discontinuous law, paper (2.10), (2.17) (state `α = θ`, not `ln θ`).
    Discontinuous,
}

impl StateLawKind {
    /// Every kind, in declaration order.
    pub const ALL: [StateLawKind; 3] = [Self::Aging, Self::Slip, Self::Discontinuous];

    /// The name (`aging`, `slip`, `discontinuous`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Aging => "aging",
            Self::Slip => "slip",
            Self::Discontinuous => "discontinuous",
        }
    }
}

// `Display` (the name) and `FromStr` (a name, or the aliases `dieterich` and `ruina`).
rsf_numeric::display_and_parse_by_name!(
    StateLawKind,
    "state law",
    Error,
    StateLawKind::ALL,
    [
        ("dieterich", StateLawKind::Aging),
        ("ruina", StateLawKind::Slip)
    ]
);

/// A built-in state law chosen at run time: one type for all of them (see the module
/// documentation). Every [`StateLaw`] method forwards to the law, so results are those of
/// the law itself, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BuiltinStateLaw {
    /// See [`Aging`].
    Aging(Aging),
    /// See [`Slip`].
    Slip(Slip),
    /// See [`Discontinuous`].
    Discontinuous(Discontinuous),
}

impl BuiltinStateLaw {
    /// The law `kind` with characteristic slip distance `l` (m; not used by the
    /// discontinuous law, whose normalisation has none).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for an invalid `l` (aging and slip laws).
    pub fn new(kind: StateLawKind, l: f64) -> Result<Self> {
        Ok(match kind {
            StateLawKind::Aging => Self::Aging(Aging::new(l)?),
            StateLawKind::Slip => Self::Slip(Slip::new(l)?),
            StateLawKind::Discontinuous => Self::Discontinuous(Discontinuous),
        })
    }

    /// Which law this is.
    pub fn kind(&self) -> StateLawKind {
        match self {
            Self::Aging(_) => StateLawKind::Aging,
            Self::Slip(_) => StateLawKind::Slip,
            Self::Discontinuous(_) => StateLawKind::Discontinuous,
        }
    }
}

macro_rules! dispatch {
    ($self:ident, $law:ident => $e:expr) => {
        match $self {
            BuiltinStateLaw::Aging($law) => $e,
            BuiltinStateLaw::Slip($law) => $e,
            BuiltinStateLaw::Discontinuous($law) => $e,
        }
    };
}

impl StateLaw for BuiltinStateLaw {
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        dispatch!(self, l => l.dpsi_dalpha(alpha, v))
    }
    fn d2psi_dalpha2(&self, alpha: f64, v: f64) -> Option<f64> {
        dispatch!(self, l => l.d2psi_dalpha2(alpha, v))
    }
    fn psi(&self, alpha: f64, v: f64) -> Option<f64> {
        dispatch!(self, l => l.psi(alpha, v))
    }
    fn state_variable(&self) -> StateVariable {
        dispatch!(self, l => l.state_variable())
    }
    fn steady_state(&self, v: f64) -> Option<f64> {
        dispatch!(self, l => l.steady_state(v))
    }
    fn check_monotone(&self) -> Result<()> {
        dispatch!(self, l => l.check_monotone())
    }
    fn update(&self, alpha_prev: f64, v: f64, tau: f64) -> Result<f64> {
        dispatch!(self, l => l.update(alpha_prev, v, tau))
    }
    fn constant_rate_update(&self, alpha_prev: f64, v: f64, tau: f64) -> Option<Result<f64>> {
        dispatch!(self, l => l.constant_rate_update(alpha_prev, v, tau))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_aliases_parse() {
        for k in StateLawKind::ALL {
            assert_eq!(k.name().parse::<StateLawKind>().unwrap(), k);
            assert_eq!(k.to_string(), k.name());
        }
        assert_eq!(
            "dieterich".parse::<StateLawKind>().unwrap(),
            StateLawKind::Aging
        );
        assert_eq!("ruina".parse::<StateLawKind>().unwrap(), StateLawKind::Slip);
        let e = "agin".parse::<StateLawKind>().unwrap_err().to_string();
        assert!(e.contains("agin") && e.contains("aging"), "{e}");
    }

    /// The run-time law gives the bits of the law it wraps.
    #[test]
    fn builtin_law_forwards_bit_for_bit() {
        let l = 1e-5;
        let aging = Aging::new(l).unwrap();
        let slip = Slip::new(l).unwrap();
        let cases = [
            (BuiltinStateLaw::new(StateLawKind::Aging, l).unwrap(), 0),
            (BuiltinStateLaw::new(StateLawKind::Slip, l).unwrap(), 1),
        ];
        for (law, which) in cases {
            for (a, v, tau) in [(-10.0, 1e-9, 1e-3), (2.0, 1e-2, 1.5e-3), (40.0, 0.0, 1.0)] {
                let (u, c) = match which {
                    0 => (
                        aging.update(a, v, tau),
                        aging.constant_rate_update(a, v, tau),
                    ),
                    _ => (slip.update(a, v, tau), slip.constant_rate_update(a, v, tau)),
                };
                let got = law.update(a, v, tau).unwrap();
                assert_eq!(got.to_bits(), u.unwrap().to_bits());
                let got = law.constant_rate_update(a, v, tau).unwrap().unwrap();
                assert_eq!(got.to_bits(), c.unwrap().unwrap().to_bits());
            }
        }
        let d = BuiltinStateLaw::new(StateLawKind::Discontinuous, f64::NAN).unwrap();
        assert_eq!(d.state_variable(), StateVariable::Theta);
        assert_eq!(d.kind(), StateLawKind::Discontinuous);
        assert!(BuiltinStateLaw::new(StateLawKind::Aging, -1.0).is_err());
    }
}
