//! The event catalogue of a fault network: every event with its onset, where it nucleated,
//! which faults it ruptured and, per fault, its moment and peak slip rate
//! (docs/fault-networks.md, "The catalogue").

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::checkpoint::Checkpoint;
use crate::error::{invalid, io_at, show_path, Result};
use crate::model::fault::block_norm;
use crate::model::Model;

use super::events::EventThresholds;
use super::files::{self, FileMode};
use super::{Flow, Observer, StepView};

/// One event of a [`FaultCatalogue`]: an interval of time during which the largest slip
/// rate of the whole network stays above the end threshold once it has crossed the onset
/// threshold (the hysteresis of [`EventThresholds`]) — the faults it ruptured are those
/// whose largest slip rate crossed the onset threshold during it ("connected in time").
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NetworkEvent {
    /// Step of the onset (the first step whose largest slip rate exceeds the onset
    /// threshold).
    pub onset_step: usize,
    /// Time of the onset step (s).
    pub onset_s: f64,
    /// Step and time (s) where the event ended; `None` while it lasts.
    pub end: Option<(usize, f64)>,
    /// The fault where it nucleated: that of the node with the largest slip rate at the
    /// onset step (an index into [`FaultCatalogue::fault_names`]).
    pub nucleation_fault: usize,
    /// That node's position (m; `D` coordinates).
    pub nucleation_x: Vec<f64>,
    /// Per fault: whether its slip rate crossed the onset threshold during the event.
    pub ruptured: Vec<bool>,
    /// Per fault: its largest slip rate during the event (m/s).
    pub peak_slip_rate: Vec<f64>,
    /// Per fault: the time of its first crossing of the onset threshold (s); `None` where it
    /// did not rupture.
    pub rupture_s: Vec<Option<f64>>,
    /// Per fault: the event's seismic moment `Σ_k μ_k w_k |δ_k(end) − δ_k(onset⁻)|` over the
    /// fault's nodes (N·m in 3-D; N·m per metre of the third dimension in 2-D), `δ` the slip
    /// vector, `onset⁻` the step before the onset, `w` the node's weight.
    pub moment: Vec<f64>,
}

impl NetworkEvent {
    /// The names of the faults it ruptured, in network order, joined by `;`.
    pub fn ruptured_names(&self, names: &[String]) -> String {
        names
            .iter()
            .zip(&self.ruptured)
            .filter(|(_, &r)| r)
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(";")
    }
}

/// An observer building the event catalogue of a fault network: the faults of Γ_F
/// ([`FrictionalBoundary::fault_names`](crate::model::FrictionalBoundary::fault_names),
/// one or several), events detected on the largest slip rate of the whole network with the
/// hysteresis of [`EventThresholds`], each event's nucleation fault and place, the faults it
/// ruptured, and per fault its moment and peak slip rate. [`write_csv`](Self::write_csv)
/// writes it as `catalogue.csv`.
///
/// A run that may stop before its end (checkpoints, a step cap) keeps the catalogue's state
/// in a resume log ([`with_resume_log`](Self::with_resume_log)) at the checkpoints' steps,
/// so that a resumed run's catalogue is the uninterrupted run's.
#[derive(Debug)]
pub struct FaultCatalogue<const D: usize, const C: usize = D> {
    thresholds: EventThresholds,
    names: Vec<String>,
    /// Per frictional node: its fault, `μ_k w_k` (N/m in 2-D, N/m² · m² in 3-D → N/m).
    fault_of: Vec<usize>,
    mu_w: Vec<f64>,
    /// Per node: the slip at the previous step, at this step and at the onset (`C` per
    /// node).
    previous: Vec<f64>,
    current: Vec<f64>,
    at_onset: Vec<f64>,
    /// Per fault: its largest slip rate at this step.
    fastest: Vec<f64>,
    events: Vec<NetworkEvent>,
    slipping: bool,
    log: Option<ResumeLog>,
}

/// The resume log of a [`FaultCatalogue`]: its state at the checkpoints' steps.
#[derive(Debug)]
struct ResumeLog {
    out: BufWriter<File>,
    path: PathBuf,
    /// The checkpoint interval (0: none) and the step cap.
    every: usize,
    cap: Option<usize>,
}

/// What a [`FaultCatalogue`] needs to continue after a checkpoint.
#[derive(serde::Serialize, serde::Deserialize)]
struct CatalogueState {
    previous: Vec<f64>,
    at_onset: Vec<f64>,
    events: Vec<NetworkEvent>,
    slipping: bool,
}

/// The header of a catalogue's resume log.
const LOG_HEADER: &str = "step,catalogue_state_json";

impl<const D: usize, const C: usize> FaultCatalogue<D, C> {
    /// A catalogue of the faults of `model` with the shear modulus `rigidity(x)` (Pa) at
    /// every frictional node (the moment's `μ`), events detected with `thresholds`.
    ///
    /// # Errors
    /// As [`EventThresholds::validate`]; [`Error::InvalidParameter`](crate::Error::InvalidParameter)
    /// named `rigidity` for a value that is not finite and positive.
    pub fn new(
        model: &Model<D, C>,
        thresholds: EventThresholds,
        rigidity: impl Fn(&[f64; D]) -> f64,
    ) -> Result<Self> {
        thresholds.validate()?;
        let fb = &model.frictional_boundary;
        let mut mu_w = Vec::with_capacity(fb.len());
        for (k, &p) in fb.nodes.iter().enumerate() {
            let mu = rigidity(&model.vertices[p]);
            if !(mu.is_finite() && mu > 0.0) {
                return Err(invalid(
                    "rigidity",
                    format!(
                        "{mu} Pa at {:?} m must be finite and positive",
                        model.vertices[p]
                    ),
                ));
            }
            mu_w.push(mu * fb.weights[k] * fb.slip_factor);
        }
        let zero = vec![0.0; C * fb.len()];
        Ok(Self {
            thresholds,
            names: fb.fault_names.clone(),
            fault_of: fb.fault_of.clone(),
            mu_w,
            previous: zero.clone(),
            current: zero.clone(),
            at_onset: zero,
            fastest: vec![0.0; fb.fault_names.len()],
            events: Vec::new(),
            slipping: false,
            log: None,
        })
    }

    /// Keeps the catalogue's state in the resume log `path` (one line per step: the step,
    /// then the state as JSON) at the steps a checkpoint is written — every `every` steps
    /// (0: none) and at the step cap `cap` — new, or continued after a checkpoint
    /// ([`FileMode::Resume`]: the state of the checkpoint's step restored, later lines
    /// removed).
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the log if it has no state of the
    /// checkpoint's step, or one of another network; the file's errors.
    pub fn with_resume_log(
        mut self,
        path: &Path,
        every: usize,
        cap: Option<usize>,
        mode: FileMode,
    ) -> Result<Self> {
        if let FileMode::Resume { step } = mode {
            let state = self.logged_state(path, step)?;
            self.previous = state.previous;
            self.at_onset = state.at_onset;
            self.events = state.events;
            self.slipping = state.slipping;
        }
        let out = files::open(path, LOG_HEADER, 0, mode.start(false))?;
        self.log = Some(ResumeLog {
            out,
            path: path.to_path_buf(),
            every,
            cap,
        });
        Ok(self)
    }

    /// The state of step `step` in the resume log `path`, of this network's sizes.
    fn logged_state(&self, path: &Path, step: usize) -> Result<CatalogueState> {
        let fail = |reason: String| crate::Error::Resume {
            path: show_path(path),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(io_at("read", path))?;
        let prefix = format!("{step},");
        let json = text
            .lines()
            .skip(1)
            .find_map(|l| l.strip_prefix(&prefix))
            .ok_or_else(|| fail(format!("it has no state of the checkpoint's step {step}")))?;
        let state: CatalogueState = serde_json::from_str(json)
            .map_err(|e| fail(format!("the state of step {step}: {e}")))?;
        if state.previous.len() != self.previous.len()
            || state
                .events
                .iter()
                .any(|e| e.moment.len() != self.names.len())
        {
            return Err(fail(format!(
                "the state of step {step} is of another network (its sizes differ)"
            )));
        }
        Ok(state)
    }

    /// Checks, without changing anything, that the resume log `path` and the checkpoint
    /// `c` of a run of `model` are of the same run: the log's state of the checkpoint's
    /// step holds the slip of every frictional node of the checkpoint's displacement, bit
    /// for bit — so that a folder whose manifest is missing cannot take another run's
    /// checkpoint and splice the two runs (issue 87). A checkpoint at step 0 has nothing
    /// to compare (every run of a scene starts at the same state).
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the log if it has no state of the
    /// step, one of another network, or another slip; [`Error::File`](crate::Error::File).
    pub fn check_checkpoint_state(
        &self,
        path: &Path,
        model: &Model<D, C>,
        c: &Checkpoint,
    ) -> Result<()> {
        let step = c.state.step;
        if step == 0 {
            return Ok(());
        }
        let state = self.logged_state(path, step)?;
        let mut slip = vec![0.0; self.previous.len()];
        if c.state.kinematics.u.len() != model.initial_displacement.len() {
            return Err(crate::Error::Resume {
                path: show_path(path),
                reason: "the checkpoint's displacement is of another model".into(),
            });
        }
        slips(model, &c.state.kinematics.u, &mut slip);
        let differs = slip
            .iter()
            .zip(&state.previous)
            .position(|(a, b)| a.to_bits() != b.to_bits());
        match differs {
            None => Ok(()),
            Some(i) => Err(crate::Error::Resume {
                path: show_path(path),
                reason: format!(
                    "its state of the checkpoint's step {step} has the slip {:e} m at \
                     frictional node {}, the checkpoint {:e} m: the files in this folder are \
                     of another run than the checkpoint's, and continuing would splice the \
                     two; resume into the checkpoint's own folder",
                    state.previous[i],
                    i / C,
                    slip[i]
                ),
            }),
        }
    }

    /// Appends the state after step `step` to the resume log where a checkpoint is
    /// written.
    fn log_state(&mut self, step: usize) -> Result<()> {
        let Some(log) = self.log.as_mut() else {
            return Ok(());
        };
        if !((log.every > 0 && step % log.every == 0) || log.cap == Some(step)) {
            return Ok(());
        }
        let state = CatalogueState {
            previous: self.previous.clone(),
            at_onset: self.at_onset.clone(),
            events: self.events.clone(),
            slipping: self.slipping,
        };
        let json = serde_json::to_string(&state)
            .map_err(|e| invalid("catalogue", format!("its state as JSON: {e}")))?;
        let out = &mut log.out;
        writeln!(out, "{step},{json}")
            .and_then(|()| out.flush())
            .map_err(io_at("write", &log.path))
    }

    /// The faults' names (the catalogue's per-fault entries are in this order).
    pub fn fault_names(&self) -> &[String] {
        &self.names
    }

    /// The events so far (the last may still last).
    pub fn events(&self) -> &[NetworkEvent] {
        &self.events
    }

    /// Writes the catalogue as CSV to `path` (created or replaced): a header, then one row
    /// per event — `event, onset_s, end_s, duration_s, nucleation_fault, nucleation_x,
    /// nucleation_y[, nucleation_z], ruptured` (the faults' names joined by `;`), then per
    /// fault `peak_slip_rate_{name}` (m/s), `moment_{name}` (N·m, per metre in 2-D) and
    /// `rupture_s_{name}` (empty where it did not rupture). Numbers in Rust's shortest
    /// round-trip form (`{:e}`), an event still under way with empty end and duration.
    ///
    /// # Errors
    /// [`Error::File`](crate::Error::File) naming the file.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let io = io_at("write", path);
        let mut out =
            std::io::BufWriter::new(std::fs::File::create(path).map_err(io_at("create", path))?);
        let axes = ["x", "y", "z"];
        let mut header = vec![
            "event".to_owned(),
            "onset_s".into(),
            "end_s".into(),
            "duration_s".into(),
            "nucleation_fault".into(),
        ];
        header.extend(axes[..D].iter().map(|a| format!("nucleation_{a}")));
        header.push("ruptured".into());
        for n in &self.names {
            header.push(format!("peak_slip_rate_{n}"));
            header.push(format!("moment_{n}"));
            header.push(format!("rupture_s_{n}"));
        }
        writeln!(out, "{}", header.join(",")).map_err(&io)?;
        for (i, e) in self.events.iter().enumerate() {
            let mut row = vec![
                (i + 1).to_string(),
                format!("{:e}", e.onset_s),
                e.end.map_or(String::new(), |(_, t)| format!("{t:e}")),
                e.end
                    .map_or(String::new(), |(_, t)| format!("{:e}", t - e.onset_s)),
                self.names[e.nucleation_fault].clone(),
            ];
            row.extend(e.nucleation_x.iter().map(|x| format!("{x:e}")));
            row.push(e.ruptured_names(&self.names));
            for f in 0..self.names.len() {
                row.push(format!("{:e}", e.peak_slip_rate[f]));
                row.push(format!("{:e}", e.moment[f]));
                row.push(e.rupture_s[f].map_or(String::new(), |t| format!("{t:e}")));
            }
            writeln!(out, "{}", row.join(",")).map_err(&io)?;
        }
        out.flush().map_err(&io)
    }
}

/// The slip vector (`C` components, the model's unknown: `s·u` on an antisymmetric fault)
/// of every frictional node of `u` into `out`, node after node.
fn slips<const D: usize, const C: usize>(model: &Model<D, C>, u: &[f64], out: &mut [f64]) {
    for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
        for c in 0..C {
            out[C * k + c] = u[C * p + c] - model.initial_displacement[C * p + c];
        }
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for FaultCatalogue<D, C> {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> Result<Flow> {
        let fb = &s.model.frictional_boundary;
        let (step, t) = (s.report.step, s.report.time);
        let v = &s.state.kinematics.v;
        // The fastest node of the network, and per fault.
        let mut fastest = (0, 0.0f64);
        let per_fault = &mut self.fastest;
        per_fault.fill(0.0);
        for k in 0..fb.len() {
            let rate = block_norm::<C>(v, fb.nodes[k]);
            let f = self.fault_of[k];
            per_fault[f] = per_fault[f].max(rate);
            if rate > fastest.1 {
                fastest = (k, rate);
            }
        }
        let (onset, end) = (self.thresholds.onset, self.thresholds.end);
        if !self.slipping && fastest.1 > onset {
            self.slipping = true;
            self.at_onset.clone_from(&self.previous);
            let nf = self.names.len();
            self.events.push(NetworkEvent {
                onset_step: step,
                onset_s: t,
                end: None,
                nucleation_fault: self.fault_of[fastest.0],
                nucleation_x: s.model.vertices[fb.nodes[fastest.0]].to_vec(),
                ruptured: vec![false; nf],
                peak_slip_rate: vec![0.0; nf],
                rupture_s: vec![None; nf],
                moment: vec![0.0; nf],
            });
        }
        let ended = self.slipping && fastest.1 < end;
        slips(s.model, &s.state.kinematics.u, &mut self.current);
        let slip = &self.current;
        if self.slipping {
            let e = self.events.last_mut().expect("an event under way");
            for (f, &rate) in self.fastest.iter().enumerate() {
                e.peak_slip_rate[f] = e.peak_slip_rate[f].max(rate);
                if rate > onset && !e.ruptured[f] {
                    e.ruptured[f] = true;
                    e.rupture_s[f] = Some(t);
                }
            }
            e.moment.iter_mut().for_each(|m| *m = 0.0);
            for k in 0..fb.len() {
                let d: f64 = (0..C)
                    .map(|c| {
                        let x = slip[C * k + c] - self.at_onset[C * k + c];
                        x * x
                    })
                    .sum::<f64>()
                    .sqrt();
                e.moment[self.fault_of[k]] += self.mu_w[k] * d;
            }
            if ended {
                e.end = Some((step, t));
                self.slipping = false;
            }
        }
        std::mem::swap(&mut self.previous, &mut self.current);
        self.log_state(step)?;
        Ok(Flow::Continue(()))
    }

    /// Only Γ_F: a run condensed onto it need not extend the field.
    fn reads_volume(&self) -> bool {
        false
    }
}
