//! The files of SEAS BP6-QD-A/S/C (docs/seas-bp6.md, "Output"; Lambert & Dunham's
//! description §4): the nine on-fault stations `fltst_strk±XX` with pore pressure and
//! Darcy velocity columns, `global.dat` (maximum slip rate and moment rate) and the four
//! profiles `slip.dat`, `shear_stress.dat`, `normal_stress.dat`, `darcy_vel.dat` on
//! `−10 km ≤ z ≤ 10 km`, with the SCEC header conventions of the other benchmarks.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use rsf::observe::FaultTractions;
use rsf::pore_pressure::PorePressure;
use rsf::{Flow, Model, Observer, SimulationState, StepView};

use crate::error::{invalid, Result};
use crate::reserve::Reserve;
use crate::resume::{read_log, write_log, LogMark};
use crate::setup::SeasSetup;
use crate::text::{create_output_dir, positions_row, write_row, File, FileLayout, Positions};

/// The stations of BP6 along the fault (km): `fltst_strk-15` … `fltst_strk+75`.
pub const SEAS_BP6_STATIONS: [f64; 9] = [-1.5, 0.0, 0.5, 1.0, 1.5, 2.5, 3.5, 5.0, 7.5];

/// Name of the resume log of [`SeasBp6Output`] (JSON).
pub const SEAS_BP6_RESUME_LOG: &str = "bp6_resume.json";

/// Smallest slip rate written as `log10 V` (m/s): a locked node (BP6-C) has `V = 0`.
pub const BP6_SLIP_RATE_FLOOR: f64 = 1e-20;

/// The station file of position `z` km: `fltst_strk` and `z` in hundreds of metres with
/// its sign and two digits (`-15`, `+00`, `+75`).
pub fn bp6_station_name(z_km: f64) -> String {
    let h = (z_km * 10.0).round() as i64;
    format!("fltst_strk{}{:02}", if h < 0 { '-' } else { '+' }, h.abs())
}

const STATION_COLUMNS: [(&str, &str); 7] = [
    ("t", "Time (s)"),
    ("slip", "Slip (m)"),
    ("slip_rate", "Slip rate (log10 m/s)"),
    ("shear_stress", "Shear stress (MPa)"),
    ("pore_pressure", "Pore pressure (MPa)"),
    ("darcy_vel", "Darcy velocity (m/s)"),
    ("state", "State (log10 s)"),
];

const GLOBAL_COLUMNS: [(&str, &str); 3] = [
    ("t", "Time (s)"),
    ("max_slip_rate", "Max slip rate (log10 m/s)"),
    ("moment_rate", "Moment rate (N/s)"),
];

/// What a profile holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Quantity {
    Slip,
    ShearStress,
    NormalStress,
    Darcy,
}

impl Quantity {
    const ALL: [Self; 4] = [
        Self::Slip,
        Self::ShearStress,
        Self::NormalStress,
        Self::Darcy,
    ];
    fn file(self) -> &'static str {
        match self {
            Self::Slip => "slip.dat",
            Self::ShearStress => "shear_stress.dat",
            Self::NormalStress => "normal_stress.dat",
            Self::Darcy => "darcy_vel.dat",
        }
    }
    fn column(self) -> (&'static str, &'static str) {
        match self {
            Self::Slip => ("slip", "Slip (m) at the positions z of the first data row"),
            Self::ShearStress => (
                "shear_stress",
                "Shear stress (MPa) at the positions z of the first data row",
            ),
            Self::NormalStress => (
                "normal_stress",
                "Effective normal stress (MPa) at the positions z of the first data row",
            ),
            Self::Darcy => (
                "darcy_vel",
                "Darcy velocity (m/s) at the positions z of the first data row",
            ),
        }
    }
}

/// Where a run's fault is: for every frictional node its position `z` along the fault
/// (m) and the dof of its slip; the fault's normal stress without pressure and its
/// radiation damping.
#[derive(Debug, Clone, PartialEq)]
pub struct Bp6Fault {
    /// `z` of every frictional node (m, increasing).
    pub positions: Vec<f64>,
    /// The dof of every frictional node's slip.
    pub slip_dofs: Vec<usize>,
    /// The length (m) of fault each node stands for (its weight).
    pub lengths: Vec<f64>,
    /// Shear modulus μ (Pa), for the moment rate.
    pub shear_modulus: f64,
    /// Effective normal stress without the injection, `σ̄₀` (Pa).
    pub sigma_n: f64,
    /// Whether the friction has a state (BP6-A, -S; the state column is 0 for BP6-C).
    pub has_state: bool,
}

impl Bp6Fault {
    /// The nodes around `z` and their linear weights (one node at or beyond the ends).
    fn around(&self, z: f64) -> [(usize, f64); 2] {
        let p = &self.positions;
        let j = p.partition_point(|&x| x < z);
        if j == 0 {
            return [(0, 1.0), (0, 0.0)];
        }
        if j == p.len() {
            return [(p.len() - 1, 1.0), (0, 0.0)];
        }
        if p[j] == z {
            return [(j, 1.0), (j, 0.0)];
        }
        let f = (z - p[j - 1]) / (p[j] - p[j - 1]);
        [(j - 1, 1.0 - f), (j, f)]
    }
}

struct Station {
    file: File,
    z: f64,
    nodes: [(usize, f64); 2],
}

struct Profile {
    file: File,
    quantity: Quantity,
    points: Vec<(f64, [(usize, f64); 2])>,
}

/// The output's own state at a step (what its files hold), as the resume log keeps it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct Mark {
    step: usize,
    /// The run's time after the step (s; `None` in a log of a version before issue 87).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    t: Option<f64>,
    written: usize,
    last_station_t: f64,
    tau: (f64, f64),
    steps: usize,
    profile_written: usize,
    last_profile_t: f64,
}

impl LogMark for Mark {
    fn step(&self) -> usize {
        self.step
    }
    fn time(&self) -> Option<f64> {
        self.t
    }
}

/// The BP6 files of a run (an [`Observer`]), its fault alone or its finite-element model:
/// the stations [`SEAS_BP6_STATIONS`], `global.dat` and the four profiles at 100 m on
/// `|z| ≤ 10 km` (201 positions), each value interpolated linearly between the two
/// frictional nodes around its position (a node itself where there is one). Rows at the
/// first accepted step at least `station_interval` (default 1 h; 0: every step) after the
/// last, profile rows every `profile_interval` (default 3 h); a first row of every file at `t = 0`
/// ([`write_initial_state`](Self::write_initial_state)). Columns: slip (the change of the
/// slip dof), `log10 |V|` (floored at [`BP6_SLIP_RATE_FLOOR`]), the shear stress
/// `τ = τ⁰ + Δτ − ηV` (MPa: the friction where the node slides, the elastic traction
/// `(F − K u)_k/w_k` of a locked node of a model with a stiffness), the pressure change
/// `p` and the Darcy velocity of the run's pore-pressure field, `log10 θ` (0 without a
/// state); the profiles' normal stress is `σ̄₀ − p`. Rows are kept in memory and every file
/// is written whole, atomically, by [`finish`](Observer::finish). The disk space of the
/// rows is held as they grow — a file of zeros, [`RESERVE_FILE`](crate::RESERVE_FILE), in
/// the output folder, given back just before the files are written — so that a full disk
/// stops the run when it happens, not after it.
pub struct SeasBp6Output {
    dir: PathBuf,
    setup: SeasSetup,
    fault: Bp6Fault,
    pressure: Arc<dyn PorePressure<2>>,
    stations: Vec<Station>,
    global: File,
    profiles: Vec<Profile>,
    station_interval: f64,
    profile_interval: f64,
    mark: Mark,
    persist_every: usize,
    resume_log: bool,
    /// A mark also where every run ends ([`Self::with_marks_where_runs_end`]).
    mark_at_finish: bool,
    log: Vec<Mark>,
    /// The disk space held for the rows in memory.
    reserve: Reserve,
}

impl SeasBp6Output {
    /// The output of `fault` with the pore pressure `pressure` into `dir` (created if
    /// missing); `setup` gives the headers' problem, modeler, date and element size.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `fault` (no
    /// node, positions not increasing, lengths of another number), `date`; I/O errors
    /// creating `dir`.
    pub fn new(
        dir: &Path,
        fault: Bp6Fault,
        pressure: Arc<dyn PorePressure<2>>,
        setup: SeasSetup,
    ) -> Result<Self> {
        let n = fault.positions.len();
        if n == 0
            || fault.slip_dofs.len() != n
            || fault.lengths.len() != n
            || fault.positions.windows(2).any(|w| !(w[1] > w[0]))
        {
            return Err(invalid(
                "fault",
                "needs nodes with increasing positions, one slip dof and length each",
            ));
        }
        create_output_dir(dir, &setup)?;
        let file = |name: &str, location: String, columns: &[(&str, &str)]| {
            File::new(dir.join(name), FileLayout::new(location, columns))
        };
        let stations = SEAS_BP6_STATIONS
            .iter()
            .map(|&z| Station {
                file: file(
                    &bp6_station_name(z),
                    format!("on fault, {z} km along strike"),
                    &STATION_COLUMNS,
                ),
                z: z * 1e3,
                nodes: fault.around(z * 1e3),
            })
            .collect();
        let positions: Vec<f64> = (0..=200).map(|i| -10e3 + 100.0 * i as f64).collect();
        let profiles = Quantity::ALL
            .iter()
            .map(|&q| {
                let columns = [
                    ("t", "Time (s)"),
                    ("max_slip_rate", "Max slip rate (log10 m/s)"),
                    q.column(),
                ];
                let mut f = file(q.file(), format!("{} along strike", q.column().0), &columns);
                f.layout.profile = Some(Positions {
                    words: "positions z".into(),
                    coordinate: "z".into(),
                    name_per_line: false,
                });
                f.rows = positions_row(positions.iter().copied());
                f.rows.push('\n');
                Profile {
                    file: f,
                    quantity: q,
                    points: positions.iter().map(|&z| (z, fault.around(z))).collect(),
                }
            })
            .collect();
        Ok(Self {
            dir: dir.to_path_buf(),
            setup,
            global: file("global.dat", "global".into(), &GLOBAL_COLUMNS),
            fault,
            pressure,
            stations,
            profiles,
            station_interval: 3600.0,
            profile_interval: 3.0 * 3600.0,
            mark: Mark {
                step: 0,
                t: None,
                written: 0,
                last_station_t: f64::NEG_INFINITY,
                tau: (f64::INFINITY, 0.0),
                steps: 0,
                profile_written: 0,
                last_profile_t: f64::NEG_INFINITY,
            },
            persist_every: 0,
            resume_log: false,
            mark_at_finish: false,
            log: Vec::new(),
            reserve: Reserve::new(dir),
        })
    }

    /// Station rows at least `station` s apart, profile rows at least `profile` s apart
    /// (defaults 1 h and 3 h; 0: every step).
    pub fn with_intervals(mut self, station: f64, profile: f64) -> Self {
        self.station_interval = station.max(0.0);
        self.profile_interval = profile.max(0.0);
        self
    }

    /// The names of the files this output writes (besides the resume log).
    pub fn file_names() -> Vec<String> {
        let mut names: Vec<String> = SEAS_BP6_STATIONS
            .iter()
            .map(|&z| bp6_station_name(z))
            .collect();
        names.push("global.dat".into());
        names.extend(Quantity::ALL.iter().map(|q| q.file().to_string()));
        names
    }

    /// The first row of every file: the state at `t = 0`.
    pub fn write_initial_state<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        state: &SimulationState,
        friction: &dyn FaultTractions,
    ) {
        let values = self.node_values(model, state, friction);
        self.write_rows(state.time, &values);
        self.write_profiles(state.time, &values);
    }

    /// Per node: slip, V, τ (Pa), α.
    fn node_values<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        state: &SimulationState,
        friction: &dyn FaultTractions,
    ) -> Vec<[f64; 4]> {
        let f = &self.fault;
        let (u, v) = (&state.kinematics.u, &state.kinematics.v);
        let fb = &model.frictional_boundary;
        let stiff = model.stiffness.compute_nnz() > 0;
        (0..f.positions.len())
            .map(|k| {
                let dof = f.slip_dofs[k];
                let speed = v[dof].abs();
                let alpha = state.alpha[k];
                let mut tau = friction.shear_traction(k, speed, alpha);
                if speed == 0.0 && stiff {
                    // A locked node: the elastic traction (F − K u)_k / w_k.
                    let k_u: f64 = model
                        .stiffness
                        .row_idx_of_col(dof)
                        .zip(model.stiffness.val_of_col(dof))
                        .map(|(i, &a)| a * u[i])
                        .sum();
                    let elastic = (model.load[dof] - k_u) / fb.weights[k];
                    if elastic.is_finite() {
                        tau = elastic;
                    }
                }
                [u[dof] - model.initial_displacement[dof], v[dof], tau, alpha]
            })
            .collect()
    }

    fn interpolate(values: &[[f64; 4]], nodes: &[(usize, f64); 2], i: usize) -> f64 {
        nodes
            .iter()
            .filter(|(_, w)| *w != 0.0)
            .map(|&(k, w)| w * values[k][i])
            .sum()
    }

    fn vmax_and_moment_rate(&self, values: &[[f64; 4]]) -> (f64, f64) {
        let mut vmax = 0.0_f64;
        let mut sum = 0.0;
        for (x, l) in values.iter().zip(&self.fault.lengths) {
            vmax = vmax.max(x[1].abs());
            sum += l * x[1].abs();
        }
        (vmax, self.fault.shear_modulus * sum)
    }

    fn log_rate(v: f64) -> f64 {
        v.abs().max(BP6_SLIP_RATE_FLOOR).log10()
    }

    fn write_rows(&mut self, t: f64, values: &[[f64; 4]]) {
        self.mark.last_station_t = t;
        self.mark.written += 1;
        for st in &mut self.stations {
            let x = [0, 1, 2, 3].map(|i| Self::interpolate(values, &st.nodes, i));
            let point = [0.0, st.z];
            let state = if self.fault.has_state {
                x[3] / std::f64::consts::LN_10
            } else {
                0.0
            };
            let row = [
                x[0],
                Self::log_rate(x[1]),
                x[2] / 1e6,
                self.pressure.pressure(&point, t) / 1e6,
                self.pressure.darcy_velocity(&point, t).unwrap_or(0.0),
                state,
            ];
            write_row(&mut st.file.rows, t, &row);
        }
        let (vmax, moment_rate) = self.vmax_and_moment_rate(values);
        write_row(
            &mut self.global.rows,
            t,
            &[Self::log_rate(vmax), moment_rate],
        );
    }

    fn write_profiles(&mut self, t: f64, values: &[[f64; 4]]) {
        self.mark.last_profile_t = t;
        self.mark.profile_written += 1;
        let (vmax, _) = self.vmax_and_moment_rate(values);
        let mut row = Vec::with_capacity(202);
        for p in &mut self.profiles {
            row.clear();
            row.push(Self::log_rate(vmax));
            for (z, nodes) in &p.points {
                let point = [0.0, *z];
                row.push(match p.quantity {
                    Quantity::Slip => Self::interpolate(values, nodes, 0),
                    Quantity::ShearStress => Self::interpolate(values, nodes, 2) / 1e6,
                    Quantity::NormalStress => {
                        (self.fault.sigma_n - self.pressure.pressure(&point, t)) / 1e6
                    }
                    Quantity::Darcy => self.pressure.darcy_velocity(&point, t).unwrap_or(0.0),
                });
            }
            write_row(&mut p.file.rows, t, &row);
        }
    }

    fn files(&self) -> impl Iterator<Item = &File> {
        self.stations
            .iter()
            .map(|s| &s.file)
            .chain(std::iter::once(&self.global))
            .chain(self.profiles.iter().map(|p| &p.file))
    }

    /// Bytes of the rows held in memory (every file's).
    fn held_bytes(&self) -> u64 {
        self.files().map(|f| f.rows.len() as u64).sum()
    }

    /// Writes every file whole (atomically), into the space held for them (given back
    /// first).
    fn write_files(&mut self) -> Result<()> {
        self.reserve.release()?;
        let steps = (self.mark.steps > 0).then_some(self.mark.tau);
        let written = (self.mark.written, self.mark.profile_written);
        for f in self.files() {
            f.write(&self.setup, steps, written)?;
        }
        Ok(())
    }

    /// Keeps the resume log [`SEAS_BP6_RESUME_LOG`]: writes every file and a mark every
    /// `steps` steps (0: only at a step cap), so that a run continued from a checkpoint
    /// written at such a step continues its files ([`resume`](Self::resume)).
    pub fn with_resume_log(mut self, steps: usize) -> Self {
        self.resume_log = true;
        self.persist_every = steps;
        self
    }

    /// Keeps the resume log with a mark also where every run ends (its
    /// [`finish`](Observer::finish): the end time, an observer's break, Ctrl-C), so that a
    /// front end that writes a checkpoint where a run stopped — the Python package's
    /// `Simulation.checkpoint` after `advance`, its checkpoint when Ctrl-C stops a run —
    /// continues the files from it. The marks of [`with_resume_log`](Self::with_resume_log)
    /// every `steps` steps are kept.
    pub fn with_marks_where_runs_end(mut self, steps: usize) -> Self {
        self.mark_at_finish = true;
        self.with_resume_log(steps)
    }

    fn persist(&mut self) -> Result<()> {
        self.write_files()?;
        write_log(
            &mut self.log,
            &self.mark,
            &self.dir.join(SEAS_BP6_RESUME_LOG),
        )
    }

    /// Continues the files of the run in this folder at its persisted step `step` (the
    /// checkpoint's, at time `time`, s; the log's mark of the step must be at exactly that
    /// time: the files are the checkpoint's run's, issue 87): each file keeps its rows up to that step, checked as every SEAS
    /// file is (field-list lines, the profile's positions, the rows complete, the last
    /// at the mark's time).
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the resume log (no mark at `step`,
    /// a mark at another time, unreadable) or the file that cannot be continued.
    pub fn resume(&mut self, step: usize, time: f64) -> Result<()> {
        let (log, mark) = read_log::<Mark>(&self.dir.join(SEAS_BP6_RESUME_LOG), step, time, "")?;
        let station = (mark.written, mark.last_station_t);
        let profile = (mark.profile_written, mark.last_profile_t);
        let files = self
            .stations
            .iter_mut()
            .map(|s| &mut s.file)
            .chain(std::iter::once(&mut self.global))
            .chain(self.profiles.iter_mut().map(|p| &mut p.file));
        for f in files {
            f.resume_rows(station, profile)?;
        }
        self.log = log;
        self.mark = mark;
        Ok(())
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for SeasBp6Output {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        let t = s.state.time;
        let m = &mut self.mark;
        m.step = s.report.step;
        m.t = Some(s.state.time);
        m.steps += 1;
        m.tau = (m.tau.0.min(s.report.tau), m.tau.1.max(s.report.tau));
        let station = t - self.mark.last_station_t >= self.station_interval * (1.0 - 1e-12);
        let profile = t - self.mark.last_profile_t >= self.profile_interval * (1.0 - 1e-12);
        if station || profile {
            let values = self.node_values(s.model, s.state, s.friction);
            if station {
                self.write_rows(t, &values);
            }
            if profile {
                self.write_profiles(t, &values);
            }
        }
        if self.resume_log && self.persist_every > 0 && s.report.step % self.persist_every == 0 {
            self.persist()?;
        }
        self.reserve.hold(self.held_bytes())?;
        Ok(Flow::Continue(()))
    }

    fn at_step_cap(&mut self, _s: &StepView<'_, D, C>) -> rsf::Result<()> {
        if self.resume_log {
            self.persist()?;
        }
        Ok(())
    }

    fn finish(&mut self) -> rsf::Result<()> {
        if self.resume_log && self.mark_at_finish {
            return Ok(self.persist()?);
        }
        Ok(self.write_files()?)
    }

    fn name(&self) -> String {
        "SEAS BP6 output".into()
    }

    fn reads_volume(&self) -> bool {
        false
    }
}

impl std::fmt::Debug for SeasBp6Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SeasBp6Output")
            .field("dir", &self.dir)
            .finish_non_exhaustive()
    }
}

/// The stations' and profiles' positions, for readers of the files.
pub fn bp6_profile_positions() -> Vec<f64> {
    (0..=200).map(|i| -10e3 + 100.0 * i as f64).collect()
}
