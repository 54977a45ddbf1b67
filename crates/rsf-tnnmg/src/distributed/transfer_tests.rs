//! The building blocks of a distributed V-cycle against the one-process operations: the
//! residual on owned rows and the restriction and prolongation between two levels of a
//! nested hierarchy ([`DistributedTransfer`]), bit for bit at 1–4 thread ranks.

use rsf_linalg::Csc;

use super::fixtures::{cube, owners, Problem};
use super::*;
use crate::error::Error;
use crate::galerkin::Galerkin;
use crate::Parallelism;
use rsf_nonsmooth::ProblemError;
use rsf_ranks::bsr::BlockCsr;
use rsf_ranks::halo::HaloCounters;
use rsf_ranks::{Colouring, DistributedSweep, ThreadRanks};

const D: usize = 3;

/// The one-process residual `b − A x` (by rows), its restriction `Pᵀ (free ⊙ r)`, a
/// coarse vector `c` and the prolongation `x + free ⊙ (P c)`.
struct Reference {
    free: Vec<f64>,
    residual: Vec<f64>,
    restricted: Vec<f64>,
    coarse: Vec<f64>,
    prolonged: Vec<f64>,
}

/// The finest level's prolongation (from the level below).
fn prolongation(pb: &Problem) -> &faer::sparse::SparseColMat<usize, f64> {
    let h = &pb.bx.hierarchy;
    h.vector_prolongation(h.finest_level())
}

fn reference(pb: &Problem) -> Reference {
    let h = BlockCsr::<D>::from_csc(&Csc::from_faer(pb.a()).unwrap()).unwrap();
    let p = Csc::from_faer(prolongation(pb).as_ref()).unwrap();
    let (galerkin, _) = Galerkin::<D>::new(&h, &p).unwrap();
    let free: Vec<f64> = pb
        .bx
        .fixed
        .iter()
        .map(|&f| if f { 0.0 } else { 1.0 })
        .collect();
    let mut residual = vec![0.0; h.n()];
    h.residual_rows(&pb.b, &pb.x0, &mut residual, Parallelism::SEQ);
    let mut restricted = vec![0.0; p.ncols];
    galerkin.restrict(&residual, &free, &mut restricted, Parallelism::SEQ);
    let coarse: Vec<f64> = (0..p.ncols).map(|j| (0.7 * j as f64 + 0.2).sin()).collect();
    let mut prolonged = pb.x0.clone();
    galerkin.prolong_add(&coarse, &free, &mut prolonged, Parallelism::SEQ);
    Reference {
        free,
        residual,
        restricted,
        coarse,
        prolonged,
    }
}

/// One rank's results: differing bits of its owned residual, restricted and prolonged
/// values against the reference, its owned coarse and fine node counts, the transfers'
/// counters.
struct RankResult {
    differing: [usize; 3],
    owned: (usize, usize),
    counters: HaloCounters,
}

/// Values of a rank's owned nodes `nodes` (global, increasing) in `local` whose bits differ
/// from the global `reference`'s.
fn differing(nodes: &[usize], local: &[f64], reference: &[f64]) -> usize {
    nodes
        .iter()
        .enumerate()
        .flat_map(|(l, &g)| (0..D).map(move |c| (D * l + c, D * g + c)))
        .filter(|&(l, g)| local[l].to_bits() != reference[g].to_bits())
        .count()
}

/// On `size` thread ranks under `owner`: each rank's residual after a ghost update from
/// NaN ghosts, the restriction of its residual, the prolongation of the reference's coarse
/// vector onto its start.
fn on_ranks(pb: &Problem, re: &Reference, owner: &[usize], size: usize) -> Vec<RankResult> {
    let colouring = Colouring::new::<D>(pb.a()).unwrap();
    let p = prolongation(pb);
    let nc = p.ncols() / D;
    let run = |mut halo: ThreadRanks| {
        let mut sweep = DistributedSweep::<D>::new(pb.a(), owner, &colouring, &halo).unwrap();
        let mut transfer = DistributedTransfer::<D>::new(p.as_ref(), owner, &halo).unwrap();
        let rows = sweep.rows().clone();
        let (len, owned) = (rows.len(), rows.owned());
        let fine: Vec<usize> = rows.global_nodes()[..owned].to_vec();
        let coarse: Vec<usize> = fine.iter().copied().filter(|&g| g < nc).collect();
        let (mut b, mut x, mut free) = (vec![0.0; D * len], vec![0.0; D * len], vec![0.0; D * len]);
        rows.gather(&pb.b, &mut b);
        rows.gather(&pb.x0, &mut x);
        rows.gather(&re.free, &mut free);
        x[D * owned..].fill(f64::NAN);
        sweep.update_ghosts(&mut x, &mut halo);
        let mut r = vec![f64::NAN; D * owned];
        rows.residual(&b, &x, &mut r);
        let mut rc = vec![f64::NAN; D * coarse.len()];
        transfer.restrict(&r, &free, &mut rc, &mut halo);
        let c: Vec<f64> = coarse
            .iter()
            .flat_map(|&j| re.coarse[D * j..D * j + D].iter().copied())
            .collect();
        transfer.prolong_add(&c, &free, &mut x, &mut halo);
        RankResult {
            differing: [
                differing(&fine, &r, &re.residual),
                differing(&coarse, &rc, &re.restricted),
                differing(&fine, &x, &re.prolonged),
            ],
            owned: (transfer.coarse_owned(), transfer.fine_owned()),
            counters: transfer.counters(),
        }
    };
    ThreadRanks::run(size, run)
}

/// The residual on owned rows, the restriction and the prolongation between the two finest
/// levels of a cube's hierarchy (1 053 fine and 175 coarse nodes) at 1, 2, 3 and 4 thread
/// ranks, for a coordinate split and METIS's partition: every owned value has the bits of
/// the one-process operations (rsf-tnnmg's multigrid transfers, residual by rows); the
/// ranks own every coarse and fine node once; each transfer is one exchange, with messages
/// exactly when there are several ranks.
#[test]
fn residual_and_transfers_have_the_one_process_bits() {
    let pb = cube(2);
    let re = reference(&pb);
    let nc = re.coarse.len() / D;
    assert_eq!((pb.bx.mesh().num_vertices(), nc), (1053, 175));
    assert!(re.restricted.iter().all(|v| v.is_finite()));
    assert!(re.prolonged.iter().zip(&pb.x0).any(|(a, b)| a != b));
    for size in 1..=4 {
        for (name, owner) in owners(&pb, size) {
            let ranks = on_ranks(&pb, &re, &owner, size);
            let (mut coarse, mut fine) = (0, 0);
            for (r, rank) in ranks.iter().enumerate() {
                assert_eq!(rank.differing, [0; 3], "{name}: rank {r} of {size}");
                assert_eq!(rank.counters.exchanges, 2, "{name}: rank {r} of {size}");
                assert_eq!(
                    rank.counters.messages > 0,
                    size > 1,
                    "{name}: rank {r} of {size}"
                );
                coarse += rank.owned.0;
                fine += rank.owned.1;
            }
            assert_eq!((coarse, fine), (nc, pb.bx.mesh().num_vertices()), "{name}");
        }
    }
}

/// Set-up errors: a prolongation with more coarse than fine nodes, an owner vector of the
/// wrong length, an owner that is not a rank.
#[test]
fn transfer_set_up_refuses_wrong_input() {
    let pb = cube(1);
    let p = prolongation(&pb);
    let nf = p.nrows() / D;
    let halo = ThreadRanks::group(2).swap_remove(0);
    let pt = p.as_ref().transpose().to_col_major().unwrap();
    assert!(matches!(
        DistributedTransfer::<D>::new(pt.as_ref(), &vec![0; p.ncols() / D], &halo),
        Err(Error::Problem(ProblemError::InvalidMatrix(_)))
    ));
    assert!(matches!(
        DistributedTransfer::<D>::new(p.as_ref(), &vec![0; nf - 1], &halo),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    let mut owner = vec![1; nf];
    owner[3] = 2;
    assert!(matches!(
        DistributedTransfer::<D>::new(p.as_ref(), &owner, &halo),
        Err(Error::InvalidPartition(_))
    ));
    assert!(DistributedTransfer::<D>::new(p.as_ref(), &vec![1; nf], &halo).is_ok());
}
