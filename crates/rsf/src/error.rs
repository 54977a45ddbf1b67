//! Error type of the composition crate.

use rsf_state::StateVariable;

/// Errors of models, simulations, scenes and their output.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
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
    /// The compressed (hierarchical) fault operator of a run condensed onto the fault
    /// ([`FaultKernel::Hierarchical`](crate::fault_ode::FaultKernel::Hierarchical)): its
    /// set-up (an SVD that did not converge, a non-finite entry) or product.
    #[error(transparent)]
    HMatrix(#[from] rsf_hmatrix::Error),
    /// Velocity solver TNNMG or nonlinear Gauss–Seidel (including its non-convergence), or
    /// TNNMG as the initial equilibrium's linear multigrid.
    #[error(transparent)]
    Solver(#[from] rsf_tnnmg::Error),
    /// The direct velocity solver (including its non-convergence) or the condensation onto
    /// the fault (the fault ODE's, the normal stress's), e.g. an interior ordering whose
    /// cargo feature is off.
    #[error(transparent)]
    Direct(#[from] rsf_direct::Error),
    /// The fixed point iteration of a time step did not converge within its budget.
    #[error(
        "fixed point iteration of step {step} (t = {time:.6e} s) did not converge in {iterations} \
         iterations; last velocity corrections (energy norm): {}",
        last_corrections(history)
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
    /// [`SolverKind::Auto`](crate::SolverKind::Auto) found no solver within the memory
    /// budget ([`SolverOptions::memory_budget_bytes`](crate::method::SolverOptions)): the direct
    /// solver needs more and the model has no refinement hierarchy for TNNMG.
    #[error(
        "the direct solver needs about {needed_bytes} bytes (budget {budget_bytes} bytes) and \
         the model has no refinement hierarchy for TNNMG; raise the budget, refine the mesh \
         with a hierarchy or choose a solver explicitly"
    )]
    MemoryBudget {
        /// The direct solver's estimate ([`rsf_direct::DirectMemory::total_bytes`]).
        needed_bytes: usize,
        /// The budget.
        budget_bytes: usize,
    },
    /// The effective normal stress of a frictional node — of a fault inside the body
    /// ([`NormalStress::FromSlip`](crate::normal_stress::NormalStress::FromSlip)), or
    /// lowered by a pore pressure ([`crate::pore_pressure`]) — would reach zero or below
    /// (the fault would open, which the model does not allow) or is not finite.
    #[error(
        "the normal stress of frictional node {node} would be {sigma_n:e} Pa at t = {time:e} \
         s: the slip or the pore pressure unclamps the fault until it opens, which the \
         model (tied normal jump) does not represent"
    )]
    NormalStressNotPositive {
        /// The frictional node (position along Γ_F).
        node: usize,
        /// The time (s).
        time: f64,
        /// The normal stress it would have (Pa, compressive positive).
        sigma_n: f64,
    },
    /// A time step of the implicit scheme whose trial state — a fixed-point iterate or
    /// the state it converged to — was refused ([`Error::NormalStressNotPositive`]: the
    /// reason) and that cannot be retried smaller: the step is fixed, or the step control
    /// is at `tau_min`. An adaptive step retries a smaller one first (counted in
    /// [`StepReport::rejected_normal_stress`](crate::StepReport::rejected_normal_stress));
    /// the fault ODE's counterpart is [`rsf_time::Error::TrialPointRefused`]
    /// (docs/reliability.md, "Trial points outside the domain").
    #[error(
        "step {step} from t = {time:e} s: {refusals} attempt(s) refused, the last with \
         τ = {tau:e} s because {reason}; {remedy}"
    )]
    #[non_exhaustive]
    TrialStateRefused {
        /// The step index (1-based) that failed.
        step: usize,
        /// The time of the accepted state it starts from (s).
        time: f64,
        /// The last step size tried (s).
        tau: f64,
        /// Attempts of this step refused for the reason's kind.
        refusals: usize,
        /// The refusal of the last attempt.
        #[source]
        reason: Box<Error>,
        /// What to change.
        remedy: &'static str,
    },
    /// The dense Green's functions of a fault operator (or a block of them) were asked
    /// for above the caller's limit ([`GreensFunctions::dense`](crate::greens::GreensFunctions::dense),
    /// [`GreensFunctions::block`](crate::greens::GreensFunctions::block)).
    #[error(
        "the dense Green's functions of {unknowns} source slip unknowns ({bytes:.3e} bytes, \
         {unknowns} products with the operator) exceed the limit of {limit} unknowns; \
         apply the operator matrix-free (GreensFunctions::apply) or raise the limit"
    )]
    GreensTooLarge {
        /// The source unknowns asked for (the columns: `m` for the whole matrix).
        unknowns: usize,
        /// The caller's limit.
        limit: usize,
        /// Bytes of the dense matrix or block (`8 m²`, `8 m_r m_s`).
        bytes: f64,
    },
    /// An invalid parameter, named (a field of a scene or builder, an argument).
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter name (the TOML field for scenes).
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// The scales of an assembled problem (stiffness, mass, load, displacements, slip
    /// distance) cannot be computed or resolved in double precision
    /// ([`ProblemScales::check`](crate::model::ProblemScales::check), docs/reliability.md).
    #[error(
        "the problem cannot be resolved in double precision: {reason}; change {}",
        fields.join(", ")
    )]
    IllConditioned {
        /// The fields (scene fields as TOML names them) that set the failed quantity.
        fields: Vec<String>,
        /// The quantity, its value and the admissible range.
        reason: String,
    },
    /// A mesh vertex id outside the model.
    #[error("{what}: vertex {node} is out of range (the model has {nodes} vertices)")]
    NodeOutOfRange {
        /// What the vertex was given for.
        what: &'static str,
        /// The vertex id (an index into `model.vertices`).
        node: usize,
        /// Number of nodes of the model.
        nodes: usize,
    },
    /// A frictional node whose velocity components are all free: with bilateral contact
    /// the normal component must be fixed, or the fault opens (|v_n| > 0 on Γ_F).
    #[error(
        "frictional node at vertex {node} has no fixed velocity component: bilateral contact needs the \
         normal component fixed on the frictional boundary"
    )]
    FreeNormal {
        /// The mesh vertex id.
        node: usize,
    },
    /// A model without frictional nodes — a fault inside the body whose every pair's slip
    /// is prescribed ([`ModelBuilder::internal_slip_at`](crate::ModelBuilder::internal_slip_at)):
    /// a static problem, solved when the model is built
    /// ([`Model::initial_displacement`](crate::Model::initial_displacement)); what needs a
    /// frictional node (a simulation, the fault ODE) refuses it by name.
    #[error(
        "{what} needs a frictional node, and the model has none: every pair of its fault \
         inside the body has a prescribed slip (a kinematic source, whose static \
         displacement is the model's initial_displacement)"
    )]
    NoFrictionalNode {
        /// What needed one (e.g. "a simulation").
        what: &'static str,
    },
    /// The friction law and the state law disagree on what the state α is (e.g. the
    /// discontinuous law, α = θ, with Dieterich–Ruina friction, α = ln θ).
    #[error(
        "frictional node k = {node} (position on the frictional boundary): the friction law expects the state as {}, the state law \
         evolves {}",
        describe(*friction),
        describe(*state)
    )]
    StateVariableMismatch {
        /// Position `k` of the node on Γ_F (an index into
        /// `model.frictional_boundary.nodes`, not a mesh vertex id).
        node: usize,
        /// What the friction law expects.
        friction: StateVariable,
        /// What the state law evolves.
        state: StateVariable,
    },
    /// The state law of a frictional node failed its monotonicity probe. The message
    /// includes the cause (it is also [`source`](std::error::Error::source)).
    #[error(
        "state law of frictional node k = {node} (position on the frictional boundary, \
         model.frictional_boundary.nodes[{node}]): {source}"
    )]
    StateLaw {
        /// Position `k` of the node on Γ_F (an index into
        /// `model.frictional_boundary.nodes`, not a mesh vertex id).
        node: usize,
        /// What the probe found.
        #[source]
        source: rsf_state::Error,
    },
    /// A boundary part of a model description cannot be used as asked.
    #[error("boundary part `{part}`: {reason}")]
    BoundaryPart {
        /// The part's name (tag or given name).
        part: String,
        /// What is wrong.
        reason: String,
    },
    /// The frictional boundary has a corner at a node: two of the boundary facets meeting
    /// there have outer normals further apart than the builder's limit
    /// ([`ModelBuilder::max_fault_kink`](crate::ModelBuilder::max_fault_kink)), so no
    /// single normal (and nodal frame, docs/math.md §10) describes the node. Split the
    /// fault into parts, or smooth the geometry.
    #[error(
        "frictional boundary `{part}`: node {node} at {position:?} is a corner: adjacent facet \
         normals differ by {angle_degrees:.3}° (limit {limit_degrees}°), the normal and the \
         nodal frame are ill-defined there"
    )]
    FaultCorner {
        /// The part's name.
        part: String,
        /// The mesh vertex id (an index into `model.vertices`, not a fault index).
        node: usize,
        /// Its coordinates (m).
        position: Vec<f64>,
        /// The largest angle between the outer normals of two facets at the node (degrees).
        angle_degrees: f64,
        /// The limit it exceeds (degrees).
        limit_degrees: f64,
    },
    /// A facet of the frictional boundary has (numerically) zero measure, so its normal is
    /// undefined.
    #[error(
        "frictional boundary `{part}`: facet {facet} at node {node} has zero measure \
         ({measure:e}); its normal, and the nodal frame, are undefined"
    )]
    DegenerateFaultFacet {
        /// The part's name.
        part: String,
        /// A vertex id of the facet.
        node: usize,
        /// The boundary facet index ([`SimplexMesh::boundary_facet`](rsf_fem::SimplexMesh::boundary_facet)).
        facet: usize,
        /// Its measure (m in 2D, m² in 3D).
        measure: f64,
    },
    /// The outer normals of the frictional facets at a node cancel (their area-weighted
    /// mean is shorter than 10⁻⁶ of the facets' total measure): the boundary folds back on
    /// itself there, e.g. at the tip of a crack whose two faces are both in Γ_F (coincident
    /// facets with opposite normals). No normal, and no nodal frame, is defined; raised when
    /// [`ModelBuilder::max_fault_kink`](crate::ModelBuilder::max_fault_kink) admits the
    /// 180° fold (below that limit the node is an [`Error::FaultCorner`]).
    #[error(
        "frictional boundary `{part}`: node {node} at {position:?}: the outer normals of its \
         facets cancel (the boundary folds back on itself), the normal and the nodal frame \
         are undefined there"
    )]
    FaultFoldsBack {
        /// The part's name.
        part: String,
        /// The mesh vertex id (an index into `model.vertices`, not a fault index).
        node: usize,
        /// Its coordinates (m).
        position: Vec<f64>,
    },
    /// The initial equilibrium `K u₀ = F` has no unique solution under the constraints.
    /// The message includes the solver's cause (it is also
    /// [`source`](std::error::Error::source)).
    #[error(
        "the initial equilibrium K u0 = F has no unique solution under the constraints \
         (do the Dirichlet and frictional-normal constraints remove every rigid motion?): {0}"
    )]
    Equilibrium(#[source] rsf_fem::Error),
    /// A scene file could not be parsed (unknown fields are named here).
    #[error("scene file: {0}")]
    SceneFile(String),
    /// A checkpoint whose sizes do not fit the simulation it should continue
    /// ([`Simulation::restore`](crate::Simulation::restore)).
    #[error(
        "the checkpoint does not fit this simulation: its {what} is {checkpoint}, this \
         simulation's is {simulation}"
    )]
    CheckpointSize {
        /// What differs: `space dimension`, `number of nodes`, `length of u` (when not a
        /// multiple of the dimension), `length of v`, `length of a`, `number of frictional
        /// nodes (length of alpha)`.
        what: &'static str,
        /// Its value in the checkpoint.
        checkpoint: usize,
        /// Its value in the simulation.
        simulation: usize,
    },
    /// A checkpoint with a value a simulation cannot continue from: not finite, a negative
    /// time, a non-positive time step ([`Simulation::restore`](crate::Simulation::restore)).
    #[error("the checkpoint's {what} is {value:e} at entry {index}: {requirement}")]
    CheckpointValue {
        /// Which value: `time`, `time step tau`, `u`, `v`, `a`, `alpha`.
        what: &'static str,
        /// The entry (0 for scalars).
        index: usize,
        /// The value.
        value: f64,
        /// What is required.
        requirement: &'static str,
    },
    /// A run could not progress: its step size collapsed — it stayed at the method's
    /// floor, or the run's stated number of steps did not reach its end time
    /// ([`run_until`](crate::run_until)) — as an ODE solver reports a step-size underflow.
    #[error(
        "the run cannot progress at t = {time:e} s: {reason} (the last step τ = {tau:e} s, the \
         last rejected attempt's scaled error estimate {rejected_error:e}; 1 is the \
         tolerance): the step control cannot meet the tolerance there — check the model and \
         the tolerance, or raise the bound if the steps are right"
    )]
    StepSizeCollapse {
        /// Time of the last accepted step (s).
        time: f64,
        /// Its step size (s).
        tau: f64,
        /// The scaled error estimate of the last rejected attempt (∞ without a finite
        /// estimate, 0 if none was rejected).
        rejected_error: f64,
        /// Which bound was met.
        reason: String,
    },
    /// A run stopped at its step cap (`--max-steps`, [`Until::TimeOrStepCap`](crate::Until))
    /// before its end time: not a failure of the numerics but an outcome the caller asked
    /// for. The run's files are complete up to the step, and with `checkpoint` it continues
    /// from there (`--resume` with a larger cap).
    #[error(
        "the run reached its step cap of {step_cap} steps (`max_steps`) at step {step} \
         (t = {time:.6e} s of T = {end_time:e} s): {}",
        match checkpoint {
            Some(path) => format!(
                "its files and `{path}` are complete up to that step; continue with --resume \
                 and a larger --max-steps (or output bound)"
            ),
            None => "its files describe the run up to there; raise --max-steps or \
                     --max-output-gb, or shorten the end time"
                .to_string(),
        }
    )]
    StepCapReached {
        /// The cap (steps in total, across resumes).
        step_cap: usize,
        /// The step the run stopped at.
        step: usize,
        /// Its time (s).
        time: f64,
        /// The end time the run did not reach (s).
        end_time: f64,
        /// The checkpoint written at that step to continue from, if any.
        checkpoint: Option<String>,
    },
    /// A run ([`run_folder::Session::run`](crate::run_folder::Session::run)) failed after
    /// `steps` steps; the cause is its source (the [`RunError`](crate::RunError) of the
    /// steps, as an [`Error`]).
    #[error("the run failed after {steps} steps")]
    RunFailed {
        /// The steps taken before the failure (this invocation's).
        steps: usize,
        /// What failed.
        #[source]
        source: Box<Error>,
    },
    /// A resume whose end time lies before the checkpoint's time
    /// ([`run_folder::Session::start`](crate::run_folder::Session::start)): a resume
    /// continues a run forward (issue 87: such a resume exited with "0 steps").
    #[error(
        "the run's end, t = {} s, is before the checkpoint's time t = {} s (step {step}): a \
         resume continues a run forward; give an end time after the checkpoint's",
        rsf_numeric::number(*end_time),
        rsf_numeric::number(*time)
    )]
    EndBeforeCheckpoint {
        /// The run's end time (s).
        end_time: f64,
        /// The checkpoint's time (s).
        time: f64,
        /// The checkpoint's step.
        step: usize,
    },
    /// An output file (or a run folder) cannot be continued from a checkpoint.
    #[error("cannot resume `{path}`: {reason}")]
    Resume {
        /// The output file or folder.
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// A name that is not one of a choice's names.
    #[error(transparent)]
    UnknownName(#[from] rsf_numeric::UnknownName),
    /// A checkpoint file that is damaged (checksum, length or a field out of range): it is
    /// never resumed.
    #[error("checkpoint `{path}` is corrupt ({reason}); it is not resumed")]
    CheckpointCorrupt {
        /// The checkpoint file (at most about 100 characters of it).
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// A checkpoint written by a run of other physics or method than the run it should
    /// continue ([`Fingerprint::check`](crate::checkpoint::Fingerprint::check)).
    #[error(
        "the checkpoint belongs to another run: its `{field}` is {checkpoint}, this run's is \
         {run} (allow a deliberate change of `{field}` explicitly)"
    )]
    CheckpointMismatch {
        /// The differing field (a scene field, or `format`).
        field: String,
        /// Its value in the checkpoint (at most about 100 characters).
        checkpoint: String,
        /// Its value in this run (at most about 100 characters).
        run: String,
    },
    /// A file or folder that exists where a new one would be written: refused so that no
    /// result is lost ([`FileMode::Create`](crate::observe::FileMode::Create)).
    #[error("`{path}` exists and is not empty: {reason}")]
    FileExists {
        /// The file (at most about 100 characters of it).
        path: String,
        /// How to go on.
        reason: String,
    },
    /// An I/O operation on a named file or folder failed.
    #[error("cannot {action} `{path}`: {source}")]
    File {
        /// The file or folder (at most about 100 characters of it).
        path: String,
        /// What was being done (e.g. `create`, `read`, `rename into`).
        action: &'static str,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
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

/// `Ok` where `len == expected`, else [`Error::InvalidParameter`] named `name` with the
/// reason `reason(len, expected)` (e.g. a vector of another length than the model's).
pub(crate) fn check_len(
    name: &str,
    len: usize,
    expected: usize,
    reason: impl FnOnce(usize, usize) -> String,
) -> Result<()> {
    if len == expected {
        Ok(())
    } else {
        Err(invalid(name, reason(len, expected)))
    }
}

/// `Ok` where the normal stress `sigma_n` (Pa, compressive positive) of frictional node
/// `node` at `time` (s) is positive and finite, else [`Error::NormalStressNotPositive`].
pub(crate) fn check_normal_stress(node: usize, time: f64, sigma_n: f64) -> Result<()> {
    if sigma_n > 0.0 && sigma_n.is_finite() {
        Ok(())
    } else {
        Err(Error::NormalStressNotPositive {
            node,
            time,
            sigma_n,
        })
    }
}

/// A path as error messages quote it (at most about 100 characters).
pub(crate) fn show_path(path: &std::path::Path) -> String {
    rsf_numeric::excerpt(&path.display().to_string())
}

/// A closure turning an I/O error into [`Error::File`] for `action` on `path`.
pub(crate) fn io_at<'a>(
    action: &'static str,
    path: &'a std::path::Path,
) -> impl Fn(std::io::Error) -> Error + 'a {
    move |source| Error::File {
        path: show_path(path),
        action,
        source,
    }
}

fn describe(s: StateVariable) -> &'static str {
    match s {
        StateVariable::LogTheta => "alpha = ln(theta)",
        StateVariable::Theta => "alpha = theta",
    }
}

/// The last three entries of a correction history, formatted.
fn last_corrections(history: &[f64]) -> String {
    let tail = &history[history.len().saturating_sub(3)..];
    let list: Vec<String> = tail.iter().map(|c| format!("{c:.3e}")).collect();
    if history.len() > tail.len() {
        format!("…, {}", list.join(", "))
    } else {
        list.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::Error;

    #[test]
    fn a_fixed_point_failure_shows_the_last_corrections_only() {
        let e = Error::FixedPointNotConverged {
            step: 7,
            time: 0.5,
            iterations: 100,
            history: (0..100).map(f64::from).collect(),
        };
        let msg = e.to_string();
        assert!(msg.ends_with("…, 9.700e1, 9.800e1, 9.900e1"), "{msg}");
        assert!(msg.len() < 200, "{msg}");
    }
}
