//! What a method keeps beyond the common [`SimulationState`](crate::SimulationState): the
//! Runge–Kutta controller's memory and the right-hand side at the current point of a
//! [`FaultOde`](crate::FaultOde), the phase of a [`SwitchingRun`](crate::SwitchingRun).
//! A [`Checkpoint`](crate::Checkpoint) saves it beside the common state, so that every
//! method resumes bit-identically (docs/reliability.md).

use rsf_time::{RkcState, RungeKuttaState, StabilizedMemory, StepperMode};

/// The state of a [`FaultOde`](crate::FaultOde) beyond the common state.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FaultOdeState {
    /// The step controller's state: the next trial step (s) and the PI controller's memory.
    pub controller: RungeKuttaState,
    /// The right-hand side `f(t, y)` at the current point, `[V_F; α̇]` (m/s per free
    /// component on Γ_F, then 1/s per frictional node): the first stage of the next step
    /// (first same as last). Saved because re-evaluating it is not always bit-identical:
    /// a step that lands on an end time `t_e` evaluated it at `t + (t_e − t)`, which can
    /// differ from `t_e` in the last bit.
    pub rate: Vec<f64>,
    /// Right-hand-side evaluations so far (each one product with the condensed operator).
    pub evaluations: u64,
    /// With RKC2 (`rkc`, `auto`): the method in use, `auto`'s test counts and RKC2's
    /// memory (its controller, the spectral radius estimate and its eigenvector); `None`
    /// for an explicit pair alone, whose checkpoints keep the format of the runs before
    /// issue 84.
    pub stabilized: Option<StabilizedMemory>,
}

/// Values of a [`StabilizedMemory`] before its eigenvector.
const STABILIZED_HEADER: usize = 9;

impl FaultOdeState {
    /// `[dt, previous error, evaluations, rate…]`, or with RKC2's memory
    /// `[dt, previous error, evaluations, k, memory (k values), rate…]`.
    fn push_values(&self, out: &mut Vec<f64>) {
        out.push(self.controller.dt);
        out.push(self.controller.previous_error);
        out.push(self.evaluations as f64);
        if let Some(m) = &self.stabilized {
            let r = &m.rkc;
            out.push((STABILIZED_HEADER + r.eigenvector.len()) as f64);
            out.extend_from_slice(&[
                // RKC2's memory is never in ROS34PW2's mode (`rosenbrock` keeps none).
                match m.mode {
                    StepperMode::Explicit | StepperMode::Implicit => 0.0,
                    StepperMode::Stabilized => 1.0,
                },
                f64::from(m.streak),
                f64::from(m.calm),
                r.dt,
                r.previous_error,
                r.previous_dt,
                r.spectral_radius,
                r.since_estimate as f64,
                if r.estimate_due { 1.0 } else { 0.0 },
            ]);
            out.extend_from_slice(&r.eigenvector);
        }
        out.extend_from_slice(&self.rate);
    }

    /// The state written by [`push_values`](Self::push_values) (`stabilized`: with
    /// RKC2's memory).
    fn from_values(v: &[f64], stabilized: bool) -> std::result::Result<Self, String> {
        if v.len() < 3 {
            return Err("fault ODE state: fewer than 3 values".into());
        }
        let (dt, previous_error) = (v[0], v[1]);
        if !(dt > 0.0 && dt.is_finite() && previous_error > 0.0 && previous_error.is_finite()) {
            return Err(format!(
                "fault ODE controller: step {dt} s, previous error {previous_error}"
            ));
        }
        let evaluations = count(v[2], "evaluations")? as u64;
        let (memory, rate) = if stabilized {
            let k = count(*v.get(3).ok_or("RKC2 memory: no length")?, "RKC2 values")?;
            if k < STABILIZED_HEADER || v.len() < 4 + k {
                return Err(format!("RKC2 memory of {k} values in {} values", v.len()));
            }
            let m = &v[4..4 + k];
            let mode = match m[0] {
                0.0 => StepperMode::Explicit,
                1.0 => StepperMode::Stabilized,
                x => return Err(format!("integrator mode {x}")),
            };
            let small = |x: f64, what: &str| {
                count(x, what)
                    .and_then(|c| u32::try_from(c).map_err(|_| format!("{what} {x} too large")))
            };
            let rkc = RkcState {
                dt: m[3],
                previous_error: m[4],
                previous_dt: m[5],
                spectral_radius: m[6],
                since_estimate: count(m[7], "steps since the estimate")?,
                estimate_due: match m[8] {
                    0.0 => false,
                    1.0 => true,
                    x => return Err(format!("estimate due {x}")),
                },
                eigenvector: m[STABILIZED_HEADER..].to_vec(),
            };
            let finite_non_negative = [rkc.previous_error, rkc.previous_dt, rkc.spectral_radius]
                .iter()
                .all(|x| x.is_finite() && *x >= 0.0);
            if !(rkc.dt > 0.0 && rkc.dt.is_finite() && finite_non_negative) {
                return Err(format!(
                    "RKC2 controller: step {} s, previous error {}, previous step {} s, \
                     spectral radius {} 1/s",
                    rkc.dt, rkc.previous_error, rkc.previous_dt, rkc.spectral_radius
                ));
            }
            let memory = StabilizedMemory {
                mode,
                streak: small(m[1], "streak")?,
                calm: small(m[2], "calm")?,
                rkc,
            };
            (Some(memory), &v[4 + k..])
        } else {
            (None, &v[3..])
        };
        Ok(FaultOdeState {
            controller: RungeKuttaState { dt, previous_error },
            evaluations,
            rate: rate.to_vec(),
            stabilized: memory,
        })
    }
}

/// `x` as a count (exact below 2⁵³).
fn count(x: f64, what: &str) -> std::result::Result<usize, String> {
    if x >= 0.0 && x.fract() == 0.0 && x < 2f64.powi(53) {
        Ok(x as usize)
    } else {
        Err(format!("{what} {x} is not a count"))
    }
}

/// Which method of a [`SwitchingRun`](crate::SwitchingRun) is active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Phase {
    /// The quasi-dynamic fault ODE (the fault creeps).
    QuasiDynamic,
    /// The fully dynamic simulation with inertia (an event).
    Dynamic,
}

impl Phase {
    /// The phase's name (`quasi-dynamic`, `dynamic`).
    pub fn name(self) -> &'static str {
        match self {
            Phase::QuasiDynamic => "quasi-dynamic",
            Phase::Dynamic => "dynamic",
        }
    }
}

/// What a [`SwitchingRun`](crate::SwitchingRun) did so far.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SwitchingStats {
    /// Dynamic phases started.
    pub dynamic_phases: usize,
    /// Steps taken in dynamic phases.
    pub dynamic_steps: usize,
    /// Steps taken in quasi-dynamic phases.
    pub quasi_dynamic_steps: usize,
    /// Time spent in dynamic phases (s of simulated time).
    pub dynamic_time: f64,
}

/// The state of a method beyond the common [`SimulationState`](crate::SimulationState)
/// (which holds the implicit simulation's whole state, its step controller included).
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MethodState {
    /// The paper's implicit scheme ([`Simulation`](crate::Simulation)): nothing beyond
    /// the common state. Also what checkpoints of the earlier formats hold.
    #[default]
    Implicit,
    /// A quasi-dynamic run condensed onto the fault ([`FaultOde`](crate::FaultOde)).
    FaultOde(FaultOdeState),
    /// A switching run: its phase and statistics, and in the quasi-dynamic phase the fault
    /// ODE's state (the common state is the active method's).
    Switching {
        /// The active method.
        phase: Phase,
        /// What the run did so far.
        stats: SwitchingStats,
        /// The fault ODE's state (in the quasi-dynamic phase; `None` in the dynamic one,
        /// whose whole state is the common state).
        fault_ode: Option<FaultOdeState>,
    },
}

impl MethodState {
    /// The method's name: `implicit`, `fault-ode` or `switching`.
    pub fn name(&self) -> &'static str {
        match self {
            MethodState::Implicit => "implicit",
            MethodState::FaultOde(_) => "fault-ode",
            MethodState::Switching { .. } => "switching",
        }
    }

    /// The state as a tag and a list of values (exact: counts below 2⁵³ are exact in
    /// `f64`), for the checkpoint file. Tags: 0 implicit, 1 fault ODE, 2 switching; 3 and
    /// 4 the fault ODE and the switching run whose fault ODE holds RKC2's memory
    /// ([`FaultOdeState::stabilized`]; since issue 84).
    pub(crate) fn to_values(&self) -> (u64, Vec<f64>) {
        let with_rkc = |s: &FaultOdeState| u64::from(s.stabilized.is_some()) * 2;
        match self {
            MethodState::Implicit => (0, Vec::new()),
            MethodState::FaultOde(s) => {
                let mut out = Vec::with_capacity(3 + s.rate.len());
                s.push_values(&mut out);
                (1 + with_rkc(s), out)
            }
            MethodState::Switching {
                phase,
                stats,
                fault_ode,
            } => {
                let mut out = vec![
                    match phase {
                        Phase::QuasiDynamic => 0.0,
                        Phase::Dynamic => 1.0,
                    },
                    stats.dynamic_phases as f64,
                    stats.dynamic_steps as f64,
                    stats.quasi_dynamic_steps as f64,
                    stats.dynamic_time,
                ];
                if let Some(s) = fault_ode {
                    s.push_values(&mut out);
                }
                (2 + fault_ode.as_ref().map_or(0, with_rkc), out)
            }
        }
    }

    /// The state written by [`to_values`](Self::to_values).
    ///
    /// # Errors
    /// What is wrong, as text (an unknown tag, too few values, a count that is not a
    /// non-negative integer, a non-finite controller value).
    pub(crate) fn from_values(tag: u64, values: &[f64]) -> std::result::Result<Self, String> {
        match tag {
            0 if values.is_empty() => Ok(MethodState::Implicit),
            0 => Err("implicit method with method values".into()),
            1 | 3 => Ok(MethodState::FaultOde(FaultOdeState::from_values(
                values,
                tag == 3,
            )?)),
            2 | 4 => {
                if values.len() < 5 {
                    return Err("switching state: fewer than 5 values".into());
                }
                let phase = match values[0] {
                    0.0 => Phase::QuasiDynamic,
                    1.0 => Phase::Dynamic,
                    x => return Err(format!("switching phase {x}")),
                };
                let stats = SwitchingStats {
                    dynamic_phases: count(values[1], "dynamic phases")?,
                    dynamic_steps: count(values[2], "dynamic steps")?,
                    quasi_dynamic_steps: count(values[3], "quasi-dynamic steps")?,
                    dynamic_time: values[4],
                };
                if !(stats.dynamic_time >= 0.0 && stats.dynamic_time.is_finite()) {
                    return Err(format!("dynamic time {} s", stats.dynamic_time));
                }
                let rest = &values[5..];
                let fault_ode = match phase {
                    Phase::QuasiDynamic => Some(FaultOdeState::from_values(rest, tag == 4)?),
                    Phase::Dynamic if rest.is_empty() && tag == 2 => None,
                    Phase::Dynamic => return Err("dynamic phase with fault ODE values".into()),
                };
                Ok(MethodState::Switching {
                    phase,
                    stats,
                    fault_ode,
                })
            }
            t => Err(format!("unknown method tag {t}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_round_trip() {
        let ode = FaultOdeState {
            controller: RungeKuttaState {
                dt: 0.25,
                previous_error: 1e-4,
            },
            rate: vec![1.0, -2.5e-300, 3.0],
            evaluations: 12345,
            stabilized: None,
        };
        let with_rkc = FaultOdeState {
            stabilized: Some(StabilizedMemory {
                mode: StepperMode::Stabilized,
                streak: 3,
                calm: 1,
                rkc: RkcState {
                    dt: 2.5,
                    previous_error: 0.3,
                    previous_dt: 1.5,
                    spectral_radius: 1.25e-6,
                    since_estimate: 7,
                    estimate_due: false,
                    eigenvector: vec![0.5, -1e-300, 2.0],
                },
            }),
            ..ode.clone()
        };
        for s in [
            MethodState::Implicit,
            MethodState::FaultOde(with_rkc.clone()),
            MethodState::Switching {
                phase: Phase::QuasiDynamic,
                stats: SwitchingStats::default(),
                fault_ode: Some(with_rkc),
            },
            MethodState::FaultOde(ode.clone()),
            MethodState::Switching {
                phase: Phase::QuasiDynamic,
                stats: SwitchingStats {
                    dynamic_phases: 2,
                    dynamic_steps: 30,
                    quasi_dynamic_steps: 400,
                    dynamic_time: 12.5,
                },
                fault_ode: Some(ode),
            },
            MethodState::Switching {
                phase: Phase::Dynamic,
                stats: SwitchingStats::default(),
                fault_ode: None,
            },
        ] {
            let (tag, v) = s.to_values();
            assert_eq!(MethodState::from_values(tag, &v), Ok(s));
        }
        assert!(MethodState::from_values(1, &[1.0, 1.0]).is_err());
        assert!(MethodState::from_values(1, &[0.0, 1e-4, 0.0]).is_err());
        assert!(MethodState::from_values(2, &[3.0, 0.0, 0.0, 0.0, 0.0]).is_err());
        assert!(MethodState::from_values(2, &[0.0, 0.5, 0.0, 0.0, 0.0]).is_err());
        assert!(MethodState::from_values(7, &[]).is_err());
    }
}
