//! Fault networks from Python (issue 83): several named faults inside the body
//! (`rsf.Model(..., faults=[(name, points), ...])`, through the builder's
//! `internal_fault_polyline` in 2-D and `internal_fault_polygon` in 3-D), the fault of
//! every frictional node, parameters given per fault (`{"west": ..., "east": ...}`), and
//! the builder's errors attributed to the keyword `faults` and the fault's name.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use rsf::fem::{MeshHierarchy, SimplexMesh};
use rsf::ModelBuilder;

use crate::convert::{per_node, PerNode};
use crate::errors::{invalid, to_py};

/// One fault as the user gave it: its name and its points (m; a polyline's vertices in
/// 2-D, a convex planar polygon's corners in 3-D), checked for shape and finiteness; or,
/// for a Gmsh physical group inside the body, its polyline (2-D, as points) or its faces
/// (3-D: vertex indices of the mesh as read).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FaultSpec {
    pub name: String,
    pub points: Vec<Vec<f64>>,
    /// A 3-D group's faces (then `points` is empty).
    pub faces: Option<Vec<[usize; 3]>>,
}

/// The physical groups of a Gmsh mesh that lie inside the body (read with
/// `GmshOptions::interior_facets`): faults a model may name (`faults=[(name, "group")]`).
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct InteriorGroups {
    /// 2-D: each curve's polyline from one end to the other (m), or why it is not one.
    pub polylines: std::collections::BTreeMap<String, Result<Vec<Vec<f64>>, String>>,
    /// 3-D: each surface's faces (vertex indices).
    pub faces: std::collections::BTreeMap<String, Vec<[usize; 3]>>,
}

impl InteriorGroups {
    /// The groups inside the body of a 2-D Gmsh mesh.
    pub(crate) fn of_2d(g: &rsf::fem::GmshMesh<2>) -> Self {
        let polylines = g
            .interior_facets
            .keys()
            .map(|name| {
                let line = g
                    .interior_polyline(name)
                    .map(|p| p.iter().map(|x| x.to_vec()).collect())
                    .map_err(|e| e.to_string());
                (name.clone(), line)
            })
            .collect();
        Self {
            polylines,
            faces: Default::default(),
        }
    }

    /// The groups inside the body of a 3-D Gmsh mesh.
    pub(crate) fn of_3d(g: &rsf::fem::GmshMesh<3>) -> Self {
        Self {
            polylines: Default::default(),
            faces: g.interior_facets.clone(),
        }
    }

    fn names(&self) -> Vec<&String> {
        self.polylines.keys().chain(self.faces.keys()).collect()
    }
}

/// The keyword `faults` of `rsf.Model`: a list of `(name, points)` pairs, `points` of shape
/// `(k, dim)` (m) with `k ≥ 2` in 2-D (a segment or polyline) and `k ≥ 3` in 3-D (a
/// polygon's corners), or the name of one of `groups` (a Gmsh physical group inside the
/// body). Names are non-empty and unique; every coordinate is finite.
pub(crate) fn fault_specs(
    obj: Option<&Bound<'_, PyAny>>,
    dim: usize,
    groups: &InteriorGroups,
) -> PyResult<Vec<FaultSpec>> {
    let Some(obj) = obj else {
        return Ok(Vec::new());
    };
    let what = "a list of (name, points) pairs, points of shape (k, dim) in m or a Gmsh \
                physical group's name";
    let items: Vec<Bound<'_, PyAny>> = obj.extract().map_err(|_| invalid("faults", what))?;
    let min = if dim == 2 { 2 } else { 3 };
    let mut out: Vec<FaultSpec> = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let (name, points): (String, Bound<'_, PyAny>) = item
            .extract()
            .map_err(|_| invalid("faults", format!("entry {i} is not {what}")))?;
        let fail = |reason: String| invalid("faults", format!("fault `{name}`: {reason}"));
        if name.is_empty() {
            return Err(invalid("faults", format!("entry {i} has an empty name")));
        }
        if out.iter().any(|f| f.name == name) {
            return Err(fail("the name is given twice: names must be unique".into()));
        }
        if let Ok(group) = points.extract::<String>() {
            out.push(group_fault(name.clone(), &group, groups).map_err(fail)?);
            continue;
        }
        let points: Vec<Vec<f64>> = points
            .extract()
            .map_err(|_| fail(format!("points must be an array of shape (k, {dim}) in m")))?;
        if points.len() < min {
            return Err(fail(format!(
                "{} points: at least {min} in {dim}-D ({})",
                points.len(),
                if dim == 2 {
                    "a segment's ends or a polyline's vertices"
                } else {
                    "a planar polygon's corners"
                }
            )));
        }
        if let Some(p) = points.iter().find(|p| p.len() != dim) {
            return Err(fail(format!(
                "a point of {} coordinates in a {dim}-D mesh",
                p.len()
            )));
        }
        if let Some(p) = points.iter().find(|p| p.iter().any(|x| !x.is_finite())) {
            return Err(fail(format!("the point {p:?} is not finite")));
        }
        out.push(FaultSpec {
            name,
            points,
            faces: None,
        });
    }
    Ok(out)
}

/// The fault `name` along the Gmsh physical group `group` inside the body.
fn group_fault(name: String, group: &str, groups: &InteriorGroups) -> Result<FaultSpec, String> {
    if let Some(line) = groups.polylines.get(group) {
        let points = line
            .clone()
            .map_err(|e| format!("the group `{group}` is not one polyline: {e}"))?;
        return Ok(FaultSpec {
            name,
            points,
            faces: None,
        });
    }
    match groups.faces.get(group) {
        Some(faces) => Ok(FaultSpec {
            name,
            points: Vec::new(),
            faces: Some(faces.clone()),
        }),
        None => Err(format!(
            "`{}` is no physical group inside the body of the mesh (those of a mesh read by \
             Mesh.read_gmsh: {:?})",
            rsf_numeric::excerpt(group),
            groups.names()
        )),
    }
}

/// A model builder of dimension `D` that takes the faults of a network: the builder's
/// call per fault, and the check of one fault alone on a mesh (to say which fault a
/// failed build is about).
pub(crate) trait NetworkBuilder<const D: usize>: Sized {
    /// The builder with every fault inside the body, in order.
    fn with_faults(self, faults: &[FaultSpec]) -> Self;
    /// The errors of cutting `mesh` along the fault `f` alone (`None`: it can be cut).
    fn fault_alone(mesh: &SimplexMesh<D>, f: &FaultSpec) -> Option<rsf::fem::Error>;
}

fn fixed<const D: usize>(points: &[Vec<f64>]) -> Vec<[f64; D]> {
    points
        .iter()
        .map(|p| std::array::from_fn(|c| p[c]))
        .collect()
}

impl NetworkBuilder<2> for ModelBuilder<2> {
    fn with_faults(self, faults: &[FaultSpec]) -> Self {
        faults.iter().fold(self, |b, f| {
            b.internal_fault_polyline(&f.name, &fixed::<2>(&f.points))
        })
    }

    fn fault_alone(mesh: &SimplexMesh<2>, f: &FaultSpec) -> Option<rsf::fem::Error> {
        mesh.edges_along_polyline(&fixed::<2>(&f.points))
            .and_then(|e| mesh.split_along_network(&[(f.name.as_str(), &e[..])]))
            .err()
    }
}

impl NetworkBuilder<3> for ModelBuilder<3> {
    fn with_faults(self, faults: &[FaultSpec]) -> Self {
        faults.iter().fold(self, |b, f| match &f.faces {
            Some(faces) => b.internal_fault_faces(&f.name, faces),
            None => b.internal_fault_polygon(&f.name, &fixed::<3>(&f.points)),
        })
    }

    fn fault_alone(mesh: &SimplexMesh<3>, f: &FaultSpec) -> Option<rsf::fem::Error> {
        let faces = match &f.faces {
            Some(faces) => Ok(faces.clone()),
            None => mesh.faces_in_polygon(&fixed::<3>(&f.points)),
        };
        faces
            .and_then(|e| mesh.split_along_network(&[(f.name.as_str(), &e[..])]))
            .err()
    }
}

/// Whether a mesh error is about a fault (the splitting's), by its kind.
fn is_fault_error(e: &rsf::fem::Error) -> bool {
    use rsf::fem::Error as F;
    matches!(
        e,
        F::FaultEdgeNotInMesh { .. }
            | F::FaultEdgeOnBoundary { .. }
            | F::FaultEdgeRepeated { .. }
            | F::FaultEdgeShared { .. }
            | F::FaultNameRepeated { .. }
            | F::FaultJunctionUnsupported { .. }
            | F::FaultNotManifold { .. }
            | F::FaultClosed { .. }
            | F::FaultDisconnected { .. }
            | F::FaultSidesNotSeparated { .. }
            | F::FaultSegmentNotResolved { .. }
            | F::FaultFaceNotInMesh { .. }
            | F::FaultFaceOnBoundary { .. }
            | F::FaultFaceRepeated { .. }
            | F::FaultEdgeNotManifold { .. }
            | F::FaultNotOrientable { .. }
            | F::FaultSurfaceNotResolved { .. }
    )
}

/// The exception of a failed build of a model with the faults `faults` on `coarse`
/// refined `refine` times: where the splitting failed, the exception of the library's
/// error kind (`ModelError` for the mesh's) with the message prefixed by the keyword
/// `faults` and — found by cutting the finest mesh along each fault alone — the name of
/// the first fault that cannot be cut by itself (a segment the mesh does not resolve, a
/// fault on the outer boundary, …); faults that are each fine but meet in an unsupported
/// junction are named by the library's message. Other errors are the library's as they are.
pub(crate) fn explain<const D: usize>(
    e: rsf::Error,
    coarse: SimplexMesh<D>,
    refine: usize,
    faults: &[FaultSpec],
) -> PyErr
where
    ModelBuilder<D>: NetworkBuilder<D>,
{
    let about_faults = matches!(&e, rsf::Error::Fem(f) if is_fault_error(f));
    if faults.is_empty() || !about_faults {
        return to_py(e);
    }
    let finest = MeshHierarchy::try_refine_uniformly(coarse, refine)
        .ok()
        .map(|h| h.finest().clone());
    let alone = finest.as_ref().and_then(|m| {
        faults
            .iter()
            .find_map(|f| ModelBuilder::<D>::fault_alone(m, f).map(|err| (f, err)))
    });
    let prefix = match &alone {
        Some((f, _)) => format!("invalid parameter `faults`: fault `{}`: ", f.name),
        None => "invalid parameter `faults`: ".to_owned(),
    };
    let cause = match alone {
        Some((_, err)) => rsf::Error::from(err),
        None => e,
    };
    Python::attach(|py| {
        let typed = to_py(cause);
        let message = format!("{prefix}{}", typed.value(py));
        PyErr::from_type(typed.get_type(py), message)
    })
}

/// The faults of a model's frictional nodes: their names and the fault of every node (an
/// index into the names, by fault index).
pub(crate) fn faults_of<const D: usize>(m: &rsf::Model<D>) -> (Vec<String>, Vec<usize>) {
    let fb = &m.frictional_boundary;
    (fb.fault_names.clone(), fb.fault_of.clone())
}

/// The fault indices of the fault `name`'s nodes, in order along it; an
/// `InvalidParameterError` named `name` listing the faults for another name.
pub(crate) fn fault_nodes<const D: usize>(m: &rsf::Model<D>, name: &str) -> PyResult<Vec<usize>> {
    let fb = &m.frictional_boundary;
    fb.fault_named(name)
        .map(|f| fb.along_fault(f))
        .ok_or_else(|| {
            invalid(
                "name",
                format!(
                    "`{}` is none of the model's faults {:?}",
                    rsf_numeric::excerpt(name),
                    fb.fault_names
                ),
            )
        })
}

/// A parameter per fault node, given as `per_node` takes it (a number, an array of one
/// value per fault node, a function of the coordinates) or per fault: a dict from every
/// fault's name to such a value for that fault's nodes alone (an array of its nodes'
/// count, in fault-node order restricted to it; a function called with its nodes'
/// coordinates). `coords` are the fault nodes' (`d` per node), `names` and `fault_of`
/// the model's faults.
pub(crate) fn per_fault_node(
    py: Python<'_>,
    name: &str,
    obj: &Bound<'_, PyAny>,
    coords: &[f64],
    d: usize,
    faults: (&[String], &[usize]),
) -> PyResult<PerNode> {
    let Ok(dict) = obj.cast::<PyDict>() else {
        return per_node(py, name, obj, coords, d);
    };
    let (names, fault_of) = faults;
    for (k, _) in dict.iter() {
        let k: String = k
            .extract()
            .map_err(|_| invalid(name, "a dict's keys are the faults' names (str)"))?;
        if !names.contains(&k) {
            return Err(invalid(
                name,
                format!(
                    "`{}` is none of the model's faults {names:?}",
                    rsf_numeric::excerpt(&k)
                ),
            ));
        }
    }
    let mut values = vec![f64::NAN; fault_of.len()];
    for (f, fault) in names.iter().enumerate() {
        let Some(v) = dict.get_item(fault)? else {
            return Err(invalid(
                name,
                format!("no value for the fault `{fault}` (a dict gives every fault's: {names:?})"),
            ));
        };
        let nodes: Vec<usize> = (0..fault_of.len()).filter(|&k| fault_of[k] == f).collect();
        let x: Vec<f64> = nodes
            .iter()
            .flat_map(|&k| coords[k * d..(k + 1) * d].iter().copied())
            .collect();
        let on_fault = per_node(py, &format!("{name}[{fault:?}]"), &v, &x, d)?;
        for (i, &k) in nodes.iter().enumerate() {
            values[k] = on_fault.at(i);
        }
    }
    Ok(PerNode::Values(values))
}
