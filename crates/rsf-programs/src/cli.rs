//! Command-line parsing shared by the examples (clap derive) and how they end: errors are
//! printed with `Display` and their causes, the exit code is non-zero.

use std::path::{Path, PathBuf};

use rsf::observe::{Every, FileMode, Interval, VtuFrames};
use rsf_scenes::{AdaptiveTimeStep, SliderScene, TimeStep};

use rsf_scenes::RunConfig;

use crate::config::ConfigArgs;
use crate::guard::AnyError;

/// The scene a slider program starts from: its type (whose fields are the flags) and its
/// value where no flag or file sets a field (the flags' defaults).
pub trait ProgramScene {
    /// The scene: [`SliderScene`] or [`Slider3dScene`](rsf_scenes::Slider3dScene).
    type Scene: RunConfig
        + std::fmt::Debug
        + clap::Args
        + clap::FromArgMatches
        + AsRef<SliderScene>
        + AsMut<SliderScene>;

    /// Whether the program takes its step counts from flags of its own (a time-step
    /// study's `--steps N1,N2,…`): then the scene's `steps` is no flag of it (clap reads it
    /// as the hidden `--scene-steps`), and a scene file that sets it is refused
    /// ([`SliderArgs::steps_ignored`]).
    const OWN_STEP_FLAGS: bool = false;

    /// The scene where no flag or file sets a field.
    fn base() -> Self::Scene;
}

/// The paper's slider ([`SliderScene::default`], Table 6.1) as a program's scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct PaperSlider;

impl ProgramScene for PaperSlider {
    type Scene = SliderScene;

    fn base() -> SliderScene {
        SliderScene::default()
    }
}

/// The paper's slider at level `J` ([`SliderScene::default`] otherwise) as a program's
/// scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct PaperSliderAt<const J: usize>;

impl<const J: usize> ProgramScene for PaperSliderAt<J> {
    type Scene = SliderScene;

    fn base() -> SliderScene {
        SliderScene {
            level: J,
            ..SliderScene::default()
        }
    }
}

/// The scene of the paper's figures 6.2–6.5 (the programs `fig6_*`): level 4 and the
/// direct solver ([`SliderScene::default`] otherwise), the step counts from the programs'
/// own flags.
#[derive(Debug, Clone, Copy, Default)]
pub struct PaperFigures;

impl ProgramScene for PaperFigures {
    type Scene = SliderScene;

    const OWN_STEP_FLAGS: bool = true;

    fn base() -> SliderScene {
        SliderScene {
            level: 4,
            solver: rsf::SolverKind::Direct,
            ..SliderScene::default()
        }
    }
}

/// The 3-D slider ([`Slider3dScene::default`](rsf_scenes::Slider3dScene::default): the
/// paper's parameters at level 2, W = 1 m, free lateral faces, inexact inner solves,
/// red–black smoothers) as a program's scene.
#[derive(Debug, Clone, Copy, Default)]
pub struct PaperSlider3d;

impl ProgramScene for PaperSlider3d {
    type Scene = rsf_scenes::Slider3dScene;

    fn base() -> rsf_scenes::Slider3dScene {
        rsf_scenes::Slider3dScene::default()
    }
}

/// The flags of a slider run (docs/design.md, "One run configuration"): every field of
/// the scene `P::Scene` ([`SliderScene`]; with the 3-D slider's also `width_m` and
/// `lateral`) is a flag of its name (`level` is `--level`, `sigma_n_pa` `--sigma-n-pa`;
/// `end_time_s` also `--end-time`, `state_law` also `--law`, `tnnmg_smoother` also
/// `--smoother`), its default `P::base()`'s value; the scene file `--scene FILE.toml`
/// (also `--config`) sets the keys no flag gave; `--adaptive TOL` is a shortcut for an
/// adaptive `time_step`. The file is read when the flags are (`clap::FromArgMatches`; its
/// error reported by [`SliderArgs::scene`]), so a program needs nothing but the field.
#[derive(Debug, Clone)]
pub struct SliderArgs<P: ProgramScene = PaperSlider> {
    /// The scene of the flags and the file (not validated: [`scene`](Self::scene)).
    pub scene: P::Scene,
    /// `--scene FILE.toml`, and the keys it set.
    pub config: ConfigArgs,
    /// Adaptive time steps with this relative tolerance.
    pub adaptive: Option<f64>,
    /// The scene file's error, reported by [`scene`](Self::scene) (so that a program
    /// reports it as its other refusals: once, on rank 0 of a run on ranks).
    file_error: Option<String>,
}

impl<P: ProgramScene> Default for SliderArgs<P> {
    fn default() -> Self {
        Self {
            scene: P::base(),
            config: ConfigArgs::default(),
            adaptive: None,
            file_error: None,
        }
    }
}

/// The flags of [`SliderArgs`] besides the scene's and the file's.
#[derive(clap::Args)]
struct Shortcuts {
    /// Adaptive time steps with this relative tolerance (docs/math.md §9), in
    /// (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1); other adaptive options
    /// from `time_step` (flag or file) if it is adaptive, else their defaults. With it,
    /// the initial step is T/N.
    #[arg(long, value_name = "TOL", allow_negative_numbers = true)]
    adaptive: Option<f64>,
}

impl<P: ProgramScene> clap::Args for SliderArgs<P> {
    fn augment_args(command: clap::Command) -> clap::Command {
        let mut command = ConfigArgs::augment_args(P::Scene::augment_args(command))
            .mut_arg("config", |a| a.long("scene").visible_alias("config"));
        if P::OWN_STEP_FLAGS {
            command = command.mut_arg("steps", |a| a.long("scene-steps").hide(true));
        }
        crate::config::with_defaults(Shortcuts::augment_args(command), &P::base())
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        Self::augment_args(command)
    }
}

impl<P: ProgramScene> clap::FromArgMatches for SliderArgs<P> {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut config = ConfigArgs::from_arg_matches(matches)?;
        let flags = P::Scene::from_arg_matches(matches)?;
        let (scene, file_error) = match config.merged(flags.clone(), matches) {
            Ok(scene) => (scene, None),
            Err(e) => (flags, Some(e.to_string())),
        };
        let Shortcuts { adaptive } = Shortcuts::from_arg_matches(matches)?;
        Ok(Self {
            scene,
            config,
            adaptive,
            file_error,
        })
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl<P: ProgramScene> SliderArgs<P> {
    /// The scene of the flags and the file, with `--adaptive`, validated; a refused value
    /// named as the user wrote it (the flag, or the file's key).
    ///
    /// # Errors
    /// The first refused setting.
    pub fn scene(&self) -> Result<P::Scene, AnyError> {
        if let Some(e) = &self.file_error {
            return Err(e.clone().into());
        }
        let mut scene = self.scene.clone();
        let slider: &mut SliderScene = scene.as_mut();
        if let Some(tol) = self.adaptive {
            // A relative tolerance ≥ 1 accepts anything and one at the machine epsilon can
            // never be met (the library refuses them too, `StepControl::validate`; here
            // the message names the flag).
            if !(tol > f64::EPSILON && tol < 1.0) {
                return Err(crate::guard::refuse(
                    "--adaptive",
                    crate::guard::written(tol),
                    &format!(
                        "is outside the admissible range ({:e}, 1): a relative tolerance \
                         ≥ 1 accepts any step, one ≤ the machine epsilon can never be met",
                        f64::EPSILON
                    ),
                ));
            }
            slider.time_step = TimeStep::Adaptive(match slider.time_step {
                TimeStep::Adaptive(a) => AdaptiveTimeStep {
                    tolerance: tol,
                    ..a
                },
                TimeStep::Fixed {} => AdaptiveTimeStep::new(tol),
            });
        }
        self.config.validate(&scene)?;
        Ok(scene)
    }

    /// `result`'s error named as the user wrote the setting it names
    /// ([`ConfigArgs::named`]): the model's conditioning check names `end_time_s`.
    ///
    /// # Errors
    /// The error of `result`, named.
    pub fn named<T>(&self, result: rsf::Result<T>) -> Result<T, AnyError> {
        result.map_err(|e| self.config.named(e))
    }

    /// Refuses a scene file that sets `steps` for a program that takes its step counts
    /// from its own flags (`flags`, e.g. `--steps`): the key would be ignored.
    ///
    /// # Errors
    /// A message naming the key, the file and the flags.
    pub fn steps_ignored(&self, flags: &str) -> Result<(), AnyError> {
        if self.config.from_file().iter().any(|k| k == "steps") {
            return Err(format!(
                "--scene: `steps = {}`: this program takes its step counts from {flags}, \
                 the key would be ignored",
                self.scene.as_ref().steps
            )
            .into());
        }
        Ok(())
    }
}

/// A one-line description of the method of `scene`: `level {level}, {time steps}, {law}
/// law, {integrator}, {solver} solver` (the time steps as [`describe_time_step`]).
pub fn describe_method(scene: &SliderScene) -> String {
    format!(
        "level {}, {}, {} law, {}, {} solver",
        scene.level,
        describe_time_step(scene),
        scene.state_law,
        scene.integrator,
        scene.solver
    )
}

/// A one-line description of the time steps of `scene`.
pub fn describe_time_step(scene: &SliderScene) -> String {
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

/// The step counts N (τ = T/N) of a time-step study.
#[derive(Debug, Clone, clap::Args)]
pub struct StepCounts {
    /// Step counts N (τ = T/N; comma separated, `1e5` accepted).
    #[arg(id = "step_counts", long = "steps", value_delimiter = ',', value_parser = step_count, default_value = "10000,100000")]
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

pub use rsf_scenes::run_config::step_count;

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

    use super::{describe_time_step, step_count, window, SliderArgs};
    use rsf_scenes::{AdaptiveTimeStep, TimeStep};

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        slider: SliderArgs,
    }

    #[test]
    fn adaptive_flag_selects_adaptive_steps() {
        let cli = Cli::try_parse_from(["x", "--level", "3", "--adaptive", "1e-3"]).unwrap();
        let scene = cli.slider.scene().unwrap();
        assert_eq!(
            scene.time_step,
            TimeStep::Adaptive(AdaptiveTimeStep::new(1e-3))
        );
        assert!(describe_time_step(&scene).contains("adaptive"));
        // Without the flag the steps stay fixed; `--steps` sets N (the initial step).
        let cli = Cli::try_parse_from(["x", "--steps", "1e5"]).unwrap();
        let scene = cli.slider.scene().unwrap();
        assert_eq!(
            (scene.steps, scene.time_step),
            (100_000, TimeStep::Fixed {})
        );
        // The flag sets the tolerance of an adaptive `time_step` and keeps its other
        // options.
        let cli = Cli::try_parse_from([
            "x",
            "--time-step",
            "{ kind = \"adaptive\", tolerance = 1e-2, tau_max_s = 0.01 }",
            "--adaptive",
            "1e-4",
        ])
        .unwrap();
        let TimeStep::Adaptive(a) = cli.slider.scene().unwrap().time_step else {
            panic!("adaptive")
        };
        assert_eq!((a.tolerance, a.tau_max_s), (1e-4, 0.01));
        // Invalid tolerances are errors naming the flag.
        for bad in ["0", "-1e-3", "nan"] {
            let cli = Cli::try_parse_from(["x".into(), format!("--adaptive={bad}")]).unwrap();
            let e = cli.slider.scene().unwrap_err();
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
        let scene = cli.slider.scene().unwrap();
        assert_eq!((scene.level, scene.state_law), (2, rsf::StateLawKind::Slip));
        // A refused value is named as its flag (the scene's key with dashes).
        let cli = Cli::try_parse_from(["x", "--end-time=-1"]).unwrap();
        let e = cli.slider.scene().unwrap_err().to_string();
        assert!(e.contains("--end-time-s"), "{e}");
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

impl crate::run_folder::FolderArgs {
    /// The folder `--out` (`out`, holding `outputs`) with these flags (`--overwrite`,
    /// `--allow-change`) and the checkpoint `resume` (`--resume FILE`) it continues from:
    /// [`Folder::overwrite`](crate::guard::Folder::overwrite),
    /// [`Folder::resume_from`](crate::guard::Folder::resume_from) and
    /// [`Folder::allow_change`](crate::guard::Folder::allow_change).
    pub fn out_folder(
        &self,
        out: &Path,
        outputs: &[&str],
        resume: Option<&Path>,
    ) -> crate::guard::Folder {
        crate::guard::Folder::new("--out", out, outputs)
            .overwrite(self.overwrite)
            .resume_from(resume)
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
        // Every choice but `auto` is the one named (by the flag or the program's default).
        let why = match self.integrator {
            OdeIntegrator::Auto => {
                "auto: Dormand–Prince 5(4) while its step is set by accuracy; RKC2 after 15 \
                 steps in a row whose h|λ| (DOPRI5's stiffness test) exceeded 3.25, the \
                 pair's stability limit, and back once RKC2's step h had h ρ ≤ 1.1 (ρ its \
                 spectral radius estimate) in 15 steps in a row"
            }
            OdeIntegrator::Rkc => "rkc: RKC2 throughout (by name)",
            OdeIntegrator::Rosenbrock => {
                "rosenbrock: ROS34PW2 throughout (by name), its stage solves by GMRES \
                 preconditioned by the nodes' local Jacobians"
            }
            OdeIntegrator::DormandPrince => "dormand-prince: the explicit pair (by name)",
            OdeIntegrator::BogackiShampine => "bogacki-shampine: the explicit pair (by name)",
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
