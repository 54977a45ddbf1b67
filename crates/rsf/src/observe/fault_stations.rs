//! Time series at stations on the faults of a network, one CSV file per station named by
//! its fault (docs/fault-networks.md, "Output").

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{invalid, io_at, Result};
use crate::model::Model;

use super::files::{self, FileMode};
use super::{Flow, Observer, StepView};

/// A station on a fault: the fault's name, a point (m) — the station is the fault's
/// frictional node nearest to it — and a label for its file name.
#[derive(Debug, Clone, PartialEq)]
pub struct FaultStation<const D: usize> {
    /// The fault's name ([`FrictionalBoundary::fault_names`](crate::model::FrictionalBoundary::fault_names)).
    pub fault: String,
    /// A point near the station (m).
    pub near: [f64; D],
    /// The file's label: the station writes `{fault}_{label}.csv`.
    pub label: String,
}

/// One open station file.
struct StationFile {
    /// The station's fault index `k` (a position on Γ_F).
    k: usize,
    /// The dofs of its slip components: the node's free (tangential) ones.
    dofs: Vec<usize>,
    out: BufWriter<File>,
    path: PathBuf,
}

/// Time series at stations on the faults of a network: for each [`FaultStation`] the file
/// `{dir}/{fault}_{label}.csv` with one row per step,
/// `step,t_s,slip_m…,slip_rate_mps,shear_traction_pa,state` — the slip's tangential
/// components in the node's frame (`slip_m` in 2-D, `slip_t1_m,slip_t2_m` in 3-D, as
/// [`StepView::slip`] turned into the frame: the jump of a fault inside the body), the slip
/// rate, the friction law's shear traction and the state `α` — flushed every step, so that
/// a killed run keeps what it wrote; [`FileMode::Resume`] continues the files after a
/// checkpoint.
pub struct FaultStations<const D: usize, const C: usize = D> {
    files: Vec<StationFile>,
}

impl<const D: usize, const C: usize> FaultStations<D, C> {
    /// The header of every station file.
    pub fn header() -> String {
        let slip = match C {
            3 => "slip_t1_m,slip_t2_m",
            _ => "slip_m",
        };
        format!("step,t_s,{slip},slip_rate_mps,shear_traction_pa,state")
    }

    /// The stations `stations` of `model` in the folder `dir`, new or continued after a
    /// checkpoint ([`FileMode`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `station` for a
    /// fault the model has not, or a label that is empty or holds a path separator; the
    /// files' errors (as [`PointSeries::new`](super::PointSeries::new)).
    pub fn new(
        dir: &Path,
        model: &Model<D, C>,
        stations: &[FaultStation<D>],
        mode: FileMode,
    ) -> Result<Self> {
        let fb = &model.frictional_boundary;
        let mut files = Vec::with_capacity(stations.len());
        for s in stations {
            let f = fb.fault_named(&s.fault).ok_or_else(|| {
                invalid(
                    "station",
                    format!(
                        "no fault `{}` (the model's faults: {})",
                        s.fault,
                        fb.fault_names.join(", ")
                    ),
                )
            })?;
            if s.label.is_empty() || s.label.contains(['/', '\\']) {
                return Err(invalid(
                    "station",
                    format!("label `{}` must be a non-empty file name part", s.label),
                ));
            }
            let distance = |k: usize| -> f64 {
                let x = &model.vertices[fb.nodes[k]];
                x.iter().zip(&s.near).map(|(a, b)| (a - b) * (a - b)).sum()
            };
            let k = fb
                .along_fault(f)
                .into_iter()
                .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
                .ok_or_else(|| {
                    invalid(
                        "station",
                        format!("fault `{}` has no frictional node", s.fault),
                    )
                })?;
            let path = dir.join(format!("{}_{}.csv", s.fault, s.label));
            let out = files::open(&path, &Self::header(), 0, mode.start(true))?;
            // The slip's components: the node's free ones (in its frame, tangential first;
            // an axis-aligned boundary node's Cartesian ones but the normal).
            let p = fb.nodes[k];
            let tangential = if C == D && C > 1 { C - 1 } else { 1 };
            let mut dofs: Vec<usize> = (C * p..C * p + C).filter(|&i| !model.fixed[i]).collect();
            if dofs.len() != tangential {
                dofs = (C * p..C * p + tangential).collect();
            }
            files.push(StationFile { k, dofs, out, path });
        }
        Ok(Self { files })
    }

    /// The fault index `k` of every station (a position on Γ_F), in the order given.
    pub fn nodes(&self) -> Vec<usize> {
        self.files.iter().map(|f| f.k).collect()
    }
}

impl<const D: usize, const C: usize> Observer<D, C> for FaultStations<D, C> {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> Result<Flow> {
        let (u, u0) = (&s.state.kinematics.u, &s.model.initial_displacement);
        for f in &mut self.files {
            let out = &mut f.out;
            let written = (|| -> std::io::Result<()> {
                write!(out, "{},{:.12e}", s.report.step, s.report.time)?;
                for &i in &f.dofs {
                    write!(out, ",{:.12e}", u[i] - u0[i])?;
                }
                writeln!(
                    out,
                    ",{:.12e},{:.12e},{:.12e}",
                    s.slip_rate(f.k),
                    s.shear_traction(f.k),
                    s.state.alpha[f.k]
                )?;
                out.flush()
            })();
            written.map_err(io_at("write", &f.path))?;
        }
        Ok(Flow::Continue(()))
    }

    /// Only Γ_F: a run condensed onto it need not extend the field.
    fn reads_volume(&self) -> bool {
        false
    }
}
