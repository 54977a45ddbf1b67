//! The fields of a run in one HDF5 file with an Xdmf index: the mesh once, one time axis,
//! each field one dataset over (time, vertex[, component]) — what h5py and xarray read
//! directly and ParaView opens through the `.xmf` file.

use std::path::PathBuf;

use rsf::checkpoint::Fingerprint;
use rsf::observe::{point_fields, FileMode, POINT_FIELDS};
use rsf::{Flow, Observer, StepView};

use crate::error::Result;
use crate::frames::{write, write_index, Field, FramesFile, Topology};

/// Writes the fields of every step it is shown (wrap it in [`rsf::observe::Every`] to
/// sample) into one HDF5 file `path` and rewrites the Xdmf index `path` with the extension
/// `.xmf` after every frame (so that an interrupted run leaves a usable index). The file
/// holds
///
/// - `/mesh/points` (vertices × 3, m; zero-padded in 2-D), `/mesh/cells` (cells × (D + 1),
///   vertex indices, `u64`), `/mesh/fault_nodes` (the vertices of Γ_F in fault order) —
///   written at the first frame;
/// - `/time` (frames, s) and `/step` (frames, `u64`): the time axis;
/// - `/fields/NAME` (frames × vertices × 3 for vectors, frames × vertices for scalars), each
///   with an attribute `unit`: the point fields of [`rsf::observe::POINT_FIELDS`] with
///   their names, units and values ([`rsf::observe::point_fields`], what the VTU frames of
///   [`rsf::observe::VtuFrames`] hold) — `displacement` (m), `velocity` (m/s), `slip` (m),
///   Cartesian 3-vectors; `slip_rate` (m/s), `state_alpha` (α = ln θ, θ in s),
///   `shear_traction` and `normal_traction` (Pa) on Γ_F, NaN at the other vertices.
///
/// The datasets are chunked one frame per chunk and grow by one frame per frame. The file
/// is open only while a frame is written (HDF5 locks an open file): between frames h5py
/// and ParaView read it, and an interrupted run leaves a closed, consistent file.
/// [`FileMode::Resume`] continues after a checkpoint: frames of later steps are cut off,
/// so the file ends as an uninterrupted run's.
///
/// ```no_run
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// use rsf::observe::{Every, FileMode, Interval};
/// let mut sim = rsf_scenes::Slider3dScene::default().build()?;
/// let fields = rsf_hdf5::Hdf5Fields::new("out/fields.h5", FileMode::Create)?;
/// let mut fields = Every::new(Interval::Steps(10), fields)?;
/// sim.run(100, &mut [&mut fields])?; // out/fields.h5 and its index out/fields.xmf
/// # Ok(())
/// # }
/// ```
pub struct Hdf5Fields {
    /// The file and its frames (also the file of [`Hdf5FaultFields`](crate::Hdf5FaultFields)).
    pub(crate) file: FramesFile,
}

impl Hdf5Fields {
    /// Fields into `path` (e.g. `out/fields.h5`; the index is `out/fields.xmf`), new or
    /// continued after a checkpoint of step `step` ([`FileMode::Resume`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) if `path` ends in
    /// `.xmf` (the index's name); [`rsf::Error::FileExists`] (as
    /// [`Error::Rsf`](crate::Error::Rsf)) for [`FileMode::Create`] if `path` exists and is
    /// not empty; [`Error::Resume`](crate::Error::Resume) for [`FileMode::Resume`] if
    /// `path` is missing or is not such a file.
    pub fn new(path: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        Ok(Self {
            file: FramesFile::new(path.into(), mode)?,
        })
    }

    /// The fields file of a run whose checkpoints carry `fingerprint`: a new file records
    /// it (the attribute `fingerprint` of `/`, JSON pairs `[field, value]`), so that a
    /// resume can tell the file's run ([`continue_run`](Self::continue_run)).
    pub fn fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.file.fingerprint = Some(fingerprint);
        self
    }

    /// The fields file of a run that shows it every `every` steps (wrapped in
    /// [`rsf::observe::Every`]): a new file records it (the attribute `every` of `/`, `u64`)
    /// so that a resume with another interval can be refused.
    pub fn every(mut self, every: usize) -> Self {
        self.file.every = Some(every);
        self
    }

    /// Fields continued in `path` after the checkpoint `c`, once the file itself shows that
    /// it holds the checkpoint's run (a file has no manifest naming its run): the run's
    /// fingerprint it recorded ([`fingerprint`](Self::fingerprint)) is the checkpoint's
    /// (fields in `allowed` may differ), and its frame of the checkpoint's step is at the
    /// checkpoint's time and holds the checkpoint's state `α` on Γ_F, bit for bit — then
    /// the frames after that step are cut, as [`FileMode::Resume`] does, so that the file
    /// ends as the uninterrupted run's. A checkpoint of step 0 keeps no frame and needs no
    /// proof. The continued file records `c`'s fingerprint. (Issue 87: a file of another
    /// run, continued, would hold two runs' frames.)
    ///
    /// # Errors
    /// [`Error::Resume`](crate::Error::Resume) naming the file: missing or not such a file; another run's
    /// fingerprint; no frame at the checkpoint's step (write checkpoints at frame steps); a
    /// frame of another time or state (another run's file) — nothing in the file changed
    /// then.
    pub fn continue_run(
        path: impl Into<PathBuf>,
        c: &rsf::Checkpoint,
        allowed: &[&str],
    ) -> Result<Self> {
        Ok(Self {
            file: FramesFile::continue_run(path.into(), c, allowed)?,
        })
    }

    /// The Xdmf index's path: the file's with the extension `.xmf`.
    pub fn index_path(&self) -> PathBuf {
        self.file.path.with_extension("xmf")
    }

    /// Rewrites the Xdmf index for the frames so far.
    fn write_index<const D: usize>(&self, s: &StepView<'_, D>, times: &[f64]) -> Result<()> {
        let m = s.model;
        let topology = Topology {
            kind: match D {
                1 => "Polyline",
                2 => "Triangle",
                _ => "Tetrahedron",
            },
            cells: m.cells.len() / (D + 1),
            corners: D + 1,
        };
        let fields: Vec<(&str, usize)> = POINT_FIELDS.iter().map(|&(n, c, _)| (n, c)).collect();
        write_index(&self.file.path, &topology, m.vertices.len(), times, &fields)
    }

    /// Appends the frame of `s` to the file (created with the mesh at the first frame);
    /// the times of all its frames.
    fn append_frame<const D: usize>(&mut self, s: &StepView<'_, D>) -> Result<Vec<f64>> {
        let m = s.model;
        let file = self.file.open(|file| {
            let mut points = vec![0.0; 3 * m.vertices.len()];
            for (p, v) in m.vertices.iter().enumerate() {
                points[3 * p..3 * p + D].copy_from_slice(v);
            }
            let cells: Vec<u64> = m.cells.iter().map(|&c| c as u64).collect();
            let fault: Vec<u64> = m
                .frictional_boundary
                .nodes
                .iter()
                .map(|&p| p as u64)
                .collect();
            write(file, "mesh/points", &points, &[m.vertices.len(), 3])?;
            write(file, "mesh/cells", &cells, &[cells.len() / (D + 1), D + 1])?;
            write(file, "mesh/fault_nodes", &fault, &[fault.len()])
        })?;
        let values = point_fields(s);
        let fields: Vec<Field<'_>> = values
            .iter()
            .zip(POINT_FIELDS)
            .map(|(f, (_, _, unit))| Field {
                name: f.name,
                components: f.components,
                unit,
                values: &f.values,
            })
            .collect();
        self.file.append(
            file,
            (s.state.time, s.report.step),
            (m.vertices.len(), &fields),
            &m.frictional_boundary.fault_names,
        )
    }
}

impl<const D: usize> Observer<D> for Hdf5Fields {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<Flow> {
        let times = self.append_frame(s)?;
        self.write_index(s, &times)?;
        Ok(Flow::Continue(()))
    }

    fn name(&self) -> String {
        format!("HDF5 fields {}", self.file.path.display())
    }
}

impl std::fmt::Debug for Hdf5Fields {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hdf5Fields")
            .field("path", &self.file.path)
            .field("mode", &self.file.mode)
            .field("frames", &self.file.frames)
            .finish_non_exhaustive()
    }
}
