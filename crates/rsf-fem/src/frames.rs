//! Nodal frames `Q_p` (tangent(s), inward normal) on boundary nodes and the change of basis
//! they induce on vectors, matrices and prolongations.

use faer::sparse::{SparseColMat, SparseColMatRef, Triplet};
use nalgebra::{SMatrix, SVector, Vector3};

use crate::dof_transform::{symmetrized, DofTransform};
use crate::{Error, Result, SparseMatrix};

/// The frame at a node with outward unit normal `n`: a rotation (row-major, det = +1) whose
/// **last column is the inward normal** `−n` (column
/// [`normal_component`](rsf_numeric::normal_component)`(D)`) and whose first `D − 1`
/// columns are unit tangents (docs/math.md §10):
///
/// * 2D: `t = (−n_y, n_x)` (the counter-clockwise traversal direction of the boundary);
/// * 3D: `t1` = the normalised projection of `hint` onto the tangent plane, or, without a
///   hint, of the Cartesian axis `e_k` with the smallest `|n_k|` (the first such `k`);
///   `t2 = −n × t1`.
///
/// With `n = (0, 0, −1)` (a bottom face, `z` up) the 3D frame is the identity.
///
/// `None` in 3D where `hint` is given and (nearly, its projection `< 1e-6` of its length)
/// normal: the hint gives no tangent there, and the caller reports the node
/// ([`Error::TangentAlongNormal`]) instead of choosing another tangent silently. Never
/// `None` without a hint.
pub fn frame_from_normal<const D: usize>(
    n: &[f64; D],
    hint: Option<&[f64; D]>,
) -> Option<[[f64; D]; D]> {
    let n = SVector::<f64, D>::from(*n);
    let mut q = SMatrix::<f64, D, D>::zeros();
    q.set_column(rsf_numeric::normal_component(D), &-n);
    match D {
        1 => {}
        // The outward normal turned counter-clockwise by 90°.
        2 => {
            q[(0, 0)] = -n[1];
            q[(1, 0)] = n[0];
        }
        _ => {
            let n = Vector3::new(n[0], n[1], n[2]);
            // The unit projection of h onto the tangent plane, unless h is (nearly) normal.
            let project = |h: Vector3<f64>| {
                let t = h - n * h.dot(&n);
                let l = t.norm();
                (l > 0.0 && l >= 1e-6 * h.norm()).then(|| t / l)
            };
            let t1 = match hint {
                Some(h) => project(Vector3::from_iterator(h.iter().copied()))?,
                // The axis with the smallest |n_k| (the first such k): |n_k| ≤ 1/√3.
                None => project(Vector3::ith(n.iamin(), 1.0))
                    .expect("an axis with |n_k| ≤ 1/√3 is never normal"),
            };
            let t2 = (-n).cross(&t1);
            q.fixed_view_mut::<3, 1>(0, 0).copy_from(&t1);
            q.fixed_view_mut::<3, 1>(0, 1).copy_from(&t2);
        }
    }
    Some(std::array::from_fn(|r| std::array::from_fn(|c| q[(r, c)])))
}

/// Per-node orthonormal frames `Q_p` (row-major `D × D`, columns = local basis vectors)
/// on a set of nodes; all other nodes keep the Cartesian basis.
///
/// With `R = blockdiag(Q_p)` (identity off the frame nodes), local coefficients are
/// `ṽ = Rᵀ v`, a matrix transforms as `Ã = Rᵀ A R` and a fine-level prolongation as
/// `P̃ = Rᵀ P` (its coarse side stays Cartesian): the [`DofTransform`] `u = R ũ`
/// (orthogonal, `R⁻¹ = Rᵀ`), whose [`congruence`](DofTransform::congruence) is
/// [`rotate_matrix`](Self::rotate_matrix) made exactly symmetric.
/// The default has no frame nodes (every node Cartesian, the identity).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NodalFrames<const D: usize> {
    /// Mesh vertices carrying a frame.
    pub nodes: Vec<usize>,
    /// `rotations[k][r][c]`: entry (r, c) of `Q` at `nodes[k]`.
    pub rotations: Vec<[[f64; D]; D]>,
}

impl<const D: usize> NodalFrames<D> {
    /// Frames at `nodes` from their outward unit normals (see the rule on
    /// [`crate::BoundaryPart::frames`]), optionally aligning the first tangent with `hint`.
    ///
    /// # Errors
    /// [`Error::TangentAlongNormal`] at the first node where `hint` is (nearly) normal,
    /// naming it and its position (`positions`: the mesh's vertices).
    pub(crate) fn from_normals(
        nodes: Vec<usize>,
        normals: &[[f64; D]],
        hint: Option<&[f64; D]>,
        positions: &[[f64; D]],
    ) -> Result<Self> {
        let rotations = normals
            .iter()
            .zip(&nodes)
            .map(|(n, &p)| {
                frame_from_normal(n, hint).ok_or_else(|| Error::TangentAlongNormal {
                    vertex: p,
                    position: positions[p].to_vec(),
                    normal: n.to_vec(),
                    direction: hint.map_or_else(Vec::new, |h| h.to_vec()),
                })
            })
            .collect::<Result<_>>()?;
        Ok(Self { nodes, rotations })
    }

    fn check(&self, n_dofs: usize) -> Result<Vec<Option<usize>>> {
        if n_dofs % D != 0 {
            return Err(Error::DimensionMismatch {
                what: "node-major vector length",
                expected: D * (n_dofs / D),
                got: n_dofs,
            });
        }
        let mut map = vec![None; n_dofs / D];
        for (k, &v) in self.nodes.iter().enumerate() {
            if v >= map.len() {
                return Err(Error::InvalidDof {
                    node: v,
                    component: 0,
                });
            }
            map[v] = Some(k);
        }
        Ok(map)
    }

    /// `v ← Rᵀ v` (Cartesian → local coefficients), node-major `v`.
    ///
    /// # Errors
    /// [`Error::InvalidDof`] if a frame node is outside `v`.
    pub fn to_local(&self, v: &mut [f64]) -> Result<()> {
        self.apply(v, true)
    }
    /// `v ← R v` (local → Cartesian coefficients).
    ///
    /// # Errors
    /// [`Error::InvalidDof`] if a frame node is outside `v`.
    pub fn to_global(&self, v: &mut [f64]) -> Result<()> {
        self.apply(v, false)
    }
    fn apply(&self, v: &mut [f64], transpose: bool) -> Result<()> {
        self.check(v.len())?;
        for (&p, q) in self.nodes.iter().zip(&self.rotations) {
            let q = SMatrix::<f64, D, D>::from_fn(|r, c| q[r][c]);
            let block = &mut v[D * p..D * p + D];
            let x = SVector::<f64, D>::from_column_slice(block);
            let w = if transpose { q.tr_mul(&x) } else { q * x };
            block.copy_from_slice(w.as_slice());
        }
        Ok(())
    }

    /// `Rᵀ A R` for a node-major square matrix (e.g. `A`, `K`, `M` on the finest level).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] / [`Error::InvalidDof`] on size problems.
    pub fn rotate_matrix(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<SparseColMat<usize, f64>> {
        self.transform(a, true, true)
    }
    /// `Rᵀ P`: rows of a (vector) prolongation into the finest level expressed in the
    /// local bases (the coarse space stays Cartesian).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] / [`Error::InvalidDof`] on size problems.
    pub fn rotate_rows(
        &self,
        p: SparseColMatRef<'_, usize, f64>,
    ) -> Result<SparseColMat<usize, f64>> {
        self.transform(p, true, false)
    }

    fn transform(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
        left: bool,
        right: bool,
    ) -> Result<SparseColMat<usize, f64>> {
        let rmap = if left {
            Some(self.check(a.nrows())?)
        } else {
            None
        };
        let cmap = if right {
            Some(self.check(a.ncols())?)
        } else {
            None
        };
        let mut t = Vec::with_capacity(a.compute_nnz() * D);
        // Left pass: B = Rᵀ A (entry (p,r),j contributes Q_p[r][c] to (p,c), j).
        let push = |i: usize, j: usize, v: f64, t: &mut Vec<Triplet<usize, usize, f64>>| match cmap
            .as_ref()
            .and_then(|m| m[j / D])
        {
            Some(k) => {
                let (q, r) = (j / D, j % D);
                for c in 0..D {
                    let f = self.rotations[k][r][c];
                    if f != 0.0 {
                        t.push(Triplet::new(i, D * q + c, v * f));
                    }
                }
            }
            None => t.push(Triplet::new(i, j, v)),
        };
        for j in 0..a.ncols() {
            for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                match rmap.as_ref().and_then(|m| m[i / D]) {
                    Some(k) => {
                        let (p, r) = (i / D, i % D);
                        for c in 0..D {
                            let f = self.rotations[k][r][c];
                            if f != 0.0 {
                                push(D * p + c, j, v * f, &mut t);
                            }
                        }
                    }
                    None => push(i, j, v, &mut t),
                }
            }
        }
        SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &t)
            .map_err(|e| Error::Faer(format!("{e:?}")))
    }
}

/// `u = R ũ` with `R = blockdiag(Q_p)`: `T⁻¹ = Tᵀ = Rᵀ`.
impl<const D: usize> DofTransform for NodalFrames<D> {
    fn is_identity(&self) -> bool {
        self.nodes.is_empty()
    }

    /// `Rᵀ A R` ([`rotate_matrix`](Self::rotate_matrix)), then `(B + Bᵀ)/2`.
    fn congruence(&self, a: &SparseMatrix) -> Result<SparseMatrix> {
        symmetrized(&self.rotate_matrix(a.as_ref())?)
    }

    /// `Rᵀ f` ([`to_local`](Self::to_local)).
    fn pull_back(&self, f: &[f64]) -> Result<Vec<f64>> {
        let mut v = f.to_vec();
        self.to_local(&mut v)?;
        Ok(v)
    }

    /// `R x` ([`to_global`](Self::to_global)).
    fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>> {
        let mut v = x.to_vec();
        self.to_global(&mut v)?;
        Ok(v)
    }

    /// `Rᵀ x` ([`to_local`](Self::to_local)).
    fn to_model(&self, x: &[f64]) -> Result<Vec<f64>> {
        self.pull_back(x)
    }

    /// `Rᵀ P` ([`rotate_rows`](Self::rotate_rows)).
    fn prolongation(&self, p: &SparseMatrix) -> Result<SparseMatrix> {
        self.rotate_rows(p.as_ref())
    }
}
