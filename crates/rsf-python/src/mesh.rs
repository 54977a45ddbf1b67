//! The mesh of a model from Python (`rsf.Mesh`): from arrays, a structured rectangle or
//! cuboid, or a Gmsh file with its physical groups (boundary parts and faults inside the
//! body).

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use rsf::fem::{Diagonal, SimplexMesh};

use crate::errors::invalid;
use crate::network::InteriorGroups;

/// A 2-D (triangles) or 3-D (tetrahedra) mesh.
#[derive(Clone)]
pub(crate) enum AnyMesh {
    Two(SimplexMesh<2>),
    Three(SimplexMesh<3>),
}

/// A simplicial mesh: triangles in 2-D, tetrahedra in 3-D (m). Build it from arrays
/// (`Mesh(points, cells)`: shapes `(n, dim)` and `(m, dim + 1)`), as a structured
/// rectangle or cuboid, or from a Gmsh MSH 4.1 file (`Mesh.read_gmsh`), whose physical
/// groups of boundary facets name parts of the model and whose groups inside the body
/// name faults (`Model(faults=[(name, "group")])`).
#[pyclass(module = "rsf._rsf", name = "Mesh")]
#[derive(Clone)]
pub struct Mesh {
    pub(crate) mesh: AnyMesh,
    /// A Gmsh mesh's physical groups inside the body (empty for the others).
    pub(crate) interior: InteriorGroups,
}

/// The rows of `points` as `D`-vectors (its columns checked by the caller).
fn points_of<const D: usize>(points: &Array2<f64>) -> Vec<[f64; D]> {
    points
        .rows()
        .into_iter()
        .map(|r| std::array::from_fn(|c| r[c]))
        .collect()
}

#[pymethods]
impl Mesh {
    /// A mesh of `points` (m, shape `(n, 2)` or `(n, 3)`) and `cells` (vertex indices, shape
    /// `(m, 3)` triangles or `(m, 4)` tetrahedra). Each may be any array-like numpy converts
    /// (nested lists, `float32` points, `int32` or whole-float cells); the rest is refused
    /// naming `points` or `cells`.
    #[new]
    fn new(points: &Bound<'_, PyAny>, cells: &Bound<'_, PyAny>) -> PyResult<Self> {
        let points = crate::arrays::reals_2d("points", points, None)?;
        let d = points.ncols();
        if !(2..=3).contains(&d) {
            return Err(invalid(
                "points",
                format!(
                    "2-D or 3-D points: shape (n, 2) or (n, 3), not {:?}",
                    points.dim()
                ),
            ));
        }
        let c = crate::arrays::indices_2d("cells", cells, d + 1)?;
        let c: Vec<usize> = c.iter().copied().collect();
        let mesh = match d {
            2 => AnyMesh::Two(SimplexMesh::new(points_of::<2>(&points), c).py_fem()?),
            _ => AnyMesh::Three(SimplexMesh::new(points_of::<3>(&points), c).py_fem()?),
        };
        Ok(Self {
            mesh,
            interior: InteriorGroups::default(),
        })
    }

    /// The rectangle `origin + [0, size]` (m) in `nx × ny` vertices (each ≥ 2), every cell
    /// cut along `diagonal` ("forward" or "backward").
    #[staticmethod]
    #[pyo3(signature = (origin, size, nx, ny, diagonal="forward"))]
    fn rectangle(
        origin: [f64; 2],
        size: [f64; 2],
        nx: i128,
        ny: i128,
        diagonal: &str,
    ) -> PyResult<Self> {
        let (nx, ny) = (
            crate::counts::count(nx, "nx")?,
            crate::counts::count(ny, "ny")?,
        );
        let diagonal = match diagonal {
            "forward" => Diagonal::Forward,
            "backward" => Diagonal::Backward,
            d => {
                return Err(invalid(
                    "diagonal",
                    format!("`{d}`: \"forward\" or \"backward\""),
                ))
            }
        };
        Ok(Self {
            mesh: AnyMesh::Two(rsf::fem::rectangle(origin, size, nx, ny, diagonal).py_fem()?),
            interior: InteriorGroups::default(),
        })
    }

    /// The cuboid `origin + [0, size]` (m) in `n` vertices per direction (tetrahedra).
    #[staticmethod]
    fn cuboid(origin: [f64; 3], size: [f64; 3], n: [i128; 3]) -> PyResult<Self> {
        let n = [
            crate::counts::count(n[0], "n")?,
            crate::counts::count(n[1], "n")?,
            crate::counts::count(n[2], "n")?,
        ];
        Ok(Self {
            mesh: AnyMesh::Three(rsf::fem::cuboid(origin, size, n).py_fem()?),
            interior: InteriorGroups::default(),
        })
    }

    /// A Gmsh MSH 4.1 file of dimension `dim` (2 or 3): its cells, its physical groups of
    /// boundary facets as tags (the names a model's parts refer to), and its physical
    /// groups of facets inside the body (a curve in 2-D, a surface in 3-D) as the faults a
    /// model may name (`Model(faults=[(name, "group")])`).
    #[staticmethod]
    #[pyo3(signature = (path, dim=2))]
    fn read_gmsh(path: PathBuf, dim: usize) -> PyResult<Self> {
        let options = rsf::fem::GmshOptions {
            interior_facets: true,
            ..rsf::fem::GmshOptions::default()
        };
        Ok(match dim {
            2 => {
                let g = rsf::fem::read_gmsh_with::<2>(&path, options).py_fem()?;
                Self {
                    interior: InteriorGroups::of_2d(&g),
                    mesh: AnyMesh::Two(g.mesh),
                }
            }
            3 => {
                let g = rsf::fem::read_gmsh_with::<3>(&path, options).py_fem()?;
                Self {
                    interior: InteriorGroups::of_3d(&g),
                    mesh: AnyMesh::Three(g.mesh),
                }
            }
            _ => return Err(invalid("dim", "2 or 3")),
        })
    }

    /// Vertex coordinates (m), shape `(n, dim)`.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (v, d) = match &self.mesh {
            AnyMesh::Two(m) => (
                m.vertices().iter().flatten().copied().collect::<Vec<_>>(),
                2,
            ),
            AnyMesh::Three(m) => (m.vertices().iter().flatten().copied().collect(), 3),
        };
        numpy::IntoPyArray::into_pyarray(v, py).reshape([v_len(d, &self.mesh), d])
    }

    /// The space dimension, 2 or 3.
    #[getter]
    pub(crate) fn dim(&self) -> usize {
        match self.mesh {
            AnyMesh::Two(_) => 2,
            AnyMesh::Three(_) => 3,
        }
    }
}

fn v_len(_d: usize, m: &AnyMesh) -> usize {
    match m {
        AnyMesh::Two(m) => m.vertices().len(),
        AnyMesh::Three(m) => m.vertices().len(),
    }
}

/// The mesh crate's result as Python's.
pub(crate) trait OrPyFem<T> {
    fn py_fem(self) -> PyResult<T>;
}

impl<T> OrPyFem<T> for Result<T, rsf::fem::Error> {
    fn py_fem(self) -> PyResult<T> {
        self.map_err(|e| crate::errors::to_py(e.into()))
    }
}
