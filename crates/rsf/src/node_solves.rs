//! The per-node part of a fault-ODE evaluation (docs/math.md §12): every frictional node's
//! slip rate from its traction and state, and its state rate — split over threads by
//! contiguous nodes, or, with a hierarchical kernel, inside the parts of the ℋ-product
//! ([`PartNodes`]: each thread sums its rows of `S u` and solves the nodes of those rows
//! in one task, one parallel region per evaluation). Nodes are independent and each row
//! of the product is summed in a fixed order, so every split gives the same bits.

use std::ops::Range;

use rsf_friction::{ConvexPotential, FrictionLaw};
use rsf_hmatrix::HMatrix;
use rsf_state::StateLaw;

use crate::fault_operator::{FaultOperator, RowSplit};

/// Fewest frictional nodes for which the per-node solves of an evaluation are split over
/// threads (below it a split costs more than the solves: ~0.2 µs each).
pub(crate) const PARALLEL_NODES_MIN: usize = 64;

/// A node's solve in multiply-adds of the ℋ-product, what the split of the rows balances:
/// an estimate (about 0.2 µs against 0.5 ns per multiply-add); on BP1 at Δz = 25 and
/// 12.5 m two threads took the same time per evaluation, within the noise, for any value
/// from 100 to 1000.
const SOLVE_WORK: f64 = 400.0;

/// The per-node part of an evaluation: every node's slip rate from its traction and state,
/// and its state rate.
pub(crate) struct NodeSolves<'a, L, S, const C: usize> {
    pub friction: &'a [L],
    pub state_laws: &'a [S],
    pub uses_state: bool,
    pub first: &'a [usize],
    pub weights: &'a [f64],
    pub fixed_velocity: &'a [[f64; C]],
    /// η of every frictional node (Pa·s/m).
    pub eta: &'a [f64],
    /// The loading history's rate `G'(t)` (factor of the Dirichlet velocities).
    pub speed: f64,
    /// `α` of every frictional node.
    pub alpha: &'a [f64],
    /// Per node, the factor `σ̄_n/σ̄_n⁰` of its potential (a normal stress that changes
    /// with slip), or `None`: 1.
    pub scale: Option<(&'a [f64], &'a [f64])>,
    /// Per node, the effective normal stress `σ̄_n − p` (Pa) its law is evaluated at
    /// ([`FrictionLaw::potential_at_normal_stress`]; a pore pressure), or `None`. Takes
    /// the place of `scale`.
    pub effective: Option<&'a [f64]>,
}

impl<L: FrictionLaw, S: StateLaw, const C: usize> NodeSolves<'_, L, S, C> {
    /// Nodes `k0..k1` in `pieces` contiguous parts on rayon's current pool (halving
    /// recursively: no allocation); `r` is `g(t) − S u_F` (all free components), `dyu`
    /// holds the nodes' free components' rates (`first[k0]..first[k1]`), `dya` their state
    /// rates.
    pub fn solve(
        &self,
        (k0, k1): (usize, usize),
        pieces: usize,
        r: &[f64],
        dyu: &mut [f64],
        dya: &mut [f64],
    ) {
        if pieces <= 1 || k1 - k0 < 2 {
            let base = self.first[k0];
            for k in k0..k1 {
                let (a, b) = (self.first[k], self.first[k + 1]);
                dya[k - k0] = self.solve_node(k, &r[a..b], &mut dyu[a - base..b - base]);
            }
            return;
        }
        let left = pieces / 2;
        let mid = k0 + (k1 - k0) * left / pieces;
        let (u_lo, u_hi) = dyu.split_at_mut(self.first[mid] - self.first[k0]);
        let (a_lo, a_hi) = dya.split_at_mut(mid - k0);
        rayon::join(
            || self.solve((k0, mid), left, r, u_lo, a_lo),
            || self.solve((mid, k1), pieces - left, r, u_hi, a_hi),
        );
    }

    /// Node `k`: its free components' slip rates into `out` from its rows `r` of
    /// `g(t) − S u_F`; returns its state rate.
    fn solve_node(&self, k: usize, r: &[f64], out: &mut [f64]) -> f64 {
        self.solve_node_at(k, self.alpha[k], r, out)
    }

    /// [`solve_node`](Self::solve_node) at the state `alpha` instead of node `k`'s (the
    /// local Jacobian's differences).
    pub fn solve_node_at(&self, k: usize, alpha: f64, r: &[f64], out: &mut [f64]) -> f64 {
        let inv_w = 1.0 / self.weights[k];
        let mut traction = [0.0; C];
        for (tr, r) in traction.iter_mut().zip(r) {
            *tr = r * inv_w;
        }
        let law = &self.friction[k];
        match self
            .effective
            .and_then(|s| law.potential_at_normal_stress(alpha, s[k]))
        {
            Some(p) => p.minimize_block(self.eta[k], &traction[..r.len()], 1.0, out),
            None => {
                let w = self
                    .scale
                    .map_or(1.0, |(sigma, sigma0)| sigma[k] / sigma0[k]);
                law.potential(alpha)
                    .minimize_block(self.eta[k], &traction[..r.len()], w, out);
            }
        }
        let mut v2: f64 = out.iter().map(|v| v * v).sum();
        for f in &self.fixed_velocity[k] {
            v2 += (f * self.speed) * (f * self.speed);
        }
        if self.uses_state {
            -self.state_laws[k].dpsi_dalpha(alpha, v2.sqrt())
        } else {
            0.0
        }
    }
}

/// `g(t)` of the right-hand side: `g0 + G(t) g1` (all free components).
#[derive(Clone, Copy)]
pub(crate) struct Loading<'a> {
    pub g0: &'a [f64],
    pub g1: &'a [f64],
    /// `G(t)`, the loading history's integral.
    pub big_g: f64,
}

impl Loading<'_> {
    /// Row `i` of `g(t) − S u_F` from row `i` of `S u_F` (the sums of the sequential
    /// evaluation: `g` first, then the product subtracted — `r + (−1)·su` there, the same
    /// number as `r − su`).
    #[inline]
    fn residual(&self, i: usize, su: f64) -> f64 {
        (self.g0[i] + self.big_g * self.g1[i]) - su
    }
}

/// Where [`PartNodes::evaluate`] writes the rates: of the free slip components (`dyu`) and
/// of the state of every node (`dya`).
pub(crate) struct RatesOut<'a> {
    /// Slip rates, one per free component.
    pub dyu: &'a mut [f64],
    /// State rates, one per node.
    pub dya: &'a mut [f64],
}

/// The nodes of each part of a row split ([`RowSplit`]: an ℋ-product's parts on threads,
/// an operator's parts on ranks) and their results: a node belongs to the part holding
/// all of its rows, and a node whose rows lie in two parts is solved after the parts. Set
/// up once per split.
pub(crate) struct PartNodes {
    parts: Vec<PartBuffers>,
    /// The rows of each part (positions in the split's order), as split.
    ranges: Vec<Range<usize>>,
    straddling: Vec<usize>,
    /// Position of every free component in the split's order (the ℋ-matrix's cluster
    /// order on threads).
    position: Vec<usize>,
    /// The split's order (the inverse of `position`).
    order: Vec<usize>,
    /// Per part, the positions (ascending) of its rows that belong to nodes across parts:
    /// what a part shared out to another process sends of its rows
    /// ([`SharedEvaluation`](crate::ranks::SharedEvaluation)).
    straddling_rows: Vec<Vec<usize>>,
    /// What the last [`evaluate_part`](Self::evaluate_part) sends.
    send: Vec<f64>,
    /// A part's rows of `g(t) − S u_F` ([`evaluate_part`](Self::evaluate_part); scratch of
    /// the longest part).
    residual: Vec<f64>,
}

/// One part's nodes and the rates it computes (node after node).
#[derive(Clone, Default)]
struct PartBuffers {
    nodes: Vec<usize>,
    dyu: Vec<f64>,
    dya: Vec<f64>,
}

impl PartNodes {
    /// Splits `h`'s rows into `threads` parts ([`HMatrix::split_rows`], balanced for a
    /// node's solve per row) and gives each node to its part; `first` as in
    /// [`NodeSolves`].
    pub fn new(h: &mut HMatrix, threads: usize, first: &[usize]) -> Self {
        let ranges = h.split_rows(threads, Self::work_per_row(first));
        let order = h.permutation().to_vec();
        Self::from_split(RowSplit { order, ranges }, first)
    }

    /// The work of a node's solve per row, in multiply-adds (what a split balances).
    pub fn work_per_row(first: &[usize]) -> f64 {
        let nodes = first.len() - 1;
        SOLVE_WORK * nodes as f64 / first[nodes].max(1) as f64
    }

    /// Gives each node to the part of `split` holding its rows (`split` valid for the
    /// `first[nodes]` rows).
    pub fn from_split(split: RowSplit, first: &[usize]) -> Self {
        let nodes = first.len() - 1;
        let m = first[nodes];
        let RowSplit { order, ranges } = split;
        let mut position = vec![0; m];
        for (p, &i) in order.iter().enumerate() {
            position[i] = p;
        }
        let part_of = |p: usize| ranges.partition_point(|r| r.end <= p);
        let mut parts = vec![PartBuffers::default(); ranges.len()];
        let mut straddling = Vec::new();
        for k in 0..nodes {
            let (a, b) = (first[k], first[k + 1]);
            // A node without free components (fixed velocity) has no rows: part 0 solves it.
            let owner = if a < b { part_of(position[a]) } else { 0 };
            if (a..b).all(|i| part_of(position[i]) == owner) {
                parts[owner].nodes.push(k);
                parts[owner].dyu.extend(std::iter::repeat_n(0.0, b - a));
                parts[owner].dya.push(0.0);
            } else {
                straddling.push(k);
            }
        }
        let mut straddling_rows = vec![Vec::new(); ranges.len()];
        for &k in &straddling {
            for i in first[k]..first[k + 1] {
                straddling_rows[part_of(position[i])].push(position[i]);
            }
        }
        for rows in &mut straddling_rows {
            rows.sort_unstable();
        }
        let longest = ranges.iter().map(Range::len).max().unwrap_or(0);
        Self {
            parts,
            ranges,
            straddling,
            position,
            order,
            straddling_rows,
            send: Vec::new(),
            residual: vec![0.0; longest],
        }
    }

    /// The number of parts (at most the number asked for: one per leaf cluster at most).
    pub fn len(&self) -> usize {
        self.parts.len()
    }

    /// How many values part `p` sends when shared out ([`evaluate_part`](Self::evaluate_part)).
    pub fn send_len(&self, p: usize) -> usize {
        let b = &self.parts[p];
        b.dyu.len() + b.dya.len() + self.straddling_rows[p].len()
    }

    /// Part `p` alone (one process's share): its rows of `g(t) − S u`
    /// ([`FaultOperator::part_subtract`] of the operator that made the split), its nodes'
    /// solves, and what it sends ([`sent`](Self::sent)): its nodes' slip rates, their
    /// state rates and its rows of the nodes across parts — what
    /// [`unpack`](Self::unpack) reads, part after part.
    ///
    /// # Errors
    /// The product's, before anything is sent.
    pub fn evaluate_part<L: FrictionLaw, S: StateLaw, const C: usize>(
        &mut self,
        operator: &mut dyn FaultOperator,
        p: usize,
        u: &[f64],
        solves: &NodeSolves<'_, L, S, C>,
        load: Loading<'_>,
    ) -> crate::Result<()> {
        let range = self.ranges[p].clone();
        let residual = &mut self.residual[..range.len()];
        // `g` first, then the product subtracted: the sums of the sequential evaluation.
        for (r, &i) in residual.iter_mut().zip(&self.order[range.clone()]) {
            *r = load.g0[i] + load.big_g * load.g1[i];
        }
        operator.part_subtract(u, p, residual)?;
        let position = &self.position;
        let buf = &mut self.parts[p];
        buf.solve(|i| residual[position[i] - range.start], solves);
        let send = &mut self.send;
        send.clear();
        send.extend_from_slice(&buf.dyu);
        send.extend_from_slice(&buf.dya);
        send.extend(
            self.straddling_rows[p]
                .iter()
                .map(|&q| residual[q - range.start]),
        );
        Ok(())
    }

    /// What the last [`evaluate_part`](Self::evaluate_part) sends.
    pub fn sent(&self) -> &[f64] {
        &self.send
    }

    /// Every part's values sent by [`evaluate_part`](Self::evaluate_part), concatenated
    /// in part order (`all`), into the rates; the nodes across parts solved from the rows
    /// of `g(t) − S u` the parts sent (`rows`: scratch of the product's length, the split's
    /// order).
    pub fn unpack<L: FrictionLaw, S: StateLaw, const C: usize>(
        &self,
        all: &[f64],
        solves: &NodeSolves<'_, L, S, C>,
        rows: &mut [f64],
        rates: RatesOut<'_>,
    ) {
        let RatesOut { dyu, dya } = rates;
        let first = solves.first;
        let mut at = 0;
        for (buf, straddling_rows) in self.parts.iter().zip(&self.straddling_rows) {
            let (u_len, a_len) = (buf.dyu.len(), buf.dya.len());
            buf.scatter(
                first,
                &all[at..at + u_len],
                &all[at + u_len..at + u_len + a_len],
                dyu,
                dya,
            );
            at += u_len + a_len;
            for &q in straddling_rows {
                rows[q] = all[at];
                at += 1;
            }
        }
        debug_assert_eq!(at, all.len());
        self.solve_straddling(|i| rows[self.position[i]], solves, dyu, dya);
    }

    /// The nodes across parts, from their rows of `g(t) − S u` (`residual(i)`, row `i`).
    fn solve_straddling<L: FrictionLaw, S: StateLaw, const C: usize>(
        &self,
        residual: impl Fn(usize) -> f64,
        solves: &NodeSolves<'_, L, S, C>,
        dyu: &mut [f64],
        dya: &mut [f64],
    ) {
        let first = solves.first;
        for &k in &self.straddling {
            let (a, b) = (first[k], first[k + 1]);
            let mut r = [0.0; C];
            for (rc, i) in r.iter_mut().zip(a..b) {
                *rc = residual(i);
            }
            dya[k] = solves.solve_node(k, &r[..b - a], &mut dyu[a..b]);
        }
    }

    /// The evaluation by parts: `S u` by `h`'s parts (the split of [`PartNodes::new`]),
    /// each part solving its nodes inside its task, then the nodes across parts; the
    /// rates into `dyu` (all free components) and `dya` (all nodes). Bit-identical to
    /// [`NodeSolves::solve`] after the whole product.
    ///
    /// # Errors
    /// The product's ([`HMatrix::apply_by_parts`]), before anything is written.
    pub fn evaluate<L: FrictionLaw + Sync, S: StateLaw + Sync, const C: usize>(
        &mut self,
        h: &mut HMatrix,
        u: &[f64],
        solves: &NodeSolves<'_, L, S, C>,
        load: Loading<'_>,
        rates: RatesOut<'_>,
    ) -> Result<(), rsf_hmatrix::Error> {
        let RatesOut { dyu, dya } = rates;
        let (position, ranges) = (&self.position, &self.ranges);
        h.apply_by_parts(u, &mut self.parts, |rows, buf| {
            assert_eq!(
                rows.rows, ranges[rows.part],
                "the ℋ-matrix's rows were split again after the nodes were given to parts"
            );
            let start = rows.rows.start;
            buf.solve(|i| load.residual(i, rows.z[position[i] - start]), solves);
        })?;
        let su = h.last_product();
        self.solve_straddling(|i| load.residual(i, su[self.position[i]]), solves, dyu, dya);
        for buf in &self.parts {
            buf.scatter(solves.first, &buf.dyu, &buf.dya, dyu, dya);
        }
        Ok(())
    }
}

impl PartBuffers {
    /// The part's nodes' solves from their rows of `g(t) − S u` (`residual(i)`, row `i`).
    fn solve<L: FrictionLaw, S: StateLaw, const C: usize>(
        &mut self,
        residual: impl Fn(usize) -> f64,
        solves: &NodeSolves<'_, L, S, C>,
    ) {
        let first = solves.first;
        let mut offset = 0;
        for (j, &k) in self.nodes.iter().enumerate() {
            let (a, b) = (first[k], first[k + 1]);
            let mut r = [0.0; C];
            for (rc, i) in r.iter_mut().zip(a..b) {
                *rc = residual(i);
            }
            let out = &mut self.dyu[offset..offset + (b - a)];
            self.dya[j] = solves.solve_node(k, &r[..b - a], out);
            offset += b - a;
        }
    }

    /// The part's nodes' rates (`part_u`, `part_a`: node after node, as in the buffers)
    /// into the whole rates.
    fn scatter(
        &self,
        first: &[usize],
        part_u: &[f64],
        part_a: &[f64],
        dyu: &mut [f64],
        dya: &mut [f64],
    ) {
        let mut offset = 0;
        for (j, &k) in self.nodes.iter().enumerate() {
            let (a, b) = (first[k], first[k + 1]);
            dyu[a..b].copy_from_slice(&part_u[offset..offset + (b - a)]);
            dya[k] = part_a[j];
            offset += b - a;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_friction::{AsinhLaw, RateStateParams};
    use rsf_hmatrix::{HOptions, Points};
    use rsf_state::Aging;

    /// The per-node data of an evaluation of `nodes` nodes of `C` components: the laws,
    /// weights, states, slip `u` and loading `g0 + 0.75 g1`.
    struct Fixture<const C: usize> {
        friction: Vec<AsinhLaw>,
        state_laws: Vec<Aging>,
        first: Vec<usize>,
        weights: Vec<f64>,
        fixed_velocity: Vec<[f64; C]>,
        alpha: Vec<f64>,
        u: Vec<f64>,
        g0: Vec<f64>,
        g1: Vec<f64>,
        eta: Vec<f64>,
    }

    impl<const C: usize> Fixture<C> {
        fn new(nodes: usize) -> Self {
            let m = C * nodes;
            let params = RateStateParams {
                mu0: 0.6,
                a: 0.01,
                b: 0.015,
                v0: 1e-6,
                l: 0.008,
                sigma_n: 50e6,
            };
            Self {
                friction: vec![AsinhLaw::new(params).unwrap(); nodes],
                state_laws: vec![Aging::new(params.l).unwrap(); nodes],
                first: (0..=nodes).map(|k| C * k).collect(),
                weights: (0..nodes).map(|k| 20.0 + (k % 3) as f64).collect(),
                fixed_velocity: vec![[0.0; C]; nodes],
                alpha: (0..nodes).map(|k| 8.0 + (k as f64 * 0.37).sin()).collect(),
                u: (0..m).map(|i| 1e-3 * ((i as f64) * 0.71).cos()).collect(),
                g0: (0..m).map(|i| 6e8 + 1e6 * (i % 7) as f64).collect(),
                g1: (0..m).map(|i| 1e5 * (i % 5) as f64).collect(),
                eta: vec![5e6; nodes],
            }
        }

        fn load(&self) -> Loading<'_> {
            Loading {
                g0: &self.g0,
                g1: &self.g1,
                big_g: 0.75,
            }
        }

        fn solves(&self) -> NodeSolves<'_, AsinhLaw, Aging, C> {
            NodeSolves {
                friction: &self.friction,
                state_laws: &self.state_laws,
                uses_state: true,
                first: &self.first,
                weights: &self.weights,
                fixed_velocity: &self.fixed_velocity,
                eta: &self.eta,
                speed: 1e-9,
                alpha: &self.alpha,
                scale: None,
                effective: None,
            }
        }

        /// `g0 + 0.75 g1`, what the product is subtracted from.
        fn loading(&self) -> Vec<f64> {
            let big_g = self.load().big_g;
            self.g0
                .iter()
                .zip(&self.g1)
                .map(|(a, b)| a + big_g * b)
                .collect()
        }
    }

    /// Two components per node (1 m apart, not coincident, so that the cluster tree's
    /// median splits can put them in different leaves and parts): the evaluation by parts
    /// gives the bits of the whole product followed by the sequential solves, for every
    /// number of parts, with nodes across parts among them.
    #[test]
    fn the_evaluation_by_parts_has_the_bits_of_the_sequential_one() {
        const C: usize = 2;
        let nodes = 61;
        let m = C * nodes;
        let coords: Vec<f64> = (0..m)
            .map(|i| 25.0 * (i / C) as f64 + (i % C) as f64)
            .collect();
        let points = Points::new(&coords, 1).unwrap();
        let s = faer::Mat::from_fn(m, m, |i, j| {
            let d = (coords[i] - coords[j]).abs();
            let same = if i % C == j % C { 1.0 } else { 0.3 };
            same * 3e7 / (1.0 + d / 25.0) + if i == j { 1e8 } else { 0.0 }
        });
        let options = HOptions {
            leaf_size: 5,
            ..HOptions::with_epsilon(1e-9)
        };
        let fx = Fixture::<C>::new(nodes);
        let (first, u, load, solves) = (&fx.first, &fx.u, fx.load(), fx.solves());
        let mut h = HMatrix::from_dense(s.as_ref(), &points, &options).unwrap();
        let mut r = fx.loading();
        h.apply_add(u, &mut r, -1.0, faer::Par::Seq).unwrap();
        let (mut dyu, mut dya) = (vec![0.0; m], vec![0.0; nodes]);
        solves.solve((0, nodes), 1, &r, &mut dyu, &mut dya);
        assert!(dyu.iter().chain(&dya).all(|v| v.is_finite() && *v != 0.0));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let mut straddled = 0;
        for threads in 1..=6 {
            let mut parts = PartNodes::new(&mut h, threads, first);
            straddled += parts.straddling.len();
            let owned: usize = parts.parts.iter().map(|p| p.nodes.len()).sum();
            assert_eq!(owned + parts.straddling.len(), nodes);
            let (mut pu, mut pa) = (vec![f64::NAN; m], vec![f64::NAN; nodes]);
            parts
                .evaluate(
                    &mut h,
                    u,
                    &solves,
                    load,
                    RatesOut {
                        dyu: &mut pu,
                        dya: &mut pa,
                    },
                )
                .unwrap();
            assert_eq!(bits(&pu), bits(&dyu), "{threads} parts");
            assert_eq!(bits(&pa), bits(&dya), "{threads} parts");
        }
        assert!(
            straddled > 0,
            "no node across two parts: the test misses that path"
        );
    }

    /// A dense operator whose every row is one sum in column order, by parts or whole.
    struct RowSums(
        faer::Mat<f64>,
        crate::fault_operator::KernelReport,
        RowSplit,
    );

    impl RowSums {
        fn row(&self, i: usize, x: &[f64]) -> f64 {
            (0..x.len()).fold(0.0, |acc, j| acc + self.0[(i, j)] * x[j])
        }
    }

    impl FaultOperator for RowSums {
        fn dim(&self) -> usize {
            self.0.nrows()
        }
        fn subtract_product(
            &mut self,
            x: &[f64],
            r: &mut [f64],
            _: rsf_linalg::Parallelism,
        ) -> crate::Result<()> {
            for (i, ri) in r.iter_mut().enumerate() {
                *ri += -self.row(i, x);
            }
            Ok(())
        }
        fn report(&self) -> &crate::fault_operator::KernelReport {
            &self.1
        }
        fn split_rows(&mut self, _: usize, _: f64) -> crate::Result<RowSplit> {
            Ok(self.2.clone())
        }
        fn part_subtract(&mut self, x: &[f64], part: usize, r: &mut [f64]) -> crate::Result<()> {
            let range = self.2.ranges[part].clone();
            for (ri, &i) in r.iter_mut().zip(&self.2.order[range]) {
                *ri += -self.row(i, x);
            }
            Ok(())
        }
    }

    /// Parts shared out to processes (`evaluate_part` of each, their values concatenated,
    /// `unpack`) give the bits of the sequential evaluation, with a split in another order
    /// than the rows' whose parts cut nodes (three components) in two.
    #[test]
    fn parts_shared_out_have_the_bits_of_the_sequential_evaluation() {
        const C: usize = 3;
        let nodes = 23;
        let m = C * nodes;
        let s = faer::Mat::from_fn(m, m, |i, j| {
            let d = (i as f64 - j as f64).abs();
            3e7 / (1.0 + d) + if i == j { 1e8 } else { 0.0 }
        });
        let split = RowSplit {
            order: (0..m).rev().collect(),
            ranges: vec![0..7, 7..31, 31..32, 32..m],
        };
        split.validate(m).unwrap();
        let mut op = RowSums(
            s,
            crate::fault_operator::KernelReport::dense(m),
            split.clone(),
        );
        let fx = Fixture::<C>::new(nodes);
        let (first, u, load, solves) = (&fx.first, &fx.u, fx.load(), fx.solves());
        let mut r = fx.loading();
        op.subtract_product(u, &mut r, rsf_linalg::Parallelism::SEQ)
            .unwrap();
        let (mut dyu, mut dya) = (vec![0.0; m], vec![0.0; nodes]);
        solves.solve((0, nodes), 1, &r, &mut dyu, &mut dya);
        let mut parts = PartNodes::from_split(split, first);
        assert!(!parts.straddling.is_empty(), "no node across parts");
        let mut all = Vec::new();
        for p in 0..parts.len() {
            parts.evaluate_part(&mut op, p, u, &solves, load).unwrap();
            assert_eq!(parts.sent().len(), parts.send_len(p));
            all.extend_from_slice(parts.sent());
        }
        let (mut pu, mut pa) = (vec![f64::NAN; m], vec![f64::NAN; nodes]);
        let mut rows = vec![0.0; m];
        parts.unpack(
            &all,
            &solves,
            &mut rows,
            RatesOut {
                dyu: &mut pu,
                dya: &mut pa,
            },
        );
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&pu), bits(&dyu));
        assert_eq!(bits(&pa), bits(&dya));
    }
}
