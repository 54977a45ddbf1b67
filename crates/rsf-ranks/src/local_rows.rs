//! One rank's rows of a node-block matrix: its owned nodes' block rows in local numbering
//! (owned nodes first, then the ghost layer), and the node graph a partitioner splits.

use faer::sparse::SparseColMatRef;

use crate::block::{load, store, sub_mul_vec, Block};
use crate::bsr::BlockCsr;
use crate::error::Result;
use rsf_linalg::ProblemError;

/// The block rows of the nodes one rank owns, in local numbering.
///
/// Local nodes are the owned nodes in increasing global order (`0..owned()`), then the
/// ghosts — the nodes of other ranks adjacent to an owned node (a stored block `A_pq`) — in
/// increasing global order (`owned()..len()`). A local vector holds `D` values per local
/// node, node-major (length `D · len()`). Each owned row keeps its diagonal block and its
/// off-diagonal blocks with local column indices **in increasing global column order**
/// (the one-process row order, not the local one): a row sum over
/// [`neighbours`](Self::neighbours) has the same bits as the same sum in one process.
///
/// Built from the whole matrix, which every rank holds for now (a later phase builds the
/// rows from the rank's part of the mesh).
#[derive(Debug, Clone)]
pub struct LocalRows<const D: usize> {
    rank: usize,
    /// Global node of each local node.
    global: Vec<usize>,
    owned: usize,
    /// Owner rank of each ghost (ghost `g` is local node `owned + g`).
    ghost_owner: Vec<usize>,
    /// Owned row `p`'s off-diagonal blocks are `ptr[p]..ptr[p + 1]`.
    ptr: Vec<usize>,
    col: Vec<u32>,
    /// Shared by the clones (copied on the first [`set_row`](Self::set_row) of a shared
    /// one): TNNMG's nonlinear smoother and its V-cycle's fine level hold the same
    /// off-diagonal blocks of `A`, which never change, once.
    val: std::sync::Arc<Vec<Block<D>>>,
    diag: Vec<Block<D>>,
}

impl<const D: usize> LocalRows<D> {
    /// The rows of rank `rank` of the symmetric-pattern matrix `a` (`D n × D n`,
    /// node-major: node `p` owns the dofs `D p .. D p + D`), node `p` being owned by rank
    /// `owner[p]` (length `n`).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] as [`Colouring::new`](crate::Colouring::new);
    /// [`ProblemError::DimensionMismatch`] if `owner` does not have one entry per node.
    pub fn new(a: SparseColMatRef<'_, usize, f64>, owner: &[usize], rank: usize) -> Result<Self> {
        let a = BlockCsr::<D>::from_symmetric(a)?;
        Self::of_blocks(&a, owner, rank)
    }

    /// [`new`](Self::new) of a block matrix.
    pub fn of_blocks(a: &BlockCsr<D>, owner: &[usize], rank: usize) -> Result<Self> {
        Self::build(a.nodes(), owner, rank, |p, row| {
            row.extend(a.neighbours(p).map(|(q, blk)| (q, *blk)));
            a.diag[p]
        })
    }

    /// [`new`](Self::new) without a copy of the whole matrix: only the owned nodes'
    /// columns of `a` are read, each column as the row of a symmetric matrix (as
    /// [`BlockCsr::from_csc`] reads them, with the same blocks), so `a`'s symmetry is the
    /// caller's to ensure (it is not checked). What a rank keeps of a matrix it needs only
    /// its rows of (the energy norm's).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `a` is not `D · owner.len()` square.
    pub fn of_columns(
        a: SparseColMatRef<'_, usize, f64>,
        owner: &[usize],
        rank: usize,
    ) -> Result<Self> {
        let nodes = owner.len();
        if a.nrows() != D * nodes || a.ncols() != D * nodes {
            return Err(ProblemError::DimensionMismatch {
                what: "matrix (D rows per node of the owners)",
                expected: D * nodes,
                got: a.nrows(),
            }
            .into());
        }
        // slot[q] = (the call that placed A_pq, its position in the row); a row is read
        // twice (`build`), each call its own stamp.
        let (mut slot, mut call) = (vec![(usize::MAX, 0); nodes], 0);
        Self::build(nodes, owner, rank, |p, row| {
            call += 1;
            let mut diag = [[0.0; D]; D];
            for c in 0..D {
                for (i, &v) in a.row_idx_of_col(D * p + c).zip(a.val_of_col(D * p + c)) {
                    let (q, cc) = (i / D, i % D);
                    let blk = if q == p {
                        &mut diag
                    } else {
                        if slot[q].0 != call {
                            slot[q] = (call, row.len());
                            row.push((q, [[0.0; D]; D]));
                        }
                        &mut row[slot[q].1].1
                    };
                    blk[c][cc] = v;
                }
            }
            row.sort_unstable_by_key(|(q, _)| *q);
            diag
        })
    }

    /// The rows of rank `rank` among `nodes` nodes owned by `owner`: `row(p, out)` appends
    /// owned node `p`'s off-diagonal blocks `(q, A_pq)` in increasing `q` to the empty
    /// `out` and returns `A_pp` (called twice per owned node: for the ghosts, then for the
    /// values).
    fn build(
        nodes: usize,
        owner: &[usize],
        rank: usize,
        mut row: impl FnMut(usize, &mut Vec<(usize, Block<D>)>) -> Block<D>,
    ) -> Result<Self> {
        ProblemError::check_length("owner (one rank per node)", nodes, owner.len())?;
        let mut global: Vec<usize> = (0..nodes).filter(|&p| owner[p] == rank).collect();
        let owned = global.len();
        let mut is_ghost = vec![false; nodes];
        let mut blocks = 0;
        let mut scratch = Vec::new();
        for &p in &global {
            scratch.clear();
            row(p, &mut scratch);
            blocks += scratch.len();
            for &(q, _) in &scratch {
                is_ghost[q] = owner[q] != rank;
            }
        }
        global.extend((0..nodes).filter(|&q| is_ghost[q]));
        let ghost_owner = global[owned..].iter().map(|&q| owner[q]).collect();
        let mut local_of = vec![u32::MAX; nodes];
        for (l, &p) in global.iter().enumerate() {
            // BlockCsr has fewer than 2³² nodes.
            local_of[p] = l as u32;
        }
        let mut ptr = Vec::with_capacity(owned + 1);
        ptr.push(0);
        // Sized exactly: no spare capacity kept, no copy while growing (the fine level's
        // rows are most of a rank's memory).
        let (mut col, mut val) = (Vec::with_capacity(blocks), Vec::with_capacity(blocks));
        let mut diag = Vec::with_capacity(owned);
        for &p in &global[..owned] {
            scratch.clear();
            diag.push(row(p, &mut scratch));
            // In increasing global column order.
            for &(q, blk) in &scratch {
                col.push(local_of[q]);
                val.push(blk);
            }
            ptr.push(col.len());
        }
        Ok(Self {
            rank,
            global,
            owned,
            ghost_owner,
            ptr,
            col,
            val: std::sync::Arc::new(val),
            diag,
        })
    }

    /// The rank whose rows these are.
    pub fn rank(&self) -> usize {
        self.rank
    }

    /// Number of owned nodes (the local nodes `0..owned()`).
    pub fn owned(&self) -> usize {
        self.owned
    }

    /// Number of ghost nodes (the local nodes `owned()..len()`).
    pub fn ghosts(&self) -> usize {
        self.global.len() - self.owned
    }

    /// Number of local nodes, owned and ghosts (a local vector has `D · len()` values).
    pub fn len(&self) -> usize {
        self.global.len()
    }

    /// Whether the rank has no local node.
    pub fn is_empty(&self) -> bool {
        self.global.is_empty()
    }

    /// The global node of every local node (length [`len`](Self::len)): increasing over the
    /// owned nodes, then increasing over the ghosts.
    pub fn global_nodes(&self) -> &[usize] {
        &self.global
    }

    /// The local node of the owned global node `p`.
    ///
    /// # Panics
    /// If the rank does not own `p`.
    pub fn local_of_owned(&self, p: usize) -> usize {
        self.global[..self.owned]
            .binary_search(&p)
            .unwrap_or_else(|_| panic!("node {p} is not owned by rank {}", self.rank))
    }

    /// The owner rank of every ghost (length [`ghosts`](Self::ghosts)).
    pub fn ghost_owners(&self) -> &[usize] {
        &self.ghost_owner
    }

    /// The diagonal block `A_pp` of owned node `p` (`p < owned()`), row-major.
    ///
    /// # Panics
    /// If `p ≥ owned()`.
    pub fn diag(&self, p: usize) -> &[[f64; D]; D] {
        &self.diag[p]
    }

    /// The off-diagonal blocks of owned node `p`'s row as `(q, A_pq)` with `q` a local node,
    /// in increasing global column order.
    ///
    /// # Panics
    /// If `p ≥ owned()`.
    pub fn neighbours(&self, p: usize) -> impl Iterator<Item = (usize, &[[f64; D]; D])> {
        let r = self.ptr[p]..self.ptr[p + 1];
        self.col[r.clone()]
            .iter()
            .zip(&self.val[r])
            .map(|(&q, b)| (q as usize, b))
    }

    /// Replaces the values of owned row `p`: its diagonal block and its off-diagonal blocks
    /// in increasing global column order (the pattern is kept: `off` has one block per
    /// stored block of the row, as the whole matrix the rows were built from, with the same
    /// pattern, gives them).
    ///
    /// # Panics
    /// If `p ≥ owned()`, or (debug builds) `off` does not have the row's length.
    pub fn set_row<'a>(
        &mut self,
        p: usize,
        diag: &Block<D>,
        off: impl Iterator<Item = &'a Block<D>>,
    ) {
        self.diag[p] = *diag;
        let r = self.ptr[p]..self.ptr[p + 1];
        let mut n = 0;
        let val = std::sync::Arc::make_mut(&mut self.val);
        for (v, b) in val[r.clone()].iter_mut().zip(off) {
            *v = *b;
            n += 1;
        }
        debug_assert_eq!(n, r.len(), "row {p}'s pattern");
    }

    /// Replaces the diagonal block of owned row `p`.
    ///
    /// # Panics
    /// If `p ≥ owned()`.
    pub fn set_diag(&mut self, p: usize, diag: &Block<D>) {
        self.diag[p] = *diag;
    }

    /// The residual `r = b − A x` on the owned rows: for every owned node `p`,
    /// `b_p − A_pp x_p − Σ_q A_pq x_q` with the off-diagonal blocks in increasing global
    /// column order — the arithmetic of the one-process residual by rows, so each owned
    /// row has its bits when `x`'s ghosts are current (after a ghost update). `b` and `r`
    /// hold at least the owned nodes' values (`D · owned()`; only those are read and
    /// written), `x` is a local vector (`D · len()`).
    ///
    /// # Panics
    /// If a vector is shorter than that.
    pub fn residual(&self, b: &[f64], x: &[f64], r: &mut [f64]) {
        assert!(x.len() >= D * self.len(), "local vector length");
        for p in 0..self.owned {
            let mut s = load::<D>(b, p);
            sub_mul_vec(&mut s, &self.diag[p], &load::<D>(x, p));
            for (q, blk) in self.neighbours(p) {
                sub_mul_vec(&mut s, blk, &load::<D>(x, q));
            }
            store(r, p, &s);
        }
    }

    /// The local values of a global node-major vector: `local` (length `D · len()`)
    /// receives the `D` values of every local node's global node from `global`.
    ///
    /// # Panics
    /// If `local` is not `D · len()` long or `global` has fewer than `D` values per node of
    /// the matrix.
    pub fn gather<T: Copy>(&self, global: &[T], local: &mut [T]) {
        assert_eq!(local.len(), D * self.len(), "local vector length");
        for (l, &p) in local.chunks_exact_mut(D).zip(&self.global) {
            l.copy_from_slice(&global[D * p..D * p + D]);
        }
    }

    /// The owned nodes' values of a local vector (length `D · len()`) into their places in
    /// a global node-major vector; the other entries of `global` are left alone.
    ///
    /// # Panics
    /// If `local` is not `D · len()` long or `global` is too short.
    pub fn scatter_owned(&self, local: &[f64], global: &mut [f64]) {
        assert_eq!(local.len(), D * self.len(), "local vector length");
        for (l, &p) in local.chunks_exact(D).zip(&self.global[..self.owned]) {
            global[D * p..D * p + D].copy_from_slice(l);
        }
    }
}

/// The node graph of the symmetric-pattern matrix `a` (`D n × D n`, node-major) in CSR
/// form, as graph partitioners take it: the neighbours of node `p` are
/// `adjncy[xadj[p]..xadj[p + 1]]`, increasing (the nodes `q ≠ p` with a stored block
/// `A_pq`; explicit zeros count); `xadj` has `n + 1` entries. Symmetric, without
/// self-loops.
///
/// # Errors
/// [`ProblemError::InvalidMatrix`] as [`Colouring::new`](crate::Colouring::new).
pub fn node_graph<const D: usize>(
    a: SparseColMatRef<'_, usize, f64>,
) -> Result<(Vec<usize>, Vec<usize>)> {
    let a = BlockCsr::<D>::from_symmetric(a)?;
    let mut xadj = Vec::with_capacity(a.nodes() + 1);
    xadj.push(0);
    let mut adjncy = Vec::new();
    for p in 0..a.nodes() {
        adjncy.extend(a.neighbours(p).map(|(q, _)| q));
        xadj.push(adjncy.len());
    }
    Ok((xadj, adjncy))
}

/// The test boxes of the distributed pieces (here, below the sweep's tests that use them
/// too: the layers of tests/layers.rs).
#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rsf_fem::ElasticBox;

    const D: usize = 3;

    /// The box [0, 1.5] × [0, 1] × [0, 1] of 3 × 2 × 2 Kuhn-split cubes, refined
    /// `refinements` times ([`ElasticBox`]: the face z = 0 clamped, the face x = 0 on rollers).
    pub(crate) fn cube(refinements: usize) -> ElasticBox {
        ElasticBox::new([1.5, 1.0, 1.0], [4, 3, 3], refinements).unwrap()
    }

    /// The owner vectors tested at `size` ranks: slabs along x, and METIS's partition of the
    /// node graph when the workspace is built with METIS.
    pub(crate) fn owners(bx: &ElasticBox, size: usize) -> Vec<(&'static str, Vec<usize>)> {
        let mut out = vec![("coordinates", bx.slabs(size, 0))];
        if rsf_metis::is_available() {
            let (xadj, adjncy) = node_graph::<D>(bx.stiffness.as_ref()).unwrap();
            let part = rsf_metis::part_graph_kway(&xadj, &adjncy, size).unwrap();
            out.push(("metis", part));
        }
        out
    }

    /// A rank's rows read from the owned columns alone have the same local numbering,
    /// ghosts, pattern and bits as those cut from the whole block matrix, at 1 to 4 ranks
    /// and every tested partition; a matrix of the wrong size is refused.
    #[test]
    fn rows_from_the_owned_columns_are_the_rows_of_the_whole_matrix() {
        let bx = cube(1);
        let a = bx.stiffness.as_ref();
        for size in 1..=4 {
            for (name, owner) in owners(&bx, size) {
                for rank in 0..size {
                    let whole = LocalRows::<D>::new(a, &owner, rank).unwrap();
                    let part = LocalRows::<D>::of_columns(a, &owner, rank).unwrap();
                    let what = format!("{name}, rank {rank} of {size}");
                    assert_eq!(part.global, whole.global, "{what}");
                    assert_eq!(part.owned, whole.owned, "{what}");
                    assert_eq!(part.ghost_owner, whole.ghost_owner, "{what}");
                    assert_eq!(part.ptr, whole.ptr, "{what}");
                    assert_eq!(part.col, whole.col, "{what}");
                    let bits = |b: &[Block<D>]| -> Vec<u64> {
                        b.iter().flatten().flatten().map(|x| x.to_bits()).collect()
                    };
                    assert_eq!(bits(&part.val), bits(&whole.val), "{what}");
                    assert_eq!(bits(&part.diag), bits(&whole.diag), "{what}");
                    assert_eq!(part.val.capacity(), part.val.len(), "{what}: exact size");
                }
            }
        }
        let n = bx.mesh().num_vertices();
        assert!(matches!(
            LocalRows::<D>::of_columns(a, &vec![0; n - 1], 0),
            Err(crate::Error::Problem(
                ProblemError::DimensionMismatch { .. }
            ))
        ));
    }
}
