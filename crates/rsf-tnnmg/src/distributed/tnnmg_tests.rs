//! TNNMG on ranks on a cube's elasticity problem with Tresca friction on its top face: the same bits at 1–4 thread ranks under two partitions, the counters against the
//! plans, the one-process TNNMG's minimiser, a non-reproducible sum detected, the set-up's
//! errors.

use faer::sparse::SparseColMatRef;
use rsf_nonsmooth::{BlockNonlinearity, NonsmoothSolver, SolveReport, Stopping};

use super::fixtures::{cube, owners, Problem};
use super::*;
use crate::error::Error;
use crate::smoother_order::SmootherOrder;
use crate::{Tnnmg, TnnmgOptions};
use rsf_nonsmooth::ProblemError;
use rsf_ranks::halo::HaloCounters;
use rsf_ranks::{RankGroup, ThreadRanks};

const D: usize = 3;

/// Tresca friction of bound `g` and viscous weight `q` on the nodes of the top face z = 1.
fn friction(pb: &Problem, g: f64, q: f64) -> BlockTresca<D> {
    let nodes: Vec<usize> = (pb.bx.mesh().vertices().iter().enumerate())
        .filter(|(_, v)| v[2] == 1.0)
        .map(|(p, _)| p)
        .collect();
    let k = nodes.len();
    BlockTresca::new(nodes, vec![g; k], vec![q; k]).unwrap()
}

fn prolongations(pb: &Problem) -> Vec<SparseColMatRef<'_, usize, f64>> {
    let h = &pb.bx.hierarchy;
    (1..=h.finest_level())
        .map(|j| h.vector_prolongation(j).as_ref())
        .collect()
}

/// TNNMG on the thread rank `halo` for the problem's fixed dofs and prolongations: the
/// matrix `a`, the energy-norm matrix `e` (if any), options `opts`, the nodes' ranks `owner`.
fn rank_solver(
    pb: &Problem,
    a: SparseColMatRef<'_, usize, f64>,
    e: Option<SparseColMatRef<'_, usize, f64>>,
    opts: DistributedTnnmgOptions,
    owner: &[usize],
    halo: impl RankGroup + 'static,
) -> DistributedTnnmg<D> {
    let ps = prolongations(pb);
    DistributedTnnmg::<D>::new(a, &pb.bx.fixed, &ps, e, opts, owner, Box::new(halo)).unwrap()
}

fn options(record_energy: bool) -> DistributedTnnmgOptions {
    DistributedTnnmgOptions {
        stopping: Stopping {
            absolute: 1e-10,
            relative: 0.0,
            max_iterations: 100,
        },
        smoothing: VCycleShape { pre: 2, post: 2 },
        record_energy,
        ..DistributedTnnmgOptions::default()
    }
}

/// One rank's end of a solve.
struct RankSolve {
    v: Vec<f64>,
    report: SolveReport,
    counters: TnnmgCounters,
    per_iteration: TnnmgCounters,
    per_solution: HaloCounters,
    /// What a full update of the hierarchy sends.
    per_full_update: HaloCounters,
}

/// The solve from the box's start on `size` thread ranks under `owner`, every rank's
/// end; `broken` makes the line search's sums non-reproducible. The same solver solves
/// `solves` times (1 or more) from the start, each time to the same bits (checked), and
/// the last solve is returned (the counters over all).
#[expect(
    clippy::too_many_arguments,
    reason = "the problem, its partition, the options, the runs"
)]
fn solve_on_ranks(
    pb: &Problem,
    nl: &BlockTresca<D>,
    owner: &[usize],
    size: usize,
    opts: DistributedTnnmgOptions,
    broken: bool,
    solves: usize,
) -> Vec<RankSolve> {
    ThreadRanks::run(size, |halo| {
        let mut s = rank_solver(pb, pb.a(), None, opts, owner, halo);
        if broken {
            s = s.with_naive_line_sums();
        }
        let mut v = pb.x0.clone();
        let mut report = s.solve(&pb.b, nl, &mut v).unwrap();
        for _ in 1..solves {
            let first = std::mem::replace(&mut v, pb.x0.clone());
            report = s.solve(&pb.b, nl, &mut v).unwrap();
            assert_eq!(differing(&v, &first), 0, "a second solve");
        }
        RankSolve {
            v,
            report,
            counters: s.counters(),
            per_iteration: s.per_iteration().unwrap(),
            per_solution: s.per_solution(),
            per_full_update: s.per_full_update(),
        }
    })
}

/// The solve on one thread rank ([`solve_on_ranks`] once, every node on rank 0).
fn one_rank(pb: &Problem, nl: &BlockTresca<D>, opts: DistributedTnnmgOptions) -> RankSolve {
    let owner = vec![0; pb.x0.len() / D];
    solve_on_ranks(pb, nl, &owner, 1, opts, false, 1).remove(0)
}

fn differing(x: &[f64], y: &[f64]) -> usize {
    x.iter()
        .zip(y)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count()
}

/// At 1, 2, 3 and 4 thread ranks, under the coordinate split, slabs along z (ranks without
/// a frictional node) and METIS's partition (when built with METIS): every rank's solution has the bits of the one-rank solve, the
/// iteration counts agree; the friction both sticks (truncated blocks) and slips; what
/// every rank counted is its plans' per iteration times the iterations plus the
/// solution's all-gather, and the hierarchy's two full updates (set-up and first
/// iteration) and incremental ones; at several ranks every rank sends point-to-point messages, and
/// an iteration makes at least four collectives (two gathers of the active blocks, two
/// reductions).
#[test]
fn tnnmg_on_ranks_has_the_same_bits_at_one_to_four_ranks() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let one = solve_on_ranks(
        &pb,
        &nl,
        &vec![0; pb.x0.len() / D],
        1,
        options(false),
        false,
        1,
    );
    let reference = &one[0];
    assert!(reference.report.iterations > 2, "{:?}", reference.report);
    let stuck = nl
        .active_blocks()
        .iter()
        .filter(|&&p| reference.v[D * p..D * p + D] == [0.0; D])
        .count();
    assert!(
        stuck > 0 && stuck < nl.active_blocks().len(),
        "stuck {stuck} of {}",
        nl.active_blocks().len()
    );
    for size in 2..=4 {
        let mut partitions = owners(&pb, size);
        // Slabs along z: the frictional top face on the last rank only.
        partitions.push(("z slabs", pb.bx.slabs(size, 2)));
        for (name, owner) in partitions {
            let ranks = solve_on_ranks(&pb, &nl, &owner, size, options(false), false, 1);
            for (r, rank) in ranks.iter().enumerate() {
                assert_eq!(
                    differing(&rank.v, &reference.v),
                    0,
                    "{name}: rank {r} of {size}"
                );
                assert_eq!(rank.report.iterations, reference.report.iterations);
                assert_eq!(
                    rank.report.correction.to_bits(),
                    reference.report.correction.to_bits()
                );
                let it = rank.report.iterations as u64;
                let mut want = rank.per_iteration;
                want = TnnmgCounters {
                    iterations: it,
                    full_updates: 1,
                    smoother: want.smoother.times(it),
                    cycles: want.cycles.times(it),
                    gathers: want.gathers.times(it),
                    reductions: want.reductions.times(it),
                    solution: rank.per_solution,
                    // The set-up's full update and the solve's first; the others
                    // incremental.
                    hierarchy: rank.per_full_update.times(2) + want.hierarchy.times(it - 1),
                    // One agreement on the parts, three gathers of the fine graph and
                    // diagonal.
                    setup: HaloCounters {
                        collectives: 4,
                        ..rank.counters.setup
                    },
                };
                assert_eq!(rank.counters, want, "{name}: rank {r} of {size}");
                let total = rank.per_iteration.total();
                assert_eq!(total.messages > 0, size > 1, "{name}: rank {r} of {size}");
                assert!(total.collectives >= 4, "{name}: rank {r} of {size}");
            }
        }
    }
}

/// The inexact-Newton rule (at most 4 V-cycles per iteration, stopping at a residual
/// reduction of 0.1) at 1–4 thread ranks: the same bits and iteration counts as one
/// rank, fewer iterations than one cycle per iteration, no more reductions and cycles than
/// the plan's most; two solves with the same active blocks set the hierarchy up in full
/// once, and the second has the first's bits.
#[test]
fn inexact_newton_on_ranks_has_the_same_bits() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let opts = DistributedTnnmgOptions {
        v_cycles: 4,
        linear_reduction: Some(0.1),
        ..options(false)
    };
    let nodes = pb.x0.len() / D;
    let one = &solve_on_ranks(&pb, &nl, &vec![0; nodes], 1, opts, false, 2)[0];
    let classical = &one_rank(&pb, &nl, options(false));
    assert!(
        one.report.iterations < classical.report.iterations,
        "{} against {}",
        one.report.iterations,
        classical.report.iterations
    );
    assert_eq!(one.counters.full_updates, 1);
    let most = one
        .per_iteration
        .cycles
        .times(2 * one.report.iterations as u64);
    assert!(
        one.counters.cycles.exchanges < most.exchanges,
        "some iterations stop early"
    );
    for size in 2..=4 {
        let owner = pb.bx.slabs(size, 2);
        let ranks = solve_on_ranks(&pb, &nl, &owner, size, opts, false, 2);
        for (r, rank) in ranks.iter().enumerate() {
            assert_eq!(differing(&rank.v, &one.v), 0, "rank {r} of {size}");
            assert_eq!(rank.report.iterations, one.report.iterations);
            assert_eq!(rank.counters.full_updates, 1);
            let it = 2 * rank.report.iterations as u64;
            let plan = rank.per_iteration;
            for (got, most) in [
                (rank.counters.cycles, plan.cycles.times(it)),
                (rank.counters.reductions, plan.reductions.times(it)),
            ] {
                assert!(got.exchanges <= most.exchanges && got.values <= most.values);
            }
        }
    }
}

/// Conjugate gradients preconditioned by the V-cycle (at most 4 steps per iteration,
/// with and without the reduction 0.1) at 1–4 thread ranks: the same bits and iteration
/// counts as one rank, no more reductions and cycles than the plan's most, at most as
/// many iterations as the classical cycles, and the classical solve's minimiser (relative
/// A-norm distance below 1e-8).
#[test]
fn cg_on_ranks_has_the_same_bits() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let classical = &one_rank(&pb, &nl, options(false));
    for reduction in [None, Some(0.1)] {
        let opts = DistributedTnnmgOptions {
            v_cycles: 4,
            linear_correction: crate::LinearCorrection::PreconditionedCg,
            linear_reduction: reduction,
            ..options(false)
        };
        let one = &one_rank(&pb, &nl, opts);
        assert!(
            one.report.iterations <= classical.report.iterations,
            "{reduction:?}: {} against {}",
            one.report.iterations,
            classical.report.iterations
        );
        let diff: Vec<f64> = one.v.iter().zip(&classical.v).map(|(a, b)| a - b).collect();
        let (d, norm) = (a_norm(&pb, &diff), a_norm(&pb, &classical.v));
        assert!(d <= 1e-8 * norm, "{reduction:?}: distance {d}, norm {norm}");
        for size in 2..=4 {
            for owner in [pb.bx.slabs(size, 0), pb.bx.slabs(size, 2)] {
                let ranks = solve_on_ranks(&pb, &nl, &owner, size, opts, false, 1);
                for (r, rank) in ranks.iter().enumerate() {
                    let what = format!("{reduction:?}: rank {r} of {size}");
                    assert_eq!(differing(&rank.v, &one.v), 0, "{what}");
                    assert_eq!(rank.report.iterations, one.report.iterations, "{what}");
                    let it = rank.report.iterations as u64;
                    let plan = rank.per_iteration;
                    for (got, most) in [
                        (rank.counters.cycles, plan.cycles.times(it)),
                        (rank.counters.reductions, plan.reductions.times(it)),
                    ] {
                        assert!(got.exchanges <= most.exchanges, "{what}");
                        assert!(got.values <= most.values, "{what}");
                    }
                }
            }
        }
    }
}

/// The stopping norm of another matrix (`E = 4A`, through the energy-norm rows): every
/// term is four times the A-norm's, exactly, so the correction's norm is exactly twice
/// it and a tolerance twice as large stops at the same iteration with the same bits, at
/// 1 and 3 ranks; an energy-norm matrix of the wrong size is refused.
#[test]
fn an_energy_norm_matrix_is_used() {
    use faer::sparse::SparseColMat;
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let a = pb.a();
    let e = four_a(&pb);
    let nodes = pb.x0.len() / D;
    let reference = &one_rank(&pb, &nl, options(false));
    let mut opts = options(false);
    opts.stopping.absolute = 2e-10;
    for size in [1, 3] {
        let owner = pb.bx.slabs(size, 0);
        let ranks = ThreadRanks::run(size, |halo| {
            let mut s = rank_solver(&pb, a, Some(e.as_ref()), opts, &owner, halo);
            let mut v = pb.x0.clone();
            let report = s.solve(&pb.b, &nl, &mut v).unwrap();
            (v, report)
        });
        for (r, (v, report)) in ranks.iter().enumerate() {
            assert_eq!(differing(v, &reference.v), 0, "rank {r} of {size}");
            assert_eq!(report.iterations, reference.report.iterations);
            assert_eq!(report.correction, 2.0 * reference.report.correction);
        }
    }
    let halo = ThreadRanks::group(1).pop().unwrap();
    let ps = prolongations(&pb);
    let small = SparseColMat::<usize, f64>::try_new_from_triplets(3, 3, &[]).unwrap();
    let wrong = DistributedTnnmg::<D>::new(
        a,
        &pb.bx.fixed,
        &ps,
        Some(small.as_ref()),
        options(false),
        &vec![0; nodes],
        Box::new(halo),
    );
    assert!(matches!(
        wrong,
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
}

/// No nonlinearity (a linear system, no active block: empty gathers): the same bits at
/// 1 and 3 ranks, and the solution of `A v = b` on the free dofs (residual below 1e-8 of
/// the right-hand side's).
#[test]
fn a_linear_problem_on_ranks() {
    let pb = cube(2);
    let nl = rsf_nonsmooth::NoNonlinearity;
    let mut solutions = Vec::new();
    for size in [1, 3] {
        let owner = pb.bx.slabs(size, 0);
        let ranks = ThreadRanks::run(size, |halo| {
            let mut s = rank_solver(&pb, pb.a(), None, options(false), &owner, halo);
            let mut v = pb.x0.clone();
            s.solve(&pb.b, &nl, &mut v).unwrap();
            v
        });
        solutions.extend(ranks);
    }
    for v in &solutions {
        assert_eq!(differing(v, &solutions[0]), 0);
    }
    let (a, v) = (pb.a(), &solutions[0]);
    let mut r = pb.b.clone();
    for j in 0..a.ncols() {
        for (i, x) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            r[i] -= x * v[j];
        }
    }
    let free = |x: &[f64]| {
        (x.iter().zip(&pb.bx.fixed))
            .filter(|(_, &f)| !f)
            .map(|(x, _)| x * x)
            .sum::<f64>()
            .sqrt()
    };
    assert!(
        free(&r) <= 1e-8 * free(&pb.b),
        "{} of {}",
        free(&r),
        free(&pb.b)
    );
}

/// `J(v) = ½ vᵀAv − bᵀv + Σ φ` of a whole vector, summed in f64 (an independent
/// evaluation).
fn energy(pb: &Problem, nl: &BlockTresca<D>, v: &[f64]) -> f64 {
    let a = pb.a();
    let mut av = vec![0.0; v.len()];
    for j in 0..a.ncols() {
        for (i, x) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            av[i] += x * v[j];
        }
    }
    let quad: f64 = (0..v.len())
        .map(|i| 0.5 * v[i] * av[i] - pb.b[i] * v[i])
        .sum();
    let phi: f64 = (nl.active_blocks().iter().enumerate())
        .map(|(k, &p)| nl.value(k, &[v[D * p], v[D * p + 1], v[D * p + 2]]))
        .sum();
    quad + phi
}

/// `E = 4A`: an energy-norm matrix whose norm is twice the A-norm.
fn four_a(pb: &Problem) -> faer::sparse::SparseColMat<usize, f64> {
    use faer::sparse::{SparseColMat, Triplet};
    let a = pb.a();
    let mut t = Vec::new();
    for j in 0..a.ncols() {
        for (i, x) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            t.push(Triplet::new(i, j, 4.0 * x));
        }
    }
    SparseColMat::<usize, f64>::try_new_from_triplets(a.nrows(), a.ncols(), &t).unwrap()
}

/// The A-norm of `x`, summed in f64.
fn a_norm(pb: &Problem, x: &[f64]) -> f64 {
    let a = pb.a();
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            s += x[i] * v * x[j];
        }
    }
    s.sqrt()
}

/// The solve at 3 ranks against the one-process TNNMG (multi-colour order, the same
/// hierarchy and cycle): the two minimisers agree to the stopping tolerance's order
/// (relative A-norm distance below 1e-8, the corrections stop at 1e-10 in the A-norm of a
/// solution of norm ~10), the recorded energies decrease (up to round-off of the energy's
/// size times 1e-14) and match an independent evaluation of `J` at the solution.
#[test]
fn tnnmg_on_ranks_finds_the_one_process_minimiser() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let (_, owner) = owners(&pb, 3).remove(0);
    let ranks = solve_on_ranks(&pb, &nl, &owner, 3, options(true), false, 1);
    let v = &ranks[0].v;
    let energies = ranks[0].report.energy.as_ref().unwrap();
    assert_eq!(energies.len(), ranks[0].report.iterations + 1);
    for w in energies.windows(2) {
        assert!(w[1] <= w[0] + 1e-14 * w[0].abs(), "{energies:?}");
    }
    assert!(energies[0] > energies[energies.len() - 1]);
    let j = energy(&pb, &nl, v);
    let last = energies[energies.len() - 1];
    assert!((j - last).abs() <= 1e-12 * j.abs(), "J {j} recorded {last}");
    let h = &pb.bx.hierarchy;
    let ps: Vec<_> = (1..=h.finest_level())
        .map(|j| h.vector_prolongation(j).clone())
        .collect();
    let opts = TnnmgOptions {
        stopping: options(false).stopping,
        smoother: SmootherOrder::MultiColour,
        smoothing: (2, 2),
        ..TnnmgOptions::classical()
    };
    let mut one = Tnnmg::<D>::new(pb.a(), &pb.bx.fixed, &ps, None, opts).unwrap();
    let mut w = pb.x0.clone();
    one.solve(&pb.b, &nl, &mut w).unwrap();
    let diff: Vec<f64> = v.iter().zip(&w).map(|(a, b)| a - b).collect();
    let (d, norm) = (a_norm(&pb, &diff), a_norm(&pb, &w));
    assert!(d <= 1e-8 * norm, "distance {d}, norm {norm}");
    assert!(
        differing(v, &w) > 0,
        "different iterations, not the same bits"
    );
}

/// A broken reduction (each rank's line-search sums rounded in floating point before the
/// exact combination) changes the bits at some rank count: the test above can fail.
#[test]
fn a_non_reproducible_sum_changes_the_bits() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let reference = &one_rank(&pb, &nl, options(false));
    let broken: usize = (2..=4)
        .map(|size| {
            let (_, owner) = owners(&pb, size).remove(0);
            let ranks = solve_on_ranks(&pb, &nl, &owner, size, options(false), true, 1);
            differing(&ranks[0].v, &reference.v)
        })
        .sum();
    assert!(broken > 0, "the naive sums gave the same bits");
}

/// Wrong input is refused with errors, not panics.
#[test]
fn distributed_tnnmg_refuses_wrong_input() {
    let pb = cube(1);
    let nodes = pb.x0.len() / D;
    let ps = prolongations(&pb);
    let make =
        |ps: &[SparseColMatRef<'_, usize, f64>], opts: DistributedTnnmgOptions, owner: &[usize]| {
            let halo = ThreadRanks::group(1).pop().unwrap();
            DistributedTnnmg::<D>::new(pb.a(), &pb.bx.fixed, ps, None, opts, owner, Box::new(halo))
        };
    let owner = vec![0; nodes];
    assert!(matches!(
        make(&[], options(false), &owner),
        Err(Error::Problem(ProblemError::InvalidOption(_)))
    ));
    let zero_cycles = DistributedTnnmgOptions {
        v_cycles: 0,
        ..options(false)
    };
    assert!(matches!(
        make(&ps, zero_cycles, &owner),
        Err(Error::Problem(ProblemError::InvalidOption(_)))
    ));
    assert!(matches!(
        make(&ps, options(false), &owner[1..]),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    assert!(matches!(
        make(&ps, options(false), &vec![1; nodes]),
        Err(Error::InvalidPartition(_))
    ));
    let mut s = make(&ps, options(false), &owner).unwrap();
    let nl = friction(&pb, 1.0, 0.1);
    let mut v = pb.x0.clone();
    assert!(s.solve(&pb.b[1..], &nl, &mut v).is_err());
}

/// Each rank given only its owned nodes' columns of `A` (the others empty: what a rank
/// that assembles its own part holds) solves with the bits of the one-rank solve on the
/// whole matrix, at 2–4 thread ranks; a non-finite entry in one rank's columns ends every
/// rank's set-up with an error (that rank's own, the other naming it) instead of leaving
/// the others waiting in a collective.
#[test]
fn a_rank_needs_only_its_own_columns() {
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let reference = &one_rank(&pb, &nl, options(false));
    let set_up = |owner: &[usize], halo: ThreadRanks, poison: Option<f64>| {
        let rank = halo.rank();
        let a = columns(pb.a(), owner, rank, poison);
        let ps = prolongations(&pb);
        let (fixed, opts) = (&pb.bx.fixed, options(false));
        DistributedTnnmg::<D>::new_owned(a, fixed, &ps, None, opts, owner, Box::new(halo))
    };
    for size in 2..=4 {
        let owner = pb.bx.slabs(size, 0);
        let solutions = ThreadRanks::run(size, |halo| {
            let mut s = set_up(&owner, halo, None).unwrap();
            let mut v = pb.x0.clone();
            s.solve(&pb.b, &nl, &mut v).unwrap();
            v
        });
        for (r, v) in solutions.iter().enumerate() {
            assert_eq!(differing(v, &reference.v), 0, "rank {r} of {size}");
        }
    }
    let owner = pb.bx.slabs(2, 0);
    let errors = ThreadRanks::run(2, |halo| {
        let poison = (halo.rank() == 1).then_some(f64::NAN);
        set_up(&owner, halo, poison).err()
    });
    assert!(
        matches!(
            errors[1],
            Some(Error::Problem(ProblemError::InvalidMatrix(_)))
        ),
        "{errors:?}"
    );
    assert!(
        matches!(errors[0], Some(Error::InvalidPartition(_))),
        "{errors:?}"
    );
}

/// `a` with only the columns of the nodes `rank` owns (the others empty), its first
/// stored value replaced by `poison` if given.
fn columns(
    a: SparseColMatRef<'_, usize, f64>,
    owner: &[usize],
    rank: usize,
    poison: Option<f64>,
) -> faer::sparse::SparseColMat<usize, f64> {
    let mut triplets = Vec::new();
    for j in (0..a.ncols()).filter(|&j| owner[j / D] == rank) {
        for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            triplets.push(faer::sparse::Triplet::new(i, j, v));
        }
    }
    if let Some(x) = poison {
        triplets[0].val = x;
    }
    faer::sparse::SparseColMat::try_new_from_triplets(a.nrows(), a.ncols(), &triplets).unwrap()
}

/// The solver's own norm of a whole vector (what `FullStep::with_norm_from_solver`
/// measures a step's change with, holding no copy of `E`): at 1 to 4 thread ranks every
/// rank gets the bits of the one-rank value; it is the A-norm of an independent f64 sum
/// up to round-off (1e-12 relative), and with `E = 4A` twice that.
#[test]
fn the_norm_of_a_whole_vector_has_the_same_bits_on_every_rank() {
    let pb = cube(2);
    let a = pb.a();
    let e = four_a(&pb);
    // A vector with every dof nonzero and of mixed signs.
    let x: Vec<f64> = (0..pb.x0.len())
        .map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0)
        .collect();
    let exact = a_norm(&pb, &x);
    for (e, scale) in [(None, 1.0), (Some(e.as_ref()), 2.0)] {
        let mut one_rank: Option<f64> = None;
        for size in 1..=4 {
            let owner = pb.bx.slabs(size, 0);
            let norms = ThreadRanks::run(size, |halo| {
                let mut s = rank_solver(&pb, a, e, options(false), &owner, halo);
                s.energy_norm_of(&x).unwrap()
            });
            let reference = *one_rank.get_or_insert(norms[0]);
            for (r, norm) in norms.iter().enumerate() {
                assert_eq!(norm.to_bits(), reference.to_bits(), "rank {r} of {size}");
            }
        }
        let norm = one_rank.unwrap();
        assert!(
            (norm - scale * exact).abs() <= 1e-12 * scale * exact,
            "{norm} against {}",
            scale * exact
        );
    }
}

/// `FullStep::with_norm_from_solver` over TNNMG on ranks (no copy of `E` in the wrapper):
/// for solves of several iterations the step's change is measured with the ranks' rows;
/// at 1 to 3 thread ranks every rank has the one-rank change's bits, and it agrees with
/// the change a wrapper holding the whole `A` measures (1e-12 relative).
#[test]
fn a_full_step_on_ranks_measures_its_change_with_the_solvers_norm() {
    use rsf_nonsmooth::{FullStep, StepSolver};
    let pb = cube(2);
    let nl = friction(&pb, 1.0, 0.1);
    let nodes = nl.active_blocks().to_vec();
    let solve = |owner: &[usize], size: usize, own_norm: bool| {
        ThreadRanks::run(size, |halo| {
            let s = rank_solver(&pb, pb.a(), None, options(false), owner, halo);
            let mut step = if own_norm {
                FullStep::new(s, None).unwrap().with_norm_from_solver()
            } else {
                FullStep::new(s, Some(pb.a())).unwrap()
            };
            step.begin_step(&pb.b, &pb.x0, &nodes).unwrap();
            let report = step.solve_step(&nl, options(false).stopping).unwrap();
            assert!(report.iterations > 1, "a solve of several iterations");
            step.last_change()
        })
    };
    let nodes_count = pb.x0.len() / D;
    let whole = solve(&vec![0; nodes_count], 1, false)[0];
    let reference = solve(&vec![0; nodes_count], 1, true)[0];
    assert!(
        (reference - whole).abs() <= 1e-12 * whole,
        "{reference} against {whole}"
    );
    for size in 2..=3 {
        let owner = pb.bx.slabs(size, 0);
        for (r, change) in solve(&owner, size, true).iter().enumerate() {
            assert_eq!(change.to_bits(), reference.to_bits(), "rank {r} of {size}");
        }
    }
}
