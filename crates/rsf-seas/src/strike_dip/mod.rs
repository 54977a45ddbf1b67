//! The files of SEAS BP5-QD (docs/seas-bp5.md, "Output"): the ten on-fault stations
//! `fltst_strk±XXdp±YY` (8 columns), the nine off-fault stations `blkst_strk±XXfn±YYdp±ZZ`
//! (7 columns), `global.dat` (maximum slip rate and moment rate) and the event catalogue
//! `events.csv`, with the SCEC header conventions of BP1 and BP3: the stations on a
//! strike–dip grid of the fault.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rsf::checkpoint::write_atomically;
use rsf::{Flow, Model, Observer, StepView};

use crate::error::{invalid, io_at, Result};
use crate::setup::{SeasSampling, SeasSetup};
use crate::text::{c_exp, is_iso_date, positions_row, write_row, FileLayout, Positions};

mod layout;
mod mark;
mod resume;
mod stations;
mod text;

use crate::reserve::Reserve;
use layout::{BodySource, FaultLayout, SlipMap};
use mark::Mark;
pub use mark::{Bp5Event, SEAS_BP5_RESUME_LOG};
pub use stations::{
    bp5_body_station_points, StrikeDipFault, SEAS_BP5_BODY_STATIONS, SEAS_BP5_FAULT_STATIONS,
};
use text::{
    body_station_name, fault_station_name, File, Profile, BODY_COLUMNS, FAULT_COLUMNS,
    GLOBAL_COLUMNS, SLIP_PROFILE_COLUMNS, STRESS_PROFILE_COLUMNS,
};
pub use text::{NEVER_RUPTURED, RUPTURE_THRESHOLD, SLIP_RATE_FLOOR};

/// An on-fault station: the cells around it and their bilinear weights.
struct FaultStation {
    file: File,
    cells: [(usize, f64); 4],
}

/// An off-fault station: its file and where its displacement comes from.
struct BodyStation {
    file: File,
    source: BodySource,
}

/// The BP5 files of a run of `rsf_scenes::SeasBp5`, its fault alone or its volume model
/// (an [`Observer`]). Rows are kept in memory and every file is written whole,
/// atomically, by [`finish`](Observer::finish) (at the end of each run call), its header
/// completed (time-step bounds, number of rows). The disk space of the rows is held as
/// they grow — a file of zeros, [`RESERVE_FILE`](crate::RESERVE_FILE), in the output folder, given back just
/// before the files are written — so that a full disk stops the run when it happens, not
/// after it.
pub struct SeasBp5Output {
    dir: PathBuf,
    setup: SeasSetup,
    fault: Vec<FaultStation>,
    body: Vec<BodyStation>,
    global: File,
    profiles: Vec<Profile>,
    layout: FaultLayout,
    mu: f64,
    /// Radiation damping η (Pa·s/m): the shear stress written is `friction + ηV`.
    eta: f64,
    v_p: f64,
    mark: Mark,
    /// Persist the files and the resume log every this many steps (0: only at a step
    /// cap), if the log is kept.
    persist_every: usize,
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
        if body_columns.len() != SEAS_BP5_BODY_STATIONS.len() {
            return Err(invalid(
                "body_columns",
                format!(
                    "{} for {} stations",
                    body_columns.len(),
                    SEAS_BP5_BODY_STATIONS.len()
                ),
            ));
        }
        let layout = FaultLayout {
            areas: vec![dx * dx; cells.len()],
            slip: (0..cells.len())
                .map(|k| SlipMap {
                    dof: 3 * k,
                    e2: [0.0, 1.0, 0.0],
                    e3: [0.0, 0.0, -1.0],
                })
                .collect(),
            origin: cells[0],
            spacing: dx,
            n,
            index: (0..cells.len()).collect(),
            positions: cells,
        };
        let body = SEAS_BP5_BODY_STATIONS
            .iter()
            .zip(body_columns)
            .map(|(&(_, n, _), columns)| BodySource::Columns {
                side: n.signum(),
                columns,
            })
            .collect();
        Self::build(dir, region, layout, body, setup)
    }

    /// The output of the fault `region` on its finite-element volume model `model`
    /// (`rsf_scenes::SeasBp5::fe_model` with spacing `dx` on the fault) into `dir`: the on-fault
    /// stations from the frictional nodes (the grid of spacing `dx` over the
    /// rate-and-state region; slip and slip rate the jump of each split pair in Cartesian
    /// components), the off-fault stations at the mesh vertices nearest them (read
    /// through [`Observer::volume_vertices`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `model` for a
    /// model without an internal fault or whose frictional nodes do not fill the grid; I/O
    /// errors creating `dir`. (`rsf_scenes::SeasBp5::volume_output` makes BP5's.)
    pub fn for_volume(
        dir: &Path,
        region: &StrikeDipFault,
        model: &Model<3, 3>,
        dx: f64,
        setup: SeasSetup,
    ) -> Result<Self> {
        let fault = model
            .internal_fault
            .as_ref()
            .ok_or_else(|| invalid("model", "has no fault inside the body"))?;
        let fb = &model.frictional_boundary;
        let pair_of: std::collections::HashMap<usize, usize> = fault
            .pairs()
            .iter()
            .enumerate()
            .map(|(i, &(minus, _))| (minus, i))
            .collect();
        let n = [
            (region.length / dx).round() as usize + 1,
            (region.width / dx).round() as usize + 1,
        ];
        let origin = [-0.5 * region.length, 0.0];
        let mut index = vec![usize::MAX; n[0] * n[1]];
        let mut layout = FaultLayout {
            positions: Vec::with_capacity(fb.len()),
            areas: fb.weights.clone(),
            slip: Vec::with_capacity(fb.len()),
            origin,
            spacing: dx,
            n,
            index: Vec::new(),
        };
        for (k, &p) in fb.nodes.iter().enumerate() {
            let x = model.vertices[p];
            let i = *pair_of
                .get(&p)
                .ok_or_else(|| invalid("model", format!("frictional node {k} is not a pair")))?;
            let r = fault.transform.frames[i];
            layout.positions.push([x[1], -x[2]]);
            layout.slip.push(SlipMap {
                dof: 3 * p,
                e2: r[1],
                e3: r[2].map(|c| -c),
            });
            let (fi, fj) = ((x[1] - origin[0]) / dx, -x[2] / dx);
            let (i, j) = (fi.round(), fj.round());
            if (fi - i).abs() > 1e-6 || (fj - j).abs() > 1e-6 || i < 0.0 || j < 0.0 {
                return Err(invalid(
                    "model",
                    format!("frictional node {k} at {x:?} is off the {dx} m grid"),
                ));
            }
            let (i, j) = (i as usize, j as usize);
            if i >= n[0] || j >= n[1] {
                return Err(invalid(
                    "model",
                    format!("frictional node {k} at {x:?} is outside the rate-and-state region"),
                ));
            }
            index[j * n[0] + i] = k;
        }
        if let Some(g) = index.iter().position(|&k| k == usize::MAX) {
            return Err(invalid(
                "model",
                format!(
                    "no frictional node at grid point ({}, {}) of the rate-and-state region",
                    g % n[0],
                    g / n[0]
                ),
            ));
        }
        layout.index = index;
        let body = bp5_body_station_points()
            .iter()
            .map(|x| model.nearest_node(x).map(BodySource::Vertex))
            .collect::<rsf::Result<_>>()?;
        Self::build(dir, region, layout, body, setup)
    }

    fn build(
        dir: &Path,
        region: &StrikeDipFault,
        layout: FaultLayout,
        body: Vec<BodySource>,
        setup: SeasSetup,
    ) -> Result<Self> {
        if !is_iso_date(&setup.date) {
            return Err(invalid(
                "date",
                format!("{:?} is not a calendar date YYYY-MM-DD", setup.date),
            ));
        }
        std::fs::create_dir_all(dir).map_err(io_at("create", dir))?;
        let file = |name: &str, location: String, columns: &[(&str, &str)]| File {
            path: dir.join(name),
            layout: FileLayout::new(location, columns),
            rows: String::new(),
        };
        // Profiles along dip at x₂ = 0 and along strike at x₃ = 10 km, at the grid's
        // rows and columns.
        let g = &layout;
        let along_dip: Vec<f64> = (0..g.n[1])
            .map(|j| g.origin[1] + j as f64 * g.spacing)
            .collect();
        let along_strike: Vec<f64> = (0..g.n[0])
            .map(|i| g.origin[0] + i as f64 * g.spacing)
            .collect();
        let mut profiles = Vec::new();
        for slip in [true, false] {
            for dip in [true, false] {
                let (name, quantity) = if slip {
                    ("slip_2", &SLIP_PROFILE_COLUMNS)
                } else {
                    ("stress_2", &STRESS_PROFILE_COLUMNS)
                };
                let (positions, coordinate, location) = if dip {
                    (&along_dip, "x3", format!("{name} along dip at x2 = 0 km"))
                } else {
                    (
                        &along_strike,
                        "x2",
                        format!("{name} along strike at x3 = 10 km"),
                    )
                };
                let points = positions
                    .iter()
                    .map(|&x| g.bilinear(if dip { [0.0, x] } else { [x, 10e3] }))
                    .collect();
                let mut f = file(
                    &format!("{name}_{}.dat", if dip { "depth" } else { "strike" }),
                    location,
                    quantity,
                );
                f.layout.profile = Some(Positions {
                    words: format!("positions {coordinate}"),
                    coordinate: coordinate.into(),
                });
                // The benchmark's first data row: `0 0` and the positions.
                f.rows = positions_row(positions.iter().copied());
                f.rows.push('\n');
                profiles.push(Profile {
                    file: f,
                    slip,
                    points,
                });
            }
        }
        let nodes = g.positions.len();
        let fault = SEAS_BP5_FAULT_STATIONS
            .iter()
            .map(|&(s, d)| FaultStation {
                file: file(
                    &fault_station_name(s, d),
                    format!("on fault, {s} km along strike, {d} km down-dip"),
                    &FAULT_COLUMNS,
                ),
                cells: layout.bilinear([s * 1e3, d * 1e3]),
            })
            .collect();
        let body = SEAS_BP5_BODY_STATIONS
            .iter()
            .zip(body)
            .map(|(&(s, n, d), source)| BodyStation {
                file: file(
                    &body_station_name(s, n, d),
                    format!(
                        "off fault, {s} km along strike, {n} km normal to the fault, {d} km depth"
                    ),
                    &BODY_COLUMNS,
                ),
                source,
            })
            .collect();
        Ok(Self {
            dir: dir.to_path_buf(),
            setup,
            fault,
            body,
            global: file("global.dat", "global".into(), &GLOBAL_COLUMNS),
            profiles,
            layout,
            mu: region.shear_modulus,
            eta: region.radiation_damping,
            v_p: region.plate_rate,
            mark: Mark {
                step: 0,
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
        let (vmax, moment_rate) = self.max_and_moment_rate(&state.kinematics.v).0;
        self.write_rows(model, state, friction, (vmax, moment_rate));
        self.write_profiles(state, friction, vmax);
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
        let (u, v) = (&state.kinematics.u, &state.kinematics.v);
        let slip = &self.layout.slip;
        let eta = self.eta;
        let value = |k: usize, want_slip: bool| -> f64 {
            if want_slip {
                return slip[k].of(u).0;
            }
            let (v2, v3) = slip[k].of(v);
            let speed = v2.hypot(v3);
            let friction_2 = if speed > 0.0 {
                friction.shear_traction(k, speed, state.alpha[k]) * v2 / speed
            } else {
                0.0
            };
            (friction_2 + eta * v2) / 1e6
        };
        let mut values = Vec::new();
        for p in &mut self.profiles {
            values.clear();
            values.push(vmax.max(SLIP_RATE_FLOOR).log10());
            for cells in &p.points {
                let x: f64 = cells
                    .iter()
                    .filter(|(_, w)| *w != 0.0)
                    .map(|&(k, w)| w * value(k, p.slip))
                    .sum();
                values.push(x);
            }
            write_row(&mut p.file.rows, t, &values);
        }
    }

    /// `((max |V|, moment rate), fastest cell)`.
    fn max_and_moment_rate(&self, v: &[f64]) -> ((f64, f64), usize) {
        let (mut vmax, mut kmax, mut sum) = (0.0_f64, 0, 0.0);
        for (k, (map, area)) in self.layout.slip.iter().zip(&self.layout.areas).enumerate() {
            let (v2, v3) = map.of(v);
            let speed = v2.hypot(v3);
            sum += area * speed;
            if speed > vmax {
                (vmax, kmax) = (speed, k);
            }
        }
        ((vmax, self.mu * sum), kmax)
    }

    /// Bytes of the rows held in memory (every file's).
    fn held_bytes(&self) -> u64 {
        let files = self
            .fault
            .iter()
            .map(|s| &s.file)
            .chain(self.body.iter().map(|s| &s.file))
            .chain(std::iter::once(&self.global))
            .chain(self.profiles.iter().map(|p| &p.file));
        files.map(|f| f.rows.len() as u64).sum::<u64>() + 100 * self.layout.positions.len() as u64
    }

    /// Writes every file whole (atomically) and the catalogue, into the space held for
    /// them (given back first).
    fn write_files(&mut self) -> Result<()> {
        self.reserve.release()?;
        self.write_all_files()
    }

    /// [`write_files`](Self::write_files)' writing.
    fn write_all_files(&self) -> Result<()> {
        let files = self
            .fault
            .iter()
            .map(|s| &s.file)
            .chain(self.body.iter().map(|s| &s.file))
            .chain(std::iter::once(&self.global))
            .chain(self.profiles.iter().map(|p| &p.file));
        for f in files {
            let steps = (self.mark.steps > 0).then_some(self.mark.tau);
            let rows = match f.layout.profile {
                Some(_) => self.mark.profile_written,
                None => self.mark.written,
            };
            let text = format!("{}{}", f.header(&self.setup, steps, rows), f.rows);
            write_atomically(&f.path, text.as_bytes())?;
        }
        self.write_rupture()?;
        let mut csv = String::from(
            "event,t_start_s,t_end_s,peak_slip_rate_mps,hypocentre_x2_m,hypocentre_x3_m\n",
        );
        for (i, e) in self.mark.events.iter().enumerate() {
            let _ = writeln!(
                csv,
                "{},{:e},{:e},{:e},{},{}",
                i + 1,
                e.t_start,
                e.t_end.unwrap_or(f64::NAN),
                e.peak_slip_rate,
                e.hypocentre[0],
                e.hypocentre[1]
            );
        }
        Ok(write_atomically(
            &self.dir.join("events.csv"),
            csv.as_bytes(),
        )?)
    }

    /// The names of the benchmark files this output writes (stations and `global.dat`;
    /// besides them `events.csv` and, with [`with_resume_log`](Self::with_resume_log),
    /// [`SEAS_BP5_RESUME_LOG`]).
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

    /// The events so far.
    pub fn events(&self) -> &[Bp5Event] {
        &self.mark.events
    }

    /// The sampling.
    fn sampling(&self) -> &SeasSampling {
        &self.setup.sampling
    }

    /// Writes a row of every file at the state of `s` (max slip rate `vmax`, m/s).
    fn write_rows(
        &mut self,
        model: &Model<3, 3>,
        state: &rsf::SimulationState,
        friction: &dyn rsf::observe::FaultTractions,
        (vmax, moment_rate): (f64, f64),
    ) {
        let t = state.time;
        self.mark.last_station_t = t;
        self.mark.written += 1;
        let (u, v) = (&state.kinematics.u, &state.kinematics.v);
        let n = model.vertices.len();
        let slip = &self.layout.slip;
        let eta = self.eta;
        // Per node: slip₂, slip₃, V₂, V₃, τ₂, τ₃, α (benchmark components: x₃ down); the
        // shear stress τ⁰ + Δτ = friction + ηV.
        let cell = |k: usize| -> [f64; 7] {
            let (s2, s3) = slip[k].of(u);
            let (v2, v3) = slip[k].of(v);
            let speed = v2.hypot(v3);
            let alpha = state.alpha[k];
            let shear = friction.shear_traction(k, speed, alpha);
            let (t2, t3) = if speed > 0.0 {
                (shear * v2 / speed, shear * v3 / speed)
            } else {
                (0.0, 0.0)
            };
            [s2, s3, v2, v3, t2 + eta * v2, t3 + eta * v3, alpha]
        };
        for st in &mut self.fault {
            let mut x = [0.0; 7];
            for &(k, w) in &st.cells {
                if w != 0.0 {
                    let c = cell(k);
                    for (xi, ci) in x.iter_mut().zip(c) {
                        *xi += w * ci;
                    }
                }
            }
            let log_rate = |r: f64| r.abs().max(SLIP_RATE_FLOOR).log10();
            let values = [
                x[0],
                x[1],
                log_rate(x[2]),
                log_rate(x[3]),
                x[4] / 1e6,
                x[5] / 1e6,
                x[6] / std::f64::consts::LN_10,
            ];
            write_row(&mut st.file.rows, t, &values);
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
            let values = [d[0], d[1], -d[2], vel[0], vel[1], -vel[2]];
            write_row(&mut st.file.rows, t, &values);
        }
        let values = [vmax.max(SLIP_RATE_FLOOR).log10(), moment_rate];
        write_row(&mut self.global.rows, t, &values);
    }
}

impl SeasBp5Output {
    /// `rupture.dat`: per fault node `x2 x3 t` (m, m, s), the first time after the first
    /// event that its slip rate reached [`RUPTURE_THRESHOLD`] ([`NEVER_RUPTURED`] if it
    /// did not).
    fn write_rupture(&self) -> Result<()> {
        let steps = (self.mark.steps > 0).then_some(self.mark.tau);
        let location = format!(
            "on fault, the first time after the first event that each node's slip rate \
             reached {RUPTURE_THRESHOLD:e} m/s ({NEVER_RUPTURED:e} s: never)"
        );
        let columns = [("x2", "x2 (m)"), ("x3", "x3 (m)"), ("t", "t (s)")];
        let mut text = FileLayout::new(location, &columns).header(
            &self.setup,
            steps,
            self.layout.positions.len(),
        );
        text.push('\n');
        for (x, t) in self.layout.positions.iter().zip(&self.mark.rupture) {
            let _ = writeln!(
                text,
                "{} {} {}",
                c_exp(x[0], 6, 14),
                c_exp(x[1], 6, 14),
                c_exp(t.unwrap_or(NEVER_RUPTURED), 13, 21)
            );
        }
        Ok(write_atomically(
            &self.dir.join("rupture.dat"),
            text.as_bytes(),
        )?)
    }
}

impl Observer<3, 3> for SeasBp5Output {
    fn observe(&mut self, s: &StepView<'_, 3, 3>) -> rsf::Result<Flow> {
        let t = s.state.time;
        let m = &mut self.mark;
        m.step = s.report.step;
        m.steps += 1;
        m.tau = (m.tau.0.min(s.report.tau), m.tau.1.max(s.report.tau));
        let ((vmax, moment_rate), kmax) = self.max_and_moment_rate(&s.state.kinematics.v);
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
            self.write_rows(s.model, s.state, s.friction, (vmax, moment_rate));
        }
        let profile_dt = if in_event {
            sampling.profile_event
        } else {
            sampling.profile_quiet
        };
        if t - self.mark.last_profile_t >= profile_dt * (1.0 - 1e-12) {
            self.write_profiles(s.state, s.friction, vmax);
        }
        // After the first event (the patch's): each node's first time at the threshold.
        if self.mark.events.first().is_some_and(|e| e.t_end.is_some()) {
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
        Ok(self.write_files()?)
    }

    fn name(&self) -> String {
        "SEAS BP5 output".into()
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
