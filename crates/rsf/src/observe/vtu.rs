//! ParaView output: one VTU file per recorded step plus a `.pvd` time index
//! (feature `vtk`, via `vtkio`); on ranks, one piece per rank and a `.pvtu` per step.

use std::fmt::Write as _;
use std::path::PathBuf;

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, ScalarType, UnstructuredGridPiece,
    Version, VertexNumbers, Vtk,
};

use crate::error::{io_at, show_path, Error, Result};
use rsf_ranks::RankGroup;

use super::fields::point_fields;
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
///
/// On ranks ([`VtuFrames::pieces`]) every rank writes its piece of each frame,
/// `frame_NNNNNN_rRRRR.vtu` (RRRR its rank, four digits or more), and rank 0 writes
/// `frame_NNNNNN.pvtu` (the parallel file naming the pieces) and lists it in
/// `frames.pvd`.
pub struct VtuFrames {
    dir: PathBuf,
    frames: Vec<(f64, String)>,
    /// The model's fault names (the values of the point field `fault` index them), set at
    /// the first frame written.
    fault_names: Vec<String>,
    /// On ranks: this rank's share of the frames.
    pieces: Option<Pieces>,
}

/// One rank's share of the frames written in pieces.
struct Pieces {
    /// The owner rank of every mesh vertex.
    owner: Vec<usize>,
    ranks: Box<dyn RankGroup + Send>,
    /// This rank's cells and their points, found at the first frame.
    share: Option<Share>,
}

/// The cells a rank owns and the points they use.
struct Share {
    /// The owned cells' vertices in this piece's point numbering, cell after cell.
    connectivity: Vec<u64>,
    /// The piece's points: their mesh vertex numbers, ascending (piece point `i` is mesh
    /// vertex `points[i]`).
    points: Vec<usize>,
}

/// The rank whose piece holds `cell` (its vertices): the owner of its lowest-numbered
/// vertex.
fn cell_owner(cell: &[usize], owner: &[usize]) -> Option<usize> {
    cell.iter().min().map(|&p| owner[p])
}

impl Share {
    /// The cells of `cells` (`k` vertices each) whose lowest-numbered vertex `rank` owns,
    /// and the points they use.
    fn new(cells: &[usize], k: usize, owner: &[usize], rank: usize) -> Self {
        let owned: Vec<&[usize]> = cells
            .chunks_exact(k)
            .filter(|c| cell_owner(c, owner) == Some(rank))
            .collect();
        let mut points: Vec<usize> = owned.iter().flat_map(|c| c.iter().copied()).collect();
        points.sort_unstable();
        points.dedup();
        let local = |p: &usize| points.binary_search(p).expect("a vertex of the piece") as u64;
        let connectivity = owned.iter().flat_map(|c| c.iter().map(local)).collect();
        Self {
            connectivity,
            points,
        }
    }
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
            fault_names: Vec::new(),
            pieces: None,
        };
        frames.read_index(mode)?;
        Ok(frames)
    }

    /// Frames in parallel pieces into `dir`, this process being rank `ranks.rank()` of
    /// `ranks.size()` processes that run the same simulation (every rank constructs one and
    /// shows it the same steps). Every frame's cells are shared out: a cell belongs to the
    /// owner of its lowest-numbered vertex (`owner[p]` the rank of mesh vertex `p`, one
    /// entry per vertex, each in `0..ranks.size()`). Each rank writes
    /// `frame_NNNNNN_rRRRR.vtu`: its cells and the points they use (in ascending vertex
    /// order), the point data of [`new`](Self::new)'s frames at those points and
    /// `global_node` (`UInt64`: the mesh vertex of each point, which joins the pieces; a
    /// vertex on the border of two pieces is in both, with the same values). A rank that
    /// owns no cell writes an empty piece. After every rank has written its piece (one
    /// all-gather of one value per rank per frame: a collective), rank 0 writes
    /// `frame_NNNNNN.pvtu` (the arrays' names, types and component counts and the pieces'
    /// names, every rank's listed), removes pieces of that step by ranks `≥ ranks.size()`
    /// left by an earlier run on more ranks, and lists the `.pvtu` in `frames.pvd`.
    ///
    /// Rank 0 creates the folder and keeps the index as [`new`](Self::new) does (`mode` is
    /// rank 0's; the other ranks create the folder at their first frame and ignore
    /// `mode`). A resumed run may use another rank count than the run it continues: each
    /// `.pvtu` names its own pieces, and `frames.pvd` may list `.vtu` and `.pvtu` frames.
    ///
    /// Each rank computes the point data from its replicated state at every vertex, as
    /// [`new`](Self::new) does, and writes those of its piece only: about `1/size` of a
    /// frame plus the points on the piece's border.
    ///
    /// # Errors
    /// Rank 0: those of [`new`](Self::new). Later, from the observer: I/O errors naming
    /// the piece or the `.pvtu`, and [`Error::InvalidParameter`] if `owner` does not have
    /// one entry per mesh vertex (an entry outside `0..ranks.size()` is no error: that
    /// vertex's cells are in no piece).
    ///
    /// # Panics
    /// At a frame, as `ranks`' all-gather may (a transport that fails).
    pub fn pieces(
        dir: impl Into<PathBuf>,
        mode: FileMode,
        owner: Vec<usize>,
        ranks: Box<dyn RankGroup + Send>,
    ) -> Result<Self> {
        let dir = dir.into();
        let root = ranks.rank() == 0;
        let mut frames = Self {
            dir,
            frames: Vec::new(),
            fault_names: Vec::new(),
            pieces: Some(Pieces {
                owner,
                ranks,
                share: None,
            }),
        };
        if root {
            std::fs::create_dir_all(&frames.dir)
                .map_err(io_at("create the frame folder", &frames.dir))?;
            frames.read_index(mode)?;
        }
        Ok(frames)
    }

    /// The size of every rank's piece of a frame written by [`pieces`](Self::pieces) on
    /// `ranks` ranks: `(points, cells)` per rank, for a mesh of `cells` (the vertex numbers
    /// of one cell after another, `k` per cell, as [`Model::cells`](crate::Model::cells)) with the vertex owners
    /// `owner` (one rank per vertex). A piece holds the cells whose lowest-numbered vertex
    /// its rank owns and the points they use, so the points of all pieces exceed the
    /// mesh's vertices by those on the pieces' borders. For a bound of the bytes the
    /// frames write.
    ///
    /// # Panics
    /// If a vertex number in `cells` is not below `owner.len()`, or `k` is 0.
    pub fn piece_sizes(
        cells: &[usize],
        k: usize,
        owner: &[usize],
        ranks: usize,
    ) -> Vec<(usize, usize)> {
        let mut sizes = vec![(0, 0); ranks];
        // (rank, vertex) of every point of a piece, with repeats.
        let mut points = Vec::with_capacity(cells.len());
        for cell in cells.chunks_exact(k) {
            if let Some(r) = cell_owner(cell, owner).filter(|&r| r < ranks) {
                sizes[r].1 += 1;
                points.extend(cell.iter().map(|&p| (r, p)));
            }
        }
        points.sort_unstable();
        points.dedup();
        for (r, _) in points {
            sizes[r].0 += 1;
        }
        sizes
    }

    /// Refuses an existing index for [`FileMode::Create`]; reads the frames of steps
    /// `≤ step` from `frames.pvd` for [`FileMode::Resume`].
    fn read_index(&mut self, mode: FileMode) -> Result<()> {
        if mode == FileMode::Create {
            super::files::refuse_existing(&self.dir.join("frames.pvd"))?;
        }
        let FileMode::Resume { step } = mode else {
            return Ok(());
        };
        let index = self.dir.join("frames.pvd");
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
            // One process's frames and those of ranks (a run resumed on another rank
            // count lists both).
            let frame_step: usize = file
                .strip_prefix("frame_")
                .and_then(|f| f.strip_suffix(".vtu").or_else(|| f.strip_suffix(".pvtu")))
                .and_then(|n| n.parse().ok())
                .ok_or_else(|| fail("malformed frame name"))?;
            let time = t.parse().map_err(|_| fail("malformed time"))?;
            if frame_step <= step {
                self.frames.push((time, file.to_owned()));
            }
        }
        Ok(())
    }

    /// Rewrites `frames.pvd` atomically ([`write_atomically`](crate::checkpoint::write_atomically):
    /// errors name the file). Only rank 0 of frames in pieces keeps an index.
    fn write_index(&self) -> Result<()> {
        if self.pieces.as_ref().is_some_and(|p| p.ranks.rank() != 0) {
            return Ok(());
        }
        let mut f = String::from("<?xml version=\"1.0\"?>\n");
        f.push_str("<VTKFile type=\"Collection\" version=\"0.1\">\n");
        // The names of the values of the point field `fault` (ParaView shows the index;
        // XML comments are what a collection file can carry besides its data sets).
        let named = self.fault_names.iter().any(|n| !n.is_empty());
        for (i, name) in self.fault_names.iter().enumerate().filter(|_| named) {
            let name = name.replace("--", "- -");
            let _ = writeln!(f, "  <!-- fault {i}: {name} -->");
        }
        f.push_str("  <Collection>\n");
        for (t, name) in &self.frames {
            // Writing into a String cannot fail.
            let _ = writeln!(f, "    <DataSet timestep=\"{t:.9e}\" file=\"{name}\"/>");
        }
        f.push_str("  </Collection>\n</VTKFile>\n");
        crate::checkpoint::write_atomically(&self.dir.join("frames.pvd"), f.as_bytes())
    }
}

/// The name of rank `rank`'s piece of the frame of step `step`.
fn piece_name(step: usize, rank: usize) -> String {
    format!("frame_{step:06}_r{rank:04}.vtu")
}

/// A data array of point data (vectors for 3 components, else scalars).
fn attribute(name: &str, components: usize, data: Vec<f64>) -> Attribute {
    match components {
        3 => Attribute::vectors(name).with_data(data),
        c => Attribute::scalars(name, c as u32).with_data(data),
    }
}

/// The values of `points` (mesh vertices) of a vertex-major array of `c` components.
fn gather(values: &[f64], c: usize, points: &[usize]) -> Vec<f64> {
    points
        .iter()
        .flat_map(|&p| values[c * p..c * p + c].iter().copied())
        .collect()
}

/// The VTK XML name of a scalar type.
fn xml_type(t: ScalarType) -> &'static str {
    match t {
        ScalarType::Bit | ScalarType::U8 => "UInt8",
        ScalarType::I8 => "Int8",
        ScalarType::U16 => "UInt16",
        ScalarType::I16 => "Int16",
        ScalarType::U32 => "UInt32",
        ScalarType::I32 => "Int32",
        ScalarType::U64 => "UInt64",
        ScalarType::I64 => "Int64",
        ScalarType::F32 => "Float32",
        ScalarType::F64 => "Float64",
    }
}

/// The `.pvtu` of a frame written in `pieces` whose point data are `point` (the pieces'
/// own arrays: their names, types and component counts).
///
/// Written here, not by vtkio: vtkio 0.7.0-rc2 reads parallel XML files (its
/// `Piece::Source`) but does not write them — its writer loads the pieces a
/// `Piece::Source` names and writes them inline as a serial file, and the parallel types
/// of its XML model (`PUnstructured`) have private fields. A `.pvtu` is only an index.
/// (vtkio reads this file's pieces but not its `PDataArray`s: its model expects elements
/// named `data_array` there, so it finds no arrays in any standard `.pvtu`.)
fn pvtu(point: &[Attribute], pieces: &[String]) -> String {
    let mut f = String::from("<?xml version=\"1.0\"?>\n");
    f.push_str(
        "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n",
    );
    for a in point {
        if let Attribute::DataArray(a) = a {
            // Writing into a String cannot fail.
            let _ = writeln!(
                f,
                "      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>",
                xml_type(a.data.scalar_type()),
                a.name,
                a.num_comp()
            );
        }
    }
    f.push_str("    </PPointData>\n    <PPoints>\n");
    f.push_str("      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n");
    f.push_str("    </PPoints>\n");
    for name in pieces {
        let _ = writeln!(f, "    <Piece Source=\"{name}\"/>");
    }
    f.push_str("  </PUnstructuredGrid>\n</VTKFile>\n");
    f
}

/// The VTU file of the mesh vertices `vertices` (the points, in this order, padded to 3
/// coordinates), the cells `connectivity` (`k` point numbers per cell, of `cell_type`) and
/// the point data `point`, titled `title`.
fn grid<const D: usize>(
    vertices: impl ExactSizeIterator<Item = [f64; D]>,
    connectivity: Vec<u64>,
    cell_type: CellType,
    point: Vec<Attribute>,
    title: String,
) -> Vtk {
    let mut points = vec![0.0; 3 * vertices.len()];
    for (p, v) in vertices.enumerate() {
        for c in 0..D.min(3) {
            points[3 * p + c] = v[c];
        }
    }
    let ncells = connectivity.len() / (D + 1);
    let piece = UnstructuredGridPiece {
        points: points.into(),
        cells: Cells {
            cell_verts: VertexNumbers::XML {
                connectivity,
                offsets: (1..=ncells).map(|k| (k * (D + 1)) as u64).collect(),
            },
            types: vec![cell_type; ncells],
        },
        data: Attributes {
            point,
            cell: Vec::new(),
        },
    };
    Vtk {
        version: Version::new_xml(1, 0),
        title,
        byte_order: ByteOrder::LittleEndian,
        data: DataSet::inline(piece),
        file_path: None,
    }
}

/// Writes `vtk` to `path`; errors name the file.
fn export(vtk: Vtk, path: &std::path::Path, action: &'static str) -> Result<()> {
    vtk.export(path).map_err(|e| Error::File {
        path: show_path(path),
        action,
        source: std::io::Error::other(e.to_string()),
    })
}

impl VtuFrames {
    /// This rank's piece of the frame of `s`, then (rank 0) its `.pvtu`.
    fn write_piece<const D: usize>(
        &mut self,
        s: &StepView<'_, D>,
        cell_type: CellType,
    ) -> Result<()> {
        let m = s.model;
        let step = s.report.step;
        let pieces = self.pieces.as_mut().expect("frames in pieces");
        let (rank, size) = (pieces.ranks.rank(), pieces.ranks.size());
        if pieces.owner.len() != m.vertices.len() {
            return Err(Error::InvalidParameter {
                name: "VTU frame pieces".into(),
                reason: format!(
                    "{} owners for a mesh of {} vertices",
                    pieces.owner.len(),
                    m.vertices.len()
                ),
            });
        }
        let share = pieces
            .share
            .get_or_insert_with(|| Share::new(&m.cells, D + 1, &pieces.owner, rank));
        let mut point: Vec<Attribute> = point_fields(s)
            .into_iter()
            .map(|f| {
                attribute(
                    f.name,
                    f.components,
                    gather(&f.values, f.components, &share.points),
                )
            })
            .collect();
        point.push(
            Attribute::scalars("global_node", 1)
                .with_data(share.points.iter().map(|&p| p as u64).collect::<Vec<_>>()),
        );
        let index = (rank == 0).then(|| {
            let names: Vec<String> = (0..size).map(|r| piece_name(step, r)).collect();
            pvtu(&point, &names)
        });
        let vtk = grid(
            share.points.iter().map(|&p| m.vertices[p]),
            share.connectivity.clone(),
            cell_type,
            point,
            format!("rsf step {step}, piece {rank} of {size}"),
        );
        // The other ranks reach their first frame after collective solves, when rank 0
        // has prepared the run's folder.
        std::fs::create_dir_all(&self.dir).map_err(io_at("create the frame folder", &self.dir))?;
        export(
            vtk,
            &self.dir.join(piece_name(step, rank)),
            "write the VTU piece",
        )?;
        // Every piece on disk before the `.pvtu` names it (and before rank 0's checkpoint).
        let mut all = vec![0.0; size];
        pieces.ranks.all_gather(&[0.0], &vec![1; size], &mut all);
        let Some(index) = index else {
            return Ok(());
        };
        // Pieces of this step by more ranks (an earlier run on more ranks, resumed here).
        for r in size.. {
            if std::fs::remove_file(self.dir.join(piece_name(step, r))).is_err() {
                break;
            }
        }
        let name = format!("frame_{step:06}.pvtu");
        crate::checkpoint::write_atomically(&self.dir.join(&name), index.as_bytes())?;
        self.frames.push((s.report.time, name));
        self.write_index()
    }
}

impl<const D: usize> Observer<D> for VtuFrames {
    fn observe(&mut self, s: &StepView<'_, D>) -> Result<Flow> {
        let cell_type = match D {
            1 => CellType::Line,
            2 => CellType::Triangle,
            _ => CellType::Tetra,
        };
        if self.fault_names.is_empty() {
            self.fault_names = s.model.frictional_boundary.fault_names.clone();
        }
        if self.pieces.is_some() {
            self.write_piece(s, cell_type)?;
            return Ok(Flow::Continue(()));
        }
        let m = s.model;
        let vtk = grid(
            m.vertices.iter().copied(),
            m.cells.iter().map(|&c| c as u64).collect(),
            cell_type,
            point_fields(s)
                .into_iter()
                .map(|f| attribute(f.name, f.components, f.values))
                .collect(),
            format!("rsf step {}", s.report.step),
        );
        let name = format!("frame_{:06}.vtu", s.report.step);
        export(vtk, &self.dir.join(&name), "write the VTU frame")?;
        self.frames.push((s.report.time, name));
        self.write_index()?;
        Ok(Flow::Continue(()))
    }

    fn finish(&mut self) -> Result<()> {
        self.write_index()
    }
}

#[cfg(test)]
mod tests {
    use super::{piece_name, pvtu, Share, VtuFrames};
    use vtkio::model::{
        Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version,
        VertexNumbers, Vtk,
    };

    /// Two triangles of a square (vertices 0–3) and one of a second square (2, 3, 4): each
    /// cell goes to the owner of its lowest-numbered vertex, with the points it uses.
    #[test]
    fn a_cell_belongs_to_the_owner_of_its_lowest_vertex() {
        let cells = [3, 1, 0, 1, 2, 3, 4, 3, 2];
        let owner = [1, 0, 0, 0, 2];
        let one = Share::new(&cells, 3, &owner, 1);
        assert_eq!(one.points, [0, 1, 3]);
        assert_eq!(one.connectivity, [2, 1, 0]);
        let zero = Share::new(&cells, 3, &owner, 0);
        assert_eq!(zero.points, [1, 2, 3, 4]);
        assert_eq!(zero.connectivity, [0, 1, 2, 3, 2, 1]);
        let two = Share::new(&cells, 3, &owner, 2);
        assert!(two.points.is_empty() && two.connectivity.is_empty());
        assert_eq!(
            VtuFrames::piece_sizes(&cells, 3, &owner, 3),
            [(4, 2), (3, 1), (0, 0)]
        );
        assert_eq!(piece_name(12, 3), "frame_000012_r0003.vtu");
        assert_eq!(piece_name(1_234_567, 12_345), "frame_1234567_r12345.vtu");
    }

    /// An empty piece (a rank that owns no cell) and the `.pvtu` naming it (the arrays'
    /// names, types and component counts, the pieces) are read back by vtkio.
    #[test]
    fn an_empty_piece_and_its_pvtu_read_back() {
        let dir = std::env::temp_dir().join(format!("rsf_vtu_empty_piece_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let point = vec![
            Attribute::vectors("velocity").with_data(Vec::<f64>::new()),
            Attribute::scalars("global_node", 1).with_data(Vec::<u64>::new()),
        ];
        let names = vec![piece_name(7, 0)];
        std::fs::write(dir.join("frame_000007.pvtu"), pvtu(&point, &names)).unwrap();
        let piece = UnstructuredGridPiece {
            points: Vec::<f64>::new().into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity: Vec::new(),
                    offsets: Vec::new(),
                },
                types: Vec::<CellType>::new(),
            },
            data: Attributes {
                point,
                cell: Vec::new(),
            },
        };
        Vtk {
            version: Version::new_xml(1, 0),
            title: String::new(),
            byte_order: ByteOrder::LittleEndian,
            data: DataSet::inline(piece),
            file_path: None,
        }
        .export(dir.join(&names[0]))
        .unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.join("frame_000007.pvtu")).unwrap(),
            r#"<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PUnstructuredGrid GhostLevel="0">
    <PPointData>
      <PDataArray type="Float64" Name="velocity" NumberOfComponents="3"/>
      <PDataArray type="UInt64" Name="global_node" NumberOfComponents="1"/>
    </PPointData>
    <PPoints>
      <PDataArray type="Float64" NumberOfComponents="3"/>
    </PPoints>
    <Piece Source="frame_000007_r0000.vtu"/>
  </PUnstructuredGrid>
</VTKFile>
"#
        );
        let vtk = Vtk::import(dir.join("frame_000007.pvtu")).unwrap();
        let DataSet::UnstructuredGrid { meta, pieces } = vtk.data else {
            panic!("not an unstructured grid")
        };
        assert!(matches!(
            meta.as_deref(),
            Some(vtkio::model::MetaData::UnstructuredGrid { .. })
        ));
        assert_eq!(pieces.len(), 1);
        let loaded = pieces[0].load_piece_data(vtk.file_path.as_deref()).unwrap();
        assert_eq!(loaded.num_points(), 0);
        assert_eq!(loaded.cells.num_cells(), 0);
        std::fs::remove_dir_all(&dir).ok();
    }
}
