//! The paper's model problem (Pipping, Sander & Kornhuber §6.1, Table 6.1): a 5 m × 1 m
//! elastic block, sheared at its top with a ramped velocity, sliding on its rate-and-state
//! frictional bottom. The main job of the workspace: the root package's binary (its
//! build compiles the slider's programs alone, not the SEAS programs of the examples).
//!
//! ```sh
//! cargo run --release                       # j = 4, N = 1e4, Dieterich, Newmark
//! cargo run --release -- --level 3 --law ruina --solver direct
//! cargo run --release -- --scene scenes/pipping_slider.toml
//! cargo run --release -- --mu0 0.5 --sigma-n-pa 1e5   # every field of the scene is a flag
//! cargo run --release -- --level 3 --adaptive 1e-3   # adaptive τ
//! cargo run --release -- --level 3 --frame-every 50   # ParaView frames
//! cargo run --release -- --checkpoint-every 1000   # then, after a kill:
//! cargo run --release -- --checkpoint-every 1000 --resume out/pipping_slider/checkpoint.bin
//! ```
//!
//! Writes to `out/pipping_slider/` (or `--out DIR`): `timeseries.csv` (a
//! `rsf::observe::PointSeries` at x0 = (2.5, 0)), `frictional_profile.csv` (a
//! `rsf::observe::FrictionalProfile` over the window, default [0.6725T, 0.6775T]),
//! `slip_rate_map.csv` (the profile of the whole run, 600 samples), `summary.json` (with
//! accepted and rejected steps and, for adaptive steps, the resolved tolerances), and the
//! figures `displacement_x0.png`, `slip_rate_x0.png`, `slip_rate_map.png`; with
//! `--frame-every N`, VTU frames of every N-th step and their index `frames/frames.pvd`
//! for ParaView (displacement, velocity; on Γ_F slip, slip rate, state, shear and normal
//! traction). Summary and
//! figures are computed from the CSV files, so a resumed run (which continues the files
//! from the checkpoint's step) reports the whole run.
//!
//! A folder holding another run's files is refused (`--overwrite` replaces them); on
//! `--resume` the checkpoint's checksum, its fingerprint (the scene; `--allow-change
//! end_time_s` for a deliberate change) and the folder's rows are checked before any file
//! is cut (docs/reliability.md).

use std::process::ExitCode;

use rsf_programs::pipping_slider::{run_prepared, Cli};

fn main() -> ExitCode {
    rsf_programs::guard::main::<Cli>(run_prepared)
}
