//! The faults inside the body as the model keeps them: [`InternalFault`], its slip nodes
//! and their sides.

use rsf_fem::{FaultNetwork, FaultSides, MeanJumpTransform, SparseMatrix};

/// The faults inside the body of a [`Model`](crate::Model) built with
/// [`ModelBuilder::internal_fault`](crate::ModelBuilder::internal_fault) (called once per
/// fault): the split mesh's pairs `(p⁻, p⁺)` of every fault, the junctions where two
/// faults meet (2-D), and the change of variables `u = T u′` (docs/math.md §15–16) in
/// which the model's matrices, loads, states and checkpoints are written. In `u′` the block
/// of `p⁻` is the jump `u⁺ − u⁻` in the pair's frame (tangential slip, then the normal
/// component, tied to 0 for a vector field: no opening), the block of `p⁺` a weighted mean
/// `(1 − β) u⁻ + β u⁺` (Cartesian; `β` the plus side's share of the stiffness at the pair,
/// ½ for a body the same on both sides, [`MeanJumpTransform::minus_share`]); at a junction
/// the blocks of [`rsf_fem::JunctionBlocks`] (a mean, each going-through fault's jump, a
/// block tied to 0); every other vertex is Cartesian. Γ_F is the [slip nodes](Self::slip_nodes):
/// the pairs' minus vertices and the junctions' jump vertices (not the tips, which stay
/// shared and do not slip, nor a branch's ending fault at the junction).
#[derive(Debug, Clone)]
pub struct InternalFault<const D: usize = 2> {
    /// The faults cut open, their split pairs, tips, faces and junctions
    /// ([`FaultNetwork`]; one fault for [`internal_fault`](crate::ModelBuilder::internal_fault)
    /// called once).
    pub network: FaultNetwork<D>,
    /// `T` and `T⁻¹` (`C·n × C·n`), the frames of the slip nodes and the sides' shares of
    /// the jump: the model's change of variables ([`Model::transform`](crate::Model::transform),
    /// a [`DofTransform`](rsf_fem::DofTransform): `T x` of a model vector is Cartesian at
    /// every vertex, `T⁻¹ x` goes back).
    pub transform: MeanJumpTransform<D>,
    /// Per vertex: `Some((pair, is_plus))` for a vertex of a split pair, index into
    /// [`pairs`](Self::pairs).
    pair_of: Vec<Option<(usize, bool)>>,
    pairs: Vec<(usize, usize)>,
    /// The fault of every pair.
    pair_fault: Vec<usize>,
    /// Per vertex: the junction it is a copy of.
    junction_of: Vec<Option<usize>>,
    /// Every slip node: the pairs' minus vertices, then the junctions' jumps.
    slip_nodes: Vec<SlipNode>,
    /// Per junction copy: a unit vector from the vertex into its sector.
    into_sector: Vec<(usize, [f64; D])>,
    /// The coarsest level of the hierarchy cut along the faults.
    coarsest_split_level: usize,
}

/// A vertex of a fault inside the body whose block is a fault's jump — where the fault
/// slips (its tangential components) unless the slip is prescribed: a split pair's minus
/// vertex, or the copy of a junction that holds the jump of a fault going on through it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlipNode {
    /// The vertex (of the model's split mesh) whose block is the jump.
    pub vertex: usize,
    /// The fault (its index in [`InternalFault::faults`]).
    pub fault: usize,
    /// The index of its frame in [`MeanJumpTransform::frames`] (and of its share in
    /// [`MeanJumpTransform::minus_share`]).
    pub frame: usize,
    /// Its split pair (index into [`InternalFault::pairs`]); `None` at a junction.
    pub pair: Option<usize>,
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

impl<const D: usize> InternalFault<D> {
    /// The faults of `network` on a split mesh of `num_vertices` vertices with their
    /// transform; `into_sector` gives every junction copy's direction into its sector.
    pub(crate) fn new(
        network: FaultNetwork<D>,
        transform: MeanJumpTransform<D>,
        num_vertices: usize,
        into_sector: Vec<(usize, [f64; D])>,
    ) -> Self {
        let mut pairs = Vec::new();
        let mut pair_fault = Vec::new();
        for (f, sides) in network.faults().iter().enumerate() {
            for pair in sides.pairs() {
                pairs.push(pair);
                pair_fault.push(f);
            }
        }
        let mut pair_of = vec![None; num_vertices];
        for (k, &(mi, pl)) in pairs.iter().enumerate() {
            pair_of[mi] = Some((k, false));
            pair_of[pl] = Some((k, true));
        }
        let mut slip_nodes: Vec<SlipNode> = pairs
            .iter()
            .zip(&pair_fault)
            .enumerate()
            .map(|(k, (&(mi, _), &fault))| SlipNode {
                vertex: mi,
                fault,
                frame: k,
                pair: Some(k),
            })
            .collect();
        let mut junction_of = vec![None; num_vertices];
        for (j, blocks) in transform.junctions.iter().enumerate() {
            for s in &blocks.sectors {
                junction_of[s.copy] = Some(j);
            }
            slip_nodes.extend(blocks.jumps.iter().map(|&(fault, vertex, frame)| SlipNode {
                vertex,
                fault,
                frame,
                pair: None,
            }));
        }
        Self {
            network,
            transform,
            pair_of,
            pairs,
            pair_fault,
            junction_of,
            slip_nodes,
            into_sector,
            coarsest_split_level: 0,
        }
    }

    /// The faults, in the order the builder was given them.
    pub fn faults(&self) -> &[FaultSides<D>] {
        self.network.faults()
    }

    /// The name of fault `f` (an index into [`faults`](Self::faults)).
    ///
    /// # Panics
    /// If there is no fault `f`.
    pub fn fault_name(&self, f: usize) -> &str {
        self.network.faults()[f].name()
    }

    /// The coarsest level of the model's refinement hierarchy that is cut along the faults
    /// (0: every level; the finest level's index: only the finest). The levels below it do
    /// not resolve every fault (`rsf_fem::Error::FaultSegmentNotResolved` in 2-D,
    /// `FaultSurfaceNotResolved` in 3-D) and stay continuous across them — the decision
    /// the builder takes there, reported here (docs/faults-inside.md, "Multigrid"): their
    /// coarse corrections cannot slip, so TNNMG converges more slowly than with every
    /// level cut.
    pub fn coarsest_split_level(&self) -> usize {
        self.coarsest_split_level
    }

    pub(crate) fn with_coarsest_split_level(mut self, level: usize) -> Self {
        self.coarsest_split_level = level;
        self
    }

    /// The faults with their jump shared between the sides by their stiffness at each pair
    /// ([`MeanJumpTransform::reshared_network`]): `β_p = k⁺/(k⁻ + k⁺)` with `k^±` the trace
    /// of the diagonal block of `stiffness` (Cartesian, on the split mesh of `C` components
    /// per vertex) at the pair's two vertices; `β_p = ½` exactly (the mean) where the two
    /// agree to 1e-9 (a body the same on both sides). Junctions keep the mean of their
    /// sectors.
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
        let transform = if self.network.faults().len() == 1 && self.network.junctions().is_empty() {
            self.transform
                .reshared::<C>(&self.network.faults()[0], &share)?
        } else {
            self.transform
                .reshared_network::<C>(&self.network, &share)?
        };
        let n = self.pair_of.len();
        let level = self.coarsest_split_level;
        Ok(
            Self::new(self.network, transform, n, self.into_sector)
                .with_coarsest_split_level(level),
        )
    }

    /// The faults with the nodal frames `frames` of a frictional boundary beside them in
    /// their transform ([`MeanJumpTransform::with_nodal_frames`]).
    ///
    /// # Errors
    /// The transform's.
    pub(crate) fn with_boundary_frames<const C: usize>(
        mut self,
        frames: &rsf_fem::NodalFrames<C>,
    ) -> crate::Result<Self> {
        self.transform = self.transform.with_nodal_frames(frames)?;
        Ok(self)
    }

    /// The split pairs `(p⁻, p⁺)` of every fault, fault after fault (tips and junctions
    /// excluded).
    pub fn pairs(&self) -> &[(usize, usize)] {
        &self.pairs
    }

    /// The fault (index into [`faults`](Self::faults)) of pair `k` of [`pairs`](Self::pairs).
    ///
    /// # Panics
    /// If there is no pair `k`.
    pub fn pair_fault(&self, k: usize) -> usize {
        self.pair_fault[k]
    }

    /// Every slip node: the pairs' minus vertices (in the order of [`pairs`](Self::pairs)),
    /// then the junctions' jump vertices (junction after junction).
    pub fn slip_nodes(&self) -> &[SlipNode] {
        &self.slip_nodes
    }

    /// The slip nodes in order along the faults, fault after fault: indices into
    /// [`slip_nodes`](Self::slip_nodes) with the node's position in its fault's
    /// [`FaultSides::nodes`] (a junction's jump in its place along each fault going through
    /// it; an ending fault's junction and the tips have none).
    pub fn slip_nodes_along(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::with_capacity(self.slip_nodes.len());
        for (f, sides) in self.faults().iter().enumerate() {
            for (i, &(m, p)) in sides.nodes().iter().enumerate() {
                if sides.is_junction_node(i) {
                    let j = self.junction_of(m).expect("a junction's copy");
                    if let Some(k) = self.slip_nodes.iter().position(|n| {
                        n.pair.is_none() && n.fault == f && self.junction_of(n.vertex) == Some(j)
                    }) {
                        out.push((k, i));
                    }
                } else if m != p {
                    let (k, _) = self.pair_of[m].expect("a pair's minus vertex");
                    out.push((k, i));
                }
            }
        }
        out
    }

    /// The pair `(p⁻, p⁺)` that `vertex` belongs to, `None` for a vertex off the split
    /// pairs (a junction's copies included).
    pub fn pair_of(&self, vertex: usize) -> Option<(usize, usize)> {
        let (k, _) = self.pair_of.get(vertex).copied().flatten()?;
        Some(self.pairs[k])
    }

    /// The index of the pair `vertex` belongs to (into [`pairs`](Self::pairs) and the
    /// transform's pair frames), `None` for a vertex off the split pairs.
    pub fn pair_index(&self, vertex: usize) -> Option<usize> {
        self.pair_of.get(vertex).copied().flatten().map(|(k, _)| k)
    }

    /// The junction (index into [`rsf_fem::FaultNetwork::junctions`]) `vertex` is a copy
    /// of, `None` for any other vertex.
    pub fn junction_of(&self, vertex: usize) -> Option<usize> {
        self.junction_of.get(vertex).copied().flatten()
    }

    /// The copy of `vertex` on `side` if it is a vertex of a split pair, else `vertex`
    /// itself (a junction's copies each belong to their own sector).
    pub fn copy_on(&self, vertex: usize, side: FaultSide) -> usize {
        match (self.pair_of(vertex), side) {
            (Some((minus, _)), FaultSide::Minus) => minus,
            (Some((_, plus)), FaultSide::Plus) => plus,
            (None, _) => vertex,
        }
    }

    /// The point `x` of `vertex` moved into its side of the fault by `10⁻⁹` of its largest
    /// coordinate (at least 10⁻⁹ m) along the pair's normal — at a junction's copy, into its
    /// sector — for a function of position that tells the sides apart (e.g. an initial
    /// velocity that jumps across the fault); `x` itself off the faults.
    pub(crate) fn moved_into_side(&self, vertex: usize, x: &[f64; D]) -> [f64; D] {
        let size = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        if let Some(&(_, d)) = self.into_sector.iter().find(|(v, _)| *v == vertex) {
            return std::array::from_fn(|a| x[a] + 1e-9 * size * d[a]);
        }
        let Some((k, plus)) = self.pair_of.get(vertex).copied().flatten() else {
            return *x;
        };
        let r = self.transform.frames[k];
        // R's columns are (t…, −n), n pointing from the minus into the plus side.
        let delta = if plus { 1e-9 } else { -1e-9 } * size;
        std::array::from_fn(|a| x[a] + delta * -r[a][rsf_numeric::normal_component(D)])
    }

    /// The Cartesian block of `vertex` of the model vector `x` (`C` components per
    /// vertex): `w ∓ R_p j/2` at a pair's minus/plus vertex, the sector's value at a
    /// junction's copy, `None` at any other vertex.
    pub(crate) fn vertex_block<const C: usize>(
        &self,
        vertex: usize,
        x: &[f64],
    ) -> Option<[f64; C]> {
        if let Some(j) = self.junction_of(vertex) {
            return self.transform.junctions[j].cartesian_block::<D, C>(
                vertex,
                x,
                &self.transform.frames,
            );
        }
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
