//! ParaView output: one VTU file per recorded step plus a `.pvd` time index
//! (feature `vtk`, via `vtkio`).

use std::fmt::Write as _;
use std::path::PathBuf;

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

use crate::error::{io_at, show_path, Error, Result};
use crate::model::Model;

use super::files::FileMode;
use super::{Flow, Observer, StepView};

/// Writes `frame_NNNNNN.vtu` (NNNNNN the step) of every step it is shown (wrap it in
/// [`Every`](crate::observe::Every) to sample) into a folder — the
/// mesh's cells as VTK lines, triangles or tetrahedra for D = 1, 2, 3, with point data
/// `displacement` (m) and `velocity` (m/s) as 3-vectors (zero-padded; Cartesian components,
/// rotated back from the nodal frames of a slanted fault); on Γ_F only (NaN elsewhere) the
/// scalars `slip_rate` (m/s), `state_alpha` (α = ln θ, dimensionless with θ in s),
/// `shear_traction` and `normal_traction` (Pa, [`StepView::shear_traction`],
/// [`StepView::normal_traction`]; NaN where the law has no `σ̄_n`) and the vector `slip`
/// (m, [`StepView::slip`]) — and `frames.pvd` (the
/// time index ParaView opens), rewritten after every frame so that an interrupted run
/// leaves a usable index. [`FileMode::Resume`] continues after a checkpoint.
pub struct VtuFrames {
    dir: PathBuf,
    frames: Vec<(f64, String)>,
}

impl VtuFrames {
    /// Frames into `dir` (created), new or continued after a checkpoint of step `step`
    /// ([`FileMode::Resume`]: the index keeps the frames of steps `≤ step`; later ones are
    /// rewritten as the run reaches them).
    ///
    /// # Errors
    /// For [`FileMode::Create`], [`Error::FileExists`] if `dir/frames.pvd` exists. For
    /// [`FileMode::Resume`], [`Error::Resume`] if `dir/frames.pvd` is missing or
    /// malformed; I/O errors.
    pub fn new(dir: impl Into<PathBuf>, mode: FileMode) -> Result<Self> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(io_at("create the frame folder", &dir))?;
        let mut frames = Self {
            dir,
            frames: Vec::new(),
        };
        if mode == FileMode::Create {
            super::files::refuse_existing(&frames.dir.join("frames.pvd"))?;
        }
        let FileMode::Resume { step } = mode else {
            return Ok(frames);
        };
        let index = frames.dir.join("frames.pvd");
        let fail = |reason: &str| Error::Resume {
            path: show_path(&index),
            reason: reason.to_owned(),
        };
        let text = std::fs::read_to_string(&index).map_err(|e| fail(&e.to_string()))?;
        for line in text.lines().filter(|l| l.contains("<DataSet")) {
            let attr = |name: &str| {
                let start = line.find(&format!("{name}=\""))? + name.len() + 2;
                let len = line[start..].find('"')?;
                Some(&line[start..start + len])
            };
            let (Some(t), Some(file)) = (attr("timestep"), attr("file")) else {
                return Err(fail("malformed DataSet line"));
            };
            let frame_step: usize = file
                .strip_prefix("frame_")
                .and_then(|f| f.strip_suffix(".vtu"))
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| fail("malformed frame name"))?;
            let time = t.parse().map_err(|_| fail("malformed time"))?;
            if frame_step <= step {
                frames.frames.push((time, file.to_owned()));
            }
        }
        Ok(frames)
    }

    /// Rewrites `frames.pvd` atomically ([`write_atomically`](crate::checkpoint::write_atomically):
    /// errors name the file).
    fn write_index(&self) -> Result<()> {
        let mut f = String::from("<?xml version=\"1.0\"?>\n");
        f.push_str("<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
        for (t, name) in &self.frames {
            // Writing into a String cannot fail.
            let _ = writeln!(f, "    <DataSet timestep=\"{t:.9e}\" file=\"{name}\"/>");
        }
        f.push_str("  </Collection>\n</VTKFile>\n");
        crate::checkpoint::write_atomically(&self.dir.join("frames.pvd"), f.as_bytes())
    }
}

fn padded<const D: usize>(x: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0; 3 * n];
    for p in 0..n {
        for c in 0..D.min(3) {
            out[3 * p + c] = x[D * p + c];
        }
    }
    out
}

/// α = ln θ at the frictional nodes, NaN elsewhere (no state there; ParaView draws NaN
/// in its "NaN colour"); all NaN when the friction law has no state.
fn state_field<const D: usize>(s: &StepView<'_, D>, n: usize) -> Vec<f64> {
    let mut out = vec![f64::NAN; n];
    for (&p, &a) in s.model.frictional_boundary.nodes.iter().zip(&s.state.alpha) {
        out[p] = a;
    }
    out
}

/// A node-major vector of the model in Cartesian components (nodal frames rotated back,
/// an internal fault's two sides).
fn global<const D: usize>(m: &Model<D>, x: &[f64]) -> Vec<f64> {
    m.to_cartesian(x)
        .expect("the state vectors match the model")
}

/// `f(k)` at the `k`-th frictional node, NaN elsewhere.
fn fault_scalars<const D: usize>(
    s: &StepView<'_, D>,
    n: usize,
    f: impl Fn(usize) -> f64,
) -> Vec<f64> {
    let mut out = vec![f64::NAN; n];
    for (k, &p) in s.model.frictional_boundary.nodes.iter().enumerate() {
        out[p] = f(k);
    }
    out
}

/// The slip (m, Cartesian 3-vectors, zero-padded) on Γ_F, NaN elsewhere.
fn slip_field<const D: usize>(s: &StepView<'_, D>, n: usize) -> Vec<f64> {
    let mut out = vec![f64::NAN; 3 * n];
    for (k, &p) in s.model.frictional_boundary.nodes.iter().enumerate() {
        let slip = s.slip(k);
        for c in 0..3 {
            out[3 * p + c] = if c < D { slip[c] } else { 0.0 };
        }
    }
    out
}

impl<const D: usize> Observer<D> for VtuFrames {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let m = s.model;
        let n = m.vertices.len();
        let mut points = vec![0.0; 3 * n];
        for (p, v) in m.vertices.iter().enumerate() {
            for c in 0..D.min(3) {
                points[3 * p + c] = v[c];
            }
        }
        let cell_type = match D {
            1 => CellType::Line,
            2 => CellType::Triangle,
            _ => CellType::Tetra,
        };
        let ncells = m.cells.len() / (D + 1);
        let piece = UnstructuredGridPiece {
            points: points.into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity: m.cells.iter().map(|&c| c as u64).collect(),
                    offsets: (1..=ncells).map(|k| (k * (D + 1)) as u64).collect(),
                },
                types: vec![cell_type; ncells],
            },
            data: Attributes {
                point: vec![
                    Attribute::vectors("displacement")
                        .with_data(padded::<D>(&global(m, &s.state.kinematics.u), n)),
                    Attribute::vectors("velocity")
                        .with_data(padded::<D>(&global(m, &s.state.kinematics.v), n)),
                    Attribute::scalars("slip_rate", 1)
                        .with_data(fault_scalars(s, n, |k| s.slip_rate(k))),
                    Attribute::scalars("state_alpha", 1).with_data(state_field(s, n)),
                    Attribute::vectors("slip").with_data(slip_field(s, n)),
                    Attribute::scalars("shear_traction", 1)
                        .with_data(fault_scalars(s, n, |k| s.shear_traction(k))),
                    Attribute::scalars("normal_traction", 1).with_data(fault_scalars(s, n, |k| {
                        s.normal_traction(k).unwrap_or(f64::NAN)
                    })),
                ],
                cell: Vec::new(),
            },
        };
        let vtk = Vtk {
            version: Version::new_xml(1, 0),
            title: format!("rsf step {}", s.report.step),
            byte_order: ByteOrder::LittleEndian,
            data: DataSet::inline(piece),
            file_path: None,
        };
        let name = format!("frame_{:06}.vtu", s.report.step);
        let path = self.dir.join(&name);
        vtk.export(&path).map_err(|e| Error::File {
            path: show_path(&path),
            action: "write the VTU frame",
            source: std::io::Error::other(e.to_string()),
        })?;
        self.frames.push((s.report.time, name));
        self.write_index()?;
        Ok(Flow::Continue(()))
    }

    fn finish(&mut self) -> Result<()> {
        self.write_index()
    }
}
