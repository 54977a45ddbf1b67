//! The SCEC SEAS benchmark BP1-QD (Erickson et al. 2020; docs/seas-bp1.md): a vertical
//! strike-slip fault in an antiplane half-space, regularised rate-and-state friction with
//! the aging law, radiation damping, 3000 years of earthquake cycles — through the
//! library's scalar (antiplane) model, antisymmetric fault and adaptive steps.
//!
//! ```text
//! cargo run --release --example seas_bp1 -- --out out/seas_bp1
//! cargo run --release --example seas_bp1 -- --out out/bp1_coarse --dz 200 --end-years 600
//! ```
//! Flags: `--out DIR` (required; refuses a folder with files of another run unless
//! `--overwrite`), `--end-years Y` (default 3000), `--dz M` (element size on the fault,
//! default 25), `--domain-km L` (default 400), `--ratio R` (mesh growth away from the
//! fault, default 1.05), `--tolerance E` (adaptive steps, default 1e-3), `--state-change-cap`
//! (ξ, default 0.5; 0 for none), `--fixed-point-tolerance` (default 1e-10), `--inertia`
//! (Newmark, fully dynamic, no radiation damping: BP1-FD; its defaults the converged
//! set-up of docs/seas-bp1-fd.md: `--absorbing all --switch-to-dynamic 1e-2
//! --switch-to-quasi-dynamic 1e-3`), `--absorbing none|dynamic|all` (absorbing far
//! boundaries with `--inertia`, default `all`; docs/seas-bp1-fd.md),
//! `--dynamic-integrator newmark|backward-euler`,
//! `--every-step` (a station row
//! at every step instead of the benchmark's thinning), `--setup-per-time-step` (one solver
//! set-up per step size, for comparison), `--scheme runge-kutta|implicit` (default
//! `runge-kutta`: the quasi-dynamic equations condensed onto the fault and integrated by
//! the Dormand–Prince 5(4) pair; `implicit`: the paper's scheme), `--rk-tolerance`
//! (default 1e-6), `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps,
//! with the benchmark files' resume log `seas_resume.csv`), `--resume FILE` (continues the
//! files in `--out` from a checkpoint of this run: fingerprint, checkpoint and every file's
//! rows are checked before anything is cut, and the continued files are byte-identical to
//! an uninterrupted run's, with either scheme and with `--inertia`; docs/reliability.md),
//! `--allow-change FIELD,…` (a deliberate change on resume, e.g. `end_years`), `--max-steps
//! N` (stop after step N in total, across resumes, with a checkpoint and the resume log to
//! continue from with a larger N), `--kernel hierarchical|dense` (how the Runge–Kutta run
//! stores the operator condensed onto the fault: as an ℋ-matrix, the default, or dense;
//! part of the fingerprint, so a checkpoint of the other kernel is refused on `--resume`),
//! `--kernel-epsilon E` (the ℋ-matrix's accuracy; default the `--rk-tolerance`,
//! `FaultKernel::matching`), `--threads N` (threads of each evaluation: the product with
//! the operator and the per-node friction solves; default every core of the machine; the
//! same bits for every N), `--rho`, `--c-s`, `--sigma-n`, `--a0`, `--a-max`, `--b0`,
//! `--d-c`, `--v-p`, `--v-init`, `--v0`, `--f0`, `--h-top`, `--h-transition`, `--w-f` (the
//! description's parameters, SI units; default its values), `--config FILE.toml` (the
//! settings as a TOML file, keys the flags' names with underscores; a flag given wins).
//! The settings are one struct, `rsf_scenes::SeasBp1Run` (docs/design.md, "One run
//! configuration"): the flags, the file's keys, Python's `rsf.seas_bp1` keywords, the
//! checkpoint's fingerprint and `summary.json`'s `settings`.
//!
//! Writes the benchmark's files (`fltst_dp000` … `fltst_dp350`, `devol.dat`), `events.csv`,
//! `summary.json` and `overview.png` (maximum slip rate against time, slip profiles).

mod args;
mod run;

pub use args::Args;
use run::run;

crate::seas_args::ranked_entry_points! {
    Args, run, job;
    /// The program `seas_bp1` (`cargo run --release --example seas_bp1 -- --out DIR …`).
    main,
    /// The program `seas_bp1` with `writers` of the fault's fields (`--hdf5 N`,
    /// [`FieldWriters::fault_antiplane`](crate::fields::FieldWriters::fault_antiplane); the
    /// binary `seas_bp1` of crates/rsf-hdf5).
    main_with_fields,
    /// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `seas_bp1`):
    /// the Runge–Kutta run of BP1-QD with every evaluation shared by the ranks
    /// ([`rsf::FaultOde::share_evaluations`]; the dense or the ℋ-kernel), the files written
    /// by rank 0 — byte-identical to one process's (docs/scaling.md, "Past one machine").
    ///
    /// With `writers` (the `rsf-mpi` crate built with its feature `hdf5`), `--hdf5 N`
    /// writes the fault's fields from rank 0, as [`main_with_fields`] does in one process.
    main_on_ranks,
}
