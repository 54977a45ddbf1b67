//! The change of variables to mean and jump at the split pairs of a fault inside the body
//! (docs/math.md §15, docs/faults-inside.md).

use faer::sparse::linalg::matmul::sparse_sparse_matmul;
use faer::sparse::{SparseColMat, Triplet};
use faer::Par;

use crate::dof_transform::{check_len, symmetrized, DofTransform};
use crate::frames::frame_from_normal;
use crate::{
    spmv_add, Error, FaultNetwork, FaultSides, JunctionKind, Result, SimplexMesh, SparseMatrix,
};

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
    /// The junctions of a [`FaultNetwork`] (empty for a fault alone): the blocks of their
    /// copies. [`frames`](Self::frames) and [`minus_share`](Self::minus_share) have the
    /// network's split pairs first ([`FaultNetwork::pairs`]), then every junction's jumps
    /// ([`JunctionBlocks::jumps`], junction after junction; share ½).
    pub junctions: Vec<JunctionBlocks>,
}

/// The unknowns of a junction of a [`FaultNetwork`] in its mean–jump transform
/// (docs/math.md §16): the sector copies `u_S` of the vertex are written as
/// `u_S = w + Σ_f α_{S,f} R_f j_f + γ_S e` — a mean `w` (Cartesian), the jump `j_f` of every
/// fault going on through the junction in its frame `R_f` (tangential slip, normal
/// component tied: no opening), and a block `e` tied to 0 (all components: the ending
/// fault's jump of a branch, the crossing's incompatibility `u₊₊ − u₊₋ − u₋₊ + u₋₋`), so
/// that every fault's slip is single-valued at the junction and the jumps around it add up
/// to zero.
#[derive(Debug, Clone, PartialEq)]
pub struct JunctionBlocks {
    /// The vertex whose block is the mean `w`.
    pub mean: usize,
    /// Every going-through fault's jump: `(fault, vertex whose block is j_f, index of its
    /// frame in` [`MeanJumpTransform::frames`]`)`.
    pub jumps: Vec<(usize, usize, usize)>,
    /// The vertex whose block `e` is tied to 0.
    pub tied: usize,
    /// Per sector: its copy and the coefficients `α_{S,f}` (one per jump) and `γ_S` of
    /// `u_S`, and the weights of `T⁻¹`: `w = Σ ω_S u_S`, `j_f = R_fᵀ Σ β_{S,f} u_S`,
    /// `e = Σ δ_S u_S`.
    pub sectors: Vec<SectorBlocks>,
}

/// One sector's row of a [`JunctionBlocks`].
#[derive(Debug, Clone, PartialEq)]
pub struct SectorBlocks {
    /// The copy of the junction's vertex in this sector.
    pub copy: usize,
    /// `α_{S,f}`, one per jump.
    pub alpha: Vec<f64>,
    /// `γ_S`.
    pub gamma: f64,
    /// `ω_S`.
    pub omega: f64,
    /// `β_{S,f}`, one per jump.
    pub beta: Vec<f64>,
    /// `δ_S`.
    pub delta: f64,
}

impl JunctionBlocks {
    /// The Cartesian block of sector copy `vertex` of the model vector `x` (`C` entries per
    /// vertex, the transform's unknowns), `None` if `vertex` is no copy of this junction.
    ///
    /// `frames` are the transform's ([`MeanJumpTransform::frames`]); junctions exist for
    /// vector fields only (`C = D`).
    pub fn cartesian_block<const D: usize, const C: usize>(
        &self,
        vertex: usize,
        x: &[f64],
        frames: &[[[f64; D]; D]],
    ) -> Option<[f64; C]> {
        let s = self.sectors.iter().find(|s| s.copy == vertex)?;
        let block = |v: usize| -> [f64; C] { std::array::from_fn(|c| x[C * v + c]) };
        let mut out = block(self.mean);
        for (&(_, v, k), &a) in self.jumps.iter().zip(&s.alpha) {
            let j = block(v);
            let r = &frames[k];
            for (c, o) in out.iter_mut().enumerate() {
                *o += a * (0..C).map(|d| r[c][d] * j[d]).sum::<f64>();
            }
        }
        let e = block(self.tied);
        for (o, e) in out.iter_mut().zip(e) {
            *o += s.gamma * e;
        }
        Some(out)
    }
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
        let mut frames = Vec::new();
        for (i, &(a, b)) in self.nodes().iter().enumerate() {
            if a == b || self.is_junction_node(i) {
                continue;
            }
            frames.push(self.node_frame(mesh, i)?);
        }
        Ok(frames)
    }

    /// The frame `R` (columns `(t, −n)`) at node `i` of [`FaultSides::nodes`]: `n` the
    /// length-weighted mean of the normals of the fault edges at it.
    fn node_frame(&self, mesh: &SimplexMesh<2>, i: usize) -> Result<[[f64; 2]; 2]> {
        let length = |k: usize| mesh.boundary_facet_measure(self.minus_facets()[k]);
        let edges = self.normals().len();
        let mut n = [0.0; 2];
        for k in [i.wrapping_sub(1), i].into_iter().filter(|&k| k < edges) {
            let w = length(k);
            n[0] += w * self.normals()[k][0];
            n[1] += w * self.normals()[k][1];
        }
        let l = n[0].hypot(n[1]);
        if !(l > 1e-12 * length(i.min(edges - 1))) {
            return Err(Error::UndefinedNormal {
                vertex: self.nodes()[i].0,
            });
        }
        Ok(frame_from_normal::<2>(&[n[0] / l, n[1] / l], None)
            .expect("a frame without a tangent always exists"))
    }
}

impl FaultNetwork<2> {
    /// The change of variables to mean and jump of a 2-D fault network (docs/math.md §16):
    /// at every split pair of every fault as [`FaultSides::mean_jump_transform`], and at
    /// every junction the blocks of [`JunctionBlocks`] — the mean of the sector copies, the
    /// jump of each fault going on through the junction in its frame (its normal at the
    /// junction the length-weighted mean of its two edges' normals there), and a block
    /// tied to 0. A network of one fault is that fault's transform, to the bit.
    ///
    /// # Errors
    /// As [`FaultSides::mean_jump_transform`]; [`Error::Unsupported`] for junctions of a
    /// scalar field (`C = 1`).
    pub fn mean_jump_transform<const C: usize>(
        &self,
        mesh: &SimplexMesh<2>,
    ) -> Result<MeanJumpTransform> {
        if let ([one], []) = (&self.faults[..], &self.junctions[..]) {
            return one.mean_jump_transform::<C>(mesh);
        }
        let mut frames = Vec::new();
        for f in &self.faults {
            frames.extend(f.pair_frames::<C>(mesh)?);
        }
        let pairs = self.pairs();
        let mut blocks = Vec::with_capacity(self.junctions.len());
        for junction in &self.junctions {
            let mut frame_of = |f: usize| -> Result<usize> {
                let sides = &self.faults[f];
                let copies: Vec<usize> = junction.sectors.iter().map(|s| s.0).collect();
                let i = *sides
                    .junction_nodes()
                    .iter()
                    .find(|&&i| copies.contains(&sides.nodes()[i].0))
                    .expect("a junction's fault lists it");
                frames.push(sides.node_frame(mesh, i)?);
                Ok(frames.len() - 1)
            };
            blocks.push(junction_blocks(junction, &mut frame_of)?);
        }
        let shares = vec![0.5; frames.len()];
        assemble_network::<2, C>(&pairs, blocks, mesh.num_vertices(), frames, &shares)
    }
}

/// The blocks of `junction` (docs/math.md §16), the frame of a going-through fault `f` in
/// the transform's frames at index `frame_of(f)`.
fn junction_blocks(
    junction: &crate::Junction,
    frame_of: &mut dyn FnMut(usize) -> Result<usize>,
) -> Result<JunctionBlocks> {
    let copy = |k: usize| junction.sectors[k].0;
    Ok(match junction.kind {
        // u_ab = w + (a/2) R₁ j₁ + (b/2) R₂ j₂ + (ab/4) e; sectors (−−), (−+), (+−), (++).
        JunctionKind::Crossing { first, second } => JunctionBlocks {
            jumps: vec![
                (first, copy(0), frame_of(first)?),
                (second, copy(1), frame_of(second)?),
            ],
            mean: copy(2),
            tied: copy(3),
            sectors: junction
                .sectors
                .iter()
                .map(|&(c, [a, b])| {
                    let (a, b) = (f64::from(a), f64::from(b));
                    SectorBlocks {
                        copy: c,
                        alpha: vec![a / 2.0, b / 2.0],
                        gamma: a * b / 4.0,
                        omega: 0.25,
                        beta: vec![a / 2.0, b / 2.0],
                        delta: a * b,
                    }
                })
                .collect(),
        },
        // u_S = w + (σ/2) R j + (ε/2) e, σ the side of the going-through fault, ε that of
        // the ending one (0 on the far side): w = ½ u_far + ¼ (u_near₁ + u_near₂).
        JunctionKind::Branch { through, .. } => JunctionBlocks {
            jumps: vec![(through, copy(0), frame_of(through)?)],
            mean: copy(1),
            tied: copy(2),
            sectors: junction
                .sectors
                .iter()
                .map(|&(c, [sigma, eps])| {
                    let (sigma, e) = (f64::from(sigma), f64::from(eps));
                    let far = eps == 0;
                    SectorBlocks {
                        copy: c,
                        alpha: vec![sigma / 2.0],
                        gamma: e / 2.0,
                        omega: if far { 0.5 } else { 0.25 },
                        beta: vec![if far { sigma } else { sigma / 2.0 }],
                        delta: e,
                    }
                })
                .collect(),
        },
    })
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
        let frames = self.pair_frames_3d::<C>(mesh, tangent)?;
        let pairs = self.pairs();
        let half = vec![0.5; pairs.len()];
        assemble_transform::<3, C>(&pairs, mesh.num_vertices(), frames, &half)
    }

    /// The pair frames `R_p` (columns `(t1, t2, −n)`) of every split pair, in order
    /// (see `mean_jump_transform`).
    fn pair_frames_3d<const C: usize>(
        &self,
        mesh: &SimplexMesh<3>,
        tangent: Option<&[f64; 3]>,
    ) -> Result<Vec<[[f64; 3]; 3]>> {
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
        Ok(frames)
    }
}

impl FaultNetwork<3> {
    /// The change of variables to mean and jump of a 3-D network of disjoint faults: every
    /// fault's split pairs as `FaultSides::<3>::mean_jump_transform` (with the same
    /// `tangent`), fault after fault. A network of one fault is that fault's transform, to
    /// the bit.
    ///
    /// # Errors
    /// As `FaultSides::<3>::mean_jump_transform`.
    pub fn mean_jump_transform<const C: usize>(
        &self,
        mesh: &SimplexMesh<3>,
        tangent: Option<&[f64; 3]>,
    ) -> Result<MeanJumpTransform<3>> {
        if let [one] = &self.faults[..] {
            return one.mean_jump_transform::<C>(mesh, tangent);
        }
        let mut frames = Vec::new();
        for f in &self.faults {
            frames.extend(f.pair_frames_3d::<C>(mesh, tangent)?);
        }
        let pairs = self.pairs();
        let half = vec![0.5; pairs.len()];
        assemble_transform::<3, C>(&pairs, mesh.num_vertices(), frames, &half)
    }
}

/// `T` and `T⁻¹` of the pairs `pairs` on `nv` vertices with their frames and the minus
/// sides' shares of the jump (a fault alone, or a network without junctions).
fn assemble_transform<const D: usize, const C: usize>(
    pairs: &[(usize, usize)],
    nv: usize,
    frames: Vec<[[f64; D]; D]>,
    minus_share: &[f64],
) -> Result<MeanJumpTransform<D>> {
    assemble_network::<D, C>(pairs, Vec::new(), nv, frames, minus_share)
}

/// `T` and `T⁻¹` of the pairs `pairs` and the junctions `junctions` on `nv` vertices, with
/// the frames and the minus sides' shares of the pairs (then ½ for every junction jump).
fn assemble_network<const D: usize, const C: usize>(
    pairs: &[(usize, usize)],
    junctions: Vec<JunctionBlocks>,
    nv: usize,
    frames: Vec<[[f64; D]; D]>,
    minus_share: &[f64],
) -> Result<MeanJumpTransform<D>> {
    let jumps: usize = junctions.iter().map(|j| j.jumps.len()).sum();
    if minus_share.len() != pairs.len() + jumps || frames.len() != pairs.len() + jumps {
        return Err(Error::DimensionMismatch {
            what: "jump shares (one per split pair and junction jump)",
            expected: pairs.len() + jumps,
            got: minus_share.len(),
        });
    }
    if minus_share.iter().any(|b| !(0.0..=1.0).contains(b)) {
        return Err(Error::Unsupported("a jump share outside [0, 1]"));
    }
    // A vector field's jump is in the pair's frame; a scalar field's is the field's own.
    let rotated = C == D && C > 1;
    if !junctions.is_empty() && !rotated {
        return Err(Error::Unsupported(
            "fault junctions of a scalar (antiplane) field: its slips at a junction are \
             coupled, not one per fault",
        ));
    }
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
    for junction in &junctions {
        for s in &junction.sectors {
            in_pair[s.copy] = true;
            let row = |x: usize| C * s.copy + x;
            for x in 0..C {
                t.push(Triplet::new(row(x), C * junction.mean + x, 1.0));
                ti.push(Triplet::new(C * junction.mean + x, row(x), s.omega));
                for ((&(_, v, k), &alpha), &beta) in
                    junction.jumps.iter().zip(&s.alpha).zip(&s.beta)
                {
                    let r = &frames[k];
                    for y in 0..C {
                        // u_S ∋ α R j; j ∋ Rᵀ β u_S, (Rᵀ)_{yx} = R_{xy}.
                        t.push(Triplet::new(row(x), C * v + y, alpha * r[x][y]));
                        ti.push(Triplet::new(C * v + y, row(x), beta * r[x][y]));
                    }
                }
                if s.gamma != 0.0 {
                    t.push(Triplet::new(row(x), C * junction.tied + x, s.gamma));
                }
                if s.delta != 0.0 {
                    ti.push(Triplet::new(C * junction.tied + x, row(x), s.delta));
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
        junctions,
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

    /// [`reshared`](Self::reshared) for the transform of a [`FaultNetwork`]: `minus_share`
    /// has one entry per split pair of the network ([`FaultNetwork::pairs`]); the
    /// junctions keep their blocks (the mean of the sectors).
    ///
    /// # Errors
    /// As [`reshared`](Self::reshared).
    pub fn reshared_network<const C: usize>(
        &self,
        network: &FaultNetwork<D>,
        minus_share: &[f64],
    ) -> Result<MeanJumpTransform<D>> {
        if C != 1 && C != D {
            return Err(Error::Unsupported(
                "mean-jump transform for C other than 1 and the dimension",
            ));
        }
        let pairs = network.pairs();
        if minus_share.len() != pairs.len() {
            return Err(Error::DimensionMismatch {
                what: "jump shares (one per split pair)",
                expected: pairs.len(),
                got: minus_share.len(),
            });
        }
        let mut shares = minus_share.to_vec();
        shares.resize(self.minus_share.len(), 0.5);
        assemble_network::<D, C>(
            &pairs,
            self.junctions.clone(),
            self.t.nrows() / C,
            self.frames.clone(),
            &shares,
        )
    }
}

impl<const D: usize> MeanJumpTransform<D> {
    /// The same change of variables with the nodal frames `frames` at vertices off the
    /// faults (a frictional boundary beside faults inside the body): `T R` and `Rᵀ T⁻¹`,
    /// `R = blockdiag(Q_p)` at the frames' nodes (whose blocks of `T` are the identity), so
    /// that those nodes' blocks are in their frames as on a boundary fault.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a frame at a vertex of a split pair or a junction;
    /// the frames' errors ([`NodalFrames`](crate::NodalFrames)).
    pub fn with_nodal_frames<const C: usize>(
        &self,
        frames: &crate::NodalFrames<C>,
    ) -> Result<Self> {
        if frames.nodes.is_empty() {
            return Ok(self.clone());
        }
        // A frame node's block of T is the identity: its column block has one entry per
        // component, on the diagonal.
        for &p in &frames.nodes {
            let identity = (C * p..C * p + C).all(|j| {
                let rows: Vec<usize> = self.t.row_idx_of_col(j).collect();
                rows == [j]
            });
            if !identity {
                return Err(Error::Unsupported(
                    "a nodal frame at a vertex of a fault inside the body",
                ));
            }
        }
        let faer = |e: faer::sparse::FaerError| Error::Faer(format!("{e:?}"));
        let transpose = |a: &SparseMatrix| -> Result<SparseMatrix> {
            a.as_ref().transpose().to_col_major().map_err(faer)
        };
        // T R = (Rᵀ Tᵀ)ᵀ.
        let t = transpose(&frames.rotate_rows(transpose(&self.t)?.as_ref())?)?;
        let t_inv = frames.rotate_rows(self.t_inv.as_ref())?;
        Ok(Self {
            t,
            t_inv,
            ..self.clone()
        })
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
