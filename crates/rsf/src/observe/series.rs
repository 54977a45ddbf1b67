//! Time series at one mesh vertex of the model, as CSV.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::checkpoint::Checkpoint;
use crate::error::{io_at, show_path, Error, Result};
use crate::model::Model;

use super::files::{self, FileMode, AXES};
use super::{Flow, Observer, StepView};

/// Time series at one mesh vertex: one CSV row per step,
/// `t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,relaxed_iterations`
/// followed, for `D ≥ 2`, by `u_y0_m,v_y0_mps` (and `u_z0_m,v_z0_mps` in 3D): time,
/// displacement and velocity components at the vertex (the `0` stands for the observed
/// point `x0`), the largest slip rate on Γ_F, the step's fixed point iterations, τ, the step
/// index, velocity-solver iterations and damped fixed point iterations.
///
/// Components are in model coordinates ([`Model`]): Cartesian at a vertex without a nodal
/// frame (every vertex of an axis-aligned model, e.g. the paper's slider, whose files keep
/// the header above) that is not a split vertex of a fault inside the body (there the
/// jump in the pair frame or the weighted mean). At a slanted fault vertex (one with a nodal frame,
/// [`Model::frame`]) they are the slip coordinates: the component along the frame's
/// tangent(s) and along its **inward** normal `−n` ([`Model::to_global`] turns them into
/// Cartesian ones), and the header says so ([`header_at`](Self::header_at)):
/// `u_t_m,v_t_mps` in place of `u_x0_m,v_x0_mps` and `u_n_m,v_n_mps` in place of
/// `u_y0_m,v_y0_mps` in 2-D; `u_t1_m`, `u_t2_m`, `u_n_m` (and `v_…`) in 3-D. With
/// bilateral contact the normal velocity there is 0.
///
/// Rows are flushed every step (by default) so that a killed run keeps what it wrote;
/// [`FileMode::Resume`] continues a file after a checkpoint.
pub struct PointSeries<const D: usize> {
    vertex: usize,
    out: BufWriter<File>,
    /// The file, for errors.
    path: PathBuf,
    flush_every: usize,
    rows: usize,
}

/// One row of a [`PointSeries`] file, as read back by [`PointSeries::read`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeriesRow<const D: usize> {
    /// Step index n.
    pub step: usize,
    /// Time t_n (s; written with 10 significant digits).
    pub time: f64,
    /// Time step τ of the step (s; exact).
    pub tau: f64,
    /// Displacement at the vertex (m), in the file's components (Cartesian, or tangent(s)
    /// and inward normal at a vertex with a nodal frame, [`PointSeries`]).
    pub u: [f64; D],
    /// Velocity at the vertex (m/s), components as `u`.
    pub v: [f64; D],
    /// Largest slip rate on Γ_F (m/s).
    pub max_slip_rate: f64,
    /// Fixed point iterations.
    pub fixed_point_iterations: usize,
    /// Velocity-solver iterations.
    pub solver_iterations: usize,
    /// Damped fixed point iterations.
    pub relaxed_iterations: usize,
}

impl<const D: usize> PointSeries<D> {
    /// The CSV header of a series at a vertex without a nodal frame (Cartesian
    /// components, `u_x0_m, …`): every vertex of an axis-aligned model.
    pub fn header() -> String {
        Self::header_with(false)
    }

    /// The CSV header of a series at mesh vertex `vertex` of `model`: [`header`](Self::header)
    /// without a nodal frame there, the slip-coordinate names (`u_t_m, …, u_n_m, …`) with
    /// one.
    pub fn header_at(model: &Model<D>, vertex: usize) -> String {
        Self::header_with(model.frame(vertex).is_some())
    }

    /// The header in Cartesian (`framed = false`) or frame (tangent(s), normal) components.
    fn header_with(framed: bool) -> String {
        let names = component_names::<D>(framed);
        // `0`: the observed point x0 (the Cartesian names predate the frame ones).
        let at = if framed { "" } else { "0" };
        let mut h = format!(
            "t_s,u_{c}{at}_m,v_{c}{at}_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,relaxed_iterations",
            c = names[0]
        );
        for c in names.iter().skip(1) {
            h.push_str(&format!(",u_{c}{at}_m,v_{c}{at}_mps"));
        }
        h
    }

    /// The header of the existing file `path` if it is one of the two a `PointSeries<D>`
    /// writes, else the Cartesian one (whose mismatch the caller then reports).
    fn header_of_file(path: &Path) -> String {
        use std::io::BufRead;
        let framed = Self::header_with(true);
        let first = File::open(path).ok().and_then(|f| {
            let mut line = String::new();
            std::io::BufReader::new(f).read_line(&mut line).ok()?;
            Some(line)
        });
        match first {
            Some(line) if line.trim_end_matches(['\n', '\r']) == framed => framed,
            _ => Self::header(),
        }
    }

    /// The series at mesh vertex `vertex` (an index into `model.vertices`, e.g. from
    /// [`Model::nearest_node`]; not a position on Γ_F) of `model` in the file `path`, new
    /// or continued after a checkpoint ([`FileMode`]); its header is
    /// [`header_at`](Self::header_at).
    ///
    /// # Errors
    /// [`Error::NodeOutOfRange`](crate::Error::NodeOutOfRange); for [`FileMode::Resume`], [`Error::Resume`](crate::Error::Resume) if the file
    /// is missing, has another header, or its rows end before the checkpoint's step (e.g.
    /// rows buffered by [`flush_every`](Self::flush_every) and lost); I/O errors.
    pub fn new(path: &Path, model: &Model<D>, vertex: usize, mode: FileMode) -> Result<Self> {
        model.check_node("point series", vertex)?;
        Ok(Self {
            vertex,
            out: files::open(path, &Self::header_at(model, vertex), 6, mode.start(true))?,
            path: path.to_path_buf(),
            flush_every: 1,
            rows: 0,
        })
    }

    /// Flush only every `n` rows (default 1). A checkpoint written at a step whose row is
    /// not flushed yet cannot be resumed without loss ([`FileMode::Resume`] reports
    /// it): use an `n` that divides the checkpoint interval.
    pub fn flush_every(mut self, n: usize) -> Self {
        self.flush_every = n.max(1);
        self
    }

    /// Checks, without changing it, that the file `path` can be continued after a
    /// checkpoint of step `step` ([`FileMode::Resume`]), so that a run can check all its
    /// files before it cuts any.
    ///
    /// # Errors
    /// As [`new`](Self::new) with [`FileMode::Resume`].
    pub fn check_resume(path: &Path, step: usize) -> Result<()> {
        files::check_resume(path, &Self::header_of_file(path), 6, step, true)
    }

    /// Checks that the row of the checkpoint `c`'s step in the series file `path` (at the
    /// node `node`) shows the checkpoint's time, displacement and velocity exactly as the
    /// series writes them: the folder's rows and the checkpoint are of the same run. A
    /// checkpoint at step 0 has no row to compare. Changes nothing.
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the file if the row is missing or
    /// differs; [`Error::File`](crate::Error::File).
    pub fn check_checkpoint_row(path: &Path, c: &Checkpoint, node: usize) -> Result<()> {
        let step = c.state.step;
        if step == 0 {
            return Ok(());
        }
        let fail = |reason: String| Error::Resume {
            path: show_path(path),
            reason,
        };
        let text = std::fs::read(path).map_err(io_at("read", path))?;
        let want = step.to_string();
        // The complete rows (a row cut off by an interruption is no row), by the csv crate.
        let mut found = None;
        for row in files::csv_lines(&text, 0, 1, true) {
            let row = row.map_err(|(line, reason)| fail(format!("line {line}: {reason}")))?;
            if row.fields.get(6) == Some(want.as_str()) {
                found = Some(row.fields);
                break;
            }
        }
        let Some(row) = found else {
            return Err(fail(format!(
                "it has no row of the checkpoint's step {step}: the checkpoint is not of this \
                 run folder"
            )));
        };
        let (u, v) = (&c.state.kinematics.u, &c.state.kinematics.v);
        let i = D * node;
        if u.len() < i + D || v.len() < i + D {
            return Err(fail(
                "the checkpoint has fewer nodes than the series' node".into(),
            ));
        }
        let mut expected = vec![
            (0, format!("{:.9e}", c.state.time)),
            (1, format!("{:.12e}", u[i])),
            (2, format!("{:.12e}", v[i])),
        ];
        for k in 1..D {
            expected.push((9 + 2 * (k - 1), format!("{:.12e}", u[i + k])));
            expected.push((10 + 2 * (k - 1), format!("{:.12e}", v[i + k])));
        }
        for (col, value) in expected {
            if row.get(col) != Some(value.as_str()) {
                return Err(fail(format!(
                    "its row of step {step} has `{}` in column {col}, the checkpoint gives \
                     `{value}`: the checkpoint belongs to another run (nothing was changed)",
                    rsf_numeric::excerpt(row.get(col).unwrap_or("")),
                )));
            }
        }
        Ok(())
    }

    /// Reads a file written by a `PointSeries<D>` (either header; [`SeriesRow::u`] and
    /// [`SeriesRow::v`] hold the components the header names).
    ///
    /// # Errors
    /// I/O errors; [`Error::Resume`](crate::Error::Resume) for another header or a malformed row.
    pub fn read(path: &Path) -> Result<Vec<SeriesRow<D>>> {
        files::read_rows(path, &Self::header_of_file(path), parse_row::<D>)
    }
}

/// The names of the `D` components of a series: `x, y, z` (Cartesian) or the frame's
/// tangent(s) and normal (`t, n` in 2-D; `t1, t2, n` in 3-D).
fn component_names<const D: usize>(framed: bool) -> Vec<&'static str> {
    if !framed {
        return AXES.iter().take(D).copied().collect();
    }
    let tangents: &[&str] = match D {
        1 => &[],
        2 => &["t"],
        _ => &["t1", "t2"],
    };
    tangents.iter().copied().chain(["n"]).collect()
}

fn parse_row<const D: usize>(f: &[&str]) -> Option<SeriesRow<D>> {
    if f.len() != 9 + 2 * (D - 1) {
        return None;
    }
    let x = |i: usize| f[i].parse::<f64>().ok();
    let n = |i: usize| f[i].parse::<usize>().ok();
    let mut u = [0.0; D];
    let mut v = [0.0; D];
    u[0] = x(1)?;
    v[0] = x(2)?;
    for c in 1..D {
        u[c] = x(9 + 2 * (c - 1))?;
        v[c] = x(10 + 2 * (c - 1))?;
    }
    Some(SeriesRow {
        time: x(0)?,
        u,
        v,
        max_slip_rate: x(3)?,
        fixed_point_iterations: n(4)?,
        tau: x(5)?,
        step: n(6)?,
        solver_iterations: n(7)?,
        relaxed_iterations: n(8)?,
    })
}

impl<const D: usize> Observer<D> for PointSeries<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let (u, v) = (&s.state.kinematics.u, &s.state.kinematics.v);
        let r = s.report;
        let i = D * self.vertex;
        write!(
            self.out,
            "{:.9e},{:.12e},{:.12e},{:.12e},{},{:e},{},{},{}",
            r.time,
            u[i],
            v[i],
            r.max_slip_rate,
            r.fixed_point_iterations,
            r.tau,
            r.step,
            r.solver_iterations,
            r.relaxed_iterations
        )
        .map_err(io_at("write a row of", &self.path))?;
        for c in 1..D {
            write!(self.out, ",{:.12e},{:.12e}", u[i + c], v[i + c])
                .map_err(io_at("write a row of", &self.path))?;
        }
        writeln!(self.out).map_err(io_at("write a row of", &self.path))?;
        self.rows += 1;
        if self.rows % self.flush_every == 0 {
            self.out.flush().map_err(io_at("flush", &self.path))?;
        }
        Ok(Flow::Continue(()))
    }
    fn finish(&mut self) -> Result<()> {
        self.out.flush().map_err(io_at("flush", &self.path))?;
        Ok(())
    }
}
