//! A fault ODE's evaluations shared by ranks ([`FaultOde::share_evaluations`];
//! docs/scaling.md, "The fault ODE on MPI ranks").

use rsf_friction::FrictionLaw;
use rsf_state::StateLaw;

use super::FaultOde;
use crate::error::{invalid, Result};
use crate::node_solves::PartNodes;
use crate::ranks::{Exchanges, RankGroup, SharedEvaluation};

impl<const D: usize, L: FrictionLaw, S: StateLaw, const C: usize> FaultOde<D, L, S, C> {
    /// Shares the evaluations of the right-hand side with the other ranks of `ranks`
    /// (docs/scaling.md, "Past one machine"): the operator's rows are split into one part
    /// per rank ([`FaultOperator::split_rows`](crate::fault_operator::FaultOperator::split_rows)),
    /// each rank sums its rows of the product and solves their nodes, then one all-gather
    /// per evaluation gives every rank every rate. Every rank must hold the same run (the
    /// same scene, options and state) and call the same methods in the same order; the
    /// trajectory then has the same bits on every rank, at every rank count, and as
    /// unshared. Within a rank the shared part of an evaluation runs on one thread. A
    /// normal stress that changes with slip is shared too: each rank sums its rows of
    /// `S_N` (a dense one's or a 2-D fault's ℋ-matrix's), then one all-gather of the
    /// reactions before the evaluation's; a 3-D fault's `S_N` by components is evaluated
    /// whole on every rank.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `ranks` for a rank
    /// outside `0..size`, or an operator whose rows cannot be computed apart (the
    /// default of [`FaultOperator::split_rows`](crate::fault_operator::FaultOperator::split_rows);
    /// rsf's dense and ℋ kernels and the half-space operator can).
    pub fn share_evaluations(&mut self, ranks: Box<dyn RankGroup + Send>) -> Result<()> {
        if ranks.size() == 0 || ranks.rank() >= ranks.size() {
            return Err(invalid(
                "ranks",
                format!("rank {} of {} ranks", ranks.rank(), ranks.size()),
            ));
        }
        let first = &self.rates.first;
        let split = self
            .rates
            .operator
            .split_rows(ranks.size(), PartNodes::work_per_row(first))?;
        split.validate(first[first.len() - 1])?;
        self.rates.shared = Some(SharedEvaluation::new(
            ranks,
            split,
            first,
            self.rates.normal.as_mut(),
        ));
        Ok(())
    }

    /// What the ranks that share the evaluations have exchanged so far (all-gathers and
    /// values), or `None` unshared.
    pub fn exchanges(&self) -> Option<Exchanges> {
        self.rates.shared.as_ref().map(SharedEvaluation::exchanges)
    }

    /// The rank and the number of ranks that share the evaluations
    /// ([`share_evaluations`](Self::share_evaluations)); `(0, 1)` unshared.
    pub fn rank_and_size(&self) -> (usize, usize) {
        self.rates
            .shared
            .as_ref()
            .map_or((0, 1), SharedEvaluation::rank_and_size)
    }
}
