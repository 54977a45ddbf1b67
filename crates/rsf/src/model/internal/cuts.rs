//! The faults inside the body as the builder was given them ([`FaultCut`]: a name and the
//! fault's facets on any level of the hierarchy) and how the hierarchy is cut along all of
//! them at once ([`NetworkSplit`], per dimension).

use std::cell::OnceCell;

use rsf_fem::MeshHierarchy;

use super::hierarchy::{faces_on_levels, split_hierarchy, SplitHierarchy};

/// The facets of a fault (edges in 2-D, faces in 3-D, as vertex indices of the level) on
/// level `j` of a hierarchy.
type FacetsOnLevel<const D: usize> =
    Box<dyn Fn(&MeshHierarchy<D>, usize) -> crate::Result<Vec<[usize; D]>>>;

/// One fault inside the body: its name (the tags of its sides are `{name}_minus`,
/// `{name}_plus`) and its facets on every level of the hierarchy.
pub(crate) struct FaultCut<const D: usize> {
    /// The fault's name.
    pub name: String,
    /// Its facets on level `j`.
    pub facets: FacetsOnLevel<D>,
}

/// How the builder cuts its hierarchy along its faults, given the checked
/// [`fault_tangent`](crate::ModelBuilder::fault_tangent) (3-D pair frames): per dimension,
/// with the field's components fixed where the builder's type knows them.
pub(crate) type NetworkSplit<const D: usize> =
    fn(&MeshHierarchy<D>, Option<&[f64; D]>, &[FaultCut<D>]) -> crate::Result<SplitHierarchy<D>>;

impl FaultCut<2> {
    /// A 2-D fault along the polyline `points` (m): the mesh edges on its pieces.
    pub(crate) fn polyline(name: &str, points: &[[f64; 2]]) -> Self {
        let points = points.to_vec();
        Self {
            name: name.to_owned(),
            facets: Box::new(move |hierarchy, j| {
                Ok(hierarchy.level(j).edges_along_polyline(&points)?)
            }),
        }
    }
}

impl FaultCut<3> {
    /// A 3-D fault on the planar polygon `corners` (m): the mesh faces tiling it.
    pub(crate) fn polygon(name: &str, corners: &[[f64; 3]]) -> Self {
        let corners = corners.to_vec();
        Self {
            name: name.to_owned(),
            facets: Box::new(move |hierarchy, j| {
                Ok(hierarchy.level(j).faces_in_polygon(&corners)?)
            }),
        }
    }

    /// A 3-D fault given as faces of the hierarchy's level 0: on level `j` their
    /// descendants ([`faces_on_levels`]), found once; the given faces' own errors first (as
    /// faces of level 0).
    pub(crate) fn faces(name: &str, faces: &[[usize; 3]]) -> Self {
        let faces = faces.to_vec();
        let name_owned = name.to_owned();
        let levels: OnceCell<Vec<Vec<[usize; 3]>>> = OnceCell::new();
        Self {
            name: name.to_owned(),
            facets: Box::new(move |hierarchy, j| {
                if levels.get().is_none() {
                    hierarchy.level(0).split_along(&name_owned, &faces)?;
                    let _ = levels.set(faces_on_levels(hierarchy, &faces)?);
                }
                Ok(levels.get().expect("set above")[j].clone())
            }),
        }
    }
}

/// The faults' facets on level `j`.
fn facets_on<const D: usize>(
    hierarchy: &MeshHierarchy<D>,
    j: usize,
    cuts: &[FaultCut<D>],
) -> crate::Result<Vec<Vec<[usize; D]>>> {
    cuts.iter().map(|c| (c.facets)(hierarchy, j)).collect()
}

/// Cuts a 2-D hierarchy along the faults `cuts` (a network: disjoint, branching or
/// crossing), the model's field of `C` components.
pub(crate) fn split_network_2d<const C: usize>(
    hierarchy: &MeshHierarchy<2>,
    _tangent: Option<&[f64; 2]>,
    cuts: &[FaultCut<2>],
) -> crate::Result<SplitHierarchy<2>> {
    split_hierarchy(
        hierarchy,
        |j, mesh| {
            let facets = facets_on(hierarchy, j, cuts)?;
            let given: Vec<(&str, &[[usize; 2]])> = cuts
                .iter()
                .zip(&facets)
                .map(|(c, f)| (c.name.as_str(), &f[..]))
                .collect();
            Ok(mesh.split_along_network(&given)?)
        },
        |network, mesh| network.mean_jump_transform::<C>(mesh),
    )
}

/// Cuts a 3-D hierarchy along the disjoint faults `cuts`, the pair frames' first tangent
/// from `tangent`, the model's field of `C` components.
pub(crate) fn split_network_3d<const C: usize>(
    hierarchy: &MeshHierarchy<3>,
    tangent: Option<&[f64; 3]>,
    cuts: &[FaultCut<3>],
) -> crate::Result<SplitHierarchy<3>> {
    split_hierarchy(
        hierarchy,
        |j, mesh| {
            let facets = facets_on(hierarchy, j, cuts)?;
            let given: Vec<(&str, &[[usize; 3]])> = cuts
                .iter()
                .zip(&facets)
                .map(|(c, f)| (c.name.as_str(), &f[..]))
                .collect();
            Ok(mesh.split_along_network(&given)?)
        },
        |network, mesh| network.mean_jump_transform::<C>(mesh, tangent),
    )
}
