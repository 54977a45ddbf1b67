//! The files of the 3-D benchmarks on a strike–dip grid of the fault, with the SCEC
//! header conventions of BP1 and BP3: BP5-QD (docs/seas-bp5.md, "Output": the ten on-fault
//! stations `fltst_strk±XXdp±YY` (8 columns), the nine off-fault stations
//! `blkst_strk±XXfn±YYdp±ZZ` (7 columns), `global.dat`, profiles, `rupture.dat` and the
//! event catalogue `events.csv`), BP7-QD (docs/seas-bp7.md: thirteen and six stations in
//! metres, `global.dat` of four columns) and BP8-QD (docs/seas-bp8.md: nine stations with
//! the pore pressure and Darcy velocity columns, `global.dat`, ten profiles) — one output,
//! described per benchmark by its `Spec`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use rsf::pore_pressure::PorePressure;
use rsf::{Flow, Model, Observer, StepView};

use crate::error::{invalid, Result};
use crate::setup::{SeasSampling, SeasSetup};
use crate::text::{create_output_dir, positions_row, write_row, File, FileLayout, Positions};

mod files;
mod layout;
mod mark;
mod resume;
mod spec;
mod stations;
mod text;
mod volume;

use crate::reserve::Reserve;
use layout::{BodySource, FaultLayout};
use mark::Mark;
pub use mark::{Bp5Event, SEAS_BP5_RESUME_LOG};
use spec::{GlobalSpec, Spec};
pub use stations::{
    bp5_body_station_points, bp7_body_station_points, StrikeDipFault, SEAS_BP5_BODY_STATIONS,
    SEAS_BP5_FAULT_STATIONS, SEAS_BP7_BODY_STATIONS, SEAS_BP7_FAULT_STATIONS,
    SEAS_BP8_FAULT_STATIONS,
};
use text::{
    body_station_name, fault_station_name, profile_columns, Profile, Quantity, BODY_COLUMNS,
    FAULT_COLUMNS, GLOBAL_COLUMNS, PRESSURE_FAULT_COLUMNS,
};
pub use text::{NEVER_RUPTURED, RUPTURE_THRESHOLD, SLIP_RATE_FLOOR};

/// Name of the resume log of a BP7 output ([`SeasBp5Output::bp7`]).
pub const SEAS_BP7_RESUME_LOG: &str = "bp7_resume.json";

/// Name of the resume log of a BP8 output ([`SeasBp5Output::bp8`]).
pub const SEAS_BP8_RESUME_LOG: &str = "bp8_resume.json";

/// An on-fault station: the cells around it and their bilinear weights, and its model
/// point (for the pressure field).
struct FaultStation {
    file: File,
    cells: [(usize, f64); 4],
    point: [f64; 3],
}

/// An off-fault station: its file and where its displacement comes from.
struct BodyStation {
    file: File,
    source: BodySource,
}

/// The files of a run of BP5 (`rsf_scenes::SeasBp5`: its fault alone or its volume
/// model), BP7 or BP8 (a square fault in a whole space: [`bp7`](Self::bp7),
/// [`bp8`](Self::bp8)) — an [`Observer`]. Rows are kept in memory and every file is
/// written whole, atomically, by [`finish`](Observer::finish) (at the end of each run
/// call), its header completed (time-step bounds, number of rows). The disk space of the
/// rows is held as they grow — a file of zeros, [`RESERVE_FILE`](crate::RESERVE_FILE), in
/// the output folder, given back just before the files are written — so that a full disk
/// stops the run when it happens, not after it.
pub struct SeasBp5Output {
    dir: PathBuf,
    setup: SeasSetup,
    spec: Spec,
    fault: Vec<FaultStation>,
    body: Vec<BodyStation>,
    global: File,
    profiles: Vec<Profile>,
    layout: FaultLayout,
    /// `+1` where the model's `z` is the benchmark's `x₃` (a square fault), `−1` where it
    /// is `−x₃` (BP5: `z` up from the free surface).
    z_sign: f64,
    /// The pressure field of the station and profile columns (BP8).
    pressure: Option<Arc<dyn PorePressure<3>>>,
    /// The resume log's file name.
    log_name: &'static str,
    mu: f64,
    /// Radiation damping η (Pa·s/m): the shear stress written is `friction + ηV`.
    eta: f64,
    v_p: f64,
    mark: Mark,
    /// Persist the files and the resume log every this many steps (0: only at a step
    /// cap), if the log is kept.
    persist_every: usize,
    /// Whether [`finish`](Observer::finish) persists a mark too
    /// ([`with_marks_where_runs_end`](Self::with_marks_where_runs_end)).
    mark_at_finish: bool,
    /// Whether the resume log is kept.
    resume_log: bool,
    /// The resume log's marks so far.
    log: Vec<Mark>,
    /// The disk space held for the rows in memory.
    reserve: Reserve,
}

impl SeasBp5Output {
    /// The output of a fault alone, `region`, on the grid of size `dx` into `dir` (created
    /// if missing): `cells` the grid's cells, their centres `(x₂, x₃)` (m), strike fastest,
    /// from the shallowest row down (`rsf_scenes::SeasBp5::cells`), `body_columns` the
    /// displacement columns of [`SEAS_BP5_BODY_STATIONS`] (from
    /// `rsf_scenes::SeasBp5::fault_ode_with_stations` with [`bp5_body_station_points`]),
    /// `setup` the headers' problem, modeler, date and element size and the sampling.
    /// (`rsf_scenes::SeasBp5::output` makes BP5's.)
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `cells` for
    /// another number of cells than the grid of `dx` over the fault has, `body_columns`
    /// for another number of stations, `date` for a header date that is not a calendar
    /// date; I/O errors creating `dir`.
    pub fn new(
        dir: &Path,
        region: &StrikeDipFault,
        dx: f64,
        cells: Vec<[f64; 2]>,
        body_columns: Vec<Vec<f64>>,
        setup: SeasSetup,
    ) -> Result<Self> {
        let n = cell_grid(region, dx, &cells)?;
        let body = BodySource::of_columns(&SEAS_BP5_BODY_STATIONS, body_columns)?;
        let layout = FaultLayout::of_cells(cells, dx, n, -1.0);
        let spec = bp5_spec(&layout);
        Self::build(dir, region, layout, (body, spec), setup)
    }

    /// BP8's files (docs/seas-bp8.md, "Output") of a square fault alone `|x₂|, |x₃| ≤
    /// region.length/2` on the grid of size `dx` into `dir` (created if missing): `cells`
    /// the cells' centres `(x₂, x₃)` (m), `x₂` fastest, from `x₃ = −l_f` on
    /// (`rsf_scenes::SeasBp8::cells`; the model's `z` the benchmark's `x₃`), `pressure`
    /// the field whose pressure and Darcy velocity the files report (the diffusion's, not
    /// a floor's), `setup` the headers' problem, modeler, date and element size and the
    /// sampling. Nine stations `fltst_strk±XXXdp±YYY` of eleven columns, `global.dat`,
    /// ten profiles on the description's 81 positions (slip and shear stress of both
    /// components interpolated from the cells, constant beyond the outermost centres; the
    /// pressure the field's at each position); the resume log [`SEAS_BP8_RESUME_LOG`].
    ///
    /// # Errors
    /// As [`new`](Self::new) for `cells` and `date`; I/O errors creating `dir`.
    pub fn bp8(
        dir: &Path,
        region: &StrikeDipFault,
        dx: f64,
        cells: Vec<[f64; 2]>,
        pressure: Arc<dyn PorePressure<3>>,
        setup: SeasSetup,
    ) -> Result<Self> {
        let layout = square_layout(region, dx, cells)?;
        let mut out = Self::build(dir, region, layout, (Vec::new(), spec::bp8()), setup)?;
        out.pressure = Some(pressure);
        out.log_name = SEAS_BP8_RESUME_LOG;
        Ok(out)
    }

    /// BP7's files (docs/seas-bp7.md, "Output") of a square fault alone on the grid of
    /// size `dx` into `dir`, as [`bp8`](Self::bp8) for `region`, `cells` and `setup`:
    /// thirteen stations on the fault, six off it (`body_columns` their displacement per
    /// unit slip of every slip unknown, three rows of `m` each, the model's `(x₁, x₂, x₃)`
    /// components: `rsf_scenes::SeasBp7::body_columns`), `global.dat` with the maximum
    /// slip rate and the moment rate over the disc of radius `1.5 r_vw` and the moment
    /// rate over the velocity-weakening disc `r_vw` (m), slip and shear stress profiles,
    /// `rupture.dat` from the start, the catalogue; the resume log
    /// [`SEAS_BP7_RESUME_LOG`].
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn bp7(
        dir: &Path,
        region: &StrikeDipFault,
        (dx, r_vw): (f64, f64),
        cells: Vec<[f64; 2]>,
        body_columns: Vec<Vec<f64>>,
        setup: SeasSetup,
    ) -> Result<Self> {
        let body = BodySource::of_columns(&SEAS_BP7_BODY_STATIONS, body_columns)?;
        let layout = square_layout(region, dx, cells)?;
        let mut out = Self::build(dir, region, layout, (body, spec::bp7(r_vw)), setup)?;
        out.log_name = SEAS_BP7_RESUME_LOG;
        Ok(out)
    }

    fn build(
        dir: &Path,
        region: &StrikeDipFault,
        layout: FaultLayout,
        (body, spec): (Vec<BodySource>, Spec),
        setup: SeasSetup,
    ) -> Result<Self> {
        create_output_dir(dir, &setup)?;
        let file = |name: &str, location: String, columns: &[(&str, &str)]| {
            File::new(dir.join(name), FileLayout::new(location, columns))
        };
        let z_sign = layout.z_sign;
        let model_point = |x: [f64; 2]| [0.0, x[0], z_sign * x[1]];
        let profiles = spec
            .profiles
            .iter()
            .map(|p| {
                let mut f = File {
                    path: dir.join(&p.file),
                    layout: FileLayout {
                        location: p.location.clone(),
                        columns: profile_columns(p.quantity).to_vec(),
                        profile: Some(Positions {
                            words: format!("positions {}", p.coordinate),
                            coordinate: p.coordinate.into(),
                            name_per_line: spec.name_per_line,
                        }),
                    },
                    rows: positions_row(p.positions.iter().copied()),
                };
                // The benchmark's first data row: `0 0` and the positions.
                f.rows.push('\n');
                Profile {
                    file: f,
                    quantity: p.quantity,
                    points: p.points.iter().map(|&x| layout.bilinear(x)).collect(),
                    model_points: p.points.iter().map(|&x| model_point(x)).collect(),
                }
            })
            .collect();
        let columns: &[(&str, &str)] = if spec.pressure_columns {
            &PRESSURE_FAULT_COLUMNS
        } else {
            &FAULT_COLUMNS
        };
        let fault = spec
            .fault_stations
            .iter()
            .map(|st| FaultStation {
                file: file(&st.name, st.location.clone(), columns),
                cells: layout.bilinear(st.at),
                point: model_point(st.at),
            })
            .collect();
        let body = spec
            .body_stations
            .iter()
            .zip(body)
            .map(|(st, source)| BodyStation {
                file: file(&st.name, st.location.clone(), &BODY_COLUMNS),
                source,
            })
            .collect();
        let global = match spec.global {
            GlobalSpec::Whole => file("global.dat", "global".into(), &GLOBAL_COLUMNS),
            GlobalSpec::Discs { outer, inner } => file(
                "global.dat",
                format!(
                    "global: the maximum slip rate and the moment rate over the disc of radius \
                     {outer} m about the fault's centre, the moment rate over the \
                     velocity-weakening disc of radius {inner} m"
                ),
                &[
                    GLOBAL_COLUMNS[0],
                    GLOBAL_COLUMNS[1],
                    GLOBAL_COLUMNS[2],
                    (
                        "moment_rate_VW",
                        "Moment rate of the velocity-weakening disc (N-m/s)",
                    ),
                ],
            ),
        };
        let nodes = layout.positions.len();
        Ok(Self {
            dir: dir.to_path_buf(),
            setup,
            spec,
            fault,
            body,
            global,
            profiles,
            layout,
            z_sign,
            pressure: None,
            log_name: SEAS_BP5_RESUME_LOG,
            mu: region.shear_modulus,
            eta: region.radiation_damping,
            v_p: region.plate_rate,
            mark: Mark {
                step: 0,
                t: None,
                written: 0,
                last_station_t: f64::NEG_INFINITY,
                tau: (f64::INFINITY, 0.0),
                steps: 0,
                events: Vec::new(),
                profile_written: 0,
                last_profile_t: f64::NEG_INFINITY,
                rupture: vec![None; nodes],
            },
            persist_every: 0,
            mark_at_finish: false,
            resume_log: false,
            log: Vec::new(),
            reserve: Reserve::new(dir),
        })
    }

    /// The benchmark's first row: every file at the state at `t = 0` (`friction` the
    /// run's laws, e.g. `ode.problem().friction_laws()`).
    pub fn write_initial_state(
        &mut self,
        model: &Model<3, 3>,
        state: &rsf::SimulationState,
        friction: &dyn rsf::observe::FaultTractions,
    ) {
        let global = self.global_values(&state.kinematics.v).0;
        self.write_rows(model, state, friction, &global);
        self.write_profiles(state, friction, global[0]);
    }

    /// Node `k`'s slip₂, slip₃, V₂, V₃, τ₂, τ₃ and α (benchmark components: `x₃` as the
    /// layout's sign says) at `state`; the shear stress `τ⁰ + Δτ = friction + ηV`.
    fn node_values(
        &self,
        k: usize,
        state: &rsf::SimulationState,
        friction: &dyn rsf::observe::FaultTractions,
    ) -> [f64; 7] {
        let map = &self.layout.slip[k];
        let (s2, s3) = map.of(&state.kinematics.u);
        let (v2, v3) = map.of(&state.kinematics.v);
        let speed = v2.hypot(v3);
        let alpha = state.alpha[k];
        let shear = friction.shear_traction(k, speed, alpha);
        let (t2, t3) = if speed > 0.0 {
            (shear * v2 / speed, shear * v3 / speed)
        } else {
            (0.0, 0.0)
        };
        [
            s2,
            s3,
            v2,
            v3,
            t2 + self.eta * v2,
            t3 + self.eta * v3,
            alpha,
        ]
    }

    /// A row of every profile at `state` (max slip rate `vmax`, m/s).
    fn write_profiles(
        &mut self,
        state: &rsf::SimulationState,
        friction: &dyn rsf::observe::FaultTractions,
        vmax: f64,
    ) {
        let t = state.time;
        self.mark.last_profile_t = t;
        self.mark.profile_written += 1;
        let mut values = Vec::new();
        for i in 0..self.profiles.len() {
            let p = &self.profiles[i];
            values.clear();
            values.push(vmax.max(SLIP_RATE_FLOOR).log10());
            for (cells, x) in p.points.iter().zip(&p.model_points) {
                let value = match (p.quantity, &self.pressure) {
                    (Quantity::Pressure, Some(field)) => field.pressure(x, t) / 1e6,
                    (Quantity::Pressure, None) => 0.0,
                    (q, _) => {
                        let c = match q {
                            Quantity::Slip2 => 0,
                            Quantity::Slip3 => 1,
                            Quantity::Stress2 => 4,
                            _ => 5,
                        };
                        // A stress in MPa node by node, then weighted.
                        let unit = if c >= 4 { 1e6 } else { 1.0 };
                        cells
                            .iter()
                            .filter(|(_, w)| *w != 0.0)
                            .map(|&(k, w)| w * (self.node_values(k, state, friction)[c] / unit))
                            .sum::<f64>()
                    }
                };
                values.push(value);
            }
            write_row(&mut self.profiles[i].file.rows, t, &values);
        }
    }

    /// `global.dat`'s values but the time (max |V|, the moment rate, and a second moment
    /// rate for BP7) and the fastest node over the whole fault.
    fn global_values(&self, v: &[f64]) -> (Vec<f64>, usize) {
        let (mut vmax, mut kmax) = (0.0_f64, 0);
        let (mut v_disc, mut sum, mut sum_inner) = (0.0_f64, 0.0, 0.0);
        let discs = match self.spec.global {
            GlobalSpec::Whole => None,
            GlobalSpec::Discs { outer, inner } => Some((outer, inner)),
        };
        for (k, (map, area)) in self.layout.slip.iter().zip(&self.layout.areas).enumerate() {
            let (v2, v3) = map.of(v);
            let speed = v2.hypot(v3);
            if speed > vmax {
                (vmax, kmax) = (speed, k);
            }
            match discs {
                None => sum += area * speed,
                Some((outer, inner)) => {
                    let x = self.layout.positions[k];
                    let r = x[0].hypot(x[1]);
                    if r <= outer {
                        sum += area * speed;
                        v_disc = v_disc.max(speed);
                    }
                    if r <= inner {
                        sum_inner += area * speed;
                    }
                }
            }
        }
        let values = match discs {
            None => vec![vmax, self.mu * sum],
            Some(_) => vec![v_disc, self.mu * sum, self.mu * sum_inner],
        };
        (values, kmax)
    }

    /// Bytes of the rows held in memory (every file's).
    fn held_bytes(&self) -> u64 {
        self.files().map(|f| f.rows.len() as u64).sum::<u64>()
            + 100 * self.layout.positions.len() as u64
    }

    /// The names of the benchmark files BP5's output writes (stations, `global.dat`, the
    /// profiles and `rupture.dat`; besides them `events.csv` and, with
    /// [`with_resume_log`](Self::with_resume_log), [`SEAS_BP5_RESUME_LOG`]).
    pub fn file_names() -> Vec<String> {
        let mut names: Vec<String> = SEAS_BP5_FAULT_STATIONS
            .iter()
            .map(|&(s, d)| fault_station_name(s, d))
            .collect();
        names.extend(
            SEAS_BP5_BODY_STATIONS
                .iter()
                .map(|&(s, n, d)| body_station_name(s, n, d)),
        );
        names.push("global.dat".into());
        for q in ["slip_2", "stress_2"] {
            for along in ["depth", "strike"] {
                names.push(format!("{q}_{along}.dat"));
            }
        }
        names.push("rupture.dat".into());
        names
    }

    /// The names of the files BP8's output writes ([`bp8`](Self::bp8): the 20 files of
    /// the description; besides them, with [`with_resume_log`](Self::with_resume_log),
    /// [`SEAS_BP8_RESUME_LOG`]).
    pub fn bp8_file_names() -> Vec<String> {
        names_of(&spec::bp8())
    }

    /// The names of the files BP7's output writes ([`bp7`](Self::bp7): stations,
    /// `global.dat`, the profiles, `rupture.dat`, `events.csv`; besides them, with
    /// [`with_resume_log`](Self::with_resume_log), [`SEAS_BP7_RESUME_LOG`]).
    pub fn bp7_file_names() -> Vec<String> {
        names_of(&spec::bp7(200.0))
    }

    /// The events so far.
    pub fn events(&self) -> &[Bp5Event] {
        &self.mark.events
    }

    /// The sampling.
    fn sampling(&self) -> &SeasSampling {
        &self.setup.sampling
    }

    /// Writes a row of every file at the state of `s` (`global` the values of
    /// `global.dat` but the time: the maximum slip rate first, m/s).
    fn write_rows(
        &mut self,
        model: &Model<3, 3>,
        state: &rsf::SimulationState,
        friction: &dyn rsf::observe::FaultTractions,
        global: &[f64],
    ) {
        let t = state.time;
        self.mark.last_station_t = t;
        self.mark.written += 1;
        let (u, v) = (&state.kinematics.u, &state.kinematics.v);
        let n = model.vertices.len();
        let log_rate = |r: f64| r.abs().max(SLIP_RATE_FLOOR).log10();
        let mut values = Vec::with_capacity(10);
        for i in 0..self.fault.len() {
            let st = &self.fault[i];
            let mut x = [0.0; 7];
            for &(k, w) in &st.cells {
                if w != 0.0 {
                    let c = self.node_values(k, state, friction);
                    for (xi, ci) in x.iter_mut().zip(c) {
                        *xi += w * ci;
                    }
                }
            }
            values.clear();
            values.extend([
                x[0],
                x[1],
                log_rate(x[2]),
                log_rate(x[3]),
                x[4] / 1e6,
                x[5] / 1e6,
            ]);
            if self.spec.pressure_columns {
                let (p, q) = match &self.pressure {
                    Some(field) => (
                        field.pressure(&st.point, t),
                        field
                            .darcy_velocity_vector(&st.point, t)
                            .unwrap_or([0.0; 3]),
                    ),
                    None => (0.0, [0.0; 3]),
                };
                // (`+ 0.0`: no `-0` where the field has no flow.)
                values.extend([p / 1e6 + 0.0, q[1] + 0.0, self.z_sign * q[2] + 0.0]);
            }
            values.push(x[6] / std::f64::consts::LN_10);
            write_row(&mut self.fault[i].file.rows, t, &values);
        }
        let m = 2 * n;
        for st in &mut self.body {
            let mut d = [0.0; 3];
            let mut vel = [0.0; 3];
            match &st.source {
                BodySource::Columns { side, columns } => {
                    for (c, (dc, vc)) in d.iter_mut().zip(vel.iter_mut()).enumerate() {
                        let col = &columns[c * m..(c + 1) * m];
                        for k in 0..n {
                            // Back slip: the elastic part of the slip less the plate's.
                            let (g2, g3) = (col[2 * k], col[2 * k + 1]);
                            *dc += g2 * (u[3 * k + 1] - self.v_p * t) + g3 * u[3 * k + 2];
                            *vc += g2 * (v[3 * k + 1] - self.v_p) + g3 * v[3 * k + 2];
                        }
                    }
                    // Each side's rigid plate motion, ±V_p t/2 along strike.
                    d[1] += side * 0.5 * self.v_p * t;
                    vel[1] += side * 0.5 * self.v_p;
                }
                &BodySource::Vertex(p) => {
                    d.copy_from_slice(&u[3 * p..3 * p + 3]);
                    vel.copy_from_slice(&v[3 * p..3 * p + 3]);
                }
            }
            let z = self.z_sign;
            let values = [d[0], d[1], z * d[2], vel[0], vel[1], z * vel[2]];
            write_row(&mut st.file.rows, t, &values);
        }
        let mut values = vec![global[0].max(SLIP_RATE_FLOOR).log10()];
        values.extend_from_slice(&global[1..]);
        write_row(&mut self.global.rows, t, &values);
    }
}

/// The names of the files of `spec`'s output.
fn names_of(spec: &Spec) -> Vec<String> {
    let mut names: Vec<String> = spec
        .fault_stations
        .iter()
        .map(|s| s.name.clone())
        .chain(spec.body_stations.iter().map(|s| s.name.clone()))
        .collect();
    names.push("global.dat".into());
    names.extend(spec.profiles.iter().map(|p| p.file.clone()));
    if spec.rupture.is_some() {
        names.push("rupture.dat".into());
    }
    if spec.catalogue {
        names.push("events.csv".into());
    }
    names
}

/// BP5's description on `layout`'s grid: the profiles at its rows and columns.
fn bp5_spec(layout: &FaultLayout) -> Spec {
    let g = layout;
    let along_dip: Vec<f64> = (0..g.n[1])
        .map(|j| g.origin[1] + j as f64 * g.spacing)
        .collect();
    let along_strike: Vec<f64> = (0..g.n[0])
        .map(|i| g.origin[0] + i as f64 * g.spacing)
        .collect();
    spec::bp5(&along_dip, &along_strike)
}

/// The layout of a square fault alone `|x₂|, |x₃| ≤ region.length/2` on its cells of
/// side `dx` (the model's `z` the benchmark's `x₃`).
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `cells` for another
/// number of cells than the grid has.
fn square_layout(region: &StrikeDipFault, dx: f64, cells: Vec<[f64; 2]>) -> Result<FaultLayout> {
    let n = cell_grid(region, dx, &cells)?;
    Ok(FaultLayout::of_cells(cells, dx, n, 1.0))
}

/// The cells per side of the grid of size `dx` over `region`.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `cells` unless
/// `cells` has one cell per grid cell.
fn cell_grid(region: &StrikeDipFault, dx: f64, cells: &[[f64; 2]]) -> Result<[usize; 2]> {
    let n = [
        (region.length / dx).round() as usize,
        (region.width / dx).round() as usize,
    ];
    if cells.is_empty() || cells.len() != n[0] * n[1] {
        return Err(invalid(
            "cells",
            format!(
                "{} cells, the grid of {dx} m over the fault has {} × {}",
                cells.len(),
                n[0],
                n[1]
            ),
        ));
    }
    Ok(n)
}

impl Observer<3, 3> for SeasBp5Output {
    fn observe(&mut self, s: &StepView<'_, 3, 3>) -> rsf::Result<Flow> {
        let t = s.state.time;
        let m = &mut self.mark;
        m.step = s.report.step;
        m.t = Some(s.state.time);
        m.steps += 1;
        m.tau = (m.tau.0.min(s.report.tau), m.tau.1.max(s.report.tau));
        let (global, kmax) = self.global_values(&s.state.kinematics.v);
        let vmax = {
            let map = &self.layout.slip[kmax];
            let (v2, v3) = map.of(&s.state.kinematics.v);
            v2.hypot(v3)
        };
        let sampling = *self.sampling();
        let in_event = vmax >= sampling.event_threshold;
        let hypocentre = self.layout.positions[kmax];
        match self.mark.events.last_mut() {
            Some(e) if e.t_end.is_none() => {
                e.peak_slip_rate = e.peak_slip_rate.max(vmax);
                if !in_event {
                    e.t_end = Some(t);
                }
            }
            _ if in_event => self.mark.events.push(Bp5Event {
                t_start: t,
                t_end: None,
                peak_slip_rate: vmax,
                hypocentre,
            }),
            _ => {}
        }
        let dt = if in_event {
            sampling.station_event
        } else {
            sampling.station_quiet
        };
        if sampling.every_step || t - self.mark.last_station_t >= dt * (1.0 - 1e-12) {
            self.write_rows(s.model, s.state, s.friction, &global);
        }
        let profile_dt = if in_event {
            sampling.profile_event
        } else {
            sampling.profile_quiet
        };
        if t - self.mark.last_profile_t >= profile_dt * (1.0 - 1e-12) {
            self.write_profiles(s.state, s.friction, global[0]);
        }
        // Each node's first time at the threshold: after the first event (BP5's patch),
        // or from the start (BP7).
        let counting = match self.spec.rupture {
            Some(true) => self.mark.events.first().is_some_and(|e| e.t_end.is_some()),
            Some(false) => true,
            None => false,
        };
        if counting {
            let v = &s.state.kinematics.v;
            for (map, first) in self.layout.slip.iter().zip(&mut self.mark.rupture) {
                if first.is_none() {
                    let (v2, v3) = map.of(v);
                    if v2.hypot(v3) >= RUPTURE_THRESHOLD {
                        *first = Some(t);
                    }
                }
            }
        }
        if self.resume_log && self.persist_every > 0 && s.report.step % self.persist_every == 0 {
            self.persist()?;
        }
        self.reserve.hold(self.held_bytes())?;
        Ok(Flow::Continue(()))
    }

    fn at_step_cap(&mut self, _s: &StepView<'_, 3, 3>) -> rsf::Result<()> {
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
        self.spec.name.into()
    }

    fn reads_volume(&self) -> bool {
        false
    }

    fn volume_vertices(&self) -> Vec<usize> {
        self.body
            .iter()
            .filter_map(|b| match b.source {
                BodySource::Vertex(p) => Some(p),
                BodySource::Columns { .. } => None,
            })
            .collect()
    }
}
