//! The built-in velocity integrators as one run-time choice ([`Integrator`]), for scenes
//! and command lines that choose the integrator by name.

use crate::{BackwardEuler, Error, Kinematics, Newmark, Quasistatic, Result, VelocityIntegrator};

/// A built-in velocity integrator chosen at run time. Every [`VelocityIntegrator`] method
/// forwards to the integrator, so results are its own, bit for bit.
///
/// Names (`name`, `FromStr`, clap): `newmark`, `backward-euler`, `quasistatic` (the latter
/// without radiation damping; with it, build [`Quasistatic::with_radiation_damping`]).
/// In serde (scene files) the same names, or `{ quasistatic = { radiation_damping = η } }`
/// with `η` in Pa·s/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// See [`Newmark`] (β = ¼, γ = ½; paper (3.1)–(3.4)).
    Newmark,
    /// See [`BackwardEuler`].
    BackwardEuler,
    /// See [`Quasistatic`] (no inertia; optional radiation damping).
    Quasistatic(Quasistatic),
}

impl Default for Integrator {
    /// Newmark, the paper's.
    fn default() -> Self {
        Self::Newmark
    }
}

impl Integrator {
    /// The name (`newmark`, `backward-euler`, `quasistatic`); the same as
    /// [`VelocityIntegrator::name`], without the trait in scope.
    pub fn name(&self) -> &'static str {
        VelocityIntegrator::name(self)
    }

    /// Every integrator (quasistatic without radiation damping), in declaration order.
    pub const ALL: [Integrator; 3] = [
        Self::Newmark,
        Self::BackwardEuler,
        Self::Quasistatic(Quasistatic::new()),
    ];
}

rsf_numeric::display_and_parse_by_name!(Integrator, "integrator", Error, Integrator::ALL);

macro_rules! dispatch {
    ($self:ident, $i:ident => $e:expr) => {
        match $self {
            Integrator::Newmark => {
                let $i = &Newmark;
                $e
            }
            Integrator::BackwardEuler => {
                let $i = &BackwardEuler;
                $e
            }
            Integrator::Quasistatic($i) => $e,
        }
    };
}

impl VelocityIntegrator for Integrator {
    fn name(&self) -> &'static str {
        dispatch!(self, i => i.name())
    }
    fn uses_mass(&self) -> bool {
        dispatch!(self, i => i.uses_mass())
    }
    fn coefficients(&self, tau: f64) -> (f64, f64) {
        dispatch!(self, i => i.coefficients(tau))
    }
    fn radiation_damping(&self) -> f64 {
        dispatch!(self, i => i.radiation_damping())
    }
    fn load_combinations(
        &self,
        tau: f64,
        prev: &Kinematics,
        w_mass: &mut [f64],
        w_stiffness: &mut [f64],
    ) -> Result<()> {
        dispatch!(self, i => i.load_combinations(tau, prev, w_mass, w_stiffness))
    }
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics) {
        dispatch!(self, i => i.advance(tau, prev, v_new, next))
    }
    fn displacement_error(&self, tau: f64, prev: &Kinematics, next: &Kinematics, out: &mut [f64]) {
        dispatch!(self, i => i.displacement_error(tau, prev, next, out))
    }
}

#[cfg(feature = "clap")]
rsf_numeric::clap_value_enum!(Integrator, |i| match i {
    Integrator::Newmark => "Newmark, β = ¼, γ = ½ (the paper's)",
    Integrator::BackwardEuler => "Backward Euler for the velocity",
    Integrator::Quasistatic(_) => "Quasistatic (no inertia)",
});

#[cfg(feature = "serde")]
mod serde_impl {
    use super::{Integrator, Quasistatic};
    use serde::{de::Error as _, Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Damping {
        #[serde(default)]
        radiation_damping: f64,
    }

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Table {
        quasistatic: Damping,
    }

    #[derive(Serialize, Deserialize)]
    #[serde(untagged)]
    enum Repr {
        Name(String),
        Table(Table),
    }

    impl Serialize for Integrator {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            use crate::VelocityIntegrator;
            match self {
                Integrator::Quasistatic(q) if q.radiation_damping() != 0.0 => Repr::Table(Table {
                    quasistatic: Damping {
                        radiation_damping: q.radiation_damping(),
                    },
                })
                .serialize(s),
                other => s.serialize_str(other.name()),
            }
        }
    }

    impl<'de> Deserialize<'de> for Integrator {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            match Repr::deserialize(d).map_err(|_| {
                D::Error::custom(
                    "expected an integrator name (newmark, backward-euler, quasistatic) or \
                     { quasistatic = { radiation_damping = <Pa s/m> } }",
                )
            })? {
                Repr::Name(name) => name.parse().map_err(D::Error::custom),
                Repr::Table(t) => {
                    Quasistatic::with_radiation_damping(t.quasistatic.radiation_damping)
                        .map(Integrator::Quasistatic)
                        .map_err(D::Error::custom)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for i in Integrator::ALL {
            assert_eq!(i.name().parse::<Integrator>().unwrap(), i);
        }
        assert!("newmarc".parse::<Integrator>().is_err());
    }

    /// The run-time choice gives the bits of the integrator it stands for.
    #[test]
    fn dispatch_is_bit_identical() {
        let n = 4;
        let prev = Kinematics {
            u: vec![1e-3, -2e-4, 3.5e-5, 0.0],
            v: vec![1e-6, 2e-2, -3e-4, 1.0],
            a: vec![0.1, -0.2, 3.0, 0.0],
        };
        let v_new = [2e-6, 1e-2, -1e-4, 0.5];
        let tau = 1.5e-3;
        type Direct<'a> = &'a dyn Fn(&mut Kinematics, &mut [f64], &mut [f64]);
        let check = |choice: Integrator, direct: Direct| {
            let (mut a, mut b) = (Kinematics::zeros(n), Kinematics::zeros(n));
            let (mut wm_a, mut wk_a, mut wm_b, mut wk_b) =
                (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            choice.advance(tau, &prev, &v_new, &mut a);
            choice
                .load_combinations(tau, &prev, &mut wm_a, &mut wk_a)
                .unwrap();
            direct(&mut b, &mut wm_b, &mut wk_b);
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a.u), bits(&b.u));
            assert_eq!(bits(&a.a), bits(&b.a));
            assert_eq!(bits(&wm_a), bits(&wm_b));
            assert_eq!(bits(&wk_a), bits(&wk_b));
        };
        check(Integrator::Newmark, &|k, wm, wk| {
            Newmark.advance(tau, &prev, &v_new, k);
            Newmark.load_combinations(tau, &prev, wm, wk).unwrap();
        });
        check(Integrator::BackwardEuler, &|k, wm, wk| {
            BackwardEuler.advance(tau, &prev, &v_new, k);
            BackwardEuler.load_combinations(tau, &prev, wm, wk).unwrap();
        });
        let q = Quasistatic::with_radiation_damping(3.0).unwrap();
        check(Integrator::Quasistatic(q), &|k, wm, wk| {
            q.advance(tau, &prev, &v_new, k);
            q.load_combinations(tau, &prev, wm, wk).unwrap();
        });
        assert_eq!(Integrator::Quasistatic(q).radiation_damping(), 3.0);
    }
}
