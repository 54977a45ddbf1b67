//! The SEAS files of a fault along dip (the 2-D benchmarks; Erickson et al. 2020, Seismol.
//! Res. Lett. 91(2); the BP1-QD and BP3-QD problem descriptions): on-fault station time
//! series `fltst_dpXXX`, slip profiles `devol.dat` (BP3: `slip.dat`), and an event
//! catalogue `events.csv` (docs/seas-bp1.md "Output", docs/seas-bp3.md).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rsf::checkpoint::write_atomically;
use rsf::friction::{ConvexPotential, FrictionLaw};
use rsf::model::block_norm;
use rsf::observe::{create_file, FaultTractions, FileMode};
use rsf::{Flow, Model, Observer, SimulationState, StepView};

mod headers;
mod layout;
mod open;
pub(crate) mod resume;

use crate::error::{invalid, io_at, Result};
use crate::setup::{ProfileQuantity, SeasEvent, SeasLayout, SeasSetup};
use crate::text::write_row;
use layout::Layout;
use open::{check_setup, open_files};
use resume::{plan_resume, LOG_HEADER, SEAS_RESUME_LOG};

/// A station: a frictional node, its file and its law.
struct Station<L> {
    k: usize,
    path: PathBuf,
    depth: f64,
    law: L,
    out: Option<BufWriter<File>>,
}

/// A station off the fault: its vertex, file and position.
struct SurfaceFile {
    vertex: usize,
    path: PathBuf,
    position: Vec<f64>,
    out: Option<BufWriter<File>>,
}

/// The SEAS benchmark output of a run on a fault with per-node depths: station files,
/// slip profiles, event catalogue (see the module docs; [`SeasLayout`] chooses BP1's or
/// BP3's files). The slip of a node is the change
/// of its field since the start (signed for a scalar field, the Euclidean norm of the
/// change otherwise; on a model of an antisymmetric fault the field is the slip); the shear
/// stress is `σ_n μ(V, α)` of the node's law (the friction stress, MPa in the files); the
/// state column is `log10 θ = α / ln 10`.
///
/// Files are written while the run goes; [`finish`](Observer::finish) (at the end of every
/// run call) completes their headers (minimum and maximum time step, number of steps),
/// rewriting each file atomically, and writes `events.csv`; a later run call continues
/// the files.
pub struct SeasOutput<L> {
    dir: PathBuf,
    setup: SeasSetup,
    stations: Vec<Station<L>>,
    depths: Vec<f64>,
    u0: Vec<f64>,
    profile: Vec<usize>,
    /// One writer per profile file ([`SeasLayout::profile_files`]).
    profile_out: Vec<Option<BufWriter<File>>>,
    surface: usize,
    surface_files: Vec<SurfaceFile>,
    /// The laws of every frictional node (the stresses of BP3's profiles at the start).
    laws: Vec<L>,
    /// Components of the field.
    components: usize,
    last_station_t: f64,
    last_profile_t: f64,
    events: Vec<SeasEvent>,
    slip_at_start: f64,
    /// The open event's candidate end: the first step below the threshold, time and
    /// surface slip.
    pending_end: Option<(f64, f64)>,
    tau_min: f64,
    tau_max: f64,
    steps: usize,
    values: Vec<f64>,
    /// The resume log (one line of the output's state per step), if written.
    log: Option<BufWriter<File>>,
    /// Station rows (one per station file) and slip profile rows written so far.
    station_rows: usize,
    profile_rows: usize,
}

impl<L: FrictionLaw> SeasOutput<L> {
    /// Output of a run of `model` into the folder `dir` (created if missing); `laws` the
    /// friction laws of every frictional node (as given to the simulation, in
    /// `model.frictional_boundary.nodes` order).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) for laws of another
    /// length, a depth axis ≥ `D`, no station, non-positive `sigma_n` or
    /// `profile_spacing`; for [`FileMode::Resume`], those of
    /// [`check_resume`](Self::check_resume) (the files are then unchanged: they are cut
    /// only after all of them are checked);
    /// [`Error::FileExists`](crate::Error::FileExists) with [`FileMode::Create`] where a
    /// file exists; I/O errors naming the file.
    pub fn new<const D: usize, const C: usize>(
        dir: &Path,
        model: &Model<D, C>,
        laws: &[L],
        setup: SeasSetup,
        mode: FileMode,
    ) -> Result<Self> {
        check_setup::<D>(&setup, laws.len(), model.frictional_boundary.len())?;
        let layout = Layout::new(model, &setup)?;
        let (overwrite, state, log) = open_files(dir, &setup, &layout, mode)?;
        let resuming = matches!(mode, FileMode::Resume { .. });
        let mut stations = Vec::with_capacity(setup.stations.len());
        for ((name, _), &k) in setup.stations.iter().zip(&layout.stations) {
            let path = dir.join(name);
            let out = if resuming {
                None
            } else {
                Some(create_file(
                    &path,
                    &headers::station(&setup, layout.depths[k]).header(&setup, None, 0),
                    overwrite,
                )?)
            };
            stations.push(Station {
                k,
                path,
                depth: layout.depths[k],
                law: laws[k].clone(),
                out,
            });
        }
        let mut surface_files = Vec::with_capacity(layout.surface.len());
        for (st, &vertex) in setup.surface_stations.iter().zip(&layout.surface) {
            let path = dir.join(&st.name);
            let out = if resuming {
                None
            } else {
                Some(create_file(
                    &path,
                    &headers::surface(&setup, &st.position, C).header(&setup, None, 0),
                    overwrite,
                )?)
            };
            surface_files.push(SurfaceFile {
                vertex,
                path,
                position: st.position.clone(),
                out,
            });
        }
        let surface = layout.profile[0];
        let mut profile_out = Vec::new();
        for (&quantity, name) in setup
            .layout
            .profiles()
            .iter()
            .zip(setup.layout.profile_files())
        {
            profile_out.push(if resuming {
                None
            } else {
                Some(create_file(
                    &dir.join(name),
                    &format!(
                        "{}\n{}",
                        headers::profile(&setup, quantity).header(&setup, None, 0),
                        layout.profile_first_row()
                    ),
                    overwrite,
                )?)
            });
        }
        let u0 = model.initial_displacement.clone();
        Ok(Self {
            dir: dir.to_owned(),
            setup,
            stations,
            depths: layout.depths,
            u0,
            profile: layout.profile,
            profile_out,
            surface,
            surface_files,
            laws: laws.to_vec(),
            components: C,
            last_station_t: state.last_station_t,
            last_profile_t: state.last_profile_t,
            events: state.events,
            slip_at_start: state.slip_at_start,
            pending_end: state.pending_end,
            tau_min: state.tau_min,
            tau_max: state.tau_max,
            steps: state.steps,
            values: Vec::new(),
            log,
            station_rows: state.station_rows,
            profile_rows: state.profile_rows,
        })
    }

    /// The along-dip SEAS files (BP1, BP3) of the run of `model` in `out` under `session`
    /// (the library's run session, shared by the programs and the Python package), `laws`
    /// its frictional nodes' laws: opened in the session's [`mode`](rsf::run_folder::Session::mode)
    /// of `fresh` — on resume the resume log's line of the checkpoint's step must show the
    /// checkpoint's time (the files are its run's) and every file's rows are checked up to
    /// that step before any is cut — with their resume log where the run can stop before
    /// its end ([`keeps_resume_log`](rsf::run_folder::Session::keeps_resume_log)).
    ///
    /// # Errors
    /// [`new`](Self::new)'s, [`check_checkpoint_time`](Self::check_checkpoint_time)'s and
    /// [`with_resume_log`](Self::with_resume_log)'s (invalid set-up, files that exist, rows
    /// that do not match the checkpoint, I/O naming the file).
    pub fn for_session<const D: usize, const C: usize>(
        session: &rsf::run_folder::Session,
        out: &Path,
        model: &Model<D, C>,
        laws: &[L],
        setup: SeasSetup,
        fresh: FileMode,
    ) -> Result<Self> {
        if let Some(c) = session.resumed() {
            Self::check_checkpoint_time(out, c.state.step, c.state.time)?;
        }
        let mode = session.mode(fresh);
        let output = Self::new(out, model, laws, setup, mode)?;
        if session.keeps_resume_log() {
            output.with_resume_log(mode)
        } else {
            Ok(output)
        }
    }

    /// Writes the resume log [`SEAS_RESUME_LOG`] (a line of this output's state after
    /// every step, about 350 bytes) and flushes every file after each step that writes
    /// to it, so that a checkpoint of any step can be resumed with
    /// [`FileMode::Resume`]: the station files, `devol.dat`, `events.csv` and the log
    /// then end byte-identical to an uninterrupted run's. Put the output before the
    /// [`Checkpointer`](rsf::observe::Checkpointer). (A resumed output keeps writing its log.)
    ///
    /// # Errors
    /// [`Error::FileExists`](crate::Error::FileExists) for a non-empty log of an earlier
    /// run where this output was made with [`FileMode::Create`]; I/O errors.
    pub fn with_resume_log(mut self, mode: FileMode) -> Result<Self> {
        if self.log.is_none() {
            let path = self.dir.join(SEAS_RESUME_LOG);
            self.log = Some(create_file(&path, LOG_HEADER, mode == FileMode::Overwrite)?);
        }
        Ok(self)
    }

    /// Checks, without changing anything, that the files of a [`SeasOutput`] in `dir`
    /// (of `model` and `setup`, as given to [`new`](Self::new)) can be continued after a
    /// checkpoint of step `step`: the resume log has the line of that step, every station
    /// file and `devol.dat` has its column line and at least the rows written up to that
    /// step, complete, the last of them at the log's time of it.
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the file that cannot be continued
    /// (missing, another layout, rows missing or damaged); I/O errors.
    pub fn check_resume<const D: usize, const C: usize>(
        dir: &Path,
        model: &Model<D, C>,
        setup: &SeasSetup,
        step: usize,
    ) -> Result<()> {
        plan_resume(dir, setup, &Layout::new(model, setup)?, step).map(|_| ())
    }

    /// Checks, without changing anything, that the files of a [`SeasOutput`] in `dir` are
    /// of the run of a checkpoint of step `step` at time `time` (s): the resume log's line
    /// of that step shows exactly that time — so that a folder whose manifest is missing
    /// cannot take another run's checkpoint and splice the two runs (issue 87). Call it
    /// before [`new`](Self::new) with [`FileMode::Resume`].
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the resume log (missing, without the
    /// step's line, at another time); I/O errors.
    pub fn check_checkpoint_time(dir: &Path, step: usize, time: f64) -> Result<()> {
        resume::check_log_time(&dir.join(SEAS_RESUME_LOG), step, time)
    }

    /// Appends the state after step `step` (time `t`) to the resume log, if written.
    fn write_log_line(&mut self, step: usize, t: f64) -> Result<()> {
        let Some(log) = self.log.as_mut() else {
            return Ok(());
        };
        let nan = SeasEvent {
            t_start: f64::NAN,
            t_end: f64::NAN,
            hypocentre_depth: f64::NAN,
            peak_slip_rate: f64::NAN,
            surface_slip: f64::NAN,
        };
        let e = self.events.last().copied().unwrap_or(nan);
        let (pt, ps) = self.pending_end.unwrap_or((f64::NAN, f64::NAN));
        let path = self.dir.join(SEAS_RESUME_LOG);
        writeln!(
            log,
            "{step},{t:e},{},{:e},{:e},{:e},{:e},{},{},{:e},{pt:e},{ps:e},{},{:e},{:e},{:e},{:e},{:e}",
            self.steps,
            self.tau_min,
            self.tau_max,
            self.last_station_t,
            self.last_profile_t,
            self.station_rows,
            self.profile_rows,
            self.slip_at_start,
            self.events.len(),
            e.t_start,
            e.t_end,
            e.hypocentre_depth,
            e.peak_slip_rate,
            e.surface_slip
        )
        .map_err(io_at("write a line of", &path))?;
        log.flush().map_err(io_at("flush", &path))
    }

    /// The events so far (the last one may still run: `t_end` NaN).
    pub fn events(&self) -> &[SeasEvent] {
        &self.events
    }

    /// The smallest and largest time step (s) of the steps seen, and their number.
    pub fn time_steps(&self) -> (f64, f64, usize) {
        (self.tau_min, self.tau_max, self.steps)
    }

    /// The slip (m) of frictional node `k` of `model` with displacement `u`: the change
    /// of its field since the start (signed for a scalar field and for BP3's internal
    /// fault, whose first component is the jump's tangential one; the norm of the change
    /// otherwise).
    fn slip<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        u: &[f64],
        k: usize,
    ) -> f64 {
        let p = model.frictional_boundary.nodes[k];
        let u = &u[C * p..C * p + C];
        let u0 = &self.u0[C * p..C * p + C];
        if C == 1 || matches!(self.setup.layout, SeasLayout::Bp3 { .. }) {
            // A scalar field's one component, or an internal fault's jump's tangential
            // component: signed.
            u[0] - u0[0]
        } else {
            u.iter()
                .zip(u0)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
        }
    }

    /// Writes the rows of the initial state (time `state.time`, normally 0) to every
    /// station file and `devol.dat`, as the benchmark asks (a first row at t = 0): call it
    /// once, after [`new`](Self::new) with [`FileMode::Create`] or
    /// [`FileMode::Overwrite`] and [`with_resume_log`](Self::with_resume_log) if used, and
    /// before the run. (A resumed output has the rows already.) The rows are those of any
    /// step: slip 0, the initial slip rate and state; the thinning of the following rows
    /// counts from them.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `state` if rows
    /// were written already or `state` is not at step 0; I/O errors.
    pub fn write_initial_state<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        state: &SimulationState,
    ) -> Result<()> {
        if self.station_rows > 0 || self.profile_rows > 0 || state.step != 0 {
            return Err(invalid(
                "state",
                format!(
                    "the initial rows are written once, before any step (state at step {}, \
                     {} station and {} profile rows written)",
                    state.step, self.station_rows, self.profile_rows
                ),
            ));
        }
        let v = &state.kinematics.v;
        let vmax = model
            .frictional_boundary
            .nodes
            .iter()
            .map(|&p| block_norm::<C>(v, p))
            .fold(0.0f64, f64::max);
        self.write_station_rows(model, state, None)?;
        self.write_profile_row(model, state, vmax, None)?;
        self.write_log_line(0, state.time)
    }

    /// One row at `state` in every station file; `tractions` the run's (the laws' own at
    /// the initial state if `None`).
    fn write_station_rows<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        state: &SimulationState,
        tractions: Option<&dyn FaultTractions>,
    ) -> Result<()> {
        let t = state.time;
        self.last_station_t = t;
        let fb = &model.frictional_boundary;
        let v = &state.kinematics.v;
        for i in 0..self.stations.len() {
            let k = self.stations[i].k;
            let vk = block_norm::<C>(v, fb.nodes[k]);
            let alpha = state.alpha[k];
            let st = &self.stations[i];
            let mut row = String::new();
            match self.setup.layout {
                SeasLayout::Bp1 => {
                    let stress = self.setup.sigma_n * st.law.friction_coefficient(vk, alpha) / 1e6;
                    let slip = self.slip(model, &state.kinematics.u, k);
                    let values = [slip, vk.log10(), stress, alpha / std::f64::consts::LN_10];
                    write_row(&mut row, t, &values);
                }
                SeasLayout::Bp3 { .. } => {
                    let (shear, normal) = self.stresses(model, state, tractions, k);
                    let slip = self.slip(model, &state.kinematics.u, k);
                    let values = [
                        slip,
                        vk.log10(),
                        shear / 1e6,
                        normal / 1e6,
                        alpha / std::f64::consts::LN_10,
                    ];
                    write_row(&mut row, t, &values);
                }
            }
            let st = &mut self.stations[i];
            let out = writer(&mut st.out, &st.path)?;
            out.write_all(row.as_bytes())
                .map_err(io_at("write", &st.path))?;
            if self.log.is_some() {
                out.flush().map_err(io_at("flush", &st.path))?;
            }
        }
        for i in 0..self.surface_files.len() {
            let row = self.surface_row(model, state, i)?;
            let f = &mut self.surface_files[i];
            let out = writer(&mut f.out, &f.path)?;
            out.write_all(row.as_bytes())
                .map_err(io_at("write", &f.path))?;
            if self.log.is_some() {
                out.flush().map_err(io_at("flush", &f.path))?;
            }
        }
        self.station_rows += 1;
        Ok(())
    }

    /// BP3's shear stress, signed with the slip rate's tangential component (the jump's
    /// first), and normal stress (Pa, compressive positive) of frictional node `k`;
    /// `tractions` the run's (the laws' own at the initial state if `None`).
    fn stresses<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        state: &SimulationState,
        tractions: Option<&dyn FaultTractions>,
        k: usize,
    ) -> (f64, f64) {
        let p = model.frictional_boundary.nodes[k];
        let v = &state.kinematics.v;
        let vk = block_norm::<C>(v, p);
        let alpha = state.alpha[k];
        let law = &self.laws[k];
        let (shear, normal) = match tractions {
            Some(f) => (f.shear_traction(k, vk, alpha), f.normal_traction(k)),
            None => (law.potential(alpha).slope(vk), law.normal_stress()),
        };
        let signed = if v[C * p] < 0.0 { -shear } else { shear };
        (signed, normal.unwrap_or(f64::NAN))
    }

    /// The row of station off the fault `i` at `state`: time, displacement change since
    /// the start and velocity (Cartesian; the depth axis's component positive down).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `surface_stations` where the state has no value at the station's vertex.
    fn surface_row<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        state: &SimulationState,
        i: usize,
    ) -> Result<String> {
        let f = &self.surface_files[i];
        let u = model.vertex_value(f.vertex, &state.kinematics.u);
        let u0 = model.vertex_value(f.vertex, &self.u0);
        let v = model.vertex_value(f.vertex, &state.kinematics.v);
        if u.iter().chain(&v).any(|x| !x.is_finite()) {
            return Err(invalid(
                "surface_stations",
                format!(
                    "station `{}` (vertex {}): the run's state has no displacement or velocity \
                     there at t = {} s (a run condensed onto the fault computes the vertices \
                     its observers ask for: call `Stepping::watch_vertices` with \
                     `SeasOutput::surface_vertices` before writing the initial state)",
                    f.path.display(),
                    f.vertex,
                    state.time
                ),
            ));
        }
        let down = |c: usize| {
            if C == D && c == self.setup.depth_axis && !self.setup.depth_down {
                -1.0
            } else {
                1.0
            }
        };
        let values: Vec<f64> = (0..C)
            .map(|c| down(c) * (u[c] - u0[c]))
            .chain(v.iter().enumerate().map(|(c, vc)| down(c) * vc))
            .collect();
        let mut row = String::new();
        write_row(&mut row, state.time, &values);
        Ok(row)
    }

    /// The vertices of the stations off the fault (what a run condensed onto the fault
    /// must compute for them: [`Stepping::watch_vertices`](rsf::Stepping::watch_vertices),
    /// which a run calls itself with [`Observer::volume_vertices`]).
    pub fn surface_vertices(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.surface_files.iter().map(|f| f.vertex).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// One row of every profile file at `state` (`vmax` the largest slip rate on the
    /// fault; `tractions` as for [`stresses`](Self::stresses)).
    fn write_profile_row<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        state: &SimulationState,
        vmax: f64,
        tractions: Option<&dyn FaultTractions>,
    ) -> Result<()> {
        let t = state.time;
        self.last_profile_t = t;
        let files = self.setup.layout.profile_files();
        for (j, &quantity) in self.setup.layout.profiles().iter().enumerate() {
            let mut values = std::mem::take(&mut self.values);
            values.clear();
            values.push(vmax.log10());
            for &k in &self.profile {
                values.push(match quantity {
                    ProfileQuantity::Slip => self.slip(model, &state.kinematics.u, k),
                    ProfileQuantity::ShearStress => {
                        self.stresses(model, state, tractions, k).0 / 1e6
                    }
                    ProfileQuantity::NormalStress => {
                        self.stresses(model, state, tractions, k).1 / 1e6
                    }
                });
            }
            let mut row = String::new();
            write_row(&mut row, t, &values);
            self.values = values;
            let path = self.dir.join(files[j]);
            let out = writer(&mut self.profile_out[j], &path)?;
            out.write_all(row.as_bytes())
                .map_err(io_at("write", &path))?;
            if self.log.is_some() {
                out.flush().map_err(io_at("flush", &path))?;
            }
        }
        self.profile_rows += 1;
        Ok(())
    }
}

/// The open writer of `path`, reopened for appending after a [`finish`](Observer::finish)
/// (which closes the files to complete their headers; a run may continue afterwards).
fn writer<'a>(
    out: &'a mut Option<BufWriter<File>>,
    path: &Path,
) -> Result<&'a mut BufWriter<File>> {
    if out.is_none() {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(io_at("open for appending", path))?;
        *out = Some(BufWriter::new(file));
    }
    Ok(out.as_mut().expect("just opened"))
}

/// Replaces the `#` lines at the top of `path` by `header`'s `#` lines (atomically).
fn rewrite_header(path: &Path, header: &str) -> Result<()> {
    let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
    let body: String = text
        .split_inclusive('\n')
        .skip_while(|l| l.starts_with('#'))
        .collect();
    let hashes: String = header
        .lines()
        .take_while(|l| l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    Ok(write_atomically(
        path,
        format!("{hashes}{body}").as_bytes(),
    )?)
}

impl<const D: usize, const C: usize, L: FrictionLaw> Observer<D, C> for SeasOutput<L> {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        let t = s.state.time;
        let fb = &s.model.frictional_boundary;
        self.steps += 1;
        // The step just taken had the length of the time advanced, τ of the state is the next.
        self.tau_min = self.tau_min.min(s.report.tau);
        self.tau_max = self.tau_max.max(s.report.tau);
        let v = &s.state.kinematics.v;
        let (mut vmax, mut kmax) = (0.0f64, 0);
        for (k, &p) in fb.nodes.iter().enumerate() {
            let vk = block_norm::<C>(v, p);
            if vk > vmax {
                (vmax, kmax) = (vk, k);
            }
        }
        let threshold = self.setup.sampling.event_threshold;
        let in_event = vmax >= threshold;
        let surface_slip = self.slip(s.model, &s.state.kinematics.u, self.surface);
        match self.events.last_mut() {
            Some(e) if e.t_end.is_nan() => {
                e.peak_slip_rate = e.peak_slip_rate.max(vmax);
                if in_event {
                    self.pending_end = None;
                } else {
                    let (t0, slip0) = *self.pending_end.get_or_insert((t, surface_slip));
                    if t - t0 >= self.setup.sampling.event_quiet_time {
                        e.t_end = t0;
                        e.surface_slip = slip0 - self.slip_at_start;
                        self.pending_end = None;
                    }
                }
            }
            _ if in_event => {
                self.slip_at_start = surface_slip;
                self.events.push(SeasEvent {
                    t_start: t,
                    t_end: f64::NAN,
                    hypocentre_depth: self.depths[kmax],
                    peak_slip_rate: vmax,
                    surface_slip: f64::NAN,
                });
            }
            _ => {}
        }
        let sm = self.setup.sampling;
        let station_dt = if in_event {
            sm.station_event
        } else {
            sm.station_quiet
        };
        if sm.every_step || t - self.last_station_t >= station_dt * (1.0 - 1e-12) {
            self.write_station_rows(s.model, s.state, Some(s.friction))?;
        }
        let profile_dt = if in_event {
            sm.profile_event
        } else {
            sm.profile_quiet
        };
        if t - self.last_profile_t >= profile_dt * (1.0 - 1e-12) {
            self.write_profile_row(s.model, s.state, vmax, Some(s.friction))?;
        }
        self.write_log_line(s.report.step, t)?;
        Ok(Flow::Continue(()))
    }

    fn finish(&mut self) -> rsf::Result<()> {
        if let Some(log) = self.log.as_mut() {
            log.flush()
                .map_err(io_at("flush", &self.dir.join(SEAS_RESUME_LOG)))?;
        }
        let stats = (self.steps > 0).then_some((self.tau_min, self.tau_max));
        for st in &mut self.stations {
            if let Some(mut out) = st.out.take() {
                out.flush().map_err(io_at("write", &st.path))?;
            }
            rewrite_header(
                &st.path,
                &headers::station(&self.setup, st.depth).header(
                    &self.setup,
                    stats,
                    self.station_rows,
                ),
            )?;
        }
        for f in &mut self.surface_files {
            if let Some(mut out) = f.out.take() {
                out.flush().map_err(io_at("write", &f.path))?;
            }
            rewrite_header(
                &f.path,
                &headers::surface(&self.setup, &f.position, self.components).header(
                    &self.setup,
                    stats,
                    self.station_rows,
                ),
            )?;
        }
        let files = self.setup.layout.profile_files();
        for (j, &quantity) in self.setup.layout.profiles().iter().enumerate() {
            let path = self.dir.join(files[j]);
            if let Some(mut out) = self.profile_out[j].take() {
                out.flush().map_err(io_at("write", &path))?;
            }
            rewrite_header(
                &path,
                &headers::profile(&self.setup, quantity).header(
                    &self.setup,
                    stats,
                    self.profile_rows,
                ),
            )?;
        }
        let mut csv = String::from(
            "event,t_start_s,t_end_s,hypocentre_depth_m,peak_slip_rate_mps,surface_slip_m\n",
        );
        for (i, e) in self.events.iter().enumerate() {
            csv.push_str(&format!(
                "{},{:e},{:e},{},{:e},{:e}\n",
                i + 1,
                e.t_start,
                e.t_end,
                e.hypocentre_depth,
                e.peak_slip_rate,
                e.surface_slip
            ));
        }
        write_atomically(&self.dir.join("events.csv"), csv.as_bytes())
    }

    fn name(&self) -> String {
        "SEAS output".into()
    }
    fn reads_volume(&self) -> bool {
        false
    }
    fn volume_vertices(&self) -> Vec<usize> {
        self.surface_vertices()
    }
}
