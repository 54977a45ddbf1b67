//! A fault inside the body: the mesh split along it and the mean–jump change of variables
//! the model's matrices are expressed in (docs/faults-inside.md, docs/math.md §15).

use std::collections::HashMap;

use faer::sparse::{SparseColMat, Triplet};
use rsf_fem::{FaultSides, MeanJumpTransform, MeshHierarchy, SimplexMesh, SparseMatrix};

/// A fault inside the body of a [`Model`](crate::Model) built with
/// [`ModelBuilder::internal_fault`](crate::ModelBuilder::internal_fault): the split mesh's
/// pairs `(p⁻, p⁺)` and the change of variables `u = T u′` (docs/math.md §15) in which the
/// model's matrices, loads, states and checkpoints are written. In `u′` the block of `p⁻`
/// is the jump `u⁺ − u⁻` in the pair's frame (tangential slip, then the normal component,
/// tied to 0 for a vector field), the block of `p⁺` a weighted mean `(1 − β) u⁻ + β u⁺`
/// (Cartesian; `β` the plus side's share of the stiffness at the pair, ½ for a body the
/// same on both sides, [`MeanJumpTransform::minus_share`]);
/// every other vertex is Cartesian. Γ_F is the minus nodes of the pairs (not the tips, which
/// stay shared and do not slip).
#[derive(Debug, Clone)]
pub struct InternalFault<const D: usize = 2> {
    /// The split pairs, tips and faces ([`FaultSides`]).
    pub sides: FaultSides<D>,
    /// `T` and `T⁻¹` (`C·n × C·n`), the pair frames and the sides' shares of the jump: the
    /// model's change of variables ([`Model::transform`](crate::Model::transform), a
    /// [`DofTransform`](rsf_fem::DofTransform): `T x` of a model vector is Cartesian at
    /// every vertex, `T⁻¹ x` goes back).
    pub transform: MeanJumpTransform<D>,
    /// Per vertex: `Some((pair, is_plus))` for a vertex of a split pair, index into
    /// [`FaultSides::pairs`].
    pair_of: Vec<Option<(usize, bool)>>,
    pairs: Vec<(usize, usize)>,
    /// The coarsest level of the hierarchy cut along the fault.
    coarsest_split_level: usize,
}

/// A side of a fault inside the body: the minus side Ω⁻ (whose face carries the tag
/// `{name}_minus`, the first vertex `p⁻` of every split pair; the fault's normal points
/// from it into the plus side) or the plus side Ω⁺.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FaultSide {
    /// Ω⁻ (`p⁻`).
    Minus,
    /// Ω⁺ (`p⁺`).
    Plus,
}

/// A refinement hierarchy cut open along a fault: the split finest mesh, the fault on it
/// and the scalar prolongations between the levels (each level split where it resolves
/// the fault), in Cartesian components.
pub(crate) struct SplitHierarchy<const D: usize> {
    /// The finest mesh, split.
    pub mesh: SimplexMesh<D>,
    /// The fault on it with its mean–jump transform.
    pub fault: InternalFault<D>,
    /// `P_j` from level `j − 1` to level `j` (`j = 1, …`; one entry per level above the
    /// coarsest), scalar, between the split (or unsplit) levels' vertices.
    pub prolongations: Vec<SparseMatrix>,
}

/// How the builder splits its hierarchy, given the checked
/// [`fault_tangent`](crate::ModelBuilder::fault_tangent) (3-D pair frames).
pub(crate) type SplitFault<const D: usize> =
    Box<dyn Fn(&MeshHierarchy<D>, Option<&[f64; D]>) -> crate::Result<SplitHierarchy<D>>>;

/// One level of a hierarchy cut along the fault.
struct SplitLevel {
    /// Per original vertex: its plus copy if it is a split pair's minus vertex.
    plus_of: Vec<Option<usize>>,
    /// Vertices of the split level (originals, then plus copies).
    num_vertices: usize,
    /// The split level's cells (`D + 1` vertices each, flat): the same cells in the same order
    /// and vertex order as the unsplit level's, a plus-side cell naming plus copies.
    cells: Vec<usize>,
    /// `D + 1`.
    vertices_per_cell: usize,
    /// A cell of the unsplit level holding each edge `(min, max)` that touches a split
    /// vertex.
    cell_of_edge: HashMap<(usize, usize), usize>,
}

impl SplitLevel {
    fn new<const D: usize>(
        unsplit: &SimplexMesh<D>,
        split: &SimplexMesh<D>,
        sides: &FaultSides<D>,
    ) -> Self {
        let mut plus_of = vec![None; unsplit.num_vertices()];
        for (mi, pl) in sides.pairs() {
            plus_of[mi] = Some(pl);
        }
        let mut cell_of_edge = HashMap::new();
        // Every two vertices of a simplex are joined by one of its edges.
        for c in 0..unsplit.num_cells() {
            let cell = unsplit.cell(c);
            for k in 0..cell.len() {
                for &b in &cell[k + 1..] {
                    let a = cell[k];
                    if plus_of[a].is_some() || plus_of[b].is_some() {
                        cell_of_edge.entry((a.min(b), a.max(b))).or_insert(c);
                    }
                }
            }
        }
        Self {
            plus_of,
            num_vertices: split.num_vertices(),
            vertices_per_cell: D + 1,
            cells: (0..split.num_cells())
                .flat_map(|c| split.cell(c).to_vec())
                .collect(),
            cell_of_edge,
        }
    }

    /// The copy of original vertex `c` that cell `cell` uses.
    fn copy_in_cell(&self, cell: usize, c: usize) -> Option<usize> {
        let copies = [Some(c), self.plus_of[c]];
        let k = self.vertices_per_cell;
        self.cells[k * cell..k * cell + k]
            .iter()
            .copied()
            .find(|v| copies.contains(&Some(*v)))
    }
}

/// Cuts every level of `hierarchy` that resolves the fault along it (`split` of the level
/// index and mesh, e.g. [`SimplexMesh::split_along_polyline`] with the fault's points),
/// with the finest level's
/// change of variables by `transform`: the finest must (its errors are returned), coarser levels are split down to the first that
/// does not resolve it, and the coarser ones stay continuous across it. The prolongation
/// into a split level interpolates each vertex from the coarse vertices on its own side of
/// the fault (docs/faults-inside.md): the coarse space is discontinuous across the fault
/// wherever the coarse mesh can be, so multigrid's coarse corrections can slip.
///
/// Only a level that does not resolve the fault ends the cutting
/// (`FaultSegmentNotResolved`, `FaultSurfaceNotResolved`); the decision is reported by
/// [`InternalFault::coarsest_split_level`].
///
/// # Errors
/// The finest level's splitting and transform errors; [`crate::Error::InvalidParameter`]
/// named `internal_fault` for any other error of cutting a coarser level (naming the level
/// and the cause) and if the levels are not nested along the fault (a fine vertex
/// interpolating from a split coarse vertex through no coarse edge or cell).
pub(crate) fn split_hierarchy<const D: usize>(
    hierarchy: &MeshHierarchy<D>,
    split: impl Fn(usize, &SimplexMesh<D>) -> rsf_fem::Result<(SimplexMesh<D>, FaultSides<D>)>,
    transform: impl FnOnce(&FaultSides<D>, &SimplexMesh<D>) -> rsf_fem::Result<MeanJumpTransform<D>>,
) -> crate::Result<SplitHierarchy<D>> {
    let finest = hierarchy.finest_level();
    let (mesh, sides) = split(finest, hierarchy.finest())?;
    let transform = transform(&sides, &mesh)?;
    // Levels finest-first while they resolve the fault; the first that does not (the
    // only error that ends the cutting) and those below stay continuous across it, which
    // the fault reports (InternalFault::coarsest_split_level). Any other error of a
    // coarse level is returned.
    let mut levels = vec![Some(SplitLevel::new(hierarchy.finest(), &mesh, &sides))];
    let mut coarsest = finest;
    for j in (0..finest).rev() {
        let coarse = hierarchy.level(j);
        match split(j, coarse) {
            Ok((split, s)) => levels.push(Some(SplitLevel::new(coarse, &split, &s))),
            Err(
                rsf_fem::Error::FaultSegmentNotResolved { .. }
                | rsf_fem::Error::FaultSurfaceNotResolved { .. },
            ) => break,
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
    let n = mesh.num_vertices();
    Ok(SplitHierarchy {
        mesh,
        fault: InternalFault {
            coarsest_split_level: coarsest,
            ..InternalFault::new(sides, transform, n)
        },
        prolongations,
    })
}

/// The scalar prolongation `p` (unsplit fine × unsplit coarse) between split levels: a fine
/// vertex (original or plus copy) takes its original's row, each entry at a split coarse
/// vertex `c` going to the copy of `c` on the fine vertex's side: for a split fine vertex
/// (on the fault) its own side's copy; for any other, the copy used by the coarse cells
/// around the coarse edge (or vertex) it interpolates from — a coarse edge off the fault
/// lies on one side of it at `c`.
fn split_prolongation(
    p: &SparseMatrix,
    fine: Option<&SplitLevel>,
    coarse: Option<&SplitLevel>,
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
            let split_c = coarse.and_then(|l| l.plus_of[c].map(|pl| (l, pl)));
            match (split_c, fine.plus_of[i]) {
                (None, plus) => {
                    trip.push(Triplet::new(i, c, w));
                    if let Some(pl) = plus {
                        trip.push(Triplet::new(pl, c, w));
                    }
                }
                // A fault vertex interpolating from a fault vertex: side by side.
                (Some((_, c_plus)), Some(pl)) => {
                    trip.push(Triplet::new(i, c, w));
                    trip.push(Triplet::new(pl, c_plus, w));
                }
                // Off the fault: the copy the coarse cells around its support use.
                (Some((level, _)), None) => {
                    let key = match support[i][..] {
                        [a] => (a, a),
                        [a, b] => (a.min(b), a.max(b)),
                        _ => return Err(not_nested(i)),
                    };
                    let cell = if key.0 == key.1 {
                        None
                    } else {
                        level.cell_of_edge.get(&key).copied()
                    };
                    let column = cell
                        .and_then(|cell| level.copy_in_cell(cell, c))
                        .ok_or_else(|| not_nested(i))?;
                    trip.push(Triplet::new(i, column, w));
                }
            }
        }
    }
    let ncols = coarse.map_or(p.ncols(), |l| l.num_vertices);
    SparseColMat::try_new_from_triplets(fine.num_vertices, ncols, &trip)
        .map_err(|e| rsf_fem::Error::Faer(format!("{e:?}")).into())
}

impl<const D: usize> InternalFault<D> {
    /// The fault of `sides` on a split mesh of `num_vertices` vertices with its transform.
    pub(crate) fn new(
        sides: FaultSides<D>,
        transform: MeanJumpTransform<D>,
        num_vertices: usize,
    ) -> Self {
        let pairs = sides.pairs();
        let mut pair_of = vec![None; num_vertices];
        for (k, &(mi, pl)) in pairs.iter().enumerate() {
            pair_of[mi] = Some((k, false));
            pair_of[pl] = Some((k, true));
        }
        Self {
            sides,
            transform,
            pair_of,
            pairs,
            coarsest_split_level: 0,
        }
    }

    /// The coarsest level of the model's refinement hierarchy that is cut along the fault
    /// (0: every level; the finest level's index: only the finest). The levels below it do
    /// not resolve the fault (`rsf_fem::Error::FaultSegmentNotResolved` in 2-D,
    /// `FaultSurfaceNotResolved` in 3-D) and stay continuous across it — the decision
    /// the builder takes there, reported here (docs/faults-inside.md, "Multigrid"): their
    /// coarse corrections cannot slip, so TNNMG converges more slowly than with every
    /// level cut.
    pub fn coarsest_split_level(&self) -> usize {
        self.coarsest_split_level
    }

    /// The fault with its jump shared between the sides by their stiffness at each pair
    /// ([`MeanJumpTransform::reshared`]): `β_p = k⁺/(k⁻ + k⁺)` with `k^±` the trace
    /// of the diagonal block of `stiffness` (Cartesian, on the split mesh of `C` components
    /// per vertex) at the pair's two vertices; `β_p = ½` exactly (the mean) where the two
    /// agree to 1e-9 (a body the same on both sides).
    ///
    /// # Errors
    /// The transform's errors.
    pub(crate) fn shared_by_stiffness<const C: usize>(
        self,
        stiffness: &SparseMatrix,
    ) -> crate::Result<Self> {
        let diagonal = |p: usize| -> f64 {
            (C * p..C * p + C)
                .map(|j| {
                    stiffness
                        .row_idx_of_col(j)
                        .zip(stiffness.val_of_col(j))
                        .find(|&(i, _)| i == j)
                        .map_or(0.0, |(_, &v)| v)
                })
                .sum()
        };
        let share: Vec<f64> = self
            .pairs
            .iter()
            .map(|&(mi, pl)| {
                let (km, kp) = (diagonal(mi), diagonal(pl));
                if (km - kp).abs() <= 1e-9 * (km + kp) || !(km + kp > 0.0) {
                    0.5
                } else {
                    (kp / (km + kp)).clamp(0.0, 1.0)
                }
            })
            .collect();
        let transform = self.transform.reshared::<C>(&self.sides, &share)?;
        let n = self.pair_of.len();
        let coarsest_split_level = self.coarsest_split_level;
        Ok(Self {
            coarsest_split_level,
            ..Self::new(self.sides, transform, n)
        })
    }

    /// The split pairs `(p⁻, p⁺)` along the fault (tips excluded).
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The pair `(p⁻, p⁺)` that `vertex` belongs to, `None` for a vertex off the split.
    pub fn pair_of(&self, vertex: usize) -> Option<(usize, usize)> {
        let (k, _) = self.pair_of.get(vertex).copied().flatten()?;
        Some(self.pairs[k])
    }

    /// The copy of `vertex` on `side` if it is a split vertex, else `vertex` itself.
    pub fn copy_on(&self, vertex: usize, side: FaultSide) -> usize {
        match (self.pair_of(vertex), side) {
            (Some((minus, _)), FaultSide::Minus) => minus,
            (Some((_, plus)), FaultSide::Plus) => plus,
            (None, _) => vertex,
        }
    }

    /// The point `x` of `vertex` moved into its side of the fault by `10⁻⁹` of its largest
    /// coordinate (at least 10⁻⁹ m) along the pair's normal, for a function of position
    /// that tells the sides apart (e.g. an initial velocity that jumps across the fault);
    /// `x` itself off the fault.
    pub(crate) fn moved_into_side(&self, vertex: usize, x: &[f64; D]) -> [f64; D] {
        let Some((k, plus)) = self.pair_of.get(vertex).copied().flatten() else {
            return *x;
        };
        let r = self.transform.frames[k];
        // R's columns are (t…, −n), n pointing from the minus into the plus side.
        let size = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let delta = if plus { 1e-9 } else { -1e-9 } * size;
        std::array::from_fn(|a| x[a] + delta * -r[a][rsf_numeric::normal_component(D)])
    }

    /// The Cartesian block of `vertex` of the model vector `x` (`C` components per
    /// vertex): `w ∓ R_p j/2` at a pair's minus/plus vertex, `None` at any other vertex.
    pub(crate) fn vertex_block<const C: usize>(
        &self,
        vertex: usize,
        x: &[f64],
    ) -> Option<[f64; C]> {
        let (k, plus) = self.pair_of.get(vertex).copied().flatten()?;
        let (mi, pl) = self.pairs[k];
        let j: [f64; C] = std::array::from_fn(|c| x[C * mi + c]);
        let w: [f64; C] = std::array::from_fn(|c| x[C * pl + c]);
        let rj: [f64; C] = if C == D && C > 1 {
            let r = self.transform.frames[k];
            std::array::from_fn(|a| (1..C).fold(r[a][0] * j[0], |s, b| s + r[a][b] * j[b]))
        } else {
            j
        };
        let beta = self.transform.minus_share[k];
        let share = if plus { 1.0 - beta } else { -beta };
        Some(std::array::from_fn(|c| w[c] + share * rj[c]))
    }
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
                    (Some(e), 0) => Err(e.clone()),
                    _ => m.split_along_polyline("fault", &points),
                },
                |sides, m| sides.mean_jump_transform::<2>(m),
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
