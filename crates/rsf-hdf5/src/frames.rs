//! What the fields files share ([`Hdf5Fields`](crate::Hdf5Fields) and
//! [`Hdf5FaultFields`](crate::Hdf5FaultFields)): datasets of frames grown one frame at a
//! time, the cut of the frames after a checkpoint's step, the proof that a file holds a
//! checkpoint's run, the recorded sampling interval and the Xdmf index.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hdf5::{Dataset, Extent, File};
use rsf::checkpoint::Fingerprint;
use rsf::observe::{refuse_existing, FileMode};

use crate::error::{h5_at, show_path, Error, Result};

/// A fields file of frames on one mesh: its path, mode and what a new file records (the
/// run's fingerprint, the sampling interval), whether it holds its mesh yet and its
/// frames so far. The file is open only while a frame is written.
#[derive(Debug)]
pub(crate) struct FramesFile {
    pub path: PathBuf,
    pub mode: FileMode,
    /// The run's fingerprint, recorded in a new file.
    pub fingerprint: Option<Fingerprint>,
    /// The sampling interval recorded in a new file.
    pub every: Option<usize>,
    /// Whether the file holds the mesh (created, or continued after a checkpoint).
    started: bool,
    pub frames: usize,
}

/// One field of a frame: its name, components per point (3 or 1), unit and values
/// (point-major).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Field<'a> {
    pub name: &'a str,
    pub components: usize,
    pub unit: &'a str,
    pub values: &'a [f64],
}

impl FramesFile {
    /// The file `path`, new or continued after a checkpoint of step `step`
    /// ([`FileMode::Resume`]: the frames after it cut).
    ///
    /// # Errors
    /// As [`Hdf5Fields::new`](crate::Hdf5Fields::new).
    pub fn new(path: PathBuf, mode: FileMode) -> Result<Self> {
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
        let (started, frames) = match mode {
            FileMode::Resume { step } => (true, cut_frames(&path, step)?),
            _ => (false, 0),
        };
        Ok(Self {
            path,
            mode,
            fingerprint: None,
            every: None,
            started,
            frames,
        })
    }

    /// The file `path` continued after the checkpoint `c` once it shows that it holds
    /// its run ([`prove_run`]; a checkpoint of step 0 needs no proof).
    ///
    /// # Errors
    /// As [`Hdf5Fields::continue_run`](crate::Hdf5Fields::continue_run).
    pub fn continue_run(path: PathBuf, c: &rsf::Checkpoint, allowed: &[&str]) -> Result<Self> {
        let step = c.state.step;
        if step > 0 {
            prove_run(&path, c, allowed)?;
        }
        let mut file = Self::new(path, FileMode::Resume { step })?;
        file.fingerprint = Some(c.fingerprint.clone());
        Ok(file)
    }

    /// The file open for this frame: created at the first frame with the groups `mesh`
    /// (`mesh` writes it) and `fields`, the fingerprint and the interval.
    pub fn open(&mut self, mesh: impl FnOnce(&File) -> hdf5::Result<()>) -> Result<File> {
        let path = self.path.clone();
        if self.started {
            return File::open_rw(&path).map_err(h5_at("open the HDF5 file", &path));
        }
        let file = File::create(&path).map_err(h5_at("create the HDF5 file", &path))?;
        let err = h5_at("write the mesh into the HDF5 file", &path);
        file.create_group("mesh").map_err(&err)?;
        mesh(&file).map_err(&err)?;
        file.create_group("fields").map_err(&err)?;
        if let Some(fingerprint) = &self.fingerprint {
            let pairs = serde_json::to_string(&fingerprint.0)
                .map_err(|e| err(hdf5::Error::from(e.to_string())))?;
            crate::attributes::text(&file, "fingerprint", &pairs).map_err(&err)?;
        }
        if let Some(every) = self.every {
            record_every(&file, every).map_err(&err)?;
        }
        self.started = true;
        Ok(file)
    }

    /// Appends a frame at `(time, step)` of `fields` on `n` points to `file` (this file,
    /// open), closes it; the times of all its frames. The field `fault` gets the attribute
    /// `fault_names` (a JSON list).
    pub fn append(
        &mut self,
        file: File,
        (time, step): (f64, usize),
        (n, fields): (usize, &[Field<'_>]),
        fault_names: &[String],
    ) -> Result<Vec<f64>> {
        let frame = self.frames;
        let path = self.path.clone();
        let err = h5_at("write a frame into the HDF5 file", &path);
        let times = frames_dataset::<f64>(&file, "time", &[]).map_err(&err)?;
        append(&times, frame, &[time], &[]).map_err(&err)?;
        let steps = frames_dataset::<u64>(&file, "step", &[]).map_err(&err)?;
        append(&steps, frame, &[step as u64], &[]).map_err(&err)?;
        for f in fields {
            let tail: Vec<usize> = if f.components == 3 {
                vec![n, 3]
            } else {
                vec![n]
            };
            let d =
                frames_dataset::<f64>(&file, &format!("fields/{}", f.name), &tail).map_err(&err)?;
            if frame == 0 {
                crate::attributes::text(&d, "unit", f.unit).map_err(&err)?;
                if f.name == "fault" {
                    // The names the field's values index, as a JSON list of strings.
                    let names = serde_json::to_string(fault_names)
                        .map_err(|e| err(hdf5::Error::from(e.to_string())))?;
                    crate::attributes::text(&d, "fault_names", &names).map_err(&err)?;
                }
            }
            append(&d, frame, f.values, &tail).map_err(&err)?;
        }
        let all = times.read_raw().map_err(&err)?;
        // Every handle closed before the file (so that it is closed on disk).
        drop((times, steps));
        file.close().map_err(&err)?;
        self.frames += 1;
        Ok(all)
    }
}

/// The cells of a fields file's mesh as its Xdmf index names them.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Topology<'a> {
    /// The Xdmf `TopologyType` (`Polyline` and `Polyvertex` with `corners` points per cell).
    pub kind: &'a str,
    /// Number of cells.
    pub cells: usize,
    /// Vertices per cell.
    pub corners: usize,
}

/// Rewrites the Xdmf index of the fields file `path` (the index: `path` with the
/// extension `.xmf`) for the frames at `times`: a temporal collection of one grid per
/// frame, each the mesh (`/mesh/cells` of `topology`, `/mesh/points` of `points` vertices)
/// and, per field `(name, components)`, the frame's slab of `/fields/NAME` (a HyperSlab
/// item: Xdmf 3, what ParaView's and VTK's Xdmf3 readers read).
pub(crate) fn write_index(
    path: &Path,
    topology: &Topology<'_>,
    points: usize,
    times: &[f64],
    fields: &[(&str, usize)],
) -> Result<()> {
    let h5 = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let (n, k) = (points, times.len());
    let Topology {
        kind,
        cells,
        corners,
    } = *topology;
    // Poly-lines and poly-vertices say how many points each cell has.
    let per_cell = if kind.starts_with("Poly") {
        format!("\" NodesPerElement=\"{corners}")
    } else {
        String::new()
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
             <Topology TopologyType=\"{kind}{per_cell}\" NumberOfElements=\"{cells}\">\n          \
             <DataItem Dimensions=\"{cells} {corners}\" NumberType=\"UInt\" Precision=\"8\" \
             Format=\"HDF\">{h5}:/mesh/cells</DataItem>\n        </Topology>\n        \
             <Geometry GeometryType=\"XYZ\">\n          \
             <DataItem Dimensions=\"{n} 3\" NumberType=\"Float\" Precision=\"8\" \
             Format=\"HDF\">{h5}:/mesh/points</DataItem>\n        </Geometry>\n"
        );
        for &(name, c) in fields {
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
        &path.with_extension("xmf"),
        x.as_bytes(),
    )?)
}

/// Opens the fields file `path` of an interrupted run and cuts the frames after step
/// `step` (`/time`, `/step` and every `/fields/NAME`); the frames kept.
///
/// # Errors
/// [`Error::Resume`] naming the file: missing, or not a fields file.
pub(crate) fn cut_frames(path: &Path, step: usize) -> Result<usize> {
    let fail_h5 = |e: hdf5::Error| Error::Resume {
        path: show_path(path),
        reason: e.to_string(),
    };
    let file = File::open_rw(path).map_err(fail_h5)?;
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
    Ok(keep)
}

/// The attribute `every` of a fields file: the steps between its frames, where the
/// writer was told ([`record_every`]).
const EVERY: &str = "every";

/// Records the sampling interval `every` (steps between frames) as the attribute `every`
/// of `/` of the new file `file`.
pub(crate) fn record_every(file: &File, every: usize) -> hdf5::Result<()> {
    file.new_attr::<u64>()
        .shape(())
        .create(EVERY)?
        .write_scalar(&(every as u64))
}

/// Refuses to continue the fields file `path` with frames every `every` steps if it
/// records another interval (a file of frames at two spacings); a file that records none
/// is not refused.
///
/// # Errors
/// [`Error::Resume`] naming the file and both intervals; the file cannot be read.
#[cfg_attr(not(feature = "programs"), allow(dead_code))]
pub(crate) fn check_every(path: &Path, every: usize) -> Result<()> {
    let fail_h5 = |e: hdf5::Error| Error::Resume {
        path: show_path(path),
        reason: e.to_string(),
    };
    let file = File::open(path).map_err(fail_h5)?;
    if !file
        .attr_names()
        .map_err(fail_h5)?
        .iter()
        .any(|n| n == EVERY)
    {
        return Ok(());
    }
    let recorded: u64 = file
        .attr(EVERY)
        .and_then(|a| a.read_scalar())
        .map_err(fail_h5)?;
    if recorded as usize != every {
        return Err(Error::Resume {
            path: show_path(path),
            reason: format!(
                "its frames are every {recorded} steps, the resumed run's every {every}: \
                 resume with the interval of the file (--hdf5 {recorded}), or write the \
                 resumed run's fields to a new file"
            ),
        });
    }
    Ok(())
}

/// Checks that the fields file `path` holds the run of the checkpoint `c` (step > 0): its
/// frame of `c`'s step at `c`'s time with `c`'s state on Γ_F (`fields/state_alpha` at
/// `mesh/fault_nodes`), bit for bit ([`Hdf5Fields::continue_run`](crate::Hdf5Fields::continue_run), [`Hdf5FaultFields::continue_run`](crate::Hdf5FaultFields::continue_run)).
pub(crate) fn prove_run(
    path: &std::path::Path,
    c: &rsf::Checkpoint,
    allowed: &[&str],
) -> Result<()> {
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
pub(crate) fn write<T: hdf5::H5Type>(
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
pub(crate) fn frames_dataset<T: hdf5::H5Type>(
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
pub(crate) fn append<T: hdf5::H5Type>(
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
