//! The package's exceptions: every `rsf::Error` becomes a Python exception of a named class
//! carrying the library's message (the class by the error's kind), so that no Rust error
//! or panic reaches Python as anything else.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _rsf,
    RsfError,
    PyException,
    "Base class of every error of the rsf package (the library's message)."
);
create_exception!(
    _rsf,
    InvalidParameterError,
    RsfError,
    "An invalid parameter, named in the message (a scene's field, a keyword argument, a \
     part of the model)."
);
create_exception!(
    _rsf,
    ModelError,
    RsfError,
    "A model that cannot be built: the mesh, a boundary part, the conditioning checks."
);
create_exception!(
    _rsf,
    ConvergenceError,
    RsfError,
    "A solver, fixed point iteration or step control that did not converge (iterations \
     and last corrections in the message)."
);
create_exception!(
    _rsf,
    CheckpointError,
    RsfError,
    "A checkpoint that cannot be read, is corrupt or belongs to another run (the differing \
     field named)."
);
create_exception!(
    _rsf,
    RsfIOError,
    RsfError,
    "A file that cannot be read or written (the path named), or a folder holding another \
     run's files."
);

/// The exception class of a library error: by its kind, the library's message kept.
pub(crate) fn to_py(e: rsf::Error) -> PyErr {
    use rsf::Error as E;
    let message = e.to_string();
    match e {
        E::InvalidParameter { .. }
        | E::Friction(_)
        | E::State(_)
        | E::Time(_)
        | E::UnknownName(_)
        | E::NodeOutOfRange { .. }
        | E::FreeNormal { .. }
        | E::StateVariableMismatch { .. }
        | E::StateLaw { .. }
        | E::MemoryBudget { .. }
        | E::GreensTooLarge { .. }
        | E::SceneFile(_) => InvalidParameterError::new_err(message),
        E::FixedPointNotConverged { .. }
        | E::Solver(_)
        | E::Direct(_)
        | E::HMatrix(_)
        | E::NormalStressNotPositive { .. }
        | E::TrialStateRefused { .. } => ConvergenceError::new_err(message),
        E::CheckpointSize { .. }
        | E::CheckpointValue { .. }
        | E::CheckpointCorrupt { .. }
        | E::CheckpointMismatch { .. }
        | E::Resume { .. } => CheckpointError::new_err(message),
        E::FileExists { .. } | E::File { .. } | E::Io(_) => RsfIOError::new_err(message),
        _ => ModelError::new_err(message),
    }
}

/// An invalid parameter `name` of the package itself (a keyword argument).
pub(crate) fn invalid(name: &str, reason: impl std::fmt::Display) -> PyErr {
    InvalidParameterError::new_err(format!("invalid parameter `{name}`: {reason}"))
}

/// The library's result as Python's.
pub(crate) trait OrPy<T> {
    /// The error as its exception class.
    fn py(self) -> PyResult<T>;
}

impl<T> OrPy<T> for rsf::Result<T> {
    fn py(self) -> PyResult<T> {
        self.map_err(to_py)
    }
}

impl<T> OrPy<T> for Result<T, rsf_seas::Error> {
    fn py(self) -> PyResult<T> {
        self.map_err(|e| to_py(e.into()))
    }
}

#[cfg(feature = "hdf5")]
impl<T> OrPy<T> for Result<T, rsf_hdf5::Error> {
    fn py(self) -> PyResult<T> {
        self.map_err(|e| to_py(e.into()))
    }
}

/// The refusal of `state_law="discontinuous"` with a rate-and-state law: that law evolves
/// θ itself (docs/math.md, "Discontinuous": α = θ), which Dieterich–Ruina's and the
/// regularised law read as ln θ.
pub(crate) fn discontinuous_needs_theta() -> PyErr {
    invalid(
        "state_law",
        "\"discontinuous\" evolves the state θ itself (α = θ, docs/math.md), while the \
         rate-and-state laws (dieterich_ruina, regularised, the sliders' law) read α as \
         ln θ: use \"aging\" or \"slip\" with them; the discontinuous law pairs with a \
         friction coefficient μ(θ) of the state (the Rust API's StateDependentTresca), or \
         with rsf.Friction.tresca, which does not use the state",
    )
}

/// Registers the classes on the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RsfError", py.get_type::<RsfError>())?;
    m.add(
        "InvalidParameterError",
        py.get_type::<InvalidParameterError>(),
    )?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("ConvergenceError", py.get_type::<ConvergenceError>())?;
    m.add("CheckpointError", py.get_type::<CheckpointError>())?;
    m.add("RsfIOError", py.get_type::<RsfIOError>())?;
    Ok(())
}
