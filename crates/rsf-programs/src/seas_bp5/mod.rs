//! SEAS BP5-QD (a vertical strike-slip fault in a half-space, two slip components, 3-D;
//! docs/seas-bp5.md), integrated by the fault ODE with either kernel: `--kernel okada`
//! (the default) a fault alone with Okada's half-space operator, loaded by back slip;
//! `--kernel fe` the finite-element volume model (`SeasBp5::fe_model`: the fault plane
//! inside a graded box, creeping outside the rate-and-state region, the far faces moving
//! with their side) condensed onto the fault.
//!
//! ```sh
//! cargo run --release --example seas_bp5 -- --out out/bp5            # Δx = 2 km, 1800 years
//! cargo run --release --example seas_bp5 -- --dx 1000 --out out/bp5_1km --threads 2
//! cargo run --release --example seas_bp5 -- --kernel fe --dx 2500 --out out/bp5_fe
//! ```
//!
//! The scene is `rsf_scenes::SeasBp5`: the rate-and-state region (100 km × 40 km) in
//! square cells of size `--dx`, each the centre of a constant-slip element of
//! `rsf::halfspace_operator::HalfSpaceOperator::fault_alone` (dense up to 4 096
//! unknowns, an ℋ-matrix of accuracy `--epsilon` beyond). The rest of the fault plane
//! creeps at V_p: back slip (`rsf::fault_alone::FaultAlone`) represents it exactly.
//!
//! Writes the benchmark's files to `--out` (`rsf_seas::SeasBp5Output`: the ten
//! on-fault stations `fltst_strk±XXdp±YY`, the nine off-fault stations
//! `blkst_strk±XXfn±YYdp±ZZ`, `global.dat`, the slip and stress profiles, `rupture.dat`,
//! the event catalogue `events.csv`), `summary.json` and the figure `overview.png`
//! (slip₂ along dip at x₂ = 0; the maximum slip rate against time), and prints the
//! ruptures and their recurrence intervals.
//!
//! Runs: `--checkpoint-every N` (a checkpoint `checkpoint.bin` every N steps, the files
//! and their resume log `bp5_resume.json` written at the same steps), `--resume FILE`
//! (continues the files in `--out` from a checkpoint of this run: the same bytes as an
//! uninterrupted run), `--max-steps N` (stop after step N in total, with a checkpoint),
//! `--overwrite` (a folder of another run is refused, and left untouched, otherwise).
//!
//! On MPI ranks: the `rsf-mpi` crate's `seas_bp5` runs [`main_on_ranks`] (every evaluation
//! shared by the ranks, the files written by rank 0; docs/scaling.md, "The fault ODE on MPI
//! ranks").

mod args;
mod run;

pub(crate) use args::graded_mesh_fewest_vertices;
#[cfg(test)]
pub(crate) use args::plans_of_the_largest_boxes;
pub use args::Args;
pub use args::{
    graded_schur_only_nd_peak, GRADED_ND_BYTES_PER_KEPT_SQUARED, GRADED_ND_BYTES_PER_VERTEX,
};
use run::run;

crate::seas_args::ranked_entry_points! {
    Args, run;
    /// The program `seas_bp5` (`cargo run --release --example seas_bp5 -- --out DIR …`).
    main,
    /// The program `seas_bp5` with `writers` of the fault's fields (`--hdf5 N`,
    /// [`FieldWriters::fault_3d`](crate::fields::FieldWriters::fault_3d), with either
    /// kernel; the binary `seas_bp5` of crates/rsf-hdf5).
    main_with_fields,
    /// The program on the processes of a job (MPI ranks, the `rsf-mpi` crate's `seas_bp5`):
    /// every evaluation of the fault ODE shared by the ranks
    /// ([`rsf::FaultOde::share_evaluations`]: the half-space operator's elements, or the
    /// finite-element operator's rows), the files written by rank 0 — byte-identical to one
    /// process's (docs/scaling.md, "The fault ODE on MPI ranks").
    ///
    /// With `writers` (the `rsf-mpi` crate built with its feature `hdf5`), `--hdf5 N`
    /// writes the fault's fields from rank 0, as [`main_with_fields`] does in one process.
    main_on_ranks,
}
