//! The distributed linear V-cycle against its one-process reference on a cube's elasticity
//! problem: the same bits at 1–4 thread ranks after one and several cycles, with 2 and 3
//! levels; the cycle as a solver; the counters against the plans and an independent count;
//! a missing ghost update detected.

use faer::sparse::SparseColMatRef;
use rsf_linalg::Csc;

use super::fixtures::{cube, owners, Problem};
use super::*;
use crate::error::Error;
use crate::Parallelism;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::bsr::BlockCsr;
use rsf_ranks::halo::HaloCounters;
use rsf_ranks::ThreadRanks;

const D: usize = 3;

const SHAPE: VCycleShape = VCycleShape { pre: 1, post: 1 };

/// The hierarchy of `pb` with its `levels` finest levels (the last `levels − 1`
/// prolongations).
fn hierarchy(pb: &Problem, levels: usize) -> VCycleHierarchy<D> {
    let h = &pb.bx.hierarchy;
    let finest = h.finest_level();
    let ps: Vec<SparseColMatRef<'_, usize, f64>> = (finest + 2 - levels..=finest)
        .map(|j| h.vector_prolongation(j).as_ref())
        .collect();
    VCycleHierarchy::new(pb.a(), &pb.bx.fixed, &ps).unwrap()
}

/// The reference's fine iterate after each of `cycles` cycles from `x0`.
fn reference(
    pb: &Problem,
    h: &VCycleHierarchy<D>,
    shape: VCycleShape,
    cycles: usize,
) -> Vec<Vec<f64>> {
    let mut vc = ColouredVCycle::new(h, shape).unwrap();
    vc.set_rhs(&pb.b).unwrap();
    let mut x = pb.x0.clone();
    (0..cycles)
        .map(|_| {
            vc.cycle(&mut x);
            x.clone()
        })
        .collect()
}

/// One rank's end of a distributed run.
struct RankResult {
    /// Global node of each fine local node, and the number of owned ones.
    global: Vec<usize>,
    owned: usize,
    coarsest_owned: usize,
    /// The local iterate after each cycle.
    xs: Vec<Vec<f64>>,
    /// Counted over the cycles (not the first ghost update), and the plans' per cycle.
    counters: HaloCounters,
    per_cycle: HaloCounters,
}

/// `cycles` cycles on `size` thread ranks under `owner`, each rank from `x0` with its
/// ghosts first set to NaN and refreshed; `skip_ghost_update` leaves out the ghost update
/// after each prolongation (a broken cycle).
fn on_ranks(
    pb: &Problem,
    h: &VCycleHierarchy<D>,
    owner: &[usize],
    size: usize,
    cycles: usize,
    skip_ghost_update: bool,
) -> Vec<RankResult> {
    let run = |mut halo: ThreadRanks| {
        let mut vc = DistributedVCycle::<D>::new(h, owner, SHAPE, &halo).unwrap();
        vc.skip_ghost_update = skip_ghost_update;
        let rows = vc.rows();
        let (len, owned) = (rows.len(), rows.owned());
        let global = rows.global_nodes().to_vec();
        let mut b = vec![0.0; D * len];
        let mut x = vec![0.0; D * len];
        rows.gather(&pb.b, &mut b);
        rows.gather(&pb.x0, &mut x);
        x[D * owned..].fill(f64::NAN);
        vc.set_rhs(&b).unwrap();
        vc.update_ghosts(&mut x, &mut halo);
        vc.reset_counters();
        let xs = (0..cycles)
            .map(|_| {
                vc.cycle(&mut x, &mut halo);
                x.clone()
            })
            .collect();
        RankResult {
            global,
            owned,
            coarsest_owned: vc.coarsest_owned(),
            xs,
            counters: vc.counters(),
            per_cycle: vc.per_cycle(),
        }
    };
    ThreadRanks::run(size, run)
}

/// Values of a rank's local vector `x` (owned and ghosts) whose bits differ from the
/// global `reference`'s.
fn differing_bits(rank: &RankResult, x: &[f64], reference: &[f64]) -> usize {
    rank.global
        .iter()
        .enumerate()
        .flat_map(|(l, &g)| (0..D).map(move |c| (D * l + c, D * g + c)))
        .filter(|&(l, g)| x[l].to_bits() != reference[g].to_bits())
        .count()
}

/// The Euclidean norm of the free dofs' residual `b − A x`.
fn residual_norm(a: &BlockCsr<D>, pb: &Problem, x: &[f64]) -> f64 {
    let mut r = vec![0.0; a.n()];
    a.residual_rows(&pb.b, x, &mut r, Parallelism::SEQ);
    free_norm(pb, &r)
}

/// The Euclidean norm of `v` on the free dofs.
fn free_norm(pb: &Problem, v: &[f64]) -> f64 {
    v.iter()
        .zip(&pb.bx.fixed)
        .filter(|(_, &f)| !f)
        .map(|(v, _)| v * v)
        .sum::<f64>()
        .sqrt()
}

const CYCLES: usize = 4;

/// Four V(1,1)-cycles with 2 and 3 levels (1 053, 175 and 36 nodes) at 1, 2, 3 and 4
/// thread ranks, coordinate split and METIS: after every cycle every rank's owned and
/// ghost values have the bits of the one-process coloured V-cycle; the ranks own every
/// fine node once; every rank of several has ghosts.
#[test]
fn distributed_vcycles_have_the_one_process_bits() {
    let pb = cube(2);
    for levels in [2, 3] {
        let h = hierarchy(&pb, levels);
        assert_eq!(h.num_levels(), levels);
        let reference = reference(&pb, &h, SHAPE, CYCLES);
        assert!(reference.iter().flatten().all(|v| v.is_finite()));
        assert!(reference[0] != pb.x0 && reference[1] != reference[0]);
        for size in 1..=4 {
            for (name, owner) in owners(&pb, size) {
                let ranks = on_ranks(&pb, &h, &owner, size, CYCLES, false);
                let (mut owned, mut coarsest) = (0, 0);
                for (r, rank) in ranks.iter().enumerate() {
                    for (k, x) in rank.xs.iter().enumerate() {
                        assert_eq!(
                            differing_bits(rank, x, &reference[k]),
                            0,
                            "{levels} levels, {name}: rank {r} of {size}, cycle {}",
                            k + 1
                        );
                    }
                    assert_eq!(rank.global.len() > rank.owned, size > 1, "{name}: rank {r}");
                    owned += rank.owned;
                    coarsest += rank.coarsest_owned;
                }
                assert_eq!(owned, pb.bx.mesh().num_vertices(), "{name}");
                assert_eq!(coarsest, h.nodes(0), "{name}");
            }
        }
    }
}

/// The residual reduction factors of 10 cycles of the one-process multigrid of the TNNMG
/// (`LinearMultigrid`, lexicographic Gauss–Seidel, V(1,1)) on `A c = r₀` from `c = 0`,
/// `r₀ = b − A x₀` on the free dofs: the same problem as the coloured cycles from `x₀`.
fn linear_multigrid_factors(pb: &Problem, a: &BlockCsr<D>, levels: usize) -> Vec<f64> {
    use crate::multigrid::{CycleShape, LinearMultigrid};
    let h = &pb.bx.hierarchy;
    let finest = h.finest_level();
    let ps: Vec<Csc> = (finest + 2 - levels..=finest)
        .map(|j| Csc::from_faer(h.vector_prolongation(j).as_ref()).unwrap())
        .collect();
    let shape = CycleShape {
        pre: 1,
        post: 1,
        gamma: 1,
    };
    let mut mg = LinearMultigrid::new(a.clone(), ps, shape).unwrap();
    mg.fine_mask_mut().copy_from_slice(&pb.bx.fixed);
    mg.update().unwrap();
    let mut rhs = vec![0.0; a.n()];
    a.residual_rows(&pb.b, &pb.x0, &mut rhs, Parallelism::SEQ);
    for (r, &f) in rhs.iter_mut().zip(&pb.bx.fixed) {
        if f {
            *r = 0.0;
        }
    }
    let mut prev = free_norm(pb, &rhs);
    let mut c = vec![0.0; a.n()];
    (0..10)
        .map(|k| {
            mg.apply(&mut c, &mut rhs, k == 0, true);
            let r = free_norm(pb, mg.fine_residual());
            let f = r / prev;
            prev = r;
            f
        })
        .collect()
}

/// The V-cycle as a solver, against the TNNMG's one-process multigrid with its own
/// (lexicographic) smoother order: 10 V(1,1)-cycles with 3 and 2 levels from `x₀` reduce
/// the free residual in every cycle by a factor below 0.7, and the last cycle's factor
/// (near the asymptotic rate) is within 0.1 of the multigrid's; V(0,1) converges too.
/// Measured: 3 levels 0.17 in the first cycle, 0.64 in the tenth (the multigrid 0.62).
#[test]
fn vcycles_reduce_the_residual() {
    let pb = cube(2);
    let a = BlockCsr::<D>::from_csc(&Csc::from_faer(pb.a()).unwrap()).unwrap();
    for (levels, shape) in [(3, SHAPE), (2, SHAPE), (3, VCycleShape { pre: 0, post: 1 })] {
        let h = hierarchy(&pb, levels);
        let mut prev = residual_norm(&a, &pb, &pb.x0);
        let factors: Vec<f64> = reference(&pb, &h, shape, 10)
            .iter()
            .map(|x| {
                let r = residual_norm(&a, &pb, x);
                let f = r / prev;
                prev = r;
                f
            })
            .collect();
        println!("{levels} levels, {shape:?}: {factors:.3?}");
        let worst = factors.iter().copied().fold(0.0, f64::max);
        let bound = if shape == SHAPE { 0.7 } else { 0.9 };
        assert!(worst < bound, "{levels} levels, {shape:?}: {factors:?}");
        if shape == SHAPE {
            let mg = linear_multigrid_factors(&pb, &a, levels);
            println!("{levels} levels, LinearMultigrid: {mg:.3?}");
            assert!(
                (factors[9] - mg[9]).abs() < 0.1,
                "{factors:?} against {mg:?}"
            );
        }
    }
}

/// Per rank and cycle the counters equal the plans' per cycle; the exchanges are
/// `(pre + post) · colours + 3` per level above the coarsest, counted independently from
/// the colourings, and the coarsest gather one collective to which a rank that owns `k`
/// coarsest nodes contributes `3 k` values; at one rank no message is sent.
#[test]
fn vcycle_counters_match_the_plans() {
    let pb = cube(2);
    let h = hierarchy(&pb, 3);
    let exchanges: u64 = (1..3)
        .map(|l| ((SHAPE.pre + SHAPE.post) * h.num_colours(l) + 3) as u64)
        .sum();
    let sweeps = (2 * (SHAPE.pre + SHAPE.post)) as u64;
    let cycles = 3;
    for size in 1..=4 {
        for (name, owner) in owners(&pb, size) {
            let ranks = on_ranks(&pb, &h, &owner, size, cycles, false);
            let holders: Vec<usize> = ranks.iter().map(|r| r.coarsest_owned).collect();
            for (r, rank) in ranks.iter().enumerate() {
                let per = rank.per_cycle;
                assert_eq!(
                    rank.counters,
                    per.times(cycles as u64),
                    "{name}: rank {r} of {size}"
                );
                assert_eq!(
                    (per.sweeps, per.exchanges),
                    (sweeps, exchanges),
                    "{name}: rank {r}"
                );
                assert_eq!(per.messages > 0, size > 1, "{name}: rank {r} of {size}");
                assert_eq!(
                    (per.collectives, per.collective_values),
                    (1, (D * holders[r]) as u64),
                    "{name}: rank {r} of {size}: the coarsest gather"
                );
            }
        }
    }
}

/// Without the ghost update after the prolongation the post-smoothing reads stale ghosts:
/// at 2 ranks some rank's values no longer have the reference's bits after one cycle,
/// while the same run with the update has them.
#[test]
fn a_missing_ghost_update_breaks_the_bits() {
    let pb = cube(2);
    let h = hierarchy(&pb, 2);
    let reference = reference(&pb, &h, SHAPE, 1);
    for (name, owner) in owners(&pb, 2) {
        let right = on_ranks(&pb, &h, &owner, 2, 1, false);
        let wrong = on_ranks(&pb, &h, &owner, 2, 1, true);
        let count = |ranks: &[RankResult]| -> usize {
            ranks
                .iter()
                .map(|r| differing_bits(r, &r.xs[0], &reference[0]))
                .sum()
        };
        assert_eq!(count(&right), 0, "{name}");
        assert!(count(&wrong) > 0, "{name}: stale ghosts, yet the same bits");
    }
}

/// Set-up errors: no prolongation, a wrong fixed mask, a prolongation of the wrong size,
/// an owner vector of the wrong length, an owner that is not a rank, a right-hand side too
/// short.
#[test]
fn vcycle_set_up_refuses_wrong_input() {
    let pb = cube(1);
    let p = pb.bx.hierarchy.vector_prolongation(1);
    assert!(matches!(
        VCycleHierarchy::<D>::new(pb.a(), &pb.bx.fixed, &[]),
        Err(Error::Problem(ProblemError::InvalidOption(_)))
    ));
    assert!(matches!(
        VCycleHierarchy::<D>::new(pb.a(), &pb.bx.fixed[1..], &[p.as_ref()]),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    // Two prolongations into the fine level: the first does not end at the second's
    // columns.
    assert!(matches!(
        VCycleHierarchy::<D>::new(pb.a(), &pb.bx.fixed, &[p.as_ref(), p.as_ref()]),
        Err(Error::Problem(ProblemError::InvalidMatrix(_)))
    ));
    let h = hierarchy(&pb, 2);
    let nf = h.nodes(1);
    let halo = ThreadRanks::group(2).swap_remove(0);
    assert!(matches!(
        DistributedVCycle::<D>::new(&h, &vec![0; nf - 1], SHAPE, &halo),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    let mut owner = vec![0; nf];
    owner[nf / 2] = 2;
    assert!(matches!(
        DistributedVCycle::<D>::new(&h, &owner, SHAPE, &halo),
        Err(Error::InvalidPartition(_))
    ));
    let mut vc = DistributedVCycle::<D>::new(&h, &vec![0; nf], SHAPE, &halo).unwrap();
    assert!(matches!(
        vc.set_rhs(&vec![0.0; D * nf - 1]),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    assert!(vc.set_rhs(&vec![0.0; D * nf]).is_ok());
}
