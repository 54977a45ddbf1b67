//! The change of variables to mean and jump at the split pairs of a fault inside the body
//! (docs/math.md §15, docs/faults-inside.md).

use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::Par;

use crate::dof_transform::{check_len, symmetrized, DofTransform};
use crate::frames::frame_from_normal;
use crate::{spmv_add, Error, FaultSides, Result, SimplexMesh, SparseMatrix};

/// The mean–jump change of variables `u = T u'` of [`FaultSides::mean_jump_transform`]: a
/// [`DofTransform`] (`T` not orthogonal: vectors go back by `T⁻¹`) with the pair frames and
/// the sides' shares of the jump it was built from.
#[derive(Debug, Clone)]
pub struct MeanJumpTransform<const D: usize = 2> {
    /// `T` (`C·n × C·n`, `n` vertices of the split mesh): new coordinates to node-major
    /// Cartesian ones.
    pub t: SparseMatrix,
    /// `T⁻¹`: node-major Cartesian coordinates to new ones.
    pub t_inv: SparseMatrix,
    /// The pair frame `R_p` of every split pair (row-major, columns `(t, −n)`, `n` the
    /// minus side's outward normal, as [`crate::NodalFrames`]); for `C = 1` unused.
    pub frames: Vec<[[f64; D]; D]>,
    /// The share `β_p ∈ [0, 1]` of the jump the minus side takes at every split pair
    /// (`u⁻ = w − β_p R_p j`, `u⁺ = w + (1 − β_p) R_p j`); ½ for the mean.
    pub minus_share: Vec<f64>,
}

impl FaultSides<2> {
    /// The change of variables to mean and jump at every split pair `(p⁻, p⁺)`, identity
    /// elsewhere (docs/math.md §15): in the new coordinates `u'` the block of `p⁻` holds the
    /// jump `j = R_pᵀ(u⁺ − u⁻)` in the pair's frame (`C = 2`: tangential slip first, then the
    /// normal component `−n·(u⁺ − u⁻)`, minus the opening; `C = 1`: the antiplane slip) and
    /// the block of `p⁺` the mean `w = (u⁺ + u⁻)/2` in Cartesian components, so
    /// `u⁻ = w − R_p j/2`, `u⁺ = w + R_p j/2`. The pair's normal `n` is the length-weighted
    /// mean of the adjacent fault edges' normals ([`FaultSides::normals`]), as the nodal
    /// frames of docs/math.md §10.1. Then `K' = Tᵀ K T`, `b' = Tᵀ b`, and the jump's tangential
    /// components are the slip: friction acts on them, the normal one is tied (a fixed dof).
    ///
    /// # Errors
    /// [`Error::Unsupported`] unless `C` is 1 or 2; [`Error::UndefinedNormal`] if the
    /// adjacent normals of a pair cancel; [`Error::DimensionMismatch`] if `mesh` is not
    /// the split mesh of these sides.
    pub fn mean_jump_transform<const C: usize>(
        &self,
        mesh: &SimplexMesh<2>,
    ) -> Result<MeanJumpTransform> {
        let frames = self.pair_frames::<C>(mesh)?;
        let pairs = self.pairs();
        let half = vec![0.5; pairs.len()];
        assemble_transform::<2, C>(&pairs, mesh.num_vertices(), frames, &half)
    }

    /// The pair frames `R_p` (columns `(t, −n)`) of every split pair, in order.
    fn pair_frames<const C: usize>(&self, mesh: &SimplexMesh<2>) -> Result<Vec<[[f64; 2]; 2]>> {
        if C != 1 && C != 2 {
            return Err(Error::Unsupported(
                "mean-jump transform for C other than 1, 2",
            ));
        }
        let nv = mesh.num_vertices();
        self.check_split_mesh(nv)?;
        let length = |k: usize| mesh.boundary_facet_measure(self.minus_facets()[k]);
        let edges = self.normals().len();
        let mut frames = Vec::new();
        for (i, &(a, b)) in self.nodes().iter().enumerate() {
            if a == b {
                continue;
            }
            let mut n = [0.0; 2];
            for k in [i.wrapping_sub(1), i].into_iter().filter(|&k| k < edges) {
                let w = length(k);
                n[0] += w * self.normals()[k][0];
                n[1] += w * self.normals()[k][1];
            }
            let l = n[0].hypot(n[1]);
            if !(l > 1e-12 * length(i.min(edges - 1))) {
                return Err(Error::UndefinedNormal { vertex: a });
            }
            frames.push(
                frame_from_normal::<2>(&[n[0] / l, n[1] / l], None)
                    .expect("a frame without a tangent always exists"),
            );
        }
        Ok(frames)
    }
}

impl FaultSides<3> {
    /// The change of variables to mean and jump at every split pair `(p⁻, p⁺)` of a 3-D
    /// fault, identity elsewhere (docs/math.md §15), as the 2-D
    /// `FaultSides::<2>::mean_jump_transform`: the block of `p⁻` holds the jump
    /// `j = R_pᵀ(u⁺ − u⁻)` in the pair's frame (`C = 3`: the two tangential slip components
    /// along `t1`, `t2`, then the normal one `−n·(u⁺ − u⁻)`, minus the opening; `C = 1`:
    /// the scalar jump) and the block of `p⁺` the mean `w = (u⁺ + u⁻)/2` in Cartesian
    /// components, so `u⁻ = w − R_p j/2`, `u⁺ = w + R_p j/2`.
    ///
    /// The pair's normal `n` is the area-weighted mean of the normals
    /// ([`FaultSides::normals`]) of the fault faces at the pair (weights: the areas of the
    /// minus side's facets, m²), and `R_p` the frame of
    /// [`crate::NodalFrames`]: columns `(t1, t2, −n)` with `t1` the projection of `tangent`
    /// (m, any length; e.g. the dip or the strike direction) onto the plane normal to `n`,
    /// or of a Cartesian axis if `tangent` is `None`, and `t2 = −n × t1`.
    ///
    /// # Errors
    /// [`Error::Unsupported`] unless `C` is 1 or 3; [`Error::UndefinedNormal`] if the
    /// normals of the faces at a pair cancel; [`Error::TangentAlongNormal`] naming the
    /// pair's minus vertex and position where `tangent` is (nearly) normal to the fault;
    /// [`Error::DimensionMismatch`] if `mesh` is not the split mesh of these sides.
    pub fn mean_jump_transform<const C: usize>(
        &self,
        mesh: &SimplexMesh<3>,
        tangent: Option<&[f64; 3]>,
    ) -> Result<MeanJumpTransform<3>> {
        if C != 1 && C != 3 {
            return Err(Error::Unsupported(
                "mean-jump transform for C other than 1, 3",
            ));
        }
        let nv = mesh.num_vertices();
        self.check_split_mesh(nv)?;
        let nf = mesh.num_boundary_facets();
        if let Some(&f) = self
            .minus_facets()
            .iter()
            .find(|&&f| f != usize::MAX && f >= nf)
        {
            return Err(Error::DimensionMismatch {
                what: "boundary facets of the split mesh of the fault sides",
                expected: f + 1,
                got: nf,
            });
        }
        let pairs = self.pairs();
        let mut pair_of = vec![usize::MAX; nv];
        for (i, &(a, _)) in pairs.iter().enumerate() {
            pair_of[a] = i;
        }
        // The minus side keeps the original vertices: its facets name the pairs' minus ends.
        let mut sum = vec![[0.0; 3]; pairs.len()];
        let mut weight = vec![0.0; pairs.len()];
        for (&f, n) in self.minus_facets().iter().zip(self.normals()) {
            if f == usize::MAX {
                continue;
            }
            let w = mesh.boundary_facet_measure(f);
            for &v in mesh.boundary_facet(f) {
                if let Some(i) = pair_of.get(v).copied().filter(|&i| i != usize::MAX) {
                    (0..3).for_each(|r| sum[i][r] += w * n[r]);
                    weight[i] += w;
                }
            }
        }
        let mut frames = Vec::with_capacity(pairs.len());
        for ((n, w), &(a, _)) in sum.iter().zip(&weight).zip(&pairs) {
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            if !(l > 1e-12 * w) {
                return Err(Error::UndefinedNormal { vertex: a });
            }
            let n = n.map(|x| x / l);
            frames.push(frame_from_normal::<3>(&n, tangent).ok_or_else(|| {
                Error::TangentAlongNormal {
                    vertex: a,
                    position: mesh.vertices()[a].to_vec(),
                    normal: n.to_vec(),
                    direction: tangent.map_or_else(Vec::new, |t| t.to_vec()),
                }
            })?);
        }
        let half = vec![0.5; pairs.len()];
        assemble_transform::<3, C>(&pairs, nv, frames, &half)
    }
}

/// `T` and `T⁻¹` of the pairs `pairs` on `nv` vertices with their frames and the minus
/// sides' shares of the jump.
fn assemble_transform<const D: usize, const C: usize>(
    pairs: &[(usize, usize)],
    nv: usize,
    frames: Vec<[[f64; D]; D]>,
    minus_share: &[f64],
) -> Result<MeanJumpTransform<D>> {
    if minus_share.len() != pairs.len() {
        return Err(Error::DimensionMismatch {
            what: "jump shares (one per split pair)",
            expected: pairs.len(),
            got: minus_share.len(),
        });
    }
    if minus_share.iter().any(|b| !(0.0..=1.0).contains(b)) {
        return Err(Error::Unsupported("a jump share outside [0, 1]"));
    }
    // A vector field's jump is in the pair's frame; a scalar field's is the field's own.
    let rotated = C == D && C > 1;
    let mut in_pair = vec![false; nv];
    let mut t = Vec::new();
    let mut ti = Vec::new();
    for ((&(a, b), r), &beta_minus) in pairs.iter().zip(&frames).zip(minus_share) {
        let beta_plus = 1.0 - beta_minus;
        in_pair[a] = true;
        in_pair[b] = true;
        for x in 0..C {
            for y in 0..C {
                let (rxy, id) = if rotated {
                    (r[x][y], f64::from(u8::from(x == y)))
                } else {
                    (1.0, 1.0)
                };
                // u⁻ = w − β R j, u⁺ = w + (1 − β) R j.
                t.push(Triplet::new(C * a + x, C * a + y, -beta_minus * rxy));
                t.push(Triplet::new(C * b + x, C * a + y, beta_plus * rxy));
                if id != 0.0 {
                    t.push(Triplet::new(C * a + x, C * b + y, 1.0));
                    t.push(Triplet::new(C * b + x, C * b + y, 1.0));
                }
                // j = Rᵀ(u⁺ − u⁻), w = (1 − β) u⁻ + β u⁺; (Rᵀ)_{xy} = R_{yx}.
                let ryx = if rotated { r[y][x] } else { 1.0 };
                ti.push(Triplet::new(C * a + x, C * a + y, -ryx));
                ti.push(Triplet::new(C * a + x, C * b + y, ryx));
                if id != 0.0 {
                    ti.push(Triplet::new(C * b + x, C * a + y, beta_plus));
                    ti.push(Triplet::new(C * b + x, C * b + y, beta_minus));
                }
            }
        }
    }
    for p in (0..nv).filter(|&p| !in_pair[p]) {
        for x in 0..C {
            t.push(Triplet::new(C * p + x, C * p + x, 1.0));
            ti.push(Triplet::new(C * p + x, C * p + x, 1.0));
        }
    }
    let n = C * nv;
    let build = |trip: &[Triplet<usize, usize, f64>]| {
        SparseColMat::try_new_from_triplets(n, n, trip).map_err(|e| Error::Faer(format!("{e:?}")))
    };
    Ok(MeanJumpTransform {
        t: build(&t)?,
        t_inv: build(&ti)?,
        frames,
        minus_share: minus_share.to_vec(),
    })
}

impl<const D: usize> MeanJumpTransform<D> {
    /// The same change of variables with the jump shared unequally between the sides: at
    /// pair `p` (in the order of [`FaultSides::pairs`]) `u⁻ = w − β_p R_p j`,
    /// `u⁺ = w + (1 − β_p) R_p j`, so `j = R_pᵀ(u⁺ − u⁻)` is still the jump and
    /// `w = (1 − β_p) u⁻ + β_p u⁺` a weighted mean (`β_p = ½`: the mean). With `β_p` the
    /// plus side's share of the two sides' stiffness at the pair, `w` follows the stiffer
    /// side and the jump's diagonal coupling to it vanishes: a node-block smoother then
    /// relaxes the slip without dragging a stiff side along (a body on a much stiffer
    /// base, docs/faults-inside.md). `sides` are the fault's of this transform.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if `minus_share` does not have one entry per pair;
    /// [`Error::Unsupported`] for a share outside `[0, 1]` or `C` other than 1 and `D`.
    pub fn reshared<const C: usize>(
        &self,
        sides: &FaultSides<D>,
        minus_share: &[f64],
    ) -> Result<MeanJumpTransform<D>> {
        if C != 1 && C != D {
            return Err(Error::Unsupported(
                "mean-jump transform for C other than 1 and the dimension",
            ));
        }
        assemble_transform::<D, C>(
            &sides.pairs(),
            self.t.nrows() / C,
            self.frames.clone(),
            minus_share,
        )
    }
}

/// `u = T u'`: the mean and jump at every split pair, the identity elsewhere.
impl<const D: usize> DofTransform for MeanJumpTransform<D> {
    /// No split pair.
    fn is_identity(&self) -> bool {
        self.frames.is_empty()
    }

    /// `Tᵀ A T` of a symmetric matrix `a` of the split mesh (stiffness, mass, energy norm;
    /// `C·n × C·n`, node-major): two sequential sparse products `Tᵀ(A T)`, then
    /// `(B + Bᵀ)/2`. Explicit zeros of the product are kept.
    fn congruence(&self, a: &SparseMatrix) -> Result<SparseMatrix> {
        let n = self.t.nrows();
        check_len("matrix of the split mesh for Tᵀ A T", n, a.nrows())?;
        check_len("matrix of the split mesh for Tᵀ A T", n, a.ncols())?;
        let faer = |e: faer::sparse::FaerError| Error::Faer(format!("{e:?}"));
        // `A T` and `Tᵀ` dropped before the symmetrisation: the peak is `A`, then `A T` and
        // `B`, then `B` and `(B + Bᵀ)/2` with `Bᵀ`.
        let b = {
            let at =
                sparse_sparse_matmul(a.as_ref(), self.t.as_ref(), 1.0, Par::Seq).map_err(faer)?;
            let tt = self.t.as_ref().transpose().to_col_major().map_err(faer)?;
            sparse_sparse_matmul(tt.as_ref(), at.as_ref(), 1.0, Par::Seq).map_err(faer)?
        };
        symmetrized(&b)
    }

    /// `Tᵀ f`, column by column of `T`.
    fn pull_back(&self, f: &[f64]) -> Result<Vec<f64>> {
        let t = self.t.as_ref();
        check_len(
            "force vector of the split mesh for Tᵀ f",
            t.nrows(),
            f.len(),
        )?;
        Ok((0..t.ncols())
            .map(|j| {
                t.row_idx_of_col(j)
                    .zip(t.val_of_col(j))
                    .map(|(i, v)| v * f[i])
                    .sum()
            })
            .collect())
    }

    /// `T x`: at a pair `u⁻ = w − β R j`, `u⁺ = w + (1 − β) R j`.
    fn to_cartesian(&self, x: &[f64]) -> Result<Vec<f64>> {
        check_len(
            "model vector of the split mesh for T x",
            self.t.ncols(),
            x.len(),
        )?;
        let mut out = vec![0.0; x.len()];
        spmv_add(self.t.as_ref(), 1.0, x, &mut out);
        Ok(out)
    }

    /// `T⁻¹ x`: at a pair `j = Rᵀ(u⁺ − u⁻)`, `w = (1 − β) u⁻ + β u⁺`.
    fn to_model(&self, x: &[f64]) -> Result<Vec<f64>> {
        check_len(
            "Cartesian vector of the split mesh for T⁻¹ x",
            self.t_inv.ncols(),
            x.len(),
        )?;
        let mut out = vec![0.0; x.len()];
        spmv_add(self.t_inv.as_ref(), 1.0, x, &mut out);
        Ok(out)
    }

    /// `T⁻¹ P` (one sequential sparse product), e.g. of the coarse space continuous across
    /// the fault (a plus copy taking its original's row) or split along it.
    fn prolongation(&self, p: &SparseMatrix) -> Result<SparseMatrix> {
        check_len("prolongation rows for T⁻¹ P", self.t_inv.ncols(), p.nrows())?;
        sparse_sparse_matmul(self.t_inv.as_ref(), p.as_ref(), 1.0, Par::Seq)
            .map_err(|e| Error::Faer(format!("{e:?}")))
    }
}
