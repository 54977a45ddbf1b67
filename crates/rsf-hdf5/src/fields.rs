//! The fields of a run in one HDF5 file with an Xdmf index: the mesh once, one time axis,
//! each field one dataset over (time, vertex[, component]) — what h5py and xarray read
//! directly and ParaView opens through the `.xmf` file.

use std::fmt::Write as _;
use std::path::PathBuf;

use hdf5::{Dataset, Extent, File};
use rsf::checkpoint::Fingerprint;
use rsf::observe::{point_fields, refuse_existing, FileMode, POINT_FIELDS};
use rsf::{Flow, Observer, StepView};

use crate::error::{h5_at, show_path, Error, Result};

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
    path: PathBuf,
    mode: FileMode,
    /// The run's fingerprint, recorded in a new file ([`fingerprint`](Self::fingerprint)).
    fingerprint: Option<Fingerprint>,
    /// Whether the file holds the mesh (created, or continued after a checkpoint).
    started: bool,
    frames: usize,
}

impl Hdf5Fields {
    /// Fields into `path` (e.g. `out/fields.h5`; the index is `out/fields.xmf`), new or
    /// continued after a checkpoint of step `step` ([`FileMode::Resume`]).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] if `path` ends in `.xmf` (the index's name);
    /// [`rsf::Error::FileExists`] (as [`Error::Rsf`]) for [`FileMode::Create`] if `path`
    /// exists and is not empty; [`Error::Resume`] for [`FileMode::Resume`] if `path` is
    /// missing or is not such a file.
    pub fn new(path: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        let path = path.into();
        if path.extension().is_some_and(|e| e == "xmf") {
            return Err(Error::InvalidParameter {
                name: "hdf5 path".into(),
                reason: format!(
                    "{}: the Xdmf index takes the name with .xmf",
                    show_path(&path)
                ),
            });
        }
        if mode == FileMode::Create {
            refuse_existing(&path)?;
        }
        let mut fields = Self {
            path,
            mode,
            fingerprint: None,
            started: false,
            frames: 0,
        };
        if let FileMode::Resume { step } = mode {
            fields.resume(step)?;
        }
        Ok(fields)
    }

    /// The fields file of a run whose checkpoints carry `fingerprint`: a new file records
    /// it (the attribute `fingerprint` of `/`, JSON pairs `[field, value]`), so that a
    /// resume can tell the file's run ([`continue_run`](Self::continue_run)).
    pub fn fingerprint(mut self, fingerprint: Fingerprint) -> Self {
        self.fingerprint = Some(fingerprint);
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
    /// [`Error::Resume`] naming the file: missing or not such a file; another run's
    /// fingerprint; no frame at the checkpoint's step (write checkpoints at frame steps); a
    /// frame of another time or state (another run's file) — nothing in the file changed
    /// then.
    pub fn continue_run(
        path: impl Into<PathBuf>,
        c: &rsf::Checkpoint,
        allowed: &[&str],
    ) -> Result<Self> {
        let path = path.into();
        let step = c.state.step;
        if step > 0 {
            prove_run(&path, c, allowed)?;
        }
        Ok(Self::new(path, FileMode::Resume { step })?.fingerprint(c.fingerprint.clone()))
    }

    /// The Xdmf index's path: the file's with the extension `.xmf`.
    pub fn index_path(&self) -> PathBuf {
        self.path.with_extension("xmf")
    }

    /// Opens the file of an interrupted run and cuts the frames after step `step`.
    fn resume(&mut self, step: usize) -> Result<()> {
        let fail_h5 = |e: hdf5::Error| Error::Resume {
            path: show_path(&self.path),
            reason: e.to_string(),
        };
        let file = File::open_rw(&self.path).map_err(fail_h5)?;
        let steps: Vec<u64> = file
            .dataset("step")
            .and_then(|d| d.read_raw())
            .map_err(fail_h5)?;
        let keep = steps.iter().take_while(|&&s| s as usize <= step).count();
        let mut names = vec!["time".to_owned(), "step".to_owned()];
        let group = file.group("fields").map_err(fail_h5)?;
        for n in group.member_names().map_err(fail_h5)? {
            names.push(format!("fields/{n}"));
        }
        drop(group);
        for n in names {
            let d = file.dataset(&n).map_err(fail_h5)?;
            let mut shape = d.shape();
            shape[0] = keep;
            d.resize(shape).map_err(fail_h5)?;
        }
        file.close().map_err(fail_h5)?;
        self.frames = keep;
        self.started = true;
        Ok(())
    }

    /// The file open for this frame: created with the mesh at the first frame.
    fn open<const D: usize>(&mut self, s: &StepView<'_, D>) -> Result<File> {
        let path = self.path.clone();
        if self.started {
            return File::open_rw(&path).map_err(h5_at("open the HDF5 file", &path));
        }
        let file = File::create(&path).map_err(h5_at("create the HDF5 file", &path))?;
        let m = s.model;
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
        let err = h5_at("write the mesh into the HDF5 file", &path);
        file.create_group("mesh").map_err(&err)?;
        write(&file, "mesh/points", &points, &[m.vertices.len(), 3]).map_err(&err)?;
        write(&file, "mesh/cells", &cells, &[cells.len() / (D + 1), D + 1]).map_err(&err)?;
        write(&file, "mesh/fault_nodes", &fault, &[fault.len()]).map_err(&err)?;
        file.create_group("fields").map_err(&err)?;
        if let Some(fingerprint) = &self.fingerprint {
            let pairs = serde_json::to_string(&fingerprint.0)
                .map_err(|e| err(hdf5::Error::from(e.to_string())))?;
            crate::attributes::text(&file, "fingerprint", &pairs).map_err(&err)?;
        }
        self.started = true;
        Ok(file)
    }

    /// Rewrites the Xdmf index for the frames so far.
    fn write_index<const D: usize>(&self, s: &StepView<'_, D>, times: &[f64]) -> Result<()> {
        let m = s.model;
        let h5 = self
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let (n, k, cells) = (m.vertices.len(), times.len(), m.cells.len() / (D + 1));
        let topology = match D {
            1 => "Polyline\" NodesPerElement=\"2",
            2 => "Triangle",
            _ => "Tetrahedron",
        };
        let mut x = String::from(
            "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    \
             <Grid Name=\"rsf\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
        );
        for (i, t) in times.iter().enumerate() {
            let _ = write!(
                x,
                "      <Grid Name=\"frame {i}\" GridType=\"Uniform\">\n        \
                 <Time Value=\"{t:.17e}\"/>\n        \
                 <Topology TopologyType=\"{topology}\" NumberOfElements=\"{cells}\">\n          \
                 <DataItem Dimensions=\"{cells} {}\" NumberType=\"UInt\" Precision=\"8\" \
                 Format=\"HDF\">{h5}:/mesh/cells</DataItem>\n        </Topology>\n        \
                 <Geometry GeometryType=\"XYZ\">\n          \
                 <DataItem Dimensions=\"{n} 3\" NumberType=\"Float\" Precision=\"8\" \
                 Format=\"HDF\">{h5}:/mesh/points</DataItem>\n        </Geometry>\n",
                D + 1
            );
            for (name, c, _) in POINT_FIELDS {
                let (kind, dims, slab, rank, full) = if c == 3 {
                    let slab = format!("{i} 0 0 1 1 1 1 {n} 3");
                    ("Vector", format!("{n} 3"), slab, 3, format!("{k} {n} 3"))
                } else {
                    let slab = format!("{i} 0 1 1 1 {n}");
                    ("Scalar", format!("{n}"), slab, 2, format!("{k} {n}"))
                };
                let _ = write!(
                    x,
                    "        <Attribute Name=\"{name}\" AttributeType=\"{kind}\" Center=\"Node\">\n          \
                     <DataItem ItemType=\"HyperSlab\" Dimensions=\"{dims}\" Type=\"HyperSlab\">\n            \
                     <DataItem Dimensions=\"3 {rank}\" Format=\"XML\">{slab}</DataItem>\n            \
                     <DataItem Dimensions=\"{full}\" NumberType=\"Float\" Precision=\"8\" \
                     Format=\"HDF\">{h5}:/fields/{name}</DataItem>\n          </DataItem>\n        \
                     </Attribute>\n"
                );
            }
            x.push_str("      </Grid>\n");
        }
        x.push_str("    </Grid>\n  </Domain>\n</Xdmf>\n");
        Ok(rsf::checkpoint::write_atomically(
            &self.index_path(),
            x.as_bytes(),
        )?)
    }

    /// Appends the frame of `s` to the file (created at the first frame); the times of
    /// all its frames.
    fn append_frame<const D: usize>(&mut self, s: &StepView<'_, D>) -> Result<Vec<f64>> {
        let frame = self.frames;
        let path = self.path.clone();
        let err = h5_at("write a frame into the HDF5 file", &path);
        let fields = point_fields(s);
        let n = s.model.vertices.len();
        let file = self.open(s)?;
        let time = frames_dataset::<f64>(&file, "time", &[]).map_err(&err)?;
        append(&time, frame, &[s.state.time], &[]).map_err(&err)?;
        let step = frames_dataset::<u64>(&file, "step", &[]).map_err(&err)?;
        append(&step, frame, &[s.report.step as u64], &[]).map_err(&err)?;
        for (f, (_, _, unit)) in fields.iter().zip(POINT_FIELDS) {
            let tail: Vec<usize> = if f.components == 3 {
                vec![n, 3]
            } else {
                vec![n]
            };
            let name = format!("fields/{}", f.name);
            let d = frames_dataset::<f64>(&file, &name, &tail).map_err(&err)?;
            if frame == 0 {
                crate::attributes::text(&d, "unit", unit).map_err(&err)?;
                if f.name == "fault" {
                    // The names the field's values index, as a JSON list of strings.
                    let names = serde_json::to_string(&s.model.frictional_boundary.fault_names)
                        .map_err(|e| err(hdf5::Error::from(e.to_string())))?;
                    crate::attributes::text(&d, "fault_names", &names).map_err(&err)?;
                }
            }
            append(&d, frame, &f.values, &tail).map_err(&err)?;
        }
        let times = time.read_raw().map_err(&err)?;
        // Every handle closed before the file (so that it is closed on disk).
        drop((time, step));
        file.close().map_err(&err)?;
        self.frames += 1;
        Ok(times)
    }
}

/// Checks that the fields file `path` holds the run of the checkpoint `c` (step > 0): its
/// frame of `c`'s step at `c`'s time with `c`'s state on Γ_F (`fields/state_alpha` at
/// `mesh/fault_nodes`), bit for bit ([`Hdf5Fields::continue_run`]).
fn prove_run(path: &std::path::Path, c: &rsf::Checkpoint, allowed: &[&str]) -> Result<()> {
    let refuse = |reason: String| Error::Resume {
        path: show_path(path),
        reason,
    };
    let fail_h5 = |e: hdf5::Error| refuse(e.to_string());
    let (step, time) = (c.state.step, c.state.time);
    let file = File::open(path).map_err(fail_h5)?;
    if let Some(text) = crate::attributes::read_text(&file, "fingerprint").map_err(fail_h5)? {
        let pairs: Vec<(String, String)> = serde_json::from_str(&text)
            .map_err(|e| refuse(format!("its attribute `fingerprint`: {e}")))?;
        if let Err(e) = c.fingerprint.check(&Fingerprint(pairs), allowed) {
            return Err(refuse(format!(
                "it holds the fields of another run than the checkpoint's ({e}); write the \
                 resumed run's fields to a new file"
            )));
        }
    }
    let steps: Vec<u64> = file
        .dataset("step")
        .and_then(|d| d.read_raw())
        .map_err(fail_h5)?;
    let Some(frame) = steps.iter().position(|&s| s as usize == step) else {
        return Err(refuse(format!(
            "it has no frame of the checkpoint's step {step} (its frames: {} of steps {}–{}),              so it cannot show that it holds the checkpoint's run: resume from a checkpoint              written at a frame's step (a multiple of the frame interval)",
            steps.len(),
            steps.first().copied().unwrap_or(0),
            steps.last().copied().unwrap_or(0)
        )));
    };
    let times: Vec<f64> = file
        .dataset("time")
        .and_then(|d| d.read_raw())
        .map_err(fail_h5)?;
    let at = times.get(frame).copied().unwrap_or(f64::NAN);
    if at.to_bits() != time.to_bits() {
        return Err(refuse(format!(
            "its frame of step {step} is at t = {at:e} s, the checkpoint's at t = {time:e} s:              the file holds another run; write the resumed run's fields to a new file"
        )));
    }
    let nodes: Vec<u64> = file
        .dataset("mesh/fault_nodes")
        .and_then(|d| d.read_raw())
        .map_err(fail_h5)?;
    let alpha: Vec<f64> = file
        .dataset("fields/state_alpha")
        .and_then(|d| {
            let row: Vec<hdf5::SliceOrIndex> = vec![frame.into(), (..).into()];
            d.read_slice_1d(hdf5::Hyperslab::from(row))
        })
        .map_err(fail_h5)?
        .to_vec();
    let same = nodes.len() == c.state.alpha.len()
        && nodes.iter().zip(&c.state.alpha).all(|(&n, a)| {
            alpha
                .get(n as usize)
                .is_some_and(|x| x.to_bits() == a.to_bits())
        });
    if !same {
        return Err(refuse(format!(
            "its frame of step {step} holds another state on the fault than the checkpoint:              the file holds another run; write the resumed run's fields to a new file"
        )));
    }
    Ok(())
}

/// Writes `data` (of `shape`) as the new dataset `name` of `file`.
fn write<T: hdf5::H5Type>(
    file: &File,
    name: &str,
    data: &[T],
    shape: &[usize],
) -> hdf5::Result<()> {
    file.new_dataset_builder()
        .with_data(view(data, shape))
        .create(name)
        .map(|_| ())
}

/// `data` as an array view of `shape`.
pub(crate) fn view<'a, T>(data: &'a [T], shape: &[usize]) -> ndarray::ArrayViewD<'a, T> {
    ndarray::ArrayViewD::from_shape(ndarray::IxDyn(shape), data).expect("the shape of the data")
}

/// Dataset `name` of frames of `tail` (its shape after the frame axis), created
/// resizable on first use.
fn frames_dataset<T: hdf5::H5Type>(
    file: &File,
    name: &str,
    tail: &[usize],
) -> hdf5::Result<Dataset> {
    if let Ok(d) = file.dataset(name) {
        return Ok(d);
    }
    let mut shape = vec![Extent::resizable(0)];
    shape.extend(tail.iter().map(|&n| Extent::fixed(n)));
    let mut chunk = vec![1];
    chunk.extend_from_slice(tail);
    file.new_dataset::<T>()
        .chunk(chunk)
        .shape(shape)
        .create(name)
}

/// Appends `data` (one frame, shape `tail`) as frame `frame` of `d`.
fn append<T: hdf5::H5Type>(
    d: &Dataset,
    frame: usize,
    data: &[T],
    tail: &[usize],
) -> hdf5::Result<()> {
    let mut shape = vec![frame + 1];
    shape.extend_from_slice(tail);
    d.resize(shape.clone())?;
    let mut one = vec![1];
    one.extend_from_slice(tail);
    let sel: Vec<hdf5::SliceOrIndex> = std::iter::once((frame..frame + 1).into())
        .chain(tail.iter().map(|_| (..).into()))
        .collect();
    d.write_slice(view(data, &one), hdf5::Hyperslab::from(sel))
}

impl<const D: usize> Observer<D> for Hdf5Fields {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<Flow> {
        let times = self.append_frame(s)?;
        self.write_index(s, &times)?;
        Ok(Flow::Continue(()))
    }

    fn name(&self) -> String {
        format!("HDF5 fields {}", self.path.display())
    }
}

impl std::fmt::Debug for Hdf5Fields {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Hdf5Fields")
            .field("path", &self.path)
            .field("mode", &self.mode)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}
