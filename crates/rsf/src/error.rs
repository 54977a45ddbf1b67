//! Error type of the composition crate.

/// Errors of scenes, simulations and their output.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Finite elements (mesh, assembly, constraints).
    #[error(transparent)]
    Fem(#[from] rsf_fem::Error),
    /// Friction law parameters.
    #[error(transparent)]
    Friction(#[from] rsf_friction::Error),
    /// State law update.
    #[error(transparent)]
    State(#[from] rsf_state::Error),
    /// Time integrator.
    #[error(transparent)]
    Time(#[from] rsf_time::Error),
    /// Velocity solver (including its non-convergence).
    #[error(transparent)]
    Solver(#[from] rsf_tnnmg::Error),
    /// The fixed point iteration of a time step did not converge within its budget.
    #[error(
        "fixed point iteration of step {step} (t = {time:.6e} s) did not converge in {iterations} \
         iterations; velocity corrections (energy norm): {history:?}"
    )]
    FixedPointNotConverged {
        /// Time step index (1-based).
        step: usize,
        /// Time t_n (s).
        time: f64,
        /// Iterations performed.
        iterations: usize,
        /// ‖v^{ν+1} − v^ν‖ for every iteration.
        history: Vec<f64>,
    },
    /// An invalid scene or simulation parameter, named.
    #[error("invalid scene parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter (TOML field) name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A scene file could not be parsed (unknown fields are named here).
    #[error("scene file: {0}")]
    SceneFile(String),
    /// Checkpoint does not match the simulation or is corrupt.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// Output could not be written.
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

pub(crate) fn invalid(name: &str, reason: impl Into<String>) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        reason: reason.into(),
    }
}
