//! A fault inside the body: the mesh split along it and the mean–jump change of variables
//! the model's matrices are expressed in (docs/faults-inside.md, docs/math.md §15).

use rsf_fem::{spmv_add, FaultSides, MeanJumpTransform, SimplexMesh};

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

/// How the builder splits its finest mesh: the split mesh and the fault on it.
pub(crate) type SplitFault<const D: usize> =
    Box<dyn Fn(&SimplexMesh<D>) -> crate::Result<(SimplexMesh<D>, InternalFault)>>;

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
