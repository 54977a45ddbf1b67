//! The choice of method apart from the problem: [`MethodKind`].

/// Which method advances a problem in time.
///
/// Names (`name`, `FromStr`, serde, clap): `implicit`, `fault-ode`, `switching`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodKind {
    /// The paper's implicit scheme ([`Simulation`](crate::Simulation)): a velocity integrator (Newmark,
    /// backward Euler or quasistatic), each step a fixed point of a convex velocity problem
    /// (TNNMG or the direct solver) and the state update (docs/math.md §2–4).
    #[default]
    Implicit,
    /// Quasi-dynamic, condensed onto the fault and integrated by an explicit embedded
    /// Runge–Kutta pair ([`FaultOde`](crate::FaultOde), docs/math.md §12): needs radiation damping and no
    /// inertia.
    FaultOde,
    /// The fault ODE between events and the implicit scheme with inertia during them
    /// ([`SwitchingRun`](crate::SwitchingRun)).
    Switching,
}

impl MethodKind {
    /// Every kind, in declaration order.
    pub const ALL: [MethodKind; 3] = [Self::Implicit, Self::FaultOde, Self::Switching];

    /// The name (`implicit`, `fault-ode`, `switching`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Implicit => "implicit",
            Self::FaultOde => "fault-ode",
            Self::Switching => "switching",
        }
    }
}

// `Display` (the name) and `FromStr` (a name; `runge-kutta` is accepted for `fault-ode`).
rsf_numeric::display_and_parse_by_name!(
    MethodKind,
    "method",
    crate::Error,
    MethodKind::ALL,
    [("runge-kutta", MethodKind::FaultOde)]
);

#[cfg(test)]
mod tests {
    use super::MethodKind;

    #[test]
    fn names_round_trip() {
        for k in MethodKind::ALL {
            assert_eq!(k.name().parse::<MethodKind>().unwrap(), k);
        }
        assert_eq!(
            "runge-kutta".parse::<MethodKind>().unwrap(),
            MethodKind::FaultOde
        );
        assert!("rk4".parse::<MethodKind>().is_err());
    }
}
