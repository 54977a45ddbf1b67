//! The fields of a run in one HDF5 file with an Xdmf index (feature `hdf5`, through the
//! `hdf5-metno` binding of the HDF5 C library): the mesh once, one time axis, each field
//! one dataset over (time, vertex[, component]) — what h5py and xarray read directly and
//! ParaView opens through the `.xmf` file.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hdf5::{Dataset, Extent, File};

use crate::error::{show_path, Error, Result};

use super::fields::point_fields;
use super::files::FileMode;
use super::{Flow, Observer, StepView};

/// Writes the fields of every step it is shown (wrap it in
/// [`Every`](crate::observe::Every) to sample) into one HDF5 file `path` and rewrites the
/// Xdmf index `path` with the extension `.xmf` after every frame (so an interrupted run
/// leaves a usable index). The file holds
///
/// - `/mesh/points` (vertices × 3, m; zero-padded in 2-D), `/mesh/cells` (cells × (D + 1),
///   vertex indices, `u64`), `/mesh/fault_nodes` (the vertices of Γ_F in fault order) —
///   written at the first frame;
/// - `/time` (frames, s) and `/step` (frames, `u64`): the time axis;
/// - `/fields/NAME` (frames × vertices × 3 for vectors, frames × vertices for scalars): the
///   point data of the VTU frames ([`VtuFrames`](crate::observe::VtuFrames)) with the same
///   names, units and values — `displacement` (m), `velocity` (m/s), `slip` (m), Cartesian
///   3-vectors; `slip_rate` (m/s), `state_alpha` (α = ln θ, θ in s), `shear_traction` and
///   `normal_traction` (Pa) on Γ_F, NaN at the other vertices.
///
/// The datasets are chunked one frame per chunk and grow by one frame per frame. The file
/// is open only while a frame is written (HDF5 locks an open file): between frames h5py
/// and ParaView read it, and an interrupted run leaves a closed, consistent file.
/// [`FileMode::Resume`] continues after a checkpoint: frames of later steps are cut off,
/// so the file ends as an uninterrupted run's.
pub struct Hdf5Fields {
    path: PathBuf,
    mode: FileMode,
    /// Whether the file holds the mesh (created, or continued after a checkpoint).
    started: bool,
    frames: usize,
}

/// An HDF5 error on `path` as a file error naming it.
fn h5<'a>(path: &'a Path, action: &'static str) -> impl Fn(hdf5::Error) -> Error + 'a {
    move |e| Error::File {
        path: show_path(path),
        action,
        source: std::io::Error::other(e.to_string()),
    }
}

impl Hdf5Fields {
    /// Fields into `path` (e.g. `out/fields.h5`; the index is `out/fields.xmf`), new or
    /// continued after a checkpoint of step `step` ([`FileMode::Resume`]).
    ///
    /// # Errors
    /// [`Error::FileExists`] for [`FileMode::Create`] if `path` exists and is not empty;
    /// [`Error::Resume`] for [`FileMode::Resume`] if `path` is missing or is not such a file;
    /// [`Error::InvalidParameter`] if `path` ends in `.xmf` (the index's name).
    pub fn new(path: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        let path = path.into();
        if path.extension().is_some_and(|e| e == "xmf") {
            return Err(crate::error::invalid(
                "hdf5 path",
                format!(
                    "{}: the Xdmf index takes the name with .xmf",
                    path.display()
                ),
            ));
        }
        if mode == FileMode::Create {
            super::files::refuse_existing(&path)?;
        }
        let mut fields = Self {
            path,
            mode,
            started: false,
            frames: 0,
        };
        if let FileMode::Resume { step } = mode {
            fields.resume(step)?;
        }
        Ok(fields)
    }

    /// The Xdmf index's path: the file's with the extension `.xmf`.
    pub fn index_path(&self) -> PathBuf {
        self.path.with_extension("xmf")
    }

    /// Opens the file of an interrupted run and cuts the frames after step `step`.
    fn resume(&mut self, step: usize) -> Result<()> {
        let fail = |reason: String| Error::Resume {
            path: show_path(&self.path),
            reason,
        };
        let fail_h5 = |e: hdf5::Error| fail(e.to_string());
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
        if self.started {
            return File::open_rw(&self.path).map_err(h5(&self.path, "open the HDF5 file"));
        }
        {
            let path = self.path.clone();
            let file = File::create(&path).map_err(h5(&path, "create the HDF5 file"))?;
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
            let write = |name: &str, data: ndarray::ArrayViewD<'_, f64>| {
                file.new_dataset_builder()
                    .with_data(data)
                    .create(name)
                    .map(|_| ())
            };
            let write_u64 = |name: &str, data: ndarray::ArrayViewD<'_, u64>| {
                file.new_dataset_builder()
                    .with_data(data)
                    .create(name)
                    .map(|_| ())
            };
            let err = h5(&path, "write the mesh into the HDF5 file");
            file.create_group("mesh").map_err(&err)?;
            write("mesh/points", view(&points, &[m.vertices.len(), 3])).map_err(&err)?;
            write_u64("mesh/cells", view(&cells, &[cells.len() / (D + 1), D + 1])).map_err(&err)?;
            write_u64("mesh/fault_nodes", view(&fault, &[fault.len()])).map_err(&err)?;
            file.create_group("fields").map_err(&err)?;
            self.started = true;
            Ok(file)
        }
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
            for (name, c, _) in FIELDS {
                let (kind, dims, slab) = if *c == 3 {
                    ("Vector", format!("{n} 3"), format!("{i} 0 0 1 1 1 1 {n} 3"))
                } else {
                    ("Scalar", format!("{n}"), format!("{i} 0 1 1 1 {n}"))
                };
                let rank = if *c == 3 { 3 } else { 2 };
                let full = if *c == 3 {
                    format!("{k} {n} 3")
                } else {
                    format!("{k} {n}")
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
        crate::checkpoint::write_atomically(&self.index_path(), x.as_bytes())
    }
}

/// The fields' names and components, in the order of [`point_fields`] (checked there).
const FIELDS: &[(&str, usize, ())] = &[
    ("displacement", 3, ()),
    ("velocity", 3, ()),
    ("slip_rate", 1, ()),
    ("state_alpha", 1, ()),
    ("slip", 3, ()),
    ("shear_traction", 1, ()),
    ("normal_traction", 1, ()),
];

/// `data` as an array view of `shape`.
fn view<'a, T>(data: &'a [T], shape: &[usize]) -> ndarray::ArrayViewD<'a, T> {
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
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let frame = self.frames;
        let path = self.path.clone();
        let err = h5(&path, "write a frame into the HDF5 file");
        let fields = point_fields(s);
        let n = s.model.vertices.len();
        let times: Vec<f64> = {
            let file = self.open(s)?;
            let time = frames_dataset::<f64>(&file, "time", &[]).map_err(&err)?;
            append(&time, frame, &[s.state.time], &[]).map_err(&err)?;
            let step = frames_dataset::<u64>(&file, "step", &[]).map_err(&err)?;
            append(&step, frame, &[s.report.step as u64], &[]).map_err(&err)?;
            for ((name, c, data), (expected, ec, ())) in fields.iter().zip(FIELDS) {
                debug_assert_eq!((name, c), (expected, ec));
                let tail: Vec<usize> = if *c == 3 { vec![n, 3] } else { vec![n] };
                let d =
                    frames_dataset::<f64>(&file, &format!("fields/{name}"), &tail).map_err(&err)?;
                append(&d, frame, data, &tail).map_err(&err)?;
            }
            let times = time.read_raw().map_err(&err)?;
            // Every handle closed before the file (so that it is closed on disk).
            drop((time, step));
            file.close().map_err(&err)?;
            times
        };
        self.frames += 1;
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
