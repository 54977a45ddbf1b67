//! Command-line parsing shared by the examples (clap derive) and how they end: errors are
//! printed with `Display` and their causes, the exit code is non-zero.

use std::path::{Path, PathBuf};

use rsf::fem::Diagonal;
use rsf::method::{FixedPointScheme, StateIntegrator};
use rsf::observe::{Every, FileMode, Interval, VtuFrames};
use rsf::{Integrator, SolverKind, StateLawKind};
use rsf_scenes::{AdaptiveTimeStep, SliderScene, TimeStep};

/// The scene flags every slider example accepts; unset flags keep the scene's value.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SceneArgs {
    /// Scene file (TOML, fields of `rsf_scenes::SliderScene`); flags override it.
    #[arg(long, value_name = "FILE.toml")]
    pub scene: Option<PathBuf>,
    /// Refinement level j of the coarse 2 × 6-vertex grid, in [0, 10] (beyond, the mesh
    /// does not fit in memory).
    #[arg(long, value_name = "J")]
    pub level: Option<usize>,
    /// Final time T (s): positive, at most 1e10 (beyond, the time loses the digits of the
    /// steps); the step T/N must give finite coefficients of the step's matrix.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub end_time: Option<f64>,
    /// State law.
    #[arg(long, value_enum)]
    pub law: Option<StateLawKind>,
    /// State update (docs/friction-state.md).
    #[arg(long, value_enum)]
    pub state_integrator: Option<StateIntegrator>,
    /// Velocity integrator.
    #[arg(long, value_enum)]
    pub integrator: Option<Integrator>,
    /// Velocity solver.
    #[arg(long, value_enum)]
    pub solver: Option<SolverKind>,
    /// Fixed point scheme.
    #[arg(long, value_enum)]
    pub fixed_point: Option<FixedPointScheme>,
    /// Triangulation diagonal of the coarse grid.
    #[arg(long, value_enum)]
    pub diagonal: Option<Diagonal>,
    /// The block's ends x = 0 and x = 5 m absorb waves (Lysmer–Kuhlemeyer dashpots,
    /// `SliderScene::absorbing_sides`) instead of being traction-free.
    #[arg(long)]
    pub absorbing_sides: bool,
}

impl SceneArgs {
    /// `base` (or the `--scene` file) with the given flags applied, validated.
    ///
    /// # Errors
    /// I/O and scene-file errors; invalid parameters.
    pub fn scene(&self, base: SliderScene) -> Result<SliderScene, Box<dyn std::error::Error>> {
        let mut scene = match &self.scene {
            Some(path) => SliderScene::read(path)?,
            None => base,
        };
        if let Some(t) = self.end_time {
            // Also refused by the scene's validation (as `end_time_s`); here named as
            // written, with the range.
            crate::guard::in_range(
                "--end-time",
                t,
                (f64::MIN_POSITIVE, 1e10),
                "seconds; beyond 1e10 s the time loses the digits of the steps",
            )?;
        }
        if let Some(j) = self.level {
            scene.level = j;
        }
        if let Some(t) = self.end_time {
            scene.end_time_s = t;
        }
        if let Some(l) = self.law {
            scene.state_law = l;
        }
        if let Some(s) = self.state_integrator {
            scene.state_integrator = s;
        }
        if let Some(i) = self.integrator {
            scene.integrator = i;
        }
        if let Some(s) = self.solver {
            scene.solver = s;
        }
        if let Some(f) = self.fixed_point {
            scene.fixed_point = f;
        }
        if let Some(d) = self.diagonal {
            scene.diagonal = d;
        }
        if self.absorbing_sides {
            scene.absorbing_sides = true;
        }
        // A refused value is named as the user wrote it: the flag if it was given, the
        // scene file's key (`--scene FILE: … end_time_s …`) if it came from the file.
        self.named(self.for_flags(scene.validate()))?;
        Ok(scene)
    }

    /// `result`'s error named after the flags given (`--end-time` for the scene's
    /// `end_time_s`, `--level` for `level`) where it names their scene keys: the scene's
    /// validation, and the model's conditioning check when the model is built (`--end-time
    /// 1e-300` was refused naming `end_time_s`, a key the user never wrote).
    ///
    /// # Errors
    /// The error of `result`, renamed.
    pub fn for_flags<T>(&self, result: rsf::Result<T>) -> rsf::Result<T> {
        let mut checked = result;
        if self.end_time.is_some() {
            checked = for_flag("--end-time", "end_time_s", checked);
        }
        if self.level.is_some() {
            checked = for_flag("--level", "level", checked);
        }
        checked
    }

    /// Refuses a scene file that sets `steps` (to other than the default's) for a program
    /// that takes its step counts from its own flags (`flags`, e.g. `--steps`): the key
    /// would be ignored.
    ///
    /// # Errors
    /// A message naming the key, the file and the flags.
    pub fn steps_ignored(
        &self,
        scene: &SliderScene,
        flags: &str,
    ) -> Result<(), Box<dyn std::error::Error>> {
        match &self.scene {
            Some(path) if scene.steps != SliderScene::default().steps => Err(format!(
                "--scene {}: `steps = {}`: this program takes its step counts from {flags}, \
                 the key would be ignored",
                rsf_numeric::excerpt(&path.display().to_string()),
                scene.steps
            )
            .into()),
            _ => Ok(()),
        }
    }

    /// `result`'s error named after the scene file when one was given and the error
    /// names none of the flags (`--scene FILE: steps …`).
    ///
    /// # Errors
    /// The error of `result`, named.
    pub fn named<T>(&self, result: rsf::Result<T>) -> Result<T, Box<dyn std::error::Error>> {
        match (&self.scene, result) {
            (_, Ok(t)) => Ok(t),
            (Some(path), Err(e)) if !e.to_string().contains("--") => crate::guard::flag(
                &format!(
                    "--scene {}",
                    rsf_numeric::excerpt(&path.display().to_string())
                ),
                Err::<T, _>(e),
            ),
            (_, Err(e)) => Err(e.into()),
        }
    }
}

/// The flag `--frame-every N`: VTU frames of the whole body and a `.pvd` time index for
/// ParaView in the folder `frames/` of the run (`rsf::observe::VtuFrames`: displacement, velocity
/// and, on Γ_F, slip, slip rate, state, shear and normal traction).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FrameArgs {
    /// Write a VTU frame every N steps into `frames/` (ParaView opens `frames.pvd`;
    /// 0: none) [default: the example's, 0 unless it says otherwise].
    #[arg(long, value_name = "N")]
    pub frame_every: Option<usize>,
    /// `--hdf5 N`: the fields in one HDF5 file with an Xdmf index (the binaries of
    /// crates/rsf-hdf5).
    #[command(flatten)]
    pub fields: crate::fields::FieldArgs,
}

/// Bytes per vertex of a VTU frame: 16 doubles of coordinates and point data (171 bytes
/// in base64; rounded up). A 3-D level-1 frame (99 vertices, 240 cells) measured 31 862
/// bytes against the bound's 35 160.
pub const VTU_VERTEX_BYTES: f64 = 200.0;
/// Bytes per cell of a VTU frame: connectivity, offset and type (a tetrahedron 41 bytes,
/// 55 in base64; rounded up — a triangle is smaller).
pub const VTU_CELL_BYTES: f64 = 64.0;

impl FrameArgs {
    /// The bytes the frames of a run of at most `steps` steps write (`default` spacing
    /// when the flag is not given; `vertices` and `cells` of the mesh): a bound, for
    /// `rsf::run_folder::check_output_size`.
    pub fn bytes_bound(&self, default: usize, steps: f64, vertices: usize, cells: usize) -> f64 {
        let frames = match self.frame_every.unwrap_or(default) {
            0 => 0.0,
            n => (steps / n as f64).ceil(),
        };
        frames * (VTU_VERTEX_BYTES * vertices as f64 + VTU_CELL_BYTES * cells as f64)
    }

    /// The frame folder of a run writing into `out`.
    pub fn dir(out: &Path) -> PathBuf {
        out.join("frames")
    }

    /// The frame observer of a run into `out` (`None` for N = 0; `default` when the flag
    /// is not given): new frames for [`FileMode::Create`]/[`FileMode::Overwrite`],
    /// continued ones for [`FileMode::Resume`].
    ///
    /// # Errors
    /// Those of [`VtuFrames::new`] (an index of another run without `--overwrite`, a
    /// missing index on resume, I/O errors naming the path).
    pub fn observer(
        &self,
        default: usize,
        out: &Path,
        mode: FileMode,
    ) -> rsf::Result<Option<Every<VtuFrames>>> {
        self.every(default, || VtuFrames::new(Self::dir(out), mode))
    }

    /// The frame observer of one rank of a run on ranks into `out`, writing the frames in
    /// parallel pieces ([`VtuFrames::pieces`]: this rank's piece `frame_NNNNNN_rRRRR.vtu`
    /// of the cells whose lowest-numbered vertex it owns by `owner`, one rank per mesh
    /// vertex; on rank 0 also `frame_NNNNNN.pvtu` and the index). `None` for N = 0;
    /// `default` when the flag is not given. Every rank of the run calls it (each frame is
    /// a collective of `ranks`).
    ///
    /// # Errors
    /// Those of [`VtuFrames::pieces`] (on rank 0 those of [`VtuFrames::new`]).
    pub fn pieces(
        &self,
        default: usize,
        out: &Path,
        mode: FileMode,
        owner: Vec<usize>,
        ranks: Box<dyn rsf_ranks::RankGroup + Send>,
    ) -> rsf::Result<Option<Every<VtuFrames>>> {
        self.every(default, || {
            VtuFrames::pieces(Self::dir(out), mode, owner, ranks)
        })
    }

    /// `frames()` every N steps (`None` for N = 0; `default` when the flag is not given).
    fn every(
        &self,
        default: usize,
        frames: impl FnOnce() -> rsf::Result<VtuFrames>,
    ) -> rsf::Result<Option<Every<VtuFrames>>> {
        match self.frame_every.unwrap_or(default) {
            0 => Ok(None),
            n => Every::new(Interval::Steps(n), frames()?).map(Some),
        }
    }
}

/// The time-step flags of a slider run: `--steps N` (fixed τ = T/N, or the initial step of
/// adaptive steps) and `--adaptive TOL`.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct TimeStepArgs {
    /// Number of time steps N (τ = T/N; `1e4` accepted); with `--adaptive`, the initial step
    /// is T/N.
    #[arg(long, value_parser = step_count)]
    pub steps: Option<usize>,
    /// Adaptive time steps with this relative tolerance (docs/math.md §9), in
    /// (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1); other adaptive options
    /// from the scene file's `time_step` if it is adaptive, else their defaults.
    #[arg(long, value_name = "TOL", allow_negative_numbers = true)]
    pub adaptive: Option<f64>,
}

impl TimeStepArgs {
    /// `scene` with the flags applied, validated.
    ///
    /// # Errors
    /// Invalid parameters (e.g. a non-positive tolerance).
    pub fn apply(&self, mut scene: SliderScene) -> Result<SliderScene, rsf::Error> {
        if let Some(n) = self.steps {
            scene.steps = n;
        }
        if let Some(tol) = self.adaptive {
            // A relative tolerance ≥ 1 accepts anything and one at the machine epsilon can
            // never be met (the library refuses them too, `StepControl::validate`; here
            // the message names the flag).
            if !(tol > f64::EPSILON && tol < 1.0) && tol.is_finite() && tol > 0.0 {
                return Err(rsf::Error::InvalidParameter {
                    name: "--adaptive".into(),
                    reason: format!(
                        "--adaptive {tol:e} is outside the admissible range ({:e}, 1): a \
                         relative tolerance ≥ 1 accepts any step, one ≤ the machine epsilon \
                         can never be met",
                        f64::EPSILON
                    ),
                });
            }
            scene.time_step = TimeStep::Adaptive(match scene.time_step {
                TimeStep::Adaptive(a) => AdaptiveTimeStep {
                    tolerance: tol,
                    ..a
                },
                TimeStep::Fixed {} => AdaptiveTimeStep::new(tol),
            });
        }
        let checked = match self.steps {
            Some(_) => for_flag("--steps", "steps", scene.validate()),
            None => scene.validate(),
        };
        match self.adaptive {
            Some(_) => for_flag("--adaptive", "time_step.tolerance", checked)?,
            None => checked?,
        }
        Ok(scene)
    }

    /// A one-line description of the time steps of `scene`.
    pub fn describe(scene: &SliderScene) -> String {
        match scene.time_step {
            TimeStep::Fixed {} => format!("N = {} (τ = {:.3e} s)", scene.steps, scene.tau()),
            TimeStep::Adaptive(a) => format!(
                "adaptive τ (tolerance {:e}, τ0 = {:.3e} s, τ in [{:e}, {:e}] s)",
                a.tolerance,
                scene.initial_tau(),
                a.tau_min_s,
                a.tau_max_s
            ),
        }
    }
}

/// The flags of a slider run's scene and its time steps: [`SceneArgs`] (`--scene`,
/// `--level`, …) and [`TimeStepArgs`] (`--steps`, `--adaptive`).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SliderArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub scene: SceneArgs,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub time_step: TimeStepArgs,
}

impl SliderArgs {
    /// `base` (or the `--scene` file) with the scene flags, then the time-step flags
    /// applied, validated.
    ///
    /// # Errors
    /// As [`SceneArgs::scene`] and [`TimeStepArgs::apply`].
    pub fn scene(&self, base: SliderScene) -> Result<SliderScene, Box<dyn std::error::Error>> {
        Ok(self.time_step.apply(self.scene.scene(base)?)?)
    }
}

/// The step counts N (τ = T/N) of a time-step study.
#[derive(Debug, Clone, clap::Args)]
pub struct StepCounts {
    /// Step counts N (τ = T/N; comma separated, `1e5` accepted).
    #[arg(long, value_delimiter = ',', value_parser = step_count, default_value = "10000,100000")]
    pub steps: Vec<usize>,
    /// Add N = 10⁶ (hours).
    #[arg(long)]
    pub with_1e6: bool,
}

impl StepCounts {
    /// The counts, with 10⁶ appended for `--with-1e6`.
    pub fn counts(&self) -> Vec<usize> {
        let mut steps = self.steps.clone();
        if self.with_1e6 && !steps.contains(&1_000_000) {
            steps.push(1_000_000);
        }
        steps
    }
}

/// The command line of an example without options (`--help`, `--version`; anything else
/// is rejected).
#[derive(Debug, clap::Parser)]
#[command(version)]
pub struct NoArgs {}

/// A step count written as an integer or in scientific notation (`1e5`).
///
/// # Errors
/// A message for anything that is not a positive whole number.
pub fn step_count(s: &str) -> Result<usize, String> {
    let x: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if x >= 1.0 && x.fract() == 0.0 && x <= 1e12 {
        Ok(x as usize)
    } else {
        Err(format!("`{s}` is not a positive whole number of steps"))
    }
}

/// A window `A,B` of two increasing numbers.
///
/// # Errors
/// A message for anything else.
pub fn window(s: &str) -> Result<(f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("`{s}`: {e}"))?;
    match v[..] {
        [a, b] if a < b => Ok((a, b)),
        _ => Err(format!("`{s}`: expected A,B with A < B")),
    }
}

/// Parses a positive, finite number (a clap value parser: a time, a mass, a size), so that
/// `nan`, `inf`, 0 and negative values are refused where the flag is read.
///
/// # Errors
/// A message naming the value.
pub fn positive_number(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err(format!("`{s}` is not a positive finite number")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

/// The error of a library call on a user's flag, named after the flag: an
/// [`rsf::Error::InvalidParameter`] named `field` (the library's name) becomes one named
/// `flag` (what the user wrote, e.g. `rk_tolerance` for the fault ODE's `tolerance`), and
/// an [`rsf::Error::IllConditioned`] that lists `field` among the fields to change lists
/// `flag` there instead (`--end-time 1e-300` named `end_time_s`, the scene file's key, which
/// the user never wrote); other errors pass unchanged.
///
/// # Errors
/// The error of `result`, renamed.
pub fn for_flag<T>(flag: &str, field: &str, result: rsf::Result<T>) -> rsf::Result<T> {
    result.map_err(|e| match e {
        rsf::Error::InvalidParameter { name, reason } if name == field => {
            rsf::Error::InvalidParameter {
                name: flag.into(),
                reason,
            }
        }
        rsf::Error::IllConditioned { fields, reason } => rsf::Error::IllConditioned {
            fields: fields
                .into_iter()
                .map(|f| if f == field { flag.to_owned() } else { f })
                .collect(),
            reason,
        },
        e => e,
    })
}

/// The fields of the finite-element grid of BP5's volume (`SeasBp5Grid`, the scene's
/// fault zone) and the flags of `seas_bp5 --kernel fe` and `bp5_pair --kernel fe` that set
/// them; `grading` is the graded mesh's cell count, which all three size flags set.
pub const FE_GRID_FLAGS: [(&str, &str); 7] = [
    ("dx", "--dx"),
    ("domain", "--domain-km"),
    ("ratio", "--ratio"),
    ("near_fault", "--fault-zone-width-km"),
    ("fault_zone.half_width", "--fault-zone-width-km"),
    ("fault_zone.rigidity_ratio", "--fault-zone-rigidity"),
    ("grading", "--dx, --ratio, --domain-km"),
];

/// `result`'s error named after the flag that sets the refused field (`fields`: pairs of
/// a field and its flag, e.g. [`FE_GRID_FLAGS`]), so that a refusal of `--ratio 1` or
/// `--fault-zone-width-km 10` does not blame `--dx` (issue 87); other errors unchanged.
///
/// # Errors
/// The error of `result`, named.
pub fn for_fields<T>(
    fields: &[(&str, &str)],
    result: rsf::Result<T>,
) -> Result<T, Box<dyn std::error::Error>> {
    match result {
        Ok(t) => Ok(t),
        Err(rsf::Error::InvalidParameter { name, reason }) => {
            match fields.iter().find(|(field, _)| *field == name) {
                Some((_, flag)) => Err(format!("{flag}: {reason}").into()),
                None => Err(rsf::Error::InvalidParameter { name, reason }.into()),
            }
        }
        Err(e) => Err(e.into()),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::{step_count, window, SceneArgs, TimeStepArgs};
    use rsf_scenes::{AdaptiveTimeStep, SliderScene, TimeStep};

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        scene: SceneArgs,
        #[command(flatten)]
        time_step: TimeStepArgs,
    }

    #[test]
    fn adaptive_flag_selects_adaptive_steps() {
        let cli = Cli::try_parse_from(["x", "--level", "3", "--adaptive", "1e-3"]).unwrap();
        let scene = cli.scene.scene(SliderScene::default()).unwrap();
        let scene = cli.time_step.apply(scene).unwrap();
        assert_eq!(
            scene.time_step,
            TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3))
        );
        assert!(TimeStepArgs::describe(&scene).contains("adaptive"));
        // Without the flag the steps stay fixed; `--steps` sets N (the initial step).
        let cli = Cli::try_parse_from(["x", "--steps", "1e5"]).unwrap();
        let scene = cli.time_step.apply(SliderScene::default()).unwrap();
        assert_eq!(
            (scene.steps, scene.time_step),
            (100_000, TimeStep::Fixed {})
        );
        // The flag sets the tolerance of an adaptive scene and keeps its other options.
        let base = SliderScene {
            time_step: TimeStep::Adaptive(AdaptiveTimeStep {
                tau_max_s: 0.01,
                ..AdaptiveTimeStep::new(1e-2)
            }),
            ..SliderScene::default()
        };
        let cli = Cli::try_parse_from(["x", "--adaptive", "1e-4"]).unwrap();
        let scene = cli.time_step.apply(base).unwrap();
        let TimeStep::Adaptive(a) = scene.time_step else {
            panic!("adaptive")
        };
        assert_eq!((a.tolerance, a.tau_max_s), (1e-4, 0.01));
        // Invalid tolerances are errors naming the field.
        for bad in ["0", "-1e-3", "nan"] {
            let cli = Cli::try_parse_from(["x".into(), format!("--adaptive={bad}")]).unwrap();
            let e = cli.time_step.apply(SliderScene::default()).unwrap_err();
            assert!(e.to_string().contains("--adaptive"), "{bad}: {e}");
        }
        assert!(Cli::try_parse_from(["x", "--adaptive", "x"]).is_err());
    }

    #[test]
    fn a_misspelt_flag_is_an_error_with_a_suggestion() {
        let e = Cli::try_parse_from(["x", "--levle", "1"]).err().unwrap();
        assert_eq!(e.kind(), clap::error::ErrorKind::UnknownArgument);
        assert!(e.to_string().contains("--level"), "{e}");
        let e = Cli::try_parse_from(["x", "--law", "regularized"])
            .err()
            .unwrap();
        assert!(e.to_string().contains("aging"), "{e}");
        let cli = Cli::try_parse_from(["x", "--level", "2", "--law", "slip"]).unwrap();
        let scene = cli.scene.scene(rsf_scenes::SliderScene::default()).unwrap();
        assert_eq!((scene.level, scene.state_law), (2, rsf::StateLawKind::Slip));
        let cli = Cli::try_parse_from(["x", "--end-time", "-1"]).unwrap();
        assert!(cli.scene.scene(rsf_scenes::SliderScene::default()).is_err());
    }

    #[test]
    fn numbers_of_steps_and_windows() {
        assert_eq!(step_count("1e4"), Ok(10_000));
        assert!(step_count("0").is_err() && step_count("1.5").is_err());
        assert_eq!(window("0.5,0.75"), Ok((0.5, 0.75)));
        assert!(window("0.75,0.5").is_err() && window("1").is_err());
    }
}

/// How a Runge–Kutta run stores its operators condensed onto the fault (`S`, and `S_N` with
/// a normal stress from slip): the run configurations' choice.
pub use rsf_scenes::KernelChoice as KernelArg;

/// `--checkpoint-every N`, `--resume FILE`, `--allow-change FIELD,…` and `--max-steps N`
/// of the programs that checkpoint and continue their runs (the SEAS programs; their
/// session: [`crate::session::Session`]).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ResumeArgs {
    /// Write `checkpoint.bin` every N steps (0: never), and the benchmark files with their
    /// resume log at the same steps.
    #[arg(long, default_value_t = 0)]
    pub checkpoint_every: usize,
    /// Continue from this checkpoint, continuing the files in `--out`.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<std::path::PathBuf>,
    /// On `--resume`, accept a checkpoint whose fingerprint differs in these fields (comma
    /// separated, e.g. `end_years`).
    #[arg(long, value_delimiter = ',', value_name = "FIELD,…")]
    pub allow_change: Vec<String>,
    /// Stop after this many steps in total (across resumes), writing `checkpoint.bin` and
    /// the resume log to continue from with a larger value. 0 computes no step.
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
}

impl ResumeArgs {
    /// `folder` with these resume flags (`--resume FILE`, `--allow-change FIELD,…`):
    /// [`Folder::resume_from`](crate::guard::Folder::resume_from) and
    /// [`Folder::allow_change`](crate::guard::Folder::allow_change).
    pub fn folder(&self, folder: crate::guard::Folder) -> crate::guard::Folder {
        folder
            .resume_from(self.resume.as_deref())
            .allow_change(&self.allow_change)
    }
}

/// `--modeler NAME` and `--date YYYY-MM-DD` of the SEAS files' headers.
#[cfg(feature = "seas")]
#[derive(Debug, Clone, Default, clap::Args)]
pub struct SeasHeaderArgs {
    /// Modeler named in the benchmark files' headers (`# author=`).
    #[arg(long, default_value = "rsf")]
    pub modeler: String,
    /// Date in the benchmark files' headers (`# date=`, YYYY-MM-DD); default today (UTC).
    #[arg(long)]
    pub date: Option<String>,
}

#[cfg(feature = "seas")]
impl SeasHeaderArgs {
    /// The files' date: `--date`, or today's (UTC).
    pub fn date_or_today(&self) -> String {
        self.date.clone().unwrap_or_else(rsf_seas::utc_date_today)
    }

    /// Checks the flags before any work: `--modeler` one non-empty line of at most 100
    /// characters, `--date` a calendar date `YYYY-MM-DD` (`2023-02-31` is not).
    ///
    /// # Errors
    /// A message naming the flag.
    pub fn check(&self) -> Result<(), Box<dyn std::error::Error>> {
        let m = &self.modeler;
        if m.trim().is_empty() || m.chars().any(char::is_control) || m.chars().count() > 100 {
            return Err(crate::guard::refuse(
                "--modeler",
                format_args!("`{m}`"),
                "must be one non-empty line of at most 100 characters",
            ));
        }
        if let Some(d) = &self.date {
            let calendar = d.len() == 10 && d.parse::<jiff::civil::Date>().is_ok();
            if !calendar {
                return Err(crate::guard::refuse(
                    "--date",
                    format_args!("`{d}`"),
                    "is not a calendar date YYYY-MM-DD",
                ));
            }
        }
        Ok(())
    }
}

/// `--integrator auto|rkc|rosenbrock|dormand-prince|bogacki-shampine` of the fault-ODE programs
/// (docs/math.md §12, "Stiff steps").
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct IntegratorArgs {
    /// The fault ODE's integrator: `auto` (the default: Dormand–Prince 5(4) while accuracy
    /// sets its step, the stabilised RKC2 while stability would), `rkc` (RKC2
    /// throughout), `rosenbrock` (the linearly implicit ROS34PW2 throughout),
    /// `dormand-prince` (the pair every run used before issue 84) or
    /// `bogacki-shampine`. Part of a checkpoint's fingerprint unless `dormand-prince`
    /// (so the checkpoints written before the flag resume with `--integrator
    /// dormand-prince`, or continue with another integrator under `--allow-change
    /// integrator`).
    #[arg(long, value_enum, default_value_t = rsf::fault_ode::OdeIntegrator::Auto)]
    pub integrator: rsf::fault_ode::OdeIntegrator,
}

impl IntegratorArgs {
    /// `fingerprint` with the integrator, unless it is `dormand-prince` (the fingerprint
    /// of the runs before the flag).
    pub fn fingerprint(
        &self,
        fingerprint: rsf::checkpoint::Fingerprint,
    ) -> rsf::checkpoint::Fingerprint {
        rsf::fault_ode::integrator_fingerprint(fingerprint, self.integrator)
    }

    /// What `summary.json` says of the integrator: the choice, the steps, simulated time
    /// and evaluations of each method, `auto`'s changes and why it chose as it did.
    pub fn summary(&self, stats: Option<rsf::fault_ode::StepperStats>) -> serde_json::Value {
        use rsf::fault_ode::OdeIntegrator;
        let why = match self.integrator {
            OdeIntegrator::Auto => {
                "auto: Dormand–Prince 5(4) while its step is set by accuracy; RKC2 after 15 \
                 steps in a row whose h|λ| (DOPRI5's stiffness test) exceeded 3.25, the \
                 pair's stability limit, and back once RKC2's step h had h ρ ≤ 1.1 (ρ its \
                 spectral radius estimate) in 15 steps in a row"
            }
            OdeIntegrator::Rkc => "rkc: RKC2 throughout (asked for)",
            OdeIntegrator::Rosenbrock => {
                "rosenbrock: ROS34PW2 throughout (asked for), its stage solves by GMRES \
                 preconditioned by the nodes' local Jacobians"
            }
            OdeIntegrator::DormandPrince => "dormand-prince: the explicit pair (asked for)",
            OdeIntegrator::BogackiShampine => "bogacki-shampine: the explicit pair (asked for)",
        };
        serde_json::json!({
            "integrator": self.integrator.name(),
            "why": why,
            // This invocation's counts (a resumed run starts them again).
            "this_invocation": stats.map(|s| serde_json::json!({
                "explicit_steps": s.explicit_steps,
                "stabilized_steps": s.stabilized_steps,
                "explicit_time_years": s.explicit_time / rsf::observe::SECONDS_PER_YEAR,
                "stabilized_time_years": s.stabilized_time / rsf::observe::SECONDS_PER_YEAR,
                "explicit_evaluations": s.explicit_evaluations,
                "stabilized_evaluations": s.stabilized_evaluations,
                "switches": s.switches,
                "spectral_radius_estimates": s.estimates,
                "estimate_evaluations": s.estimate_evaluations,
                "max_stages": s.max_stages,
                "last_spectral_radius_per_s": s.spectral_radius,
                "max_spectral_radius_per_s": s.max_spectral_radius,
                "implicit_steps": s.implicit_steps,
                "implicit_time_years": s.implicit_time / rsf::observe::SECONDS_PER_YEAR,
                "implicit_evaluations": s.implicit_evaluations,
                "krylov_iterations": s.krylov_iterations,
                "linear_failures": s.linear_failures,
                // DOPRI5's stiffness test on the pair's steps (auto): the time-weighted
                // mean of h|λ| (the pair is stable to ≈ 3.3) and the time held above 3.25.
                "stiffness_tested_years": s.tested_time / rsf::observe::SECONDS_PER_YEAR,
                "mean_h_lambda_time_weighted": if s.tested_time > 0.0 {
                    serde_json::json!(s.stiffness_integral / s.tested_time)
                } else {
                    serde_json::Value::Null
                },
                "held_by_stability_years": s.held_time / rsf::observe::SECONDS_PER_YEAR,
            })),
        })
    }
}

/// `--kernel dense|hierarchical` and `--kernel-epsilon E` of the fault-ODE examples.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct KernelArgs {
    /// The Runge–Kutta run's operators condensed onto the fault: `hierarchical`
    /// (ℋ-matrices, rsf-hmatrix; the default) or `dense` (m² entries). Part of a
    /// checkpoint's fingerprint: a run checkpointed with one kernel is refused on
    /// `--resume` with the other (a run begun before the default changed to
    /// `hierarchical` resumes with `--kernel dense`).
    #[arg(long, value_enum, default_value_t = KernelArg::Hierarchical)]
    pub kernel: KernelArg,
    /// Relative accuracy ε of the hierarchical kernel, in [1e-14, 1e-2] (default: the
    /// Runge–Kutta tolerance, within that range).
    #[arg(long)]
    pub kernel_epsilon: Option<f64>,
}

impl KernelArgs {
    /// The kernel for a run of Runge–Kutta `tolerance`.
    ///
    /// # Errors
    /// `--kernel-epsilon` without `--kernel hierarchical`, or outside the kernel's range
    /// `(0, MAX_KERNEL_EPSILON]` (the range [`FaultKernel::validate`] applies: one source
    /// for both, issue 87 — `0.5` passed `(ε, 1)` here and was refused after the folder
    /// was made).
    ///
    /// [`FaultKernel::validate`]: rsf::fault_ode::FaultKernel::validate
    pub fn kernel(&self, tolerance: f64) -> Result<rsf::fault_ode::FaultKernel, String> {
        rsf_scenes::fault_kernel(self.kernel, self.kernel_epsilon, tolerance).map_err(|e| match e {
            rsf::Error::InvalidParameter { name, reason } => {
                format!("--{} {reason}", name.replace('_', "-"))
            }
            e => e.to_string(),
        })
    }
}

/// `fingerprint` with the fields a run in a graded box shares (`seas_bp3`, `stepover`,
/// `bp5_pair`), in this order: `dx`, `domain_km`, `ratio` (the box's flags), `end_years`
/// and `tolerance`.
#[cfg(feature = "seas")]
pub fn with_box_and_end(
    fingerprint: rsf::checkpoint::Fingerprint,
    (dx, domain_km, ratio): (f64, f64, f64),
    end_years: f64,
    tolerance: f64,
) -> rsf::checkpoint::Fingerprint {
    fingerprint
        .with("dx", dx)
        .with("domain_km", domain_km)
        .with("ratio", ratio)
        .with("end_years", end_years)
        .with("tolerance", tolerance)
}
