//! The fault's own fields of a run in one HDF5 file with an Xdmf index: the fault's nodes
//! and cells once, one time axis, each field one dataset over (time, node[, component]) —
//! also for a run without a volume mesh (a fault alone on a boundary-element kernel).

use std::collections::BTreeSet;
use std::path::PathBuf;

use rsf::checkpoint::Fingerprint;
use rsf::observe::FileMode;
use rsf::{Flow, Model, Observer, StepView};

use crate::error::Result;
use crate::fields::Hdf5Fields;
use crate::frames::{write, write_index, Field, Topology};

/// The fields of [`Hdf5FaultFields`], in the file's order: name, components (3: a
/// Cartesian 3-vector; 1: a scalar) and unit (SI, the attribute `unit` of each dataset).
///
/// - `slip` (m): the displacement jump since the initial state,
///   [`StepView::slip`](rsf::observe::StepView::slip), Cartesian; zero-padded to 3
///   components in 2-D, `(0, 0, s)` for an antiplane model (its one component is out of
///   the plane, z);
/// - `slip_rate` (m/s), `state_alpha` (α = ln θ, θ in s), `shear_traction` and
///   `normal_traction` (Pa; NaN where the law has no `σ̄_n`) — what the VTU frames hold on
///   Γ_F ([`rsf::observe::POINT_FIELDS`]);
/// - `fault`: the node's fault, an index into the model's `frictional_boundary.fault_names`
///   (the dataset's attribute `fault_names`).
pub const FAULT_FIELDS: [(&str, usize, &str); 6] = [
    ("slip", 3, "m"),
    ("slip_rate", 1, "m/s"),
    ("state_alpha", 1, "1"),
    ("shear_traction", 1, "Pa"),
    ("normal_traction", 1, "Pa"),
    ("fault", 1, "1"),
];

/// Writes the fault's fields (the frictional nodes of Γ_F, in fault order) of every step
/// it is shown (wrap it in [`rsf::observe::Every`] to sample) into one HDF5 file `path`, and
/// rewrites the Xdmf index `path` with the extension `.xmf` after every frame. The file
/// holds
///
/// - `/mesh/points` (nodes × 3, m; zero-padded in 2-D): the fault's nodes in fault order
///   (node `k` is the model's vertex `/mesh/vertex[k]`); `/mesh/fault_nodes` (`0…m−1`: every
///   point is on Γ_F, so that the file proves a run as [`crate::Hdf5Fields`]' does);
/// - `/mesh/cells` (`u64`, indices into the points), attribute `topology`: in 2-D the
///   fault's segments (`Polyline`, 2 nodes, consecutive nodes along Γ_F of one fault); in
///   3-D the triangles of the volume's tetrahedra on Γ_F (`Triangle`); on a model without
///   cells (a fault alone, whose nodes are the centres of its elements) one poly-vertex per
///   node (`Polyvertex`);
/// - `/time` (frames, s) and `/step` (frames, `u64`): the time axis;
/// - `/fields/NAME` (frames × nodes × 3, or frames × nodes), attribute `unit`: the fields of
///   [`FAULT_FIELDS`].
///
/// Resumable as [`crate::Hdf5Fields`] ([`FileMode::Resume`],
/// [`continue_run`](Self::continue_run)); the file is open only while a frame is written.
///
/// ```no_run
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// use rsf::observe::{Every, FileMode, Interval};
/// let fields = rsf_hdf5::Hdf5FaultFields::new("out/fields.h5", FileMode::Create)?;
/// let mut fields = Every::new(Interval::Steps(10), fields)?;
/// // sim.run(…, &mut [&mut fields]) on any model: out/fields.h5 and out/fields.xmf
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct Hdf5FaultFields {
    /// The file, new or continued, as an [`Hdf5Fields`]' (its fingerprint, interval and
    /// resume); its frames hold the fault's fields.
    fields: Hdf5Fields,
    /// The fault's cells (indices into its nodes), made at the first frame.
    topology: Option<(String, usize, Vec<u64>)>,
}

impl Hdf5FaultFields {
    /// The fault's fields in the file of `fields`.
    fn of(fields: Hdf5Fields) -> Self {
        Self {
            fields,
            topology: None,
        }
    }

    /// The fault's fields into `path` (the index: `path` with `.xmf`), new or continued
    /// after a checkpoint of step `step` ([`FileMode::Resume`]).
    ///
    /// # Errors
    /// As [`Hdf5Fields::new`].
    pub fn new(path: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        Hdf5Fields::new(path, mode).map(Self::of)
    }

    /// The file of a run whose checkpoints carry `fingerprint` (recorded in a new file, as
    /// [`Hdf5Fields::fingerprint`]).
    pub fn fingerprint(self, fingerprint: Fingerprint) -> Self {
        Self {
            fields: self.fields.fingerprint(fingerprint),
            ..self
        }
    }

    /// The file of a run that shows it every `every` steps (recorded in a new file, as
    /// [`Hdf5Fields::every`]).
    pub fn every(self, every: usize) -> Self {
        Self {
            fields: self.fields.every(every),
            ..self
        }
    }

    /// The file `path` continued after the checkpoint `c` once it shows that it holds the
    /// checkpoint's run: as [`Hdf5Fields::continue_run`] (its fingerprint, and its
    /// frame of the checkpoint's step at the checkpoint's time and state, bit for bit).
    ///
    /// # Errors
    /// As [`Hdf5Fields::continue_run`].
    pub fn continue_run(
        path: impl Into<PathBuf>,
        c: &rsf::Checkpoint,
        allowed: &[&str],
    ) -> Result<Self> {
        Hdf5Fields::continue_run(path, c, allowed).map(Self::of)
    }

    /// The Xdmf index's path: the file's with the extension `.xmf`.
    pub fn index_path(&self) -> PathBuf {
        self.fields.index_path()
    }

    /// Appends the frame of `s` (the file created with the fault's mesh at the first
    /// frame); the times of all its frames.
    fn append_frame<const D: usize, const C: usize>(
        &mut self,
        s: &StepView<'_, D, C>,
    ) -> Result<Vec<f64>> {
        let m = s.model;
        let nodes = &m.frictional_boundary.nodes;
        let n = nodes.len();
        let (kind, corners, cells) = self.topology.get_or_insert_with(|| fault_cells(m));
        let (corners, cells) = (*corners, &*cells);
        let file = self.fields.file.open(|file| {
            let mut points = vec![0.0; 3 * n];
            for (k, &p) in nodes.iter().enumerate() {
                points[3 * k..3 * k + D].copy_from_slice(&m.vertices[p]);
            }
            let vertex: Vec<u64> = nodes.iter().map(|&p| p as u64).collect();
            let all: Vec<u64> = (0..n as u64).collect();
            write(file, "mesh/points", &points, &[n, 3])?;
            write(file, "mesh/vertex", &vertex, &[n])?;
            write(file, "mesh/fault_nodes", &all, &[n])?;
            write(file, "mesh/cells", cells, &[cells.len() / corners, corners])?;
            let cells = file.dataset("mesh/cells")?;
            crate::attributes::text(&cells, "topology", kind.as_str())
        })?;
        let mut slip = vec![0.0; 3 * n];
        for k in 0..n {
            let u = s.slip(k);
            if C == 1 {
                slip[3 * k + 2] = u[0];
            } else {
                slip[3 * k..3 * k + C.min(3)].copy_from_slice(&u[..C.min(3)]);
            }
        }
        let scalar = |f: &dyn Fn(usize) -> f64| (0..n).map(f).collect::<Vec<f64>>();
        let values = [
            slip,
            scalar(&|k| s.slip_rate(k)),
            s.state.alpha.clone(),
            scalar(&|k| s.shear_traction(k)),
            scalar(&|k| s.normal_traction(k).unwrap_or(f64::NAN)),
            scalar(&|k| m.frictional_boundary.fault_of[k] as f64),
        ];
        let fields: Vec<Field<'_>> = FAULT_FIELDS
            .iter()
            .zip(&values)
            .map(|(&(name, components, unit), values)| Field {
                name,
                components,
                unit,
                values,
            })
            .collect();
        self.fields.file.append(
            file,
            (s.state.time, s.report.step),
            (n, &fields),
            &m.frictional_boundary.fault_names,
        )
    }
}

/// The fault's cells as indices into its nodes (fault indices): the Xdmf topology type,
/// the vertices per cell and the cells ([`Hdf5FaultFields`]).
fn fault_cells<const D: usize, const C: usize>(m: &Model<D, C>) -> (String, usize, Vec<u64>) {
    let fb = &m.frictional_boundary;
    if D == 2 {
        // Consecutive nodes along Γ_F of one fault.
        let cells = fb
            .along
            .windows(2)
            .filter(|w| fb.fault_of[w[0]] == fb.fault_of[w[1]])
            .flat_map(|w| [w[0] as u64, w[1] as u64])
            .collect();
        return ("Polyline".into(), 2, cells);
    }
    if D == 3 && !m.cells.is_empty() {
        // The faces of the tetrahedra whose three vertices are on Γ_F.
        let mut index = vec![usize::MAX; m.vertices.len()];
        for (k, &p) in fb.nodes.iter().enumerate() {
            index[p] = k;
        }
        let mut faces = BTreeSet::new();
        for t in m.cells.chunks_exact(4) {
            for skip in 0..4 {
                let mut f = [0u64; 3];
                let mut on = true;
                for (j, &v) in t.iter().enumerate().filter(|&(j, _)| j != skip) {
                    let k = index[v];
                    on &= k != usize::MAX;
                    f[j - usize::from(j > skip)] = k as u64;
                }
                if on {
                    f.sort_unstable();
                    faces.insert(f);
                }
            }
        }
        if !faces.is_empty() {
            return ("Triangle".into(), 3, faces.into_iter().flatten().collect());
        }
    }
    // A fault alone: its nodes are its elements' centres.
    let cells = (0..fb.nodes.len() as u64).collect();
    ("Polyvertex".into(), 1, cells)
}

impl<const D: usize, const C: usize> Observer<D, C> for Hdf5FaultFields {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        let times = self.append_frame(s)?;
        let (kind, corners, cells) = self.topology.as_ref().expect("made by the frame");
        let topology = Topology {
            kind,
            cells: cells.len() / corners,
            corners: *corners,
        };
        let fields: Vec<(&str, usize)> = FAULT_FIELDS.iter().map(|&(n, c, _)| (n, c)).collect();
        let n = s.model.frictional_boundary.nodes.len();
        write_index(&self.fields.file.path, &topology, n, &times, &fields)?;
        Ok(Flow::Continue(()))
    }

    fn name(&self) -> String {
        format!("HDF5 fault fields {}", self.fields.file.path.display())
    }

    /// The fault's own fields only (slip, slip rate, state): a run condensed onto the
    /// fault without the volume's factor (the Schur-only elimination of BP5's, BP7's and
    /// BP8's volumes) can be observed.
    fn reads_volume(&self) -> bool {
        false
    }
}
