//! A fault inside the body: the mesh split along it and the mean–jump change of variables
//! the model's matrices are expressed in (docs/faults-inside.md, docs/math.md §15).

use faer::sparse::{SparseColMat, Triplet};
use rsf_fem::{spmv_add, FaultSides, MeanJumpTransform, MeshHierarchy, SimplexMesh, SparseMatrix};

/// A fault inside the body of a [`Model`](crate::Model) built with
/// [`ModelBuilder::internal_fault`](crate::ModelBuilder::internal_fault): the split mesh's
/// pairs `(p⁻, p⁺)` and the change of variables `u = T u′` (docs/math.md §15) in which the
/// model's matrices, loads, states and checkpoints are written. In `u′` the block of `p⁻`
/// is the jump `u⁺ − u⁻` in the pair's frame (tangential slip, then the normal component,
/// tied to 0 for a vector field), the block of `p⁺` the mean `(u⁺ + u⁻)/2` (Cartesian);
/// every other vertex is Cartesian. Γ_F is the minus nodes of the pairs (not the tips, which
/// stay shared and do not slip).
#[derive(Debug, Clone)]
pub struct InternalFault {
    /// The split pairs, tips and faces ([`FaultSides`]).
    pub sides: FaultSides,
    /// `T` and `T⁻¹` (`C·n × C·n`) and the pair frames.
    pub transform: MeanJumpTransform,
    /// Per vertex: `Some((pair, is_plus))` for a vertex of a split pair, index into
    /// [`FaultSides::pairs`].
    pair_of: Vec<Option<(usize, bool)>>,
    pairs: Vec<(usize, usize)>,
}

/// A refinement hierarchy cut open along a fault: the split finest mesh, the fault on it
/// and the scalar prolongations between the levels (each level split where it resolves
/// the fault), in Cartesian components.
pub(crate) struct SplitHierarchy<const D: usize> {
    /// The finest mesh, split.
    pub mesh: SimplexMesh<D>,
    /// The fault on it with its mean–jump transform.
    pub fault: InternalFault,
    /// `P_j` from level `j − 1` to level `j` (`j = 1, …`; one entry per level above the
    /// coarsest), scalar, between the split (or unsplit) levels' vertices.
    pub prolongations: Vec<SparseMatrix>,
}

/// How the builder splits its hierarchy.
pub(crate) type SplitFault<const D: usize> =
    Box<dyn Fn(&MeshHierarchy<D>) -> crate::Result<SplitHierarchy<D>>>;

/// Which side of the fault's line a vertex of a split level lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Minus,
    Plus,
}

/// One level of a hierarchy cut along the segment: its split pairs by original vertex.
struct SplitLevel {
    /// Per original vertex: its plus copy if it is a split pair's minus vertex.
    plus_of: Vec<Option<usize>>,
    /// Vertices of the split level (originals, then plus copies).
    num_vertices: usize,
}

impl SplitLevel {
    fn new(sides: &FaultSides, original: usize, split: usize) -> Self {
        let mut plus_of = vec![None; original];
        for (mi, pl) in sides.pairs() {
            plus_of[mi] = Some(pl);
        }
        Self {
            plus_of,
            num_vertices: split,
        }
    }
}

/// Cuts every level of `hierarchy` that resolves the segment `from → to` along it: the
/// finest must (its errors are returned), coarser levels are split down to the first that
/// does not resolve the segment, and the coarser ones stay continuous across it. The
/// prolongation into a split level interpolates each vertex from the coarse vertices on
/// its own side of the fault (docs/faults-inside.md): the coarse space is discontinuous
/// across the fault wherever the coarse mesh can be, so multigrid's coarse corrections can
/// slip.
///
/// # Errors
/// The finest level's splitting and transform errors; [`crate::Error::InvalidParameter`]
/// named `internal_fault` if a vertex of a split level on the fault's line but not split
/// interpolates from a split coarse vertex (the levels are not nested along the fault).
pub(crate) fn split_hierarchy<const C: usize>(
    hierarchy: &MeshHierarchy<2>,
    name: &str,
    from: [f64; 2],
    to: [f64; 2],
) -> crate::Result<SplitHierarchy<2>> {
    let finest = hierarchy.finest_level();
    let (mesh, sides) = hierarchy.finest().split_along_segment(name, from, to)?;
    let transform = sides.mean_jump_transform::<C>(&mesh)?;
    // Levels finest-first while they resolve the segment.
    let mut levels = vec![Some(SplitLevel::new(
        &sides,
        hierarchy.finest().num_vertices(),
        mesh.num_vertices(),
    ))];
    for j in (0..finest).rev() {
        let coarse = hierarchy.level(j);
        match coarse.split_along_segment(name, from, to) {
            Ok((split, s)) => levels.push(Some(SplitLevel::new(
                &s,
                coarse.num_vertices(),
                split.num_vertices(),
            ))),
            Err(_) => break,
        }
    }
    levels.resize_with(finest + 1, || None);
    levels.reverse(); // levels[j] for level j
    let d = [to[0] - from[0], to[1] - from[1]];
    let len = d[0].hypot(d[1]);
    let side_of = |x: &[f64; 2]| -> Option<Side> {
        let s = (-d[1] * (x[0] - from[0]) + d[0] * (x[1] - from[1])) / len;
        if s.abs() <= 1e-9 * len {
            None
        } else if s > 0.0 {
            Some(Side::Plus)
        } else {
            Some(Side::Minus)
        }
    };
    let prolongations = (1..=finest)
        .map(|j| {
            split_prolongation(
                hierarchy.prolongation(j),
                hierarchy.level(j),
                levels[j].as_ref(),
                levels[j - 1].as_ref(),
                &side_of,
            )
        })
        .collect::<crate::Result<Vec<_>>>()?;
    let n = mesh.num_vertices();
    Ok(SplitHierarchy {
        mesh,
        fault: InternalFault::new(sides, transform, n),
        prolongations,
    })
}

/// The scalar prolongation `p` (unsplit fine × unsplit coarse) between the split levels:
/// a fine vertex (original or plus copy) takes its original's row; an entry at a split
/// coarse vertex goes to the coarse copy on the fine vertex's side (a minus vertex of a
/// pair: minus; a plus copy: plus; any other vertex: its side of the line).
fn split_prolongation(
    p: &SparseMatrix,
    fine_mesh: &SimplexMesh<2>,
    fine: Option<&SplitLevel>,
    coarse: Option<&SplitLevel>,
    side_of: &dyn Fn(&[f64; 2]) -> Option<Side>,
) -> crate::Result<SparseMatrix> {
    let Some(fine) = fine else {
        return Ok(p.clone());
    };
    let mut trip = Vec::with_capacity(2 * p.compute_nnz());
    for c in 0..p.ncols() {
        for (i, &w) in p.row_idx_of_col(c).zip(p.val_of_col(c)) {
            let copies =
                std::iter::once((i, Side::Minus)).chain(fine.plus_of[i].map(|pl| (pl, Side::Plus)));
            for (v, pair_side) in copies {
                let column = match coarse.and_then(|l| l.plus_of[c]) {
                    None => c,
                    Some(c_plus) => {
                        let side = if fine.plus_of[i].is_some() {
                            Some(pair_side)
                        } else {
                            side_of(&fine_mesh.vertices()[i])
                        };
                        match side {
                            Some(Side::Minus) => c,
                            Some(Side::Plus) => c_plus,
                            None => {
                                return Err(crate::error::invalid(
                                    "internal_fault",
                                    format!(
                                        "vertex {i} at {:?} lies on the fault's line but is                                          not split, and interpolates from a split coarse                                          vertex: the levels are not nested along the fault",
                                        fine_mesh.vertices()[i]
                                    ),
                                ))
                            }
                        }
                    }
                };
                trip.push(Triplet::new(v, column, w));
            }
        }
    }
    let ncols = coarse.map_or(p.ncols(), |l| l.num_vertices);
    SparseColMat::try_new_from_triplets(fine.num_vertices, ncols, &trip)
        .map_err(|e| rsf_fem::Error::Faer(format!("{e:?}")).into())
}

impl InternalFault {
    /// The fault of `sides` on a split mesh of `num_vertices` vertices with its transform.
    pub(crate) fn new(
        sides: FaultSides,
        transform: MeanJumpTransform,
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
        }
    }

    /// The split pairs `(p⁻, p⁺)` along the fault (tips excluded).
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// `T x`: a node-major vector of the model's unknowns (`C` per vertex) in Cartesian
    /// components at every vertex, both sides of the fault included.
    ///
    /// # Panics
    /// If `x` is not of `T`'s size (internal invariant: callers pass model vectors).
    pub fn to_cartesian(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        spmv_add(self.transform.t.as_ref(), 1.0, x, &mut out);
        out
    }

    /// `Tᵀ f`: a Cartesian force vector (load, far-field dashpot force) in the new
    /// coordinates.
    pub(crate) fn pull_back(&self, f: &[f64]) -> Vec<f64> {
        let t = self.transform.t.as_ref();
        (0..t.ncols())
            .map(|j| {
                t.row_idx_of_col(j)
                    .zip(t.val_of_col(j))
                    .map(|(i, v)| v * f[i])
                    .sum()
            })
            .collect()
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
        let rj: [f64; C] = if C == 2 {
            let r = self.transform.frames[k];
            std::array::from_fn(|a| r[a][0] * j[0] + r[a][1] * j[1])
        } else {
            j
        };
        let sign = if plus { 0.5 } else { -0.5 };
        Some(std::array::from_fn(|c| w[c] + sign * rj[c]))
    }
}
