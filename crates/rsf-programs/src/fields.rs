//! The seam through which a binary supplies writers of a run's fields (`--hdf5 N`): the
//! workspace's programs are built without the HDF5 library, the binaries of the crate
//! `crates/rsf-hdf5` (the same programs, the same flags and files) supply its writers
//! ([`FieldWriters`]) through the programs' `main_with_fields`. In a build without a writer
//! the flag is refused before any work ([`NoFieldWriter`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::guard::{written, AnyError, Limits, Plan};
use rsf::checkpoint::{Checkpoint, Fingerprint};
use rsf::observe::FileMode;
use rsf::run_folder::{output_plan, OutputEstimate, Session};
use rsf::Observer;

/// The fields file of a run in its folder (`OUT/fields.h5`; its Xdmf index `OUT/fields.xmf`).
pub const FIELDS_FILE: &str = "fields.h5";
/// The Xdmf index of [`FIELDS_FILE`].
pub const FIELDS_INDEX: &str = "fields.xmf";
/// The files of `--hdf5` in a run folder (its outputs: `--overwrite` replaces them).
pub const FIELD_OUTPUTS: [&str; 2] = [FIELDS_FILE, FIELDS_INDEX];

/// Where and how a run's fields are written: what a [`FieldWriters`] is given to make the
/// observer of one run.
#[derive(Debug, Clone, Copy)]
pub struct FieldsTarget<'a> {
    /// The file (`OUT/fields.h5`, [`FIELDS_FILE`]); its index takes the extension `.xmf`.
    pub path: &'a Path,
    /// [`FileMode::Create`] or [`FileMode::Overwrite`] for a new run,
    /// [`FileMode::Resume`] after a checkpoint.
    pub mode: FileMode,
    /// The fingerprint of the run's checkpoints (recorded in a new file, compared on resume).
    pub fingerprint: &'a Fingerprint,
    /// The checkpoint a resumed run continues from (`None` for a new run).
    pub resumed: Option<&'a Checkpoint>,
    /// The fingerprint fields a resume may change (`--allow-change`).
    pub allow_change: &'a [String],
    /// The sampling interval: a frame every this many steps (≥ 1; the steps' numbers
    /// across resumes, as the VTU frames').
    pub every: usize,
}

/// Writers of a run's fields, which a binary supplies to the programs (the HDF5 writers of
/// `crates/rsf-hdf5`). Each method makes the observer of one run, which writes a frame
/// every `target.every` steps (`--hdf5 N`): the fields of the whole body of the
/// sliders (`volume_2d`, `volume_3d`) and the fault's own fields of the SEAS programs
/// (`fault_*`: slip, slip rate, state and tractions on Γ_F's nodes, also where the run has
/// no volume mesh). Each writes `target.path` and, beside it, its index.
pub trait FieldWriters: Send + Sync {
    /// The fields of a 2-D body (`pipping_slider`).
    ///
    /// # Errors
    /// The writer's: a file of another run, a missing file on resume, I/O.
    fn volume_2d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>>;
    /// The fields of a 3-D body (`slider_3d`).
    ///
    /// # Errors
    /// As [`volume_2d`](Self::volume_2d).
    fn volume_3d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>>;
    /// The fault's fields of an antiplane model (one displacement component: `seas_bp1`,
    /// `seas_bp6`'s antiplane runs).
    ///
    /// # Errors
    /// As [`volume_2d`](Self::volume_2d).
    fn fault_antiplane(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2, 1>>>;
    /// The fault's fields of a 2-D plane-strain model (`seas_bp3`, `seas_bp6`'s in-plane
    /// runs).
    ///
    /// # Errors
    /// As [`volume_2d`](Self::volume_2d).
    fn fault_2d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>>;
    /// The fault's fields of a 3-D model (`seas_bp5`, with either kernel).
    ///
    /// # Errors
    /// As [`volume_2d`](Self::volume_2d).
    fn fault_3d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>>;
}

/// The writer of the fault's fields of a 2-D model of `C` displacement components
/// ([`FieldWriters::fault_antiplane`] for 1, [`FieldWriters::fault_2d`] for 2), for a
/// program generic in `C` (`seas_bp6`).
pub struct Fault2d<const C: usize>;

/// How [`Fault2d`] makes the fault's fields of a model of `C` components.
pub trait FaultFields2d<const C: usize> {
    /// The fault's fields for `target`, by the method of `writers` for `C` components.
    ///
    /// # Errors
    /// The writer's.
    fn make(
        writers: &dyn FieldWriters,
        target: &FieldsTarget<'_>,
    ) -> rsf::Result<Box<dyn Observer<2, C>>>;
}

impl FaultFields2d<1> for Fault2d<1> {
    fn make(
        writers: &dyn FieldWriters,
        target: &FieldsTarget<'_>,
    ) -> rsf::Result<Box<dyn Observer<2, 1>>> {
        writers.fault_antiplane(target)
    }
}

impl FaultFields2d<2> for Fault2d<2> {
    fn make(
        writers: &dyn FieldWriters,
        target: &FieldsTarget<'_>,
    ) -> rsf::Result<Box<dyn Observer<2>>> {
        writers.fault_2d(target)
    }
}

/// `--hdf5 N` asked of a program built without a writer of fields (the workspace's
/// binaries: they need no HDF5 library). Names the flag and the binary that writes HDF5.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NoFieldWriter {
    /// The program (`slider_3d`, `seas_bp1`, …).
    pub program: String,
}

impl std::fmt::Display for NoFieldWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "--hdf5: this build of `{p}` writes no HDF5 (the workspace's programs are built \
             without the HDF5 library); the binary `{p}` of crates/rsf-hdf5 writes the fields \
             (cargo build --release --manifest-path crates/rsf-hdf5/Cargo.toml, then \
             crates/rsf-hdf5/target/release/{p} with the same flags; needs libhdf5-dev; on \
             MPI ranks, the SEAS programs of crates/rsf-mpi built with --features hdf5)",
            p = self.program
        )
    }
}

impl std::error::Error for NoFieldWriter {}

/// The writers a binary supplied, if any (not a flag: set by `main_with_fields`).
#[derive(Clone, Default)]
pub struct Supplied(Option<Arc<dyn FieldWriters>>);

impl std::fmt::Debug for Supplied {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() {
            "Supplied(writers)"
        } else {
            "Supplied(none)"
        })
    }
}

/// Bytes per vertex (or fault node) and frame of a fields file: 14 doubles of the body's
/// fields (two 3-vectors, slip as a 3-vector, five scalars; the fault's files hold fewer),
/// rounded up.
pub const FIELDS_VERTEX_BYTES: f64 = 128.0;
/// Bytes per frame besides the values: the chunks' index of the file's ten datasets and the
/// frame's entry in the Xdmf index (measured on `slider_3d --level 2`, 525 vertices: 4.8 kB
/// and 3.7 kB per frame; rounded up).
pub const FIELDS_FRAME_BYTES: f64 = 12_288.0;
/// Bytes of a fields file's own structure (superblock, groups, attributes: 20 kB measured on
/// a 24-vertex mesh; rounded up).
pub const FIELDS_FILE_BYTES: f64 = 32_768.0;

/// The writers of `--hdf5` a binary supplies, if it has any (the MPI programs: with the
/// `rsf-mpi` crate's feature `hdf5`).
pub type Writers = Option<Arc<dyn FieldWriters>>;

/// The size of a fault's fields (bounds from a program's flags, for its plan): its points
/// and its cells of `corners` vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaultSize {
    /// Points (fault nodes or cell centres).
    pub points: f64,
    /// Cells.
    pub cells: f64,
    /// Vertices of a cell (2 for segments, 4 for quadrilaterals).
    pub corners: f64,
}

impl FaultSize {
    /// `points` points and `(cells, corners)`.
    pub fn of(points: f64, (cells, corners): (f64, f64)) -> Self {
        Self {
            points,
            cells,
            corners,
        }
    }
}

/// The flag `--hdf5 N`: the run's fields every N steps into one HDF5 file `OUT/fields.h5`
/// with an Xdmf index `OUT/fields.xmf` (ParaView, meshio), written by the writers a binary
/// supplies ([`FieldWriters`]; the binaries of `crates/rsf-hdf5`).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FieldArgs {
    /// Write the fields every N steps into `fields.h5` with its Xdmf index `fields.xmf`
    /// in the output folder (ParaView, h5py, meshio; 0: none) — only the binaries of
    /// crates/rsf-hdf5 (the same program with the HDF5 library) write it, the workspace's
    /// refuse the flag. A resumed run continues the file.
    #[arg(long, value_name = "N")]
    pub hdf5: Option<usize>,
    /// The writers of this build.
    #[arg(skip)]
    pub writers: Supplied,
}

impl FieldArgs {
    /// The sampling interval (steps) asked for; 0 for none.
    pub fn every(&self) -> usize {
        self.hdf5.unwrap_or(0)
    }

    /// These flags with `writers` to write the fields.
    pub fn supply(&mut self, writers: Arc<dyn FieldWriters>) {
        self.writers = Supplied(Some(writers));
    }

    /// These flags with `writers` if there are any (a binary built with or without them).
    pub fn supply_if(&mut self, writers: Writers) {
        if let Some(writers) = writers {
            self.supply(writers);
        }
    }

    /// Refuses `--hdf5 N` (N ≥ 1) in a build without writers — in the plan, before any work.
    ///
    /// # Errors
    /// [`NoFieldWriter`] naming `program`.
    pub fn check(&self, program: &str) -> Result<(), NoFieldWriter> {
        match (self.every(), &self.writers.0) {
            (0, _) | (_, Some(_)) => Ok(()),
            _ => Err(NoFieldWriter {
                program: program.to_owned(),
            }),
        }
    }

    /// `fingerprint` with the interval when the fields are written (`hdf5_every`): a resume
    /// with another interval would mix two in one file. Unchanged without the flag (the
    /// checkpoints of the runs before it).
    pub fn fingerprint(&self, fingerprint: Fingerprint) -> Fingerprint {
        match self.every() {
            0 => fingerprint,
            n => fingerprint.with("hdf5_every", n),
        }
    }

    /// The bytes the fields file of a run of at most `steps` steps writes (`points` its
    /// vertices or fault nodes, `cells` its cells of `corners` vertices): a bound, for the
    /// plan's output estimate.
    pub fn bytes_bound(&self, steps: f64, points: usize, (cells, corners): (usize, usize)) -> f64 {
        let frames = match self.every() {
            0 => return 0.0,
            n => (steps / n as f64).ceil(),
        };
        let mesh = 32.0 * points as f64 + 8.0 * (cells * corners) as f64;
        FIELDS_FILE_BYTES
            + mesh
            + frames * (FIELDS_VERTEX_BYTES * points as f64 + FIELDS_FRAME_BYTES)
    }

    /// The fields file of an adaptive run on `fault`: `(fixed, per step)` bytes — the file's
    /// structure, the mesh and one frame, then a frame every N steps (s steps write at most
    /// s/N + 1 frames); `None` without `--hdf5`. For a program that caps its steps for
    /// another output too (`seas_bp1 --every-step`): one cap for both.
    pub fn adaptive_bytes(&self, fault: FaultSize) -> Option<(f64, f64)> {
        let n = match self.every() {
            0 => return None,
            n => n as f64,
        };
        let FaultSize {
            points,
            cells,
            corners,
        } = fault;
        let frame = FIELDS_VERTEX_BYTES * points + FIELDS_FRAME_BYTES;
        let fixed = FIELDS_FILE_BYTES + 32.0 * points + 8.0 * cells * corners + frame;
        Some((fixed, frame / n))
    }

    /// `plan` with the fields file of an adaptive run (its steps unknown before it runs: the
    /// SEAS programs and the fault networks) on `fault`, within what `limits`'
    /// `--max-output-gb` leaves beside the plan's other output: with `--max-steps`
    /// (`max_steps`) the file of that many steps, refused if it does not fit; without, the
    /// step cap whose frames fit
    /// ([`rsf::run_folder::output_plan`]; [`Plan::cap_steps`]: the run stops there with a
    /// checkpoint). `plan` unchanged without `--hdf5`.
    ///
    /// # Errors
    /// The output bound, naming `--hdf5` and `--max-steps` or `--max-output-gb`.
    pub fn adaptive_output(
        &self,
        plan: Plan,
        fault: FaultSize,
        max_steps: Option<u64>,
        limits: Limits,
    ) -> Result<Plan, AnyError> {
        let points = fault.points;
        let max_gb = limits.max_output_gb;
        let Some((fixed, per_step)) = self.adaptive_bytes(fault) else {
            return Ok(plan);
        };
        let frame = FIELDS_VERTEX_BYTES * points + FIELDS_FRAME_BYTES;
        let estimate = OutputEstimate {
            bytes: max_steps.map_or(f64::INFINITY, |m| fixed + m as f64 * per_step),
            fixed_bytes: fixed,
            bytes_per_step: per_step,
            adaptive: true,
        };
        let left = max_gb - plan.output_bytes() / 1e9;
        let named = |e: rsf::Error| -> AnyError {
            format!(
                "--hdf5 {}: the fields file ({:.3e} bytes a frame) with {} GB of \
                 --max-output-gb {} left beside the run's other files: {e}",
                self.every(),
                frame,
                written(left.max(0.0)),
                written(max_gb)
            )
            .into()
        };
        let fields = if left > 0.0 {
            output_plan(estimate, max_steps, left).map_err(named)?
        } else {
            return Err(named(rsf::Error::InvalidParameter {
                name: "max_output_gb".into(),
                reason: "the other files fill it".into(),
            }));
        };
        let plan = plan.output(
            fields.bytes,
            "--hdf5, --max-steps, --max-output-gb",
            format!("the fields file, a frame every {} steps", self.every()),
        );
        Ok(match (fields.step_cap, max_steps) {
            (Some(cap), None) => plan.cap_steps(
                cap,
                format!(
                    "the frames of --hdf5 {} within --max-output-gb {}",
                    self.every(),
                    written(max_gb)
                ),
            ),
            _ => plan,
        })
    }

    /// The fields file of a run writing into `out`.
    pub fn path(out: &Path) -> PathBuf {
        out.join(FIELDS_FILE)
    }

    /// The observer of the fields of a run into `out` (`None` without the flag), a frame
    /// every N steps: `make` calls the method of the supplied writers for the run's model
    /// with the target of the run ([`FieldsTarget`]: `OUT/fields.h5`, `mode`, and the
    /// checkpoint's run when `session` resumed one).
    ///
    /// # Errors
    /// [`NoFieldWriter`] in a build without writers (the plan refused it already); the
    /// writer's errors, named `--hdf5`.
    pub fn observer<O: ?Sized>(
        &self,
        (program, out): (&str, &Path),
        run: FieldsRun<'_>,
        make: impl FnOnce(&dyn FieldWriters, &FieldsTarget<'_>) -> rsf::Result<Box<O>>,
    ) -> Result<Option<Box<O>>, crate::guard::AnyError> {
        let every = self.every();
        if every == 0 {
            return Ok(None);
        }
        let Some(writers) = &self.writers.0 else {
            return Err(NoFieldWriter {
                program: program.to_owned(),
            }
            .into());
        };
        let path = Self::path(out);
        let target = FieldsTarget {
            path: &path,
            mode: run.mode,
            fingerprint: run.fingerprint,
            resumed: run.resumed,
            allow_change: run.allow_change,
            every,
        };
        crate::guard::flag("--hdf5", make(writers.as_ref(), &target)).map(Some)
    }
}

/// The run a fields file belongs to: its file mode, checkpoint fingerprint, the checkpoint
/// it resumed from and the fields a resume may change.
#[derive(Debug, Clone, Copy)]
pub struct FieldsRun<'a> {
    /// The file mode of the run's folder (the session's).
    pub mode: FileMode,
    /// The fingerprint of the run's checkpoints.
    pub fingerprint: &'a Fingerprint,
    /// The checkpoint the run resumed from.
    pub resumed: Option<&'a Checkpoint>,
    /// `--allow-change`.
    pub allow_change: &'a [String],
}

impl<'a> FieldsRun<'a> {
    /// The run of `session` (resumed or not), whose folder the guard prepared in `fresh`
    /// mode; `allow_change` its `--allow-change`.
    pub fn of(session: &'a Session, fresh: FileMode, allow_change: &'a [String]) -> Self {
        Self {
            mode: session.mode(fresh),
            fingerprint: session.fingerprint(),
            resumed: session.resumed(),
            allow_change,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::{FieldWriters, FieldsTarget, NoFieldWriter};
    use crate::guard::{parse_from, Program};
    use crate::{bp5_pair, pipping_slider, seas_bp1, seas_bp3, seas_bp5, seas_bp6, seas_bp7};
    use crate::{seas_bp8, slider_3d, stepover};
    use rsf::Observer;

    /// Writers that make nothing (the plan does not call them).
    struct Nothing;

    /// The refusal of a writer asked for.
    fn none<T>() -> rsf::Result<T> {
        Err(rsf::Error::InvalidParameter {
            name: "writers".into(),
            reason: "none in this test".into(),
        })
    }

    impl FieldWriters for Nothing {
        fn volume_2d(&self, _: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>> {
            none()
        }
        fn volume_3d(&self, _: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>> {
            none()
        }
        fn fault_antiplane(&self, _: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2, 1>>> {
            none()
        }
        fn fault_2d(&self, _: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>> {
            none()
        }
        fn fault_3d(&self, _: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>> {
            none()
        }
    }

    /// A program with `--hdf5`, whose writers can be supplied.
    trait WithFields: Program {
        /// Supplies [`Nothing`] to the arguments' [`FieldArgs`](super::FieldArgs).
        fn supply_nothing(&mut self);
    }

    /// `impl WithFields` for each program, its [`FieldArgs`](super::FieldArgs) at the
    /// field path given.
    macro_rules! with_fields {
        ($($program:ty: $($field:ident).+;)*) => {
            $(impl WithFields for $program {
                fn supply_nothing(&mut self) {
                    self.$($field).+.supply(Arc::new(Nothing))
                }
            })*
        };
    }

    with_fields! {
        slider_3d::Cli: frames.fields;
        pipping_slider::Cli: frames.fields;
        seas_bp1::Args: job.fields;
        seas_bp3::Args: job.fields;
        seas_bp5::Args: fields;
        seas_bp6::Args: job.fields;
        seas_bp7::Args: job.fields;
        seas_bp8::Args: job.fields;
        stepover::Args: job.fields;
        bp5_pair::Args: job.fields;
    }

    /// `P` with `flags`: `--help` documents `--hdf5`; without writers `--hdf5 3` is refused
    /// by the plan naming the flag and crates/rsf-hdf5's binary `name`, `--hdf5 0` is not;
    /// with writers ([`WithFields::supply_nothing`]) the plan accepts it.
    fn refused_without_writers<P: WithFields>(name: &str, flags: &[&str]) {
        let help = P::command().render_long_help().to_string();
        assert!(help.contains("--hdf5 <N>"), "{name}: {help}");
        let args = |n: &'static str| {
            let mut a = vec![name, "--hdf5", n];
            a.extend_from_slice(flags);
            a
        };
        let (p, _) = parse_from::<P, _, _>(args("3")).unwrap();
        let e = p.plan().err().unwrap_or_else(|| panic!("{name}: accepted"));
        let refusal = e
            .downcast_ref::<NoFieldWriter>()
            .unwrap_or_else(|| panic!("{name}: {e}"));
        assert_eq!(refusal.program, name);
        let text = e.to_string();
        assert!(
            text.starts_with("--hdf5") && text.contains("crates/rsf-hdf5/target/release/"),
            "{text}"
        );
        let (p, _) = parse_from::<P, _, _>(args("0")).unwrap();
        p.plan().unwrap_or_else(|e| panic!("{name} --hdf5 0: {e}"));
        let (mut p, _) = parse_from::<P, _, _>(args("3")).unwrap();
        p.supply_nothing();
        p.plan()
            .unwrap_or_else(|e| panic!("{name} with writers: {e}"));
    }

    /// `P` with writers, `flags` and `--hdf5 N` (the default `--max-output-gb`, 10): the
    /// plan.
    fn planned<P: WithFields>(name: &str, flags: &[&str], n: &str) -> crate::guard::Plan {
        let mut a = vec![name, "--hdf5", n];
        a.extend_from_slice(flags);
        let (mut p, _) = parse_from::<P, _, _>(a).unwrap();
        p.supply_nothing();
        p.plan()
            .unwrap_or_else(|e| panic!("{name} --hdf5 {n}: {e}"))
    }

    /// An adaptive program's plan counts its fields file and, without `--max-steps`, caps
    /// the steps at what `--max-output-gb` leaves: with a frame at every step the planned
    /// output is within the limit and one more frame would pass it (BP5 at 1 km: 101 × 41
    /// nodes, a frame of 128 B a node and 12 kB); a frame every 10⁶ steps gives 10⁶ times
    /// the steps; `--max-steps` whose frames do not fit is refused naming `--hdf5`;
    /// without `--hdf5` no cap.
    #[test]
    fn an_adaptive_runs_fields_are_planned_within_the_output_limit() {
        fn check<P: WithFields>(name: &str, flags: &[&str], frame: Option<f64>) {
            let every = planned::<P>(name, flags, "1");
            let cap = every.step_cap().unwrap_or_else(|| panic!("{name}: no cap"));
            assert!(
                cap >= 1 && every.output_bytes() <= 10e9,
                "{name}: {cap}, {}",
                every.output_bytes()
            );
            if let Some(frame) = frame {
                assert!(
                    every.output_bytes() + frame > 10e9,
                    "{name}: {}",
                    every.output_bytes()
                );
            }
            let sparse = planned::<P>(name, flags, "1000000");
            assert!(
                sparse.step_cap().is_none_or(|c| c >= 1_000_000 * cap),
                "{name}: {:?} against {cap}",
                sparse.step_cap()
            );
            let none = planned::<P>(name, flags, "0");
            assert_eq!(none.step_cap(), None, "{name}");
            let mut a = vec![name, "--hdf5", "1", "--max-steps", "1000000000"];
            a.extend_from_slice(flags);
            let (mut p, _) = parse_from::<P, _, _>(a).unwrap();
            p.supply_nothing();
            let e = p
                .plan()
                .err()
                .unwrap_or_else(|| panic!("{name}: accepted"))
                .to_string();
            assert!(
                e.starts_with("--hdf5 1:") && e.contains("max_steps"),
                "{name}: {e}"
            );
        }
        let frame_1km = super::FIELDS_VERTEX_BYTES * 101.0 * 41.0 + super::FIELDS_FRAME_BYTES;
        type Check = fn(&str, &[&str], Option<f64>);
        let programs: [(&str, &[&str], Option<f64>, Check); 8] = [
            (
                "seas_bp5",
                &["--dx", "1000"],
                Some(frame_1km),
                check::<seas_bp5::Args>,
            ),
            (
                "seas_bp1",
                &["--out", "out/seas_bp1"],
                None,
                check::<seas_bp1::Args>,
            ),
            ("seas_bp3", &[], None, check::<seas_bp3::Args>),
            (
                "seas_bp6",
                &["--variant", "a"],
                None,
                check::<seas_bp6::Args>,
            ),
            ("seas_bp7", &[], None, check::<seas_bp7::Args>),
            ("seas_bp8", &[], None, check::<seas_bp8::Args>),
            ("stepover", &[], None, check::<stepover::Args>),
            ("bp5_pair", &[], None, check::<bp5_pair::Args>),
        ];
        for (name, flags, frame, check) in programs {
            check(name, flags, frame);
        }
    }

    #[test]
    fn hdf5_is_refused_by_a_build_without_writers_naming_the_flag_and_the_binary() {
        type Refused = fn(&str, &[&str]);
        let programs: [(&str, &[&str], Refused); 8] = [
            ("slider_3d", &[], refused_without_writers::<slider_3d::Cli>),
            (
                "pipping_slider",
                &[],
                refused_without_writers::<pipping_slider::Cli>,
            ),
            (
                "seas_bp1",
                &["--out", "out/seas_bp1"],
                refused_without_writers::<seas_bp1::Args>,
            ),
            ("seas_bp3", &[], refused_without_writers::<seas_bp3::Args>),
            ("seas_bp5", &[], refused_without_writers::<seas_bp5::Args>),
            (
                "seas_bp6",
                &["--variant", "a"],
                refused_without_writers::<seas_bp6::Args>,
            ),
            ("seas_bp7", &[], refused_without_writers::<seas_bp7::Args>),
            ("seas_bp8", &[], refused_without_writers::<seas_bp8::Args>),
        ];
        for (name, flags, refused) in programs {
            refused(name, flags);
        }
    }
}
