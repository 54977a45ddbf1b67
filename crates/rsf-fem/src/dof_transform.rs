//! One change of variables for every non-Cartesian basis of a model's unknowns: nodal frames
//! on a slanted or curved boundary ([`NodalFrames`](crate::NodalFrames), `T = R`), the mean
//! and jump of the split pairs of a fault inside the body
//! ([`MeanJumpTransform`](crate::MeanJumpTransform)), and their composition
//! ([`Composition`]).

use faer::sparse::{SparseColMat, Triplet};

use crate::{Error, Result, SparseMatrix};

/// A change of variables `u = T u′` of node-major vectors (`n = C · vertices` entries, `C`
/// components per vertex): `u` holds Cartesian components at every vertex, `u′` the
/// unknowns a model is written in. `T` is invertible, square (`n × n`) and sparse; a
/// quadratic form `½uᵀAu − Fᵀu` becomes `½u′ᵀ(TᵀAT)u′ − (TᵀF)ᵀu′`, so matrices (stiffness,
/// mass, energy norm, dashpots) go by [`congruence`](Self::congruence), forces (loads) by
/// [`pull_back`](Self::pull_back), fields (displacements, velocities) by
/// [`to_model`](Self::to_model) and back by [`to_cartesian`](Self::to_cartesian), and the
/// finest prolongation of a multigrid hierarchy, whose coarse side stays Cartesian, by
/// [`prolongation`](Self::prolongation).
///
/// Implemented by [`NodalFrames`](crate::NodalFrames) (`T = R = blockdiag(Q_p)`, orthogonal:
/// `T⁻¹ = Tᵀ`; docs/math.md §10.1), by [`MeanJumpTransform`](crate::MeanJumpTransform)
/// (mean and jump at split pairs, not orthogonal; docs/math.md §15) and by a
/// [`Composition`] of two. Each keeps its own arithmetic (a block rotation is not a sparse
/// matrix product), so a model's bits do not depend on which way it is reached.
///
/// # Errors (every method)
/// [`Error::DimensionMismatch`] (or [`Error::InvalidDof`] for a frame node outside the
/// vector) if an argument does not have `T`'s size; [`Error::Faer`] on allocation failure.
pub trait DofTransform {
    /// `true` if `T` is the identity (no frame node, no split pair): every method then
    /// returns its argument unchanged, and a caller may skip it (a congruence would still
    /// rebuild and symmetrise the matrix).
    fn is_identity(&self) -> bool;

    /// `Tᵀ A T` of a symmetric `n × n` matrix `a` (node-major): the matrix in the new
    /// unknowns, made exactly symmetric (`½(B + Bᵀ)` of the product `B`, on its pattern;
    /// the solvers check symmetry bit for bit), computed sequentially (the same bits on
    /// every machine).
    ///
    /// # Errors
    /// As the trait.
    fn congruence(&self, a: &SparseMatrix) -> Result<SparseMatrix>;

    /// `Tᵀ f`: a force vector `f` (`n` entries, N; a load, a dashpot's far-field force) in
    /// the new unknowns, so that `fᵀu = (Tᵀf)ᵀu′`.
    ///
    /// # Errors
    /// As the trait.
    fn pull_back(&self, f: &[f64]) -> Result<Vec<f64>>;

    /// `T x`: a field `x` in the new unknowns (`n` entries) in Cartesian components at every
    /// vertex.
    ///
    /// # Errors
    /// As the trait.
    fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>>;

    /// `T⁻¹ x`: a Cartesian field `x` (`n` entries) in the new unknowns.
    ///
    /// # Errors
    /// As the trait.
    fn to_model(&self, x: &[f64]) -> Result<Vec<f64>>;

    /// `T⁻¹ P`: a prolongation `P` onto the Cartesian dofs (`n` rows, any number of
    /// columns: a coarse space that stays Cartesian) onto the new unknowns, for multigrid
    /// on `Tᵀ A T` (its Galerkin coarse matrices `(T⁻¹P)ᵀ TᵀAT (T⁻¹P) = PᵀAP` are those of
    /// the Cartesian problem).
    ///
    /// # Errors
    /// As the trait.
    fn prolongation(&self, p: &SparseMatrix) -> Result<SparseMatrix>;

    /// The composition `u = T T₂ u″`: first this change of variables, then `next` on its
    /// unknowns `u′ = T₂ u″` (e.g. nodal frames on a boundary, then the mean and jump of a
    /// fault inside the body).
    fn then<U: DofTransform>(self, next: U) -> Composition<Self, U>
    where
        Self: Sized,
    {
        Composition {
            first: self,
            second: next,
        }
    }
}

impl<T: DofTransform + ?Sized> DofTransform for &T {
    fn is_identity(&self) -> bool {
        (**self).is_identity()
    }
    fn congruence(&self, a: &SparseMatrix) -> Result<SparseMatrix> {
        (**self).congruence(a)
    }
    fn pull_back(&self, f: &[f64]) -> Result<Vec<f64>> {
        (**self).pull_back(f)
    }
    fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>> {
        (**self).to_cartesian(x)
    }
    fn to_model(&self, x: &[f64]) -> Result<Vec<f64>> {
        (**self).to_model(x)
    }
    fn prolongation(&self, p: &SparseMatrix) -> Result<SparseMatrix> {
        (**self).prolongation(p)
    }
}

/// `u = T₁ T₂ u″` ([`DofTransform::then`]): `first` (`T₁`) takes Cartesian components to
/// its unknowns `u′`, `second` (`T₂`) those to `u″`. Every operation applies the two in
/// turn: `T₂ᵀ(T₁ᵀ A T₁)T₂`, `T₂ᵀ T₁ᵀ f`, `T₁ T₂ x`, `T₂⁻¹ T₁⁻¹ x`, `T₂⁻¹ T₁⁻¹ P`.
#[derive(Debug, Clone, PartialEq)]
pub struct Composition<A, B> {
    /// `T₁`, applied to Cartesian components.
    pub first: A,
    /// `T₂`, applied to `first`'s unknowns.
    pub second: B,
}

impl<A: DofTransform, B: DofTransform> DofTransform for Composition<A, B> {
    fn is_identity(&self) -> bool {
        self.first.is_identity() && self.second.is_identity()
    }
    fn congruence(&self, a: &SparseMatrix) -> Result<SparseMatrix> {
        self.second.congruence(&self.first.congruence(a)?)
    }
    fn pull_back(&self, f: &[f64]) -> Result<Vec<f64>> {
        self.second.pull_back(&self.first.pull_back(f)?)
    }
    fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>> {
        self.first.to_cartesian(&self.second.to_cartesian(x)?)
    }
    fn to_model(&self, x: &[f64]) -> Result<Vec<f64>> {
        self.second.to_model(&self.first.to_model(x)?)
    }
    fn prolongation(&self, p: &SparseMatrix) -> Result<SparseMatrix> {
        self.second.prolongation(&self.first.prolongation(p)?)
    }
}

/// `(B + Bᵀ)/2` on the pattern of a square, structurally symmetric `b` (a triple product
/// `TᵀAT` of a symmetric `A`, symmetric up to round-off): every stored entry contributes
/// half of itself at `(i, j)` and at `(j, i)`. An entry with both halves is
/// `½b_ij + ½b_ji` (its two halves added once, in either order: the same bits), one
/// without a partner its half alone.
///
/// Merged column by column with `Bᵀ` (one more matrix the size of `b`): the peak is three
/// matrices the size of `b`, where summing `2 nnz` triplets took about six (issue 55: the
/// congruence of a split 3-D model's matrices was its builder's peak). A `b` whose row
/// indices are not sorted within a column takes the triplets.
pub(crate) fn symmetrized(b: &SparseMatrix) -> Result<SparseMatrix> {
    let faer = |e: faer::sparse::FaerError| Error::Faer(format!("{e:?}"));
    let n = b.ncols();
    let sorted = (0..n).all(|j| b.row_idx_of_col(j).is_sorted_by(|a, c| a < c));
    if !sorted || b.nrows() != n {
        return symmetrized_by_triplets(b);
    }
    let bt = b.as_ref().transpose().to_col_major().map_err(faer)?;
    // One merge of column j of `b` and of `bᵀ` (both sorted, no duplicates): `f(i, from
    // b, from bᵀ)` per row of the union.
    let merge = |j: usize, f: &mut dyn FnMut(usize, Option<f64>, Option<f64>)| {
        let (mut x, mut y) = (
            b.row_idx_of_col(j).zip(b.val_of_col(j)).peekable(),
            bt.row_idx_of_col(j).zip(bt.val_of_col(j)).peekable(),
        );
        loop {
            match (x.peek().copied(), y.peek().copied()) {
                (Some((i, &u)), Some((k, &w))) if i == k => {
                    f(i, Some(u), Some(w));
                    x.next();
                    y.next();
                }
                (Some((i, &u)), Some((k, _))) if i < k => {
                    f(i, Some(u), None);
                    x.next();
                }
                (Some((i, &u)), None) => {
                    f(i, Some(u), None);
                    x.next();
                }
                (_, Some((k, &w))) => {
                    f(k, None, Some(w));
                    y.next();
                }
                (None, None) => break,
            }
        }
    };
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0usize);
    for j in 0..n {
        let mut count = 0;
        merge(j, &mut |_, _, _| count += 1);
        col_ptr.push(col_ptr[j] + count);
    }
    let nnz = col_ptr[n];
    let (mut row_idx, mut val) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
    for j in 0..n {
        merge(j, &mut |i, u, w| {
            row_idx.push(i);
            val.push(match (u, w) {
                (Some(u), Some(w)) => 0.5 * u + 0.5 * w,
                (Some(v), None) | (None, Some(v)) => 0.5 * v,
                (None, None) => unreachable!("a row of the union"),
            });
        });
    }
    Ok(SparseColMat::new(
        faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
        val,
    ))
}

/// [`symmetrized`] by summing `2 nnz` triplets (any order of the row indices).
fn symmetrized_by_triplets(b: &SparseMatrix) -> Result<SparseMatrix> {
    let mut t = Vec::with_capacity(2 * b.compute_nnz());
    for j in 0..b.ncols() {
        for (i, &v) in b.row_idx_of_col(j).zip(b.val_of_col(j)) {
            let h = 0.5 * v;
            t.push(Triplet::new(i, j, h));
            t.push(Triplet::new(j, i, h));
        }
    }
    SparseColMat::try_new_from_triplets(b.nrows(), b.ncols(), &t)
        .map_err(|e| Error::Faer(format!("{e:?}")))
}

/// [`Error::DimensionMismatch`] unless `got == expected`.
pub(crate) fn check_len(what: &'static str, expected: usize, got: usize) -> Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(Error::DimensionMismatch {
            what,
            expected,
            got,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        frame_from_normal, rectangle, spmv_add, Assembler, Diagonal, LinearElasticity,
        MeanJumpTransform, MeshHierarchy, NodalFrames, SimplexMesh,
    };

    /// The merged symmetrisation has the pattern and the bits of the triplets' (each entry
    /// with both halves added once, an entry without a partner halved) on a pattern that
    /// is not symmetric, with explicit zeros of both signs; unsorted rows take the
    /// triplets.
    #[test]
    fn merged_symmetrisation_has_the_bits_of_the_triplets() {
        let n = 40;
        let v = values(n * n, 7);
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let x = v[i * n + j];
                // About a third of the entries, not symmetric in pattern.
                if x.abs() < 0.33 || i == j {
                    let x = match (i + 2 * j) % 17 {
                        0 => 0.0,
                        1 => -0.0,
                        _ => x * 1e3,
                    };
                    t.push(Triplet::new(i, j, x));
                }
            }
        }
        let b = SparseColMat::try_new_from_triplets(n, n, &t).unwrap();
        let merged = symmetrized(&b).unwrap();
        let by_triplets = symmetrized_by_triplets(&b).unwrap();
        assert_eq!(merged.col_ptr(), by_triplets.col_ptr());
        assert_eq!(merged.row_idx(), by_triplets.row_idx());
        let bits = |m: &SparseMatrix| m.val().iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&merged), bits(&by_triplets));
        // Not symmetric in pattern: some entries had no partner.
        assert!(merged.compute_nnz() > b.compute_nnz());
        // Symmetric in value.
        let dense = merged.to_dense();
        for i in 0..n {
            for j in 0..n {
                assert_eq!(dense[(i, j)].to_bits(), dense[(j, i)].to_bits());
            }
        }
    }

    /// Deterministic values in (−1, 1).
    fn values(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
            })
            .collect()
    }

    fn dot(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    fn apply(a: &SparseMatrix, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; a.nrows()];
        spmv_add(a.as_ref(), 1.0, x, &mut y);
        y
    }

    /// A 2 × 2 square cut open along x = 1 for y ∈ [0.5, 1.5], its stiffness on the split
    /// mesh, the mean–jump transform of its pairs (shared unequally), and the prolongation
    /// of one refinement (rows onto the split mesh: a plus copy takes its original's row).
    fn split_square() -> (
        SimplexMesh<2>,
        SparseMatrix,
        MeanJumpTransform,
        SparseMatrix,
    ) {
        let coarse = rectangle([0.0; 2], [2.0; 2], 3, 3, Diagonal::Forward).unwrap();
        let hierarchy = MeshHierarchy::refine_uniformly(coarse, 1);
        let (mesh, sides) = hierarchy
            .finest()
            .split_along_segment("f", [1.0, 0.5], [1.0, 1.5])
            .unwrap();
        let k = Assembler::new(&mesh)
            .unwrap()
            .stiffness(&mesh, &LinearElasticity::isotropic(1e3, 0.25).unwrap())
            .unwrap();
        let half = sides.mean_jump_transform::<2>(&mesh).unwrap();
        let shares: Vec<f64> = (0..sides.pairs().len())
            .map(|k| 0.3 + 0.1 * k as f64)
            .collect();
        let t = half.reshared::<2>(&sides, &shares).unwrap();
        let p = hierarchy.vector_prolongation(1);
        let mut trip = Vec::new();
        let original: Vec<usize> = (0..mesh.num_vertices())
            .map(|v| sides.pairs().iter().find(|q| q.1 == v).map_or(v, |q| q.0))
            .collect();
        for (v, &o) in original.iter().enumerate() {
            for c in 0..2 {
                let row = 2 * o + c;
                for j in 0..p.ncols() {
                    for (i, &w) in p.row_idx_of_col(j).zip(p.val_of_col(j)) {
                        if i == row {
                            trip.push(Triplet::new(2 * v + c, j, w));
                        }
                    }
                }
            }
        }
        let p_split =
            SparseColMat::try_new_from_triplets(2 * mesh.num_vertices(), p.ncols(), &trip).unwrap();
        (mesh, k, t, p_split)
    }

    /// Frames of every `stride`-th vertex, turned by angles that differ per vertex.
    fn frames(num_vertices: usize, stride: usize) -> NodalFrames<2> {
        let nodes: Vec<usize> = (0..num_vertices).step_by(stride).collect();
        let rotations = nodes
            .iter()
            .map(|&p| {
                let phi = 0.3 + 0.7 * p as f64;
                frame_from_normal(&[phi.cos(), phi.sin()], None).unwrap()
            })
            .collect();
        NodalFrames { nodes, rotations }
    }

    /// The identities that make `t` a change of variables `u = T u′`: `T T⁻¹ = I`,
    /// `x′ᵀ(TᵀAT)y′ = (Tx′)ᵀA(Ty′)`, `(Tᵀf)ᵀx′ = fᵀ(Tx′)`, `T(T⁻¹P) = P`; `TᵀAT`
    /// exactly symmetric.
    fn check(t: &dyn DofTransform, a: &SparseMatrix, p: &SparseMatrix) {
        let n = a.nrows();
        let scale = a.val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let (x, y, f) = (values(n, 1), values(n, 2), values(n, 3));
        let back = t.to_cartesian(&t.to_model(&x).unwrap()).unwrap();
        assert!(
            back.iter().zip(&x).all(|(b, x)| (b - x).abs() < 1e-12),
            "T T⁻¹ ≠ I"
        );
        let at = t.congruence(a).unwrap();
        for j in 0..n {
            for (i, &v) in at.row_idx_of_col(j).zip(at.val_of_col(j)) {
                let vt = at.val_of_col(i)[at.row_idx_of_col(i).position(|r| r == j).unwrap()];
                assert_eq!(v.to_bits(), vt.to_bits(), "TᵀAT not exactly symmetric");
            }
        }
        let (tx, ty) = (t.to_cartesian(&x).unwrap(), t.to_cartesian(&y).unwrap());
        let lhs = dot(&x, &apply(&at, &y));
        let rhs = dot(&tx, &apply(a, &ty));
        assert!(
            (lhs - rhs).abs() <= 1e-12 * scale * n as f64,
            "{lhs} vs {rhs}"
        );
        let pf = t.pull_back(&f).unwrap();
        assert!((dot(&pf, &x) - dot(&f, &tx)).abs() < 1e-12 * n as f64);
        let c = values(p.ncols(), 4);
        let tp = t.prolongation(p).unwrap();
        let lifted = t.to_cartesian(&apply(&tp, &c)).unwrap();
        let direct = apply(p, &c);
        assert!(lifted
            .iter()
            .zip(&direct)
            .all(|(a, b)| (a - b).abs() < 1e-12));
        assert!(matches!(
            t.pull_back(&f[1..]),
            Err(Error::DimensionMismatch { .. } | Error::InvalidDof { .. })
        ));
    }

    #[test]
    fn nodal_frames_are_a_change_of_variables() {
        let (mesh, k, _, p) = split_square();
        let r = frames(mesh.num_vertices(), 3);
        assert!(!r.is_identity());
        check(&r, &k, &p);
        // Orthogonal: T⁻¹ = Tᵀ.
        let x = values(k.nrows(), 5);
        assert_eq!(r.to_model(&x).unwrap(), r.pull_back(&x).unwrap());
    }

    #[test]
    fn the_mean_and_jump_are_a_change_of_variables() {
        let (_, k, t, p) = split_square();
        assert!(!t.is_identity());
        check(&t, &k, &p);
    }

    /// Frames at some vertices, then the mean and jump: the composition is a change of
    /// variables, and each of its operations is the two in turn, bit for bit.
    #[test]
    fn a_composition_is_the_two_in_turn() {
        let (mesh, k, t, p) = split_square();
        let r = frames(mesh.num_vertices(), 4);
        let both = (&r).then(&t);
        check(&both, &k, &p);
        let in_turn = t.congruence(&r.congruence(&k).unwrap()).unwrap();
        assert_eq!(both.congruence(&k).unwrap().val(), in_turn.val());
        let x = values(k.nrows(), 6);
        let cartesian = r.to_cartesian(&t.to_cartesian(&x).unwrap()).unwrap();
        assert_eq!(both.to_cartesian(&x).unwrap(), cartesian);
        assert!(NodalFrames::<2>::default().is_identity());
        assert!(NodalFrames::<2>::default()
            .then(NodalFrames::<2>::default())
            .is_identity());
        assert!(!both.is_identity());
    }
}
