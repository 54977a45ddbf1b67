//! The grid transfers of a distributed V-cycle between two levels of a nested hierarchy:
//! restriction `Pᵀ r` and prolongation `P c` on a rank's owned nodes, each with one halo
//! exchange of the values its rows read from other ranks.

use faer::sparse::SparseColMatRef;

use crate::chunks::PositionRows;
use crate::error::{Error, Result};
use crate::galerkin::{masked, prolong_row, prolongation_blocks, restrict_row};
use rsf_linalg::Csc;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::block::{load, store, Block};
use rsf_ranks::halo::{exchange_round, HaloCounters, HaloPlan, Peer};
use rsf_ranks::RankGroup;

/// The position of rank `r`'s entry in `peers` (increasing ranks), made empty if new.
fn peer(peers: &mut Vec<Peer>, r: usize) -> usize {
    match peers.binary_search_by_key(&r, |p| p.rank) {
        Ok(k) => k,
        Err(k) => {
            peers.insert(
                k,
                Peer {
                    rank: r,
                    send: Vec::new(),
                    recv: Vec::new(),
                },
            );
            k
        }
    }
}

/// One direction of the transfer: the rows, the buffer they read (owned values, then the
/// ghosts the exchange fills), the halo plan of that exchange and its message buffers.
#[derive(Debug, Clone)]
struct Side<const D: usize> {
    /// The rows in local numbering, their positions indexing `buf`.
    rows: PositionRows<D>,
    /// Values the rows read: `D` per owned node of the source level, then per ghost
    /// (NaN until the first exchange).
    buf: Vec<f64>,
    plan: HaloPlan,
    send: Vec<f64>,
    recv: Vec<f64>,
}

impl<const D: usize> Side<D> {
    /// The side of rank `rank` whose rows are `rows` (entries by global source node,
    /// increasing) over its owned source nodes `source_owned` (increasing), the others
    /// owned by `owner`; `wanted[r]` the owned source nodes that rank `r` reads
    /// (increasing, each once).
    fn new(
        rows: Vec<Vec<(usize, Block<D>)>>,
        source_owned: &[usize],
        owner: &[usize],
        rank: usize,
        wanted: Vec<Vec<usize>>,
    ) -> Self {
        let mut ghosts: Vec<usize> = rows
            .iter()
            .flat_map(|r| r.iter().map(|&(c, _)| c))
            .filter(|&c| owner[c] != rank)
            .collect();
        ghosts.sort_unstable();
        ghosts.dedup();
        let local = |c: usize| -> u32 {
            let l = if owner[c] == rank {
                source_owned.binary_search(&c).expect("an owned node")
            } else {
                source_owned.len() + ghosts.binary_search(&c).expect("a ghost")
            };
            l as u32
        };
        let mut ptr = vec![0];
        let (mut col, mut val) = (Vec::new(), Vec::new());
        for r in &rows {
            for &(c, b) in r {
                col.push(local(c));
                val.push(b);
            }
            ptr.push(col.len());
        }
        let mut peers: Vec<Peer> = Vec::new();
        for (g, &c) in ghosts.iter().enumerate() {
            let k = peer(&mut peers, owner[c]);
            peers[k].recv.push((source_owned.len() + g) as u32);
        }
        for (r, nodes) in wanted.iter().enumerate() {
            for &c in nodes {
                let k = peer(&mut peers, r);
                peers[k].send.push(local(c));
            }
        }
        let mut plan = HaloPlan {
            peers,
            rounds: Vec::new(),
        };
        plan.make_rounds(D, |_| 0, 0);
        let (send, recv) = plan.max_round_nodes();
        Self {
            rows: PositionRows { ptr, pos: col, val },
            buf: vec![f64::NAN; D * (source_owned.len() + ghosts.len())],
            plan,
            send: vec![0.0; D * send],
            recv: vec![0.0; D * recv],
        }
    }

    /// Fills the ghosts of `buf` (its owned values set) from their owners.
    fn exchange<H: RankGroup + ?Sized>(&mut self, halo: &mut H, counters: &mut HaloCounters) {
        exchange_round::<D, H>(
            &self.plan.rounds[0],
            &mut self.buf,
            halo,
            &mut self.send,
            &mut self.recv,
            counters,
        );
    }
}

/// One rank's grid transfers between a fine level and the next coarser one of a nested
/// hierarchy: the restriction `Pᵀ (free ⊙ r)` onto its owned coarse nodes and the
/// prolongation `x += free ⊙ (P c)` onto its owned fine nodes, `P` the node-major vector
/// prolongation (`D n_f × D n_c`).
///
/// Nested numbering: coarse node `j` is fine node `j` (rsf-fem's `MeshHierarchy`: coarse
/// vertices keep their indices on the finer level), so a rank owns the coarse nodes whose
/// fine node it owns. Each direction reads values of other ranks — the restriction the
/// fine residuals of the fine nodes next to an owned coarse node, the prolongation the
/// coarse values of an owned fine node's parents — and gets them in one exchange before
/// its rows, planned from the global `P` and owners (every rank derives the same plan, as
/// the sweep's). Each owned row is the one-process transfer's arithmetic on the same
/// numbers, in the same order (the rows of `P` by increasing coarse node, its columns by
/// increasing fine node): the same bits at every rank count.
///
/// Owned nodes come first and increase in global order, as in [`LocalRows`]: the owned
/// part of a local vector of the level's rows is what the transfers read and write.
/// Allocation-free after set-up (the transport may allocate).
///
/// [`LocalRows`]: rsf_ranks::LocalRows
#[derive(Debug, Clone)]
pub struct DistributedTransfer<const D: usize> {
    rank: usize,
    fine_owned: usize,
    coarse_owned: usize,
    /// Restriction: owned coarse rows over fine values.
    restriction: Side<D>,
    /// Prolongation: owned fine rows over coarse values.
    prolongation: Side<D>,
    counters: HaloCounters,
}

impl<const D: usize> DistributedTransfer<D> {
    /// The transfers of rank `halo.rank()` for the vector prolongation `p` (`D n_f × D n_c`,
    /// node-major on both sides, `n_c ≤ n_f`), fine node `i` owned by rank `owner[i]`
    /// (length `n_f`), coarse node `j` by `owner[j]`.
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] if a dimension of `p` is not a multiple of `D`, it has more
    /// coarse than fine nodes, or a non-finite entry; [`ProblemError::DimensionMismatch`] if
    /// `owner` does not have `n_f` entries; [`Error::InvalidPartition`] if an owner is not
    /// a rank of `halo`.
    pub fn new<H: RankGroup + ?Sized>(
        p: SparseColMatRef<'_, usize, f64>,
        owner: &[usize],
        halo: &H,
    ) -> Result<Self> {
        let (rank, size) = (halo.rank(), halo.size());
        let p = Csc::from_faer(p)?;
        if p.nrows % D != 0 || p.ncols % D != 0 || p.ncols > p.nrows {
            return Err(ProblemError::InvalidMatrix(format!(
                "prolongation is {}x{}: expected dimensions divisible by {D}, at most as many \
                 columns as rows",
                p.nrows, p.ncols
            ))
            .into());
        }
        let (nf, nc) = (p.nrows / D, p.ncols / D);
        ProblemError::check_length("owner (one rank per fine node)", nf, owner.len())?;
        if let Some(i) = owner.iter().position(|&r| r >= size) {
            return Err(Error::InvalidPartition(format!(
                "node {i} is owned by rank {}, but there are {size} ranks",
                owner[i]
            )));
        }
        let (p_ptr, p_col, p_val) = prolongation_blocks::<D>(&p)?;
        let fine_owned: Vec<usize> = (0..nf).filter(|&i| owner[i] == rank).collect();
        let coarse_owned: Vec<usize> = (0..nc).filter(|&j| owner[j] == rank).collect();
        // Every (fine i, coarse j, block) of P, by fine rows (coarse j increasing).
        let p_col = &p_col;
        let row = |i: usize| (p_ptr[i]..p_ptr[i + 1]).map(move |k| (p_col[k] as usize, k));
        // Prolongation: owned fine rows; rank r reads the coarse j of its fine rows.
        let mut wanted_coarse = vec![Vec::new(); size];
        let mut wanted_fine = vec![Vec::new(); size];
        for i in 0..nf {
            for (j, _) in row(i) {
                if owner[j] == rank && owner[i] != rank {
                    wanted_coarse[owner[i]].push(j);
                }
                if owner[i] == rank && owner[j] != rank {
                    wanted_fine[owner[j]].push(i);
                }
            }
        }
        for w in wanted_coarse.iter_mut().chain(wanted_fine.iter_mut()) {
            w.sort_unstable();
            w.dedup();
        }
        let fine_rows = fine_owned
            .iter()
            .map(|&i| row(i).map(|(j, k)| (j, p_val[k])).collect())
            .collect();
        // Restriction: owned coarse rows, their fine columns increasing (the transpose
        // filled by increasing fine rows).
        let mut coarse_rows: Vec<Vec<(usize, Block<D>)>> = vec![Vec::new(); coarse_owned.len()];
        for i in 0..nf {
            for (j, k) in row(i) {
                if owner[j] == rank {
                    let at = coarse_owned
                        .binary_search(&j)
                        .expect("an owned coarse node");
                    coarse_rows[at].push((i, p_val[k]));
                }
            }
        }
        let prolongation = Side::new(fine_rows, &coarse_owned, owner, rank, wanted_coarse);
        let restriction = Side::new(coarse_rows, &fine_owned, owner, rank, wanted_fine);
        Ok(Self {
            rank,
            fine_owned: fine_owned.len(),
            coarse_owned: coarse_owned.len(),
            restriction,
            prolongation,
            counters: HaloCounters::default(),
        })
    }

    /// Number of owned fine nodes.
    pub fn fine_owned(&self) -> usize {
        self.fine_owned
    }

    /// Number of owned coarse nodes.
    pub fn coarse_owned(&self) -> usize {
        self.coarse_owned
    }

    /// What the transfers have sent (`sweeps` stays 0: one exchange per transfer).
    pub fn counters(&self) -> HaloCounters {
        self.counters
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.counters = HaloCounters::default();
    }

    /// What one restriction and one prolongation send by their plans: two exchanges,
    /// their messages and values.
    pub fn per_transfer_pair(&self) -> HaloCounters {
        self.restriction.plan.rounds[0].counters::<D>()
            + self.prolongation.plan.rounds[0].counters::<D>()
    }

    /// The restriction onto the owned coarse nodes: `coarse_j = Σ_i P_ijᵀ (free_i ⊙
    /// fine_i)` for every owned coarse node `j` (the first `D · coarse_owned()` values of
    /// `coarse`; the rest are left alone), from the owned fine values of `fine` and of the
    /// 0/1 mask `free` (their first `D · fine_owned()` values) and those of other ranks,
    /// received in one exchange. Collective.
    ///
    /// # Panics
    /// If a vector is shorter than its owned values or `halo` is another rank's.
    pub fn restrict<H: RankGroup + ?Sized>(
        &mut self,
        fine: &[f64],
        free: &[f64],
        coarse: &mut [f64],
        halo: &mut H,
    ) {
        assert_eq!(halo.rank(), self.rank, "the transport of another rank");
        let side = &mut self.restriction;
        // The masked values `fine ⊙ free` (the products the one-process restriction forms
        // per term) of the owned nodes; the exchange brings those of the other ranks.
        for i in 0..self.fine_owned {
            store(&mut side.buf, i, &masked::<D>(fine, free, i));
        }
        side.exchange(halo, &mut self.counters);
        for k in 0..self.coarse_owned {
            let s = restrict_row::<D>(side.rows.row(k).map(|(i, b)| (b, load::<D>(&side.buf, i))));
            store(coarse, k, &s);
        }
    }

    /// The prolongation onto the owned fine nodes: `fine_i += free_i ⊙ Σ_j P_ij coarse_j`
    /// for every owned fine node `i` (the first `D · fine_owned()` values of `fine`), from
    /// the owned coarse values of `coarse` (its first `D · coarse_owned()` values) and
    /// those of other ranks, received in one exchange; `free` as in
    /// [`restrict`](Self::restrict). Collective.
    ///
    /// # Panics
    /// If a vector is shorter than its owned values or `halo` is another rank's.
    pub fn prolong_add<H: RankGroup + ?Sized>(
        &mut self,
        coarse: &[f64],
        free: &[f64],
        fine: &mut [f64],
        halo: &mut H,
    ) {
        assert_eq!(halo.rank(), self.rank, "the transport of another rank");
        let n = D * self.coarse_owned;
        let side = &mut self.prolongation;
        side.buf[..n].copy_from_slice(&coarse[..n]);
        side.exchange(halo, &mut self.counters);
        for k in 0..self.fine_owned {
            let s = prolong_row::<D>(side.rows.row(k), &side.buf);
            for c in 0..D {
                fine[D * k + c] += free[D * k + c] * s[c];
            }
        }
    }
}
