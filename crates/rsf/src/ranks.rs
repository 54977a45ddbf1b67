//! Processes that share the evaluations of a fault ODE (docs/scaling.md, "Past one
//! machine"): the rows of the fault operator's product and their nodes' friction solves
//! split into one part per rank ([`FaultOperator::split_rows`]: the ℋ-matrix's leaf
//! clusters, a dense matrix's row blocks, the half-space operator's elements), each rank
//! summing its rows and solving its nodes, then one all-gather of the rates per
//! evaluation (with a normal stress from slip, each rank's rows of `S_N` and one
//! all-gather of the reactions first). Every row of the product is
//! summed by the same fixed-order kernels and every node's solve is independent, so the
//! rates have the same bits at every rank count and as in one process; the rest of a step
//! (the Runge–Kutta stages, the error norm, the observers' data) is the same arithmetic on
//! the same numbers on every rank.
//!
//! The transport is the caller's: a [`RankGroup`] (crate `rsf-ranks`: an MPI communicator
//! in the `rsf-mpi` crate; threads of one process, `rsf_ranks::ThreadRanks`, in the tests).

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use rsf_linalg::Parallelism;

use crate::fault_operator::{FaultOperator, RowSplit};
use crate::node_solves::{Loading, NodeSolves, PartNodes, RatesOut};
use crate::normal_stress::parts::NormalGather;
use crate::normal_stress::NormalCoupling;

pub(crate) use rsf_ranks::RankGroup;

/// A fault ODE's evaluation shared by ranks: the group, the nodes of each rank's part and
/// the exchange buffers (made when shared, then reused).
pub(crate) struct SharedEvaluation {
    ranks: Box<dyn RankGroup + Send>,
    parts: RankParts,
    exchanges: Exchanges,
    /// `S_N`'s rows split by ranks, with a normal stress from slip (`None` without, or
    /// where `S_N` is evaluated whole on every rank).
    normal: Option<NormalGather>,
}

/// What the ranks of a shared fault ODE have exchanged
/// ([`FaultOde::exchanges`](crate::FaultOde::exchanges)): counted by the code, the numbers a
/// model of the communication cost is fitted with (docs/scaling.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Exchanges {
    /// The number of ranks.
    pub ranks: usize,
    /// All-gathers (one per shared evaluation; two with a normal stress from slip, whose
    /// reactions are gathered first).
    pub all_gathers: u64,
    /// f64 values received by every rank over all the all-gathers (each rank receives
    /// every rank's values: 8 bytes each).
    pub values: u64,
}

/// The split of the rows into one part per rank and what each rank sends.
struct RankParts {
    nodes: PartNodes,
    /// Per rank: how many values it sends (its nodes' slip rates, their state rates, its
    /// rows of `g(t) − S u` that belong to nodes across parts).
    counts: Vec<usize>,
    all: Vec<f64>,
    /// The rows of `g(t) − S u` of the nodes across parts, in the split's order (others
    /// unused).
    straddling_rows: Vec<f64>,
}

impl SharedEvaluation {
    /// The group `ranks` sharing the evaluations of a fault ODE whose operator's rows are
    /// split into one part per rank (`split`; `first` the nodes' first unknowns).
    pub(crate) fn new(
        ranks: Box<dyn RankGroup + Send>,
        split: RowSplit,
        first: &[usize],
        normal: Option<&mut NormalCoupling>,
    ) -> Self {
        let exchanges = Exchanges {
            ranks: ranks.size(),
            ..Exchanges::default()
        };
        let nodes = PartNodes::from_split(split, first);
        let mut counts = vec![0; ranks.size()];
        for (c, p) in counts.iter_mut().zip(0..nodes.len()) {
            *c = nodes.send_len(p);
        }
        let total = counts.iter().sum();
        let parts = RankParts {
            counts,
            all: vec![0.0; total],
            straddling_rows: vec![0.0; first[first.len() - 1]],
            nodes,
        };
        let normal = normal.and_then(|n| NormalGather::new(n, ranks.size(), ranks.rank()));
        Self {
            ranks,
            parts,
            exchanges,
            normal,
        }
    }

    /// `σ̄_n` (Pa, one per frictional node) at integrated loading `big_g` and condensed
    /// unknowns `u` into `sigma`: each rank its rows of `S_N` and one all-gather where they
    /// are split, else whole on every rank; the bits of
    /// [`NormalCoupling::evaluate`] either way.
    ///
    /// # Errors
    /// As [`NormalCoupling::evaluate`], the same on every rank.
    pub(crate) fn normal_stress(
        &mut self,
        normal: &mut NormalCoupling,
        (time, big_g): (f64, f64),
        u: &[f64],
        sigma: &mut [f64],
        par: Parallelism,
    ) -> crate::Result<()> {
        match &mut self.normal {
            // A non-finite `u` (the same on every rank) gives NaN reactions, or none summed
            // where the ℋ product refuses it, on every rank alike: the same refusal.
            Some(gather) => {
                let ranks = &mut self.ranks;
                let mut all_gather = |own: &[f64], counts: &[usize], all: &mut [f64]| {
                    ranks.all_gather(own, counts, all);
                };
                if gather.reactions(normal, &mut all_gather, big_g, u, sigma)? {
                    self.exchanges.all_gathers += 1;
                    self.exchanges.values += gather.values() as u64;
                }
                normal.finish(time, sigma)
            }
            _ => normal.evaluate(time, big_g, u, sigma, par),
        }
    }

    /// What the ranks have exchanged so far.
    pub(crate) fn exchanges(&self) -> Exchanges {
        self.exchanges
    }

    /// This rank and the number of ranks.
    pub(crate) fn rank_and_size(&self) -> (usize, usize) {
        (self.ranks.rank(), self.ranks.size())
    }

    /// One evaluation shared: this rank's part of `operator`'s rows (the split of
    /// [`new`](Self::new)) and their nodes, one all-gather, then every node's rates.
    ///
    /// # Errors
    /// The part's product (every rank holds the same numbers, so every rank fails alike
    /// before the all-gather).
    pub(crate) fn evaluate<L: FrictionLaw, S: StateLaw, const C: usize>(
        &mut self,
        operator: &mut dyn FaultOperator,
        u: &[f64],
        solves: &NodeSolves<'_, L, S, C>,
        load: Loading<'_>,
        rates: RatesOut<'_>,
    ) -> crate::Result<()> {
        let rank = self.ranks.rank();
        let parts = &mut self.parts;
        let none: &[f64] = &[];
        let own = if rank < parts.nodes.len() {
            parts.nodes.evaluate_part(operator, rank, u, solves, load)?;
            parts.nodes.sent()
        } else {
            none
        };
        self.ranks.all_gather(own, &parts.counts, &mut parts.all);
        self.exchanges.all_gathers += 1;
        self.exchanges.values += parts.all.len() as u64;
        parts
            .nodes
            .unpack(&parts.all, solves, &mut parts.straddling_rows, rates);
        Ok(())
    }
}
