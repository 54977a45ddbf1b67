//! A refinement hierarchy cut open along the faults inside the body: every level that
//! resolves them split, and the prolongations between the split levels (each vertex
//! interpolated from the coarse vertices on its own side of every fault).

use std::collections::HashMap;

use faer::sparse::{SparseColMat, Triplet};
use rsf_fem::{FaultNetwork, MeanJumpTransform, MeshHierarchy, SimplexMesh, SparseMatrix};

use super::fault::InternalFault;

/// A refinement hierarchy cut open along the faults: the split finest mesh, the faults on
/// it and the scalar prolongations between the levels (each level split where it resolves
/// every fault), in Cartesian components.
pub(crate) struct SplitHierarchy<const D: usize> {
    /// The finest mesh, split.
    pub mesh: SimplexMesh<D>,
    /// The faults on it with their mean–jump transform.
    pub fault: InternalFault<D>,
    /// `P_j` from level `j − 1` to level `j` (`j = 1, …`; one entry per level above the
    /// coarsest), scalar, between the split (or unsplit) levels' vertices.
    pub prolongations: Vec<SparseMatrix>,
}

/// One level of a hierarchy cut along the faults.
struct SplitLevel<const D: usize> {
    /// Per original vertex: its plus copy if it is a split pair's minus vertex.
    plus_of: Vec<Option<usize>>,
    /// Per original vertex of a junction: its copies (the original first).
    junction_copies: HashMap<usize, Vec<usize>>,
    /// Vertices of the split level (originals, then copies).
    num_vertices: usize,
    /// The split level's cells (`D + 1` vertices each, flat): the same cells in the same order
    /// and vertex order as the unsplit level's, a plus-side cell naming plus copies.
    cells: Vec<usize>,
    /// A cell of the unsplit level holding each edge `(min, max)` that touches a split
    /// vertex.
    cell_of_edge: HashMap<(usize, usize), usize>,
    /// With junctions: the split level's vertices (m), the cells around every junction's
    /// original vertex and a cell using each copy of a split vertex (for the prolongation's
    /// rule by position, [`SplitLevel::copy_at`]).
    geometry: Option<LevelGeometry<D>>,
}

/// The positions a prolongation at a junction needs.
struct LevelGeometry<const D: usize> {
    vertices: Vec<[f64; D]>,
    cells_around: HashMap<usize, Vec<usize>>,
    a_cell_of: HashMap<usize, usize>,
}

impl<const D: usize> SplitLevel<D> {
    fn new(unsplit: &SimplexMesh<D>, split: &SimplexMesh<D>, network: &FaultNetwork<D>) -> Self {
        let mut plus_of = vec![None; unsplit.num_vertices()];
        for (mi, pl) in network.pairs() {
            plus_of[mi] = Some(pl);
        }
        let junction_copies: HashMap<usize, Vec<usize>> = network
            .junctions()
            .iter()
            .map(|j| (j.vertex(), j.sectors().iter().map(|s| s.0).collect()))
            .collect();
        let split_at = |v: usize| plus_of[v].is_some() || junction_copies.contains_key(&v);
        let mut cell_of_edge = HashMap::new();
        // Every two vertices of a simplex are joined by one of its edges.
        for c in 0..unsplit.num_cells() {
            let cell = unsplit.cell(c);
            for k in 0..cell.len() {
                for &b in &cell[k + 1..] {
                    let a = cell[k];
                    if split_at(a) || split_at(b) {
                        cell_of_edge.entry((a.min(b), a.max(b))).or_insert(c);
                    }
                }
            }
        }
        let geometry = (!junction_copies.is_empty()).then(|| {
            let mut cells_around: HashMap<usize, Vec<usize>> = HashMap::new();
            let mut a_cell_of = HashMap::new();
            for c in 0..split.num_cells() {
                for (&v, &w) in unsplit.cell(c).iter().zip(split.cell(c)) {
                    if split_at(v) {
                        cells_around.entry(v).or_default().push(c);
                        a_cell_of.entry(w).or_insert(c);
                    }
                }
            }
            LevelGeometry {
                vertices: split.vertices().to_vec(),
                cells_around,
                a_cell_of,
            }
        });
        Self {
            plus_of,
            junction_copies,
            num_vertices: split.num_vertices(),
            cells: (0..split.num_cells())
                .flat_map(|c| split.cell(c).to_vec())
                .collect(),
            cell_of_edge,
            geometry,
        }
    }

    /// The copy of original vertex `c` that cell `cell` uses.
    fn copy_in_cell(&self, cell: usize, c: usize) -> Option<usize> {
        let k = D + 1;
        let cell = &self.cells[k * cell..k * cell + k];
        if let Some(copies) = self.junction_copies.get(&c) {
            return cell.iter().copied().find(|v| copies.contains(v));
        }
        let copies = [Some(c), self.plus_of[c]];
        cell.iter().copied().find(|v| copies.contains(&Some(*v)))
    }

    /// Whether original vertex `c` is split (a pair or a junction).
    fn is_split(&self, c: usize) -> bool {
        self.plus_of[c].is_some() || self.junction_copies.contains_key(&c)
    }

    /// Every copy of original vertex `i` (itself first).
    fn copies(&self, i: usize) -> Vec<usize> {
        match (self.junction_copies.get(&i), self.plus_of[i]) {
            (Some(copies), _) => copies.clone(),
            (None, Some(pl)) => vec![i, pl],
            (None, None) => vec![i],
        }
    }

    /// The centroid (m) of a cell of this split level using copy `v` (a copy of a split
    /// vertex), if the level keeps its geometry.
    fn centroid_beside(&self, v: usize) -> Option<[f64; D]> {
        let g = self.geometry.as_ref()?;
        let c = *g.a_cell_of.get(&v)?;
        let k = D + 1;
        let cell = &self.cells[k * c..k * c + k];
        Some(std::array::from_fn(|r| {
            cell.iter().map(|&w| g.vertices[w][r]).sum::<f64>() / k as f64
        }))
    }

    /// The copy of original vertex `c` whose cells hold the point `x` (a coarse vertex's
    /// copy in the sector where a fine cell lies), if any.
    fn copy_at(&self, c: usize, x: &[f64; D]) -> Option<usize> {
        let g = self.geometry.as_ref()?;
        let k = D + 1;
        g.cells_around.get(&c)?.iter().find_map(|&cell| {
            let vs = &self.cells[k * cell..k * cell + k];
            let corners: Vec<[f64; D]> = vs.iter().map(|&w| g.vertices[w]).collect();
            simplex_holds(&corners, x).then(|| self.copy_in_cell(cell, c))?
        })
    }
}

/// Whether the simplex `corners` (`D + 1` points) holds `x` (barycentric coordinates above
/// `−10⁻⁹`).
fn simplex_holds<const D: usize>(corners: &[[f64; D]], x: &[f64; D]) -> bool {
    let volume = |p: &[[f64; D]]| -> f64 {
        let e = |i: usize, r: usize| p[i][r] - p[0][r];
        match D {
            2 => e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0),
            3 => {
                e(1, 0) * (e(2, 1) * e(3, 2) - e(2, 2) * e(3, 1))
                    - e(1, 1) * (e(2, 0) * e(3, 2) - e(2, 2) * e(3, 0))
                    + e(1, 2) * (e(2, 0) * e(3, 1) - e(2, 1) * e(3, 0))
            }
            _ => f64::NAN,
        }
    };
    let whole = volume(corners);
    (0..corners.len()).all(|i| {
        let mut p = corners.to_vec();
        p[i] = *x;
        volume(&p) / whole >= -1e-9
    })
}

/// Cuts every level of `hierarchy` that resolves the faults along them (`split` of the
/// level index and mesh, e.g. [`SimplexMesh::split_along_polylines`] with the faults'
/// points), with the finest level's change of variables by `transform`: the finest must
/// (its errors are returned), coarser levels are split down to the first that does not
/// resolve every fault, and the coarser ones stay continuous across them. The prolongation
/// into a split level interpolates each vertex from the coarse vertices on its own side of
/// every fault (docs/faults-inside.md): the coarse space is discontinuous across the faults
/// wherever the coarse mesh can be, so multigrid's coarse corrections can slip.
///
/// Only a level that does not resolve a fault ends the cutting
/// (`FaultSegmentNotResolved`, `FaultSurfaceNotResolved`); the decision is reported by
/// [`InternalFault::coarsest_split_level`].
///
/// # Errors
/// The finest level's splitting and transform errors; [`crate::Error::InvalidParameter`]
/// named `internal_fault` for any other error of cutting a coarser level (naming the level
/// and the cause) and if the levels are not nested along the faults (a fine vertex
/// interpolating from a split coarse vertex through no coarse edge or cell).
pub(crate) fn split_hierarchy<const D: usize>(
    hierarchy: &MeshHierarchy<D>,
    split: impl Fn(usize, &SimplexMesh<D>) -> crate::Result<(SimplexMesh<D>, FaultNetwork<D>)>,
    transform: impl FnOnce(&FaultNetwork<D>, &SimplexMesh<D>) -> rsf_fem::Result<MeanJumpTransform<D>>,
) -> crate::Result<SplitHierarchy<D>> {
    let finest = hierarchy.finest_level();
    let (mesh, network) = split(finest, hierarchy.finest())?;
    let transform = transform(&network, &mesh)?;
    // Levels finest-first while they resolve the faults; the first that does not (the
    // only error that ends the cutting) and those below stay continuous across them,
    // which the fault reports (InternalFault::coarsest_split_level). Any other error of a
    // coarse level is returned.
    let mut levels = vec![Some(SplitLevel::new(hierarchy.finest(), &mesh, &network))];
    let mut coarsest = finest;
    for j in (0..finest).rev() {
        let coarse = hierarchy.level(j);
        match split(j, coarse) {
            Ok((split, s)) => levels.push(Some(SplitLevel::new(coarse, &split, &s))),
            Err(crate::Error::Fem(
                rsf_fem::Error::FaultSegmentNotResolved { .. }
                | rsf_fem::Error::FaultSurfaceNotResolved { .. },
            )) => break,
            Err(e) => {
                return Err(crate::error::invalid(
                    "internal_fault",
                    format!("cutting level {j} of the hierarchy along the fault: {e}"),
                ))
            }
        }
        coarsest = j;
    }
    levels.resize_with(finest + 1, || None);
    levels.reverse(); // levels[j] for level j
    let prolongations = (1..=finest)
        .map(|j| {
            split_prolongation(
                hierarchy.prolongation(j),
                levels[j].as_ref(),
                levels[j - 1].as_ref(),
            )
        })
        .collect::<crate::Result<Vec<_>>>()?;
    let into_sector = sector_directions(&mesh, &network);
    let n = mesh.num_vertices();
    Ok(SplitHierarchy {
        fault: InternalFault::new(network, transform, n, into_sector)
            .with_coarsest_split_level(coarsest),
        mesh,
        prolongations,
    })
}

/// Every junction copy's unit direction into its sector: towards the centroid of a cell of
/// the split `mesh` that uses it.
fn sector_directions<const D: usize>(
    mesh: &SimplexMesh<D>,
    network: &FaultNetwork<D>,
) -> Vec<(usize, [f64; D])> {
    let copies: Vec<usize> = network
        .junctions()
        .iter()
        .flat_map(|j| j.sectors().iter().map(|s| s.0))
        .collect();
    if copies.is_empty() {
        return Vec::new();
    }
    let x = mesh.vertices();
    copies
        .into_iter()
        .filter_map(|v| {
            let cell = (0..mesh.num_cells()).find(|&c| mesh.cell(c).contains(&v))?;
            let vs = mesh.cell(cell);
            let centroid: [f64; D] =
                std::array::from_fn(|r| vs.iter().map(|&w| x[w][r]).sum::<f64>() / vs.len() as f64);
            let d: [f64; D] = std::array::from_fn(|r| centroid[r] - x[v][r]);
            let l = d.iter().map(|a| a * a).sum::<f64>().sqrt();
            Some((v, d.map(|a| a / l)))
        })
        .collect()
}

/// The scalar prolongation `p` (unsplit fine × unsplit coarse) between split levels: a fine
/// vertex (original or copy) takes its original's row, each entry at a split coarse vertex
/// `c` going to the copy of `c` on the fine vertex's side: for a split fine vertex (on a
/// fault) its own side's copy; for any other, the copy used by the coarse cells around the
/// coarse edge (or vertex) it interpolates from — a coarse edge off the faults lies on one
/// side of them at `c`. At a junction (a coarse or fine copy of one) the copy is found by
/// position: the coarse copy whose cells hold a fine cell that uses the fine copy.
fn split_prolongation<const D: usize>(
    p: &SparseMatrix,
    fine: Option<&SplitLevel<D>>,
    coarse: Option<&SplitLevel<D>>,
) -> crate::Result<SparseMatrix> {
    let Some(fine) = fine else {
        return Ok(p.clone());
    };
    // Each fine row's coarse support (P is stored by columns).
    let mut support: Vec<Vec<usize>> = vec![Vec::new(); p.nrows()];
    for c in 0..p.ncols() {
        for i in p.row_idx_of_col(c) {
            support[i].push(c);
        }
    }
    let not_nested = |i: usize| {
        crate::error::invalid(
            "internal_fault",
            format!(
                "fine vertex {i} interpolates from split coarse vertices {:?} through no \
                 coarse edge: the levels are not nested along the fault",
                support[i]
            ),
        )
    };
    let mut trip = Vec::with_capacity(2 * p.compute_nnz());
    for c in 0..p.ncols() {
        for (i, &w) in p.row_idx_of_col(c).zip(p.val_of_col(c)) {
            let split_c = coarse.filter(|l| l.is_split(c));
            let at_junction = fine.junction_copies.contains_key(&i)
                || split_c.is_some_and(|l| l.junction_copies.contains_key(&c));
            match (split_c, fine.plus_of[i]) {
                (None, _) => {
                    for copy in fine.copies(i) {
                        trip.push(Triplet::new(copy, c, w));
                    }
                }
                // At a junction: each fine copy takes the coarse copy of its sector.
                (Some(level), _) if at_junction => {
                    for copy in fine.copies(i) {
                        // A split fine copy: by the position of a fine cell using it; a
                        // fine vertex off the faults: by its coarse edge.
                        let column = fine
                            .centroid_beside(copy)
                            .and_then(|x| level.copy_at(c, &x))
                            .or_else(|| off_fault_copy(level, &support[i], c))
                            .ok_or_else(|| not_nested(i))?;
                        trip.push(Triplet::new(copy, column, w));
                    }
                }
                // A fault vertex interpolating from a fault vertex: side by side.
                (Some(level), Some(pl)) => {
                    let c_plus = level.plus_of[c].ok_or_else(|| not_nested(i))?;
                    trip.push(Triplet::new(i, c, w));
                    trip.push(Triplet::new(pl, c_plus, w));
                }
                // Off the faults: the copy the coarse cells around its support use.
                (Some(level), None) => {
                    let column =
                        off_fault_copy(level, &support[i], c).ok_or_else(|| not_nested(i))?;
                    trip.push(Triplet::new(i, column, w));
                }
            }
        }
    }
    let ncols = coarse.map_or(p.ncols(), |l| l.num_vertices);
    SparseColMat::try_new_from_triplets(fine.num_vertices, ncols, &trip)
        .map_err(|e| rsf_fem::Error::Faer(format!("{e:?}")).into())
}

/// The copy of split coarse vertex `c` used by the coarse cells around the coarse edge
/// `support` (a fine vertex off the faults interpolating from it).
fn off_fault_copy<const D: usize>(
    level: &SplitLevel<D>,
    support: &[usize],
    c: usize,
) -> Option<usize> {
    let key = match support[..] {
        [a] => (a, a),
        [a, b] => (a.min(b), a.max(b)),
        _ => return None,
    };
    let cell = if key.0 == key.1 {
        None
    } else {
        level.cell_of_edge.get(&key).copied()
    };
    cell.and_then(|cell| level.copy_in_cell(cell, c))
}

/// The fault faces of every level of `hierarchy` (coarsest first) from those of the
/// coarsest, `faces` (vertex triples of level 0): a face of level `j` is on the fault if
/// the coarse vertices its three vertices interpolate from (one for a vertex of level
/// `j − 1`, the edge's two for a midpoint; the prolongation's support) are the three
/// vertices of a fault face of level `j − 1`. Under uniform (red) refinement those are exactly the four
/// children of each coarse face: a conforming mesh has no other face on it.
///
/// # Errors
/// [`crate::Error::InvalidParameter`] named `internal_fault` if a level's faces are not
/// four per coarse face (the hierarchy is not a uniform refinement along the fault).
pub(crate) fn faces_on_levels(
    hierarchy: &MeshHierarchy<3>,
    faces: &[[usize; 3]],
) -> crate::Result<Vec<Vec<[usize; 3]>>> {
    let mut levels = vec![faces.to_vec()];
    for j in 1..hierarchy.num_levels() {
        let p = hierarchy.prolongation(j);
        let mut parents: Vec<Vec<usize>> = vec![Vec::new(); p.nrows()];
        for c in 0..p.ncols() {
            for i in p.row_idx_of_col(c) {
                parents[i].push(c);
            }
        }
        let coarse = levels.last().expect("level 0");
        let mut on_fault: std::collections::HashSet<[usize; 3]> = Default::default();
        for f in coarse {
            let mut k = *f;
            k.sort_unstable();
            on_fault.insert(k);
        }
        // Fine faces, each once, in the order of the cells.
        let mut found = Vec::new();
        for face in hierarchy.level(j).facets() {
            let mut support: Vec<usize> = face
                .iter()
                .flat_map(|&v| parents[v].iter().copied())
                .collect();
            support.sort_unstable();
            support.dedup();
            // A child of a coarse face interpolates from exactly its three vertices.
            if let [a, b, c] = support[..] {
                if on_fault.contains(&[a, b, c]) {
                    found.push(face);
                }
            }
        }
        if found.len() != 4 * coarse.len() {
            return Err(crate::error::invalid(
                "internal_fault",
                format!(
                    "level {j} has {} faces on the fault's {} faces of level {}: the levels \
                     are not uniform refinements along the fault",
                    found.len(),
                    coarse.len(),
                    j - 1
                ),
            ));
        }
        levels.push(found);
    }
    Ok(levels)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_fem::{rectangle, Diagonal};

    /// A coarse level that does not resolve the fault ends the cutting (reported); any
    /// other error of cutting a coarse level is the builder's error naming the level.
    #[test]
    fn only_an_unresolved_coarse_level_stops_the_cutting() {
        let mesh = rectangle([-1.0, -1.0], [2.0, 2.0], 5, 5, Diagonal::Forward).unwrap();
        let hierarchy = MeshHierarchy::try_refine_uniformly(mesh, 2).unwrap();
        let points = [[0.0, -0.5], [0.0, 0.5]];
        let run = |refused: Option<rsf_fem::Error>| {
            split_hierarchy(
                &hierarchy,
                |j, m: &SimplexMesh<2>| match (&refused, j) {
                    (Some(e), 0) => Err(e.clone().into()),
                    _ => Ok(m.split_along_polylines(&[("fault", &points[..])])?),
                },
                |network, m| network.mean_jump_transform::<2>(m),
            )
        };
        let all = run(None).unwrap();
        assert_eq!(all.fault.coarsest_split_level(), 0);
        let unresolved = run(Some(rsf_fem::Error::FaultSegmentNotResolved {
            point: [0.0, -0.5],
        }))
        .unwrap();
        assert_eq!(unresolved.fault.coarsest_split_level(), 1);
        let other = rsf_fem::Error::FaultEdgeOnBoundary {
            edge: 0,
            vertices: [0, 1],
        };
        match run(Some(other)) {
            Err(crate::Error::InvalidParameter { name, reason }) => {
                assert_eq!(name, "internal_fault");
                assert!(
                    reason.contains("level 0") && reason.contains("outer boundary"),
                    "{reason}"
                );
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("an error of a coarse level was ignored"),
        }
    }
}
