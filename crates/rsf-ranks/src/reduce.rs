//! Reproducible global sums: every rank adds its terms into exact accumulators (Neal's
//! superaccumulators, the `xsum` crate), extracts each partial sum as an exact expansion
//! (a few non-overlapping doubles), all-gathers them (one collective,
//! [`RankGroup::all_gather`]), and every rank adds all expansions exactly and rounds
//! once. The total is the correctly rounded exact sum of all
//! the terms: the same bits whatever the rank count, the partition and the order of the
//! terms.
//!
//! `xsum` 0.1.6 rounds a negative total wrongly (its negative branch rounds away from
//! zero where the exact value needs no rounding up: a single negative term comes back one
//! ulp larger in magnitude); its positive branch is correct. [`ExactAccumulator`] therefore
//! keeps the terms and their negations and rounds whichever total is not negative.

use xsum::{Xsum, XsumSmall};

/// An exact sum of f64 terms, rounded correctly (to nearest, ties to even) on demand: two
/// `xsum` accumulators, of the terms and of their negations, so that the total is always
/// rounded from the non-negative one (see the module's documentation).
#[derive(Default)]
pub(crate) struct ExactAccumulator {
    pos: XsumSmall,
    neg: XsumSmall,
}

impl ExactAccumulator {
    /// Adds `x` exactly.
    #[inline]
    pub fn add(&mut self, x: f64) {
        self.pos.add(x);
        self.neg.add(-x);
    }

    /// Adds every value of `xs` exactly.
    pub fn add_list(&mut self, xs: &[f64]) {
        for &x in xs {
            self.add(x);
        }
    }

    /// The correctly rounded value of the exact sum (the accumulator is kept).
    pub fn sum(&mut self) -> f64 {
        let s = self.pos.sum();
        if s < 0.0 {
            -self.neg.sum()
        } else {
            s
        }
    }

    /// Sets the sum to zero.
    pub fn clear(&mut self) {
        self.pos.clear();
        self.neg.clear();
    }
}

use crate::halo::HaloCounters;
use crate::transport::RankGroup;

/// Most doubles in the expansion of one exact sum of doubles: each term of
/// [`expansion`] is at most half an ulp of the previous one, so its exponent is at least 53
/// below; exponents span 2⁻¹⁰⁷⁴ … 2¹⁰²³ (2098 binades, at most 40 steps of 53), plus one.
pub(crate) const MAX_EXPANSION: usize = 41;

/// Values of one sum in a reduction's message: its expansion's length, then the
/// expansion padded with zeros to [`MAX_EXPANSION`].
const SLOT: usize = 1 + MAX_EXPANSION;

/// Writes the exact value held by `acc` as an expansion `e_0, e_1, …` into `out`
/// (decreasing magnitudes, each at most half an ulp of the previous one, `Σ e_i` the
/// exact value) and returns its length (0 for an exact zero); `acc` is left holding zero.
/// A non-finite sum (an infinite term, a NaN, or an exact value beyond the range of f64)
/// gives the single value `acc.sum()` (∞ or NaN).
///
/// # Panics
/// If `out` is shorter than [`MAX_EXPANSION`].
pub(crate) fn expansion(acc: &mut ExactAccumulator, out: &mut [f64]) -> usize {
    let mut len = 0;
    while len < MAX_EXPANSION {
        let s = acc.sum();
        if s == 0.0 {
            break;
        }
        out[len] = s;
        len += 1;
        if !s.is_finite() {
            break;
        }
        // Exact: the accumulator holds the remainder, at most half an ulp of `s`.
        acc.add(-s);
    }
    acc.clear();
    len
}

/// The correctly rounded exact sum of expansions (`+0.0` for an exact zero, whatever the
/// terms: the sign of a zero sum would otherwise depend on how the terms were split).
fn total<'a>(parts: impl Iterator<Item = &'a [f64]>) -> f64 {
    let mut acc = ExactAccumulator::default();
    for p in parts {
        acc.add_list(p);
    }
    let s = acc.sum();
    if s == 0.0 {
        0.0
    } else {
        s
    }
}

/// A fixed number of global sums reduced together in one all-gather (every rank
/// contributes its partial expansions, `42 · sums` values, and receives every other
/// rank's). Allocation-free after set-up (the transport may allocate).
pub struct ExactSums {
    rank: usize,
    accs: Vec<ExactAccumulator>,
    /// Own slots (`SLOT` per sum), the rank's contribution.
    send: Vec<f64>,
    /// `SLOT · sums` per rank.
    counts: Vec<usize>,
    /// Every rank's slots, rank `r`'s at `SLOT · sums · r`.
    recv: Vec<f64>,
    totals: Vec<f64>,
    counters: HaloCounters,
    /// Rounds each rank's terms in floating point in the order added before the exact
    /// combination (a reduction whose bits depend on the partition): for the tests that
    /// must detect it ([`use_naive_partial_sums`](Self::use_naive_partial_sums)).
    #[cfg(feature = "naive-sums")]
    naive: Option<Vec<f64>>,
}

impl std::fmt::Debug for ExactSums {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactSums")
            .field("rank", &self.rank)
            .field("sums", &self.accs.len())
            .field("counters", &self.counters)
            .finish()
    }
}

impl ExactSums {
    /// `sums` sums of rank `rank` of `size`.
    pub fn new(sums: usize, rank: usize, size: usize) -> Self {
        let len = SLOT * sums;
        Self {
            rank,
            accs: (0..sums).map(|_| ExactAccumulator::default()).collect(),
            send: vec![0.0; len],
            counts: vec![len; size],
            recv: vec![0.0; len * size],
            totals: vec![0.0; sums],
            counters: HaloCounters::default(),
            #[cfg(feature = "naive-sums")]
            naive: None,
        }
    }

    /// Number of sums.
    pub fn sums(&self) -> usize {
        self.accs.len()
    }

    /// Adds the term `x` to sum `i` (exactly).
    ///
    /// # Panics
    /// If `i` is not a sum of this reduction.
    #[inline]
    pub fn add(&mut self, i: usize, x: f64) {
        #[cfg(feature = "naive-sums")]
        if let Some(partial) = &mut self.naive {
            partial[i] += x;
            return;
        }
        self.accs[i].add(x);
    }

    /// Reduces: every sum's total over the terms added on every rank since the last
    /// reduction, correctly rounded, the same bits on every rank. Collective.
    ///
    /// # Panics
    /// If `halo` is another rank's or has another size, or as
    /// [`RankGroup::all_gather`].
    pub fn reduce<H: RankGroup + ?Sized>(&mut self, halo: &mut H) -> &[f64] {
        assert_eq!(halo.rank(), self.rank, "the transport of another rank");
        #[cfg(feature = "naive-sums")]
        if let Some(partial) = &mut self.naive {
            for (acc, p) in self.accs.iter_mut().zip(partial.iter_mut()) {
                acc.add(std::mem::take(p));
            }
        }
        self.send.fill(0.0);
        for (acc, slot) in self.accs.iter_mut().zip(self.send.chunks_exact_mut(SLOT)) {
            let len = expansion(acc, &mut slot[1..]);
            slot[0] = len as f64;
        }
        halo.all_gather(&self.send, &self.counts, &mut self.recv);
        self.counters += self.per_reduction();
        let width = SLOT * self.accs.len();
        for (i, t) in self.totals.iter_mut().enumerate() {
            // Every rank's expansion, in rank order (the sum is exact: any order).
            let parts = self.recv.chunks_exact(width).map(|m| {
                let len = (m[SLOT * i] as usize).min(MAX_EXPANSION);
                &m[SLOT * i + 1..SLOT * i + 1 + len]
            });
            *t = total(parts);
        }
        &self.totals
    }

    /// What one reduction sends: one collective of `42 · sums` values.
    pub fn per_reduction(&self) -> HaloCounters {
        HaloCounters {
            collectives: 1,
            collective_values: self.send.len() as u64,
            ..HaloCounters::default()
        }
    }

    /// What the reductions have sent since set-up (or [`reset_counters`](Self::reset_counters)).
    pub fn counters(&self) -> HaloCounters {
        self.counters
    }

    /// Sets the counters to zero.
    pub fn reset_counters(&mut self) {
        self.counters = HaloCounters::default();
    }

    /// Adds `c` to the counters (those of a reduction this one replaces).
    pub fn add_counters(&mut self, c: HaloCounters) {
        self.counters += c;
    }

    /// From now on rounds each rank's terms in floating point, in the order added, before
    /// the exact combination of the ranks' partial sums: a reduction whose bits depend on
    /// the partition, for the tests that must detect one (crate feature `naive-sums`,
    /// never on in a program's build).
    #[cfg(feature = "naive-sums")]
    pub fn use_naive_partial_sums(&mut self) {
        self.naive = Some(vec![0.0; self.accs.len()]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ThreadRanks;

    /// A deterministic generator (SplitMix64).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }
    }

    /// `terms` reduced on `size` thread ranks, term `j` on rank `split(j)`: every rank's
    /// totals (one sum, then the same terms negated as a second sum).
    fn reduced(terms: &[f64], size: usize, split: impl Fn(usize) -> usize + Sync) -> Vec<f64> {
        let totals = ThreadRanks::run(size, |mut halo| {
            let mut sums = ExactSums::new(2, halo.rank(), size);
            for (j, &x) in terms.iter().enumerate() {
                if split(j) == halo.rank() {
                    sums.add(0, x);
                    sums.add(1, -x);
                }
            }
            let t = sums.reduce(&mut halo).to_vec();
            assert_eq!(sums.counters(), sums.per_reduction());
            t
        });
        for t in &totals {
            assert_eq!(t[0].to_bits(), totals[0][0].to_bits(), "every rank's total");
            assert_eq!(t[1].to_bits(), (-totals[0][0] + 0.0).to_bits(), "negated");
        }
        totals[0].clone()
    }

    /// Integers times powers of two whose exact sum an i128 holds: the reduced sum at 1–4
    /// ranks, under several splits of the terms, is the correctly rounded exact sum (the
    /// i128 rounded once), where the naive sum in order is not.
    #[test]
    fn reduced_sums_are_the_correctly_rounded_exact_sum() {
        let mut rng = Rng(7);
        let mut naive_wrong = 0;
        for case in 0..20 {
            let n = 50 + case * 13;
            // m · 2^e with |m| < 2^50, e in [−40, 10]: exact sum · 2^40 fits an i128.
            let (terms, scaled): (Vec<f64>, Vec<i128>) = (0..n)
                .map(|_| {
                    let m = (rng.next() >> 14) as i64 - (1i64 << 49);
                    let e = (rng.next() % 51) as i32 - 40;
                    (m as f64 * 2f64.powi(e), (m as i128) << (e + 40))
                })
                .unzip();
            let exact: i128 = scaled.iter().sum();
            let want = exact as f64 * 2f64.powi(-40);
            if terms.iter().sum::<f64>() != want {
                naive_wrong += 1;
            }
            for size in 1..=4 {
                let by_index = reduced(&terms, size, |j| j % size);
                let by_block = reduced(&terms, size, |j| j * size / n);
                for got in [by_index[0], by_block[0]] {
                    assert_eq!(got.to_bits(), want.to_bits(), "case {case}, {size} ranks");
                }
            }
        }
        assert!(naive_wrong > 0, "the inputs do not need exact summation");
    }

    /// Cancellation across the whole exponent range, with known exact sums: the totals at
    /// 1–4 ranks under every split are the rounded exact values.
    #[test]
    fn reduced_sums_survive_cancellation_and_wide_exponents() {
        let tiny = f64::from_bits(1); // 2^-1074
        let cases: Vec<(Vec<f64>, f64)> = vec![
            (vec![1e300, 1.0, -1e300], 1.0),
            (
                vec![2f64.powi(1000), 2f64.powi(-1000), -2f64.powi(1000)],
                2f64.powi(-1000),
            ),
            // 1 + 2^-53 + 2^-106 lies above the midpoint of 1 and 1 + 2^-52.
            (
                vec![1.0, 2f64.powi(-53), 2f64.powi(-106)],
                1.0 + 2f64.powi(-52),
            ),
            (
                vec![f64::MAX, tiny, -f64::MAX, tiny, 3.0 * tiny],
                5.0 * tiny,
            ),
            (vec![f64::MAX, 0.5, -f64::MAX, 0.25], 0.75),
            (vec![0.1, 0.2, -0.3, 1e-20, -1e-20], f64::NAN),
            (vec![1e16, 1.0, -1e16, 1.0, 1e-300], 2.0),
            // Negative totals (xsum 0.1.6 alone gets these one ulp too large in magnitude).
            (vec![-7.25e200], -7.25e200),
            (vec![-1.0, -2f64.powi(-53)], -1.0),
            (vec![-1.0, 2f64.powi(-60), -2f64.powi(-53)], -1.0),
        ];
        // The exact sum of the doubles 0.1, 0.2 and −0.3 (multiples of 2^-56), by integers.
        let exact_tenths = {
            let (a, b, c) = (0.1f64, 0.2f64, 0.3f64);
            // Scaled to integers: every one is a multiple of 2^-56.
            let s = |x: f64| (x * 2f64.powi(56)) as i128;
            (s(a) + s(b) - s(c)) as f64 * 2f64.powi(-56)
        };
        for (k, (terms, want)) in cases.iter().enumerate() {
            let want = if k == 5 { exact_tenths } else { *want };
            for size in 1..=4 {
                for rot in 0..terms.len() {
                    let got = reduced(terms, size, |j| (j + rot) % size);
                    assert_eq!(got[0].to_bits(), want.to_bits(), "case {k}, {size} ranks");
                }
            }
        }
    }

    /// Expansions: non-overlapping and decreasing (each term at most half an ulp of the
    /// previous one), at most [`MAX_EXPANSION`] long, exact (the expansion of the
    /// expansion is itself), and the longest possible case reaches many terms.
    #[test]
    fn expansions_are_exact_and_bounded() {
        let mut rng = Rng(11);
        let mut longest = 0;
        for case in 0..200 {
            let mut acc = ExactAccumulator::default();
            let terms: Vec<f64> = (0..(1 + case % 40))
                .map(|_| {
                    let e = (rng.next() % 2000) as i32 - 1000;
                    let m = (rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    m * 2f64.powi(e)
                })
                .collect();
            acc.add_list(&terms);
            let mut out = [0.0; MAX_EXPANSION];
            let len = expansion(&mut acc, &mut out);
            longest = longest.max(len);
            for w in out[..len].windows(2) {
                let half_ulp = (w[0].abs() * f64::EPSILON * 0.5).max(f64::from_bits(1));
                assert!(
                    w[1].abs() <= half_ulp,
                    "case {case}: {} then {}",
                    w[0],
                    w[1]
                );
            }
            let mut again = ExactAccumulator::default();
            again.add_list(&out[..len]);
            let mut out2 = [0.0; MAX_EXPANSION];
            let len2 = expansion(&mut again, &mut out2);
            assert_eq!(out[..len], out2[..len2], "case {case}");
            assert_eq!(acc.sum(), 0.0, "the accumulator is cleared");
        }
        assert!(longest >= 10, "longest expansion {longest}");
    }
}
