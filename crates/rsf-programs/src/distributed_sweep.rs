//! The flags and the [`Plan`] of the `rsf-mpi` crate's program `distributed_sweep` (the
//! distributed smoother, V-cycle or TNNMG on a refined elastic box, timed on MPI ranks;
//! docs/scaling.md, "Phase 2"), here so that the guard judges them like every other
//! program's and the careless-inputs test checks them without MPI (issue 74). The body
//! that runs them is the MPI crate's (`crates/rsf-mpi/src/bin/distributed_sweep/`).

use std::path::PathBuf;

use crate::cli::step_count;
use crate::guard::{in_range, refuse, AnyError, Folder, Limits, Plan, Program};

/// The file a run writes into `--out`: the solution's values after the last repetition
/// (every rank's owned values gathered in global order, node-major, little-endian f64).
pub const VALUES: &str = "values.bin";

/// Bytes per vertex of the elastic box's set-up on one process — the stiffness (27 blocks
/// of 72 bytes and a 4-byte column per vertex), the mesh hierarchy, the colouring and
/// METIS's graph — and of the hierarchy of `--vcycle` and `--tnnmg`: measured as the peak
/// resident set per vertex of `distributed_sweep --tnnmg` on one rank (docs/reliability.md,
/// "Memory estimates"), rounded up.
pub const BOX_BYTES_PER_VERTEX: f64 = 6e3;

/// Bytes of a process before any model: the MPI library, the program and its threads.
pub const PROCESS_BYTES: f64 = 100e6;

// The sweeps (or cycles) per repetition and the repetitions of a run: it is a timing run
// (seconds to minutes), and more is a typo. One pair of literals for the help and the check.
crate::guard::flag_range!(
    pub SWEEPS,
    SWEEPS_HELP = "Sweeps per repetition (`--vcycle`: V(1,1)-cycles)",
    [1, 1e6]
);
crate::guard::flag_range!(
    pub REPETITIONS,
    REPETITIONS_HELP = "Repetitions from the same start, each timed",
    [1, 1e4]
);

/// The distributed smoother on MPI ranks: linear block Gauss–Seidel sweeps (or V-cycles,
/// or TNNMG solves) of a refined elastic box partitioned by METIS.
#[derive(Debug, clap::Parser)]
#[command(name = "distributed_sweep", version)]
pub struct Args {
    /// Refinements of the 5 × 3 × 3 box of cubes (`ElasticBox::bar`).
    #[arg(long, default_value_t = 2)]
    pub refinements: usize,
    #[arg(long, default_value = "6", value_parser = step_count, help = SWEEPS_HELP)]
    pub sweeps: usize,
    #[arg(long, default_value = "1", value_parser = step_count, help = REPETITIONS_HELP)]
    pub repetitions: usize,
    /// Output folder: the solution after the last repetition (`values.bin`, node-major
    /// little-endian f64) and the run's manifest.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    pub overwrite: bool,
    /// One rank: the one-process coloured sweep (or V-cycle) instead of the distributed one.
    #[arg(long)]
    pub reference: bool,
    /// Linear V(1,1)-cycles instead of sweeps.
    #[arg(long)]
    pub vcycle: bool,
    /// `--vcycle`: the number of finest levels of the hierarchy (default: all).
    #[arg(long)]
    pub levels: Option<usize>,
    /// TNNMG solves of a frictional problem on the box instead of sweeps.
    #[arg(long)]
    pub tnnmg: bool,
    /// `--tnnmg`: the linear correction by preconditioned CG.
    #[arg(long)]
    pub cg: bool,
    /// `--tnnmg` on one MPI rank: the solve on N threads as ranks.
    #[arg(long, value_name = "N")]
    pub thread_ranks: Option<usize>,
    #[command(flatten)]
    pub limits: Limits,
}

/// Vertices of the box refined `refinements` times: `(5·2ᴿ + 1)(3·2ᴿ + 1)²` (an `f64`: a
/// refinement of 60 is a number, not an overflow).
pub fn box_vertices(refinements: usize) -> f64 {
    let k = 2f64.powi(refinements.min(1000) as i32);
    (5.0 * k + 1.0) * (3.0 * k + 1.0) * (3.0 * k + 1.0)
}

impl Args {
    /// The file of the solution, if `--out` is given.
    pub fn values_file(&self) -> Option<PathBuf> {
        self.out.as_ref().map(|d| d.join(VALUES))
    }
}

impl Program for Args {
    crate::name_and_limits!("distributed_sweep");

    fn plan(&self) -> Result<Plan, AnyError> {
        let needs = |given: bool, flag: &str, needed: &str| -> Result<(), AnyError> {
            if given {
                Err(format!("{flag}: needs {needed} (without it, it would be ignored)").into())
            } else {
                Ok(())
            }
        };
        needs(
            self.levels.is_some() && !self.vcycle,
            "--levels",
            "--vcycle",
        )?;
        needs(self.cg && !self.tnnmg, "--cg", "--tnnmg")?;
        needs(
            self.thread_ranks.is_some() && !self.tnnmg,
            "--thread-ranks",
            "--tnnmg",
        )?;
        if self.tnnmg && (self.vcycle || self.reference) {
            return Err("--tnnmg: takes neither --vcycle nor --reference".into());
        }
        in_range(
            "--sweeps",
            self.sweeps as f64,
            SWEEPS,
            "per repetition (a timing run)",
        )?;
        in_range(
            "--repetitions",
            self.repetitions as f64,
            REPETITIONS,
            "(a timing run)",
        )?;
        if let Some(l) = self.levels {
            if l == 0 || l > self.refinements.saturating_add(1) {
                return Err(refuse(
                    "--levels",
                    l,
                    &format!(
                        "must be in [1, {}] (the box refined {} times has {} levels)",
                        self.refinements.saturating_add(1),
                        self.refinements,
                        self.refinements.saturating_add(1)
                    ),
                ));
            }
        }
        let vertices = box_vertices(self.refinements);
        let ranks = self.thread_ranks.unwrap_or(1) as f64;
        // Thread ranks hold their parts in one process: about one more box per rank.
        let memory = PROCESS_BYTES + vertices * BOX_BYTES_PER_VERTEX * ranks.max(1.0);
        let mut plan = Plan::new()
            .memory(
                memory,
                "--refinements, --thread-ranks",
                format!(
                    "the box refined {} times: {vertices:.3e} vertices",
                    self.refinements
                ),
            )
            .output(
                if self.out.is_some() {
                    24.0 * vertices
                } else {
                    0.0
                },
                "--refinements",
                "the solution's values",
            );
        if let Some(n) = self.thread_ranks {
            plan = plan.threads("--thread-ranks", n);
        }
        if let Some(out) = &self.out {
            plan = plan.folder(Folder::new("--out", out, &[VALUES]).overwrite(self.overwrite));
        }
        Ok(plan)
    }
}
