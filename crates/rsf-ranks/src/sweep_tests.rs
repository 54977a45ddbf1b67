//! The distributed sweep against the one-process coloured sweep ([`Colouring`]'s) on a
//! P1 elasticity stiffness of a refined cube with Dirichlet components: the same bits at
//! 1–4 thread ranks, a wrong halo detected, the counters against an independent count.

use faer::sparse::SparseColMat;
use rsf_fem::ElasticBox;

use super::*;
use crate::block::load;
use crate::halo::HaloCounters;
use crate::local_rows::tests::{cube, owners};
use rsf_linalg::ProblemError;

const D: usize = 3;

fn free(fixed: &[bool], p: usize) -> [bool; D] {
    std::array::from_fn(|c| !fixed[D * p + c])
}

/// The one-process coloured sweeps (`reverse` of each) from `x0`.
fn one_process(bx: &ElasticBox, colouring: &Colouring, sweeps: &[bool]) -> Vec<f64> {
    let a = bx.stiffness.as_ref();
    let mut gs = ColouredGaussSeidel::<D>::new(a, &bx.fixed, &bx.load(), colouring).unwrap();
    let mut x = bx.start();
    for &reverse in sweeps {
        gs.sweep(&mut x, reverse);
    }
    x
}

/// One rank's end of a distributed run.
struct RankResult {
    /// Global node of each local node, and the number of owned ones.
    global: Vec<usize>,
    owned: usize,
    x: Vec<f64>,
    /// Counted over the sweeps (not the set-up's ghost update), and the plan's per sweep.
    counters: HaloCounters,
    per_sweep: HaloCounters,
}

/// The sweeps on `size` thread ranks under `owner`, each rank from `x0` with its ghosts
/// first set to NaN and refreshed by [`DistributedSweep::update_ghosts`]; with
/// `dropped = Some(g)`, global node `g` is left out of every rank's halo plan.
fn on_ranks(
    bx: &ElasticBox,
    colouring: &Colouring,
    owner: &[usize],
    size: usize,
    sweeps: &[bool],
    dropped: Option<usize>,
) -> Vec<RankResult> {
    let (a, b_global, x0) = (bx.stiffness.as_ref(), bx.load(), bx.start());
    let run = |mut halo: ThreadRanks| {
        let mut ds = DistributedSweep::<D>::new(a, owner, colouring, &halo).unwrap();
        if let Some(g) = dropped {
            ds = ds.without_halo_node(colouring, g);
        }
        let rows = ds.rows();
        let (len, owned) = (rows.len(), rows.owned());
        let mut b = vec![0.0; D * len];
        let mut fixed = vec![false; D * len];
        let mut x = vec![0.0; D * len];
        rows.gather(&b_global, &mut b);
        rows.gather(&bx.fixed, &mut fixed);
        rows.gather(&x0, &mut x);
        x[D * owned..].fill(f64::NAN);
        let gs = BlockGaussSeidel::new(rows, &b, &fixed).unwrap();
        let global = rows.global_nodes().to_vec();
        ds.update_ghosts(&mut x, &mut halo);
        ds.reset_counters();
        for &reverse in sweeps {
            ds.sweep(&mut x, reverse, &mut halo, |rows, p, x| {
                gs.update(rows, p, x)
            });
        }
        RankResult {
            global,
            owned,
            x,
            counters: ds.counters(),
            per_sweep: ds.per_sweep(),
        }
    };
    ThreadRanks::run(size, run)
}

/// Values of `rank`'s local vector (owned and ghosts) whose bits differ from the
/// one-process iterate's.
fn differing_bits(rank: &RankResult, reference: &[f64]) -> usize {
    rank.global
        .iter()
        .enumerate()
        .flat_map(|(l, &g)| (0..D).map(move |c| (D * l + c, D * g + c)))
        .filter(|&(l, g)| rank.x[l].to_bits() != reference[g].to_bits())
        .count()
}

const SWEEPS: [bool; 6] = [false, true, false, false, true, true];

/// Six forward and backward sweeps at 1, 2, 3 and 4 ranks: every rank's owned and ghost
/// values have the bits of the one-process coloured sweep, for both owner vectors; every
/// rank of several owns nodes and has ghosts.
#[test]
fn distributed_sweeps_have_the_one_process_bits() {
    let bx = cube(2);
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let reference = one_process(&bx, &colouring, &SWEEPS);
    assert!(reference.iter().zip(&bx.start()).any(|(a, b)| a != b));
    assert!(reference.iter().all(|v| v.is_finite()));
    for size in 1..=4 {
        for (name, owner) in owners(&bx, size) {
            let ranks = on_ranks(&bx, &colouring, &owner, size, &SWEEPS, None);
            let mut owned = 0;
            for (r, rank) in ranks.iter().enumerate() {
                assert_eq!(
                    differing_bits(rank, &reference),
                    0,
                    "{name}: rank {r} of {size}"
                );
                assert!(rank.owned > 0, "{name}: rank {r} of {size} owns nothing");
                assert_eq!(
                    rank.global.len() > rank.owned,
                    size > 1,
                    "{name}: ghosts of rank {r}"
                );
                owned += rank.owned;
            }
            assert_eq!(
                owned,
                bx.mesh().num_vertices(),
                "{name}: every node owned once"
            );
        }
    }
}

/// A rank that owns no node (ranks 0 and 2 of 3 share the nodes, rank 1 has none) takes
/// part in every exchange without a message; the others keep the one-process bits.
#[test]
fn an_empty_rank_changes_nothing() {
    let bx = cube(1);
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let reference = one_process(&bx, &colouring, &SWEEPS);
    let owner: Vec<usize> = bx.slabs(2, 0).into_iter().map(|r| 2 * r).collect();
    let ranks = on_ranks(&bx, &colouring, &owner, 3, &SWEEPS, None);
    assert_eq!((ranks[1].owned, ranks[1].global.len()), (0, 0));
    let sweeps = SWEEPS.len() as u64;
    assert_eq!(
        ranks[1].counters,
        HaloCounters {
            sweeps,
            exchanges: sweeps * colouring.num_colours() as u64,
            ..HaloCounters::default()
        }
    );
    for r in [0, 2] {
        assert!(ranks[r].owned > 0);
        assert_eq!(differing_bits(&ranks[r], &reference), 0, "rank {r}");
    }
}

/// A plan without one ghost (a free node owned by rank 0 and a ghost on rank 1, neither
/// sent nor received): rank 1's values no longer have the one-process bits.
#[test]
fn a_wrong_halo_breaks_the_bits() {
    let bx = cube(2);
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let reference = one_process(&bx, &colouring, &SWEEPS);
    for (name, owner) in owners(&bx, 2) {
        let right = on_ranks(&bx, &colouring, &owner, 2, &SWEEPS, None);
        let rank1 = &right[1];
        let g = rank1.global[rank1.owned..]
            .iter()
            .copied()
            .find(|&g| owner[g] == 0 && free(&bx.fixed, g).iter().all(|&f| f))
            .expect("a free ghost of rank 1");
        let wrong = on_ranks(&bx, &colouring, &owner, 2, &SWEEPS, Some(g));
        assert_eq!(differing_bits(&right[1], &reference), 0, "{name}");
        assert!(
            differing_bits(&wrong[1], &reference) > 0,
            "{name}: ghost {g} dropped, yet the same bits"
        );
    }
}

/// Per sweep and rank, counted independently from the scalar pattern, the owners and the
/// colouring: the values sent are `D` per (owned node, rank where it is a ghost) pair, the
/// messages one per (colour, neighbour rank) with such a node of that colour. The sweep's
/// counters over the sweeps equal it times the number of sweeps, as does its plan's count;
/// one rank sends nothing; on two ranks the values sent are `D` per ghost of the other.
#[test]
fn counters_match_an_independent_count() {
    let bx = cube(2);
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let a = bx.stiffness.as_ref();
    let nodes = bx.mesh().num_vertices();
    // Node adjacency from the scalar pattern: (p, q) for every entry (D p + ·, D q + ·).
    let mut pairs = Vec::new();
    for j in 0..a.ncols() {
        for i in a.symbolic().row_idx_of_col(j) {
            if i / D != j / D {
                pairs.push((j / D, i / D));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let sweeps = SWEEPS.len() as u64;
    for size in 1..=4 {
        for (name, owner) in owners(&bx, size) {
            let ranks = on_ranks(&bx, &colouring, &owner, size, &SWEEPS, None);
            // (sender, node, receiver) triples, deduplicated.
            let mut sent: Vec<(usize, usize, usize)> = pairs
                .iter()
                .filter(|&&(p, q)| owner[p] != owner[q])
                .map(|&(p, q)| (owner[p], p, owner[q]))
                .collect();
            sent.sort_unstable();
            sent.dedup();
            for (r, rank) in ranks.iter().enumerate() {
                let mine: Vec<_> = sent.iter().filter(|t| t.0 == r).collect();
                let values = (D * mine.len()) as u64;
                let mut messages: Vec<(usize, usize)> = mine
                    .iter()
                    .map(|&&(_, p, s)| (colouring.colour_of(p), s))
                    .collect();
                messages.sort_unstable();
                messages.dedup();
                let want = HaloCounters {
                    sweeps: 1,
                    exchanges: colouring.num_colours() as u64,
                    messages: messages.len() as u64,
                    values,
                    ..HaloCounters::default()
                };
                assert_eq!(rank.per_sweep, want, "{name}: rank {r} of {size}");
                let total = HaloCounters {
                    sweeps,
                    exchanges: sweeps * want.exchanges,
                    messages: sweeps * want.messages,
                    values: sweeps * want.values,
                    ..HaloCounters::default()
                };
                assert_eq!(rank.counters, total, "{name}: rank {r} of {size}");
                assert_eq!(rank.counters.bytes(), 8 * total.values);
                if size == 1 {
                    assert_eq!((want.messages, want.values), (0, 0));
                }
                if size == 2 {
                    let ghosts_of_other = ranks[1 - r].global.len() - ranks[1 - r].owned;
                    assert_eq!(values, (D * ghosts_of_other) as u64, "{name}: rank {r}");
                }
            }
        }
    }
    assert!(nodes > 1000);
}

/// Set-up errors: an owner vector of the wrong length, an owner that is not a rank, a
/// colouring of another matrix.
#[test]
fn set_up_refuses_wrong_owners_and_colourings() {
    let bx = cube(1);
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let n = bx.mesh().num_vertices();
    let halo = ThreadRanks::group(2).swap_remove(0);
    let new = |owner: &[usize], colouring: &Colouring| {
        DistributedSweep::<D>::new(bx.stiffness.as_ref(), owner, colouring, &halo)
    };
    assert!(matches!(
        new(&vec![0; n - 1], &colouring),
        Err(Error::Problem(ProblemError::DimensionMismatch { .. }))
    ));
    let mut owner = vec![0; n];
    owner[n / 2] = 2;
    assert!(matches!(
        new(&owner, &colouring),
        Err(Error::InvalidPartition(_))
    ));
    // The colouring of a diagonal matrix: every node colour 0.
    let diagonal = SparseColMat::<usize, f64>::try_new_from_triplets(
        D * n,
        D * n,
        &(0..D * n)
            .map(|i| faer::sparse::Triplet::new(i, i, 1.0))
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let one_colour = Colouring::new::<D>(diagonal.as_ref()).unwrap();
    assert_eq!(one_colour.num_colours(), 1);
    assert!(matches!(
        new(&vec![0; n], &one_colour),
        Err(Error::InvalidPartition(_))
    ));
    assert!(new(&vec![1; n], &colouring).is_ok());
}

/// The halo of METIS partitions of a cube's elasticity stiffness (docs/scaling.md, "The
/// distributed smoother"): per rank the owned and ghost nodes, the neighbour ranks and what
/// one sweep sends, counted by the sweep on thread ranks (and checked against its plan).
/// Not a check of numbers: run with
/// `cargo test --release -p rsf-ranks --features rsf-metis/metis --lib
/// sweep_tests::halo_table -- --ignored --nocapture`.
#[test]
#[ignore = "prints the halo table of docs/scaling.md; needs METIS"]
fn halo_table() {
    assert!(
        rsf_metis::is_available(),
        "build with --features rsf-metis/metis"
    );
    println!(
        "| refinements | nodes | dofs | colours | parts | rank | owned nodes | ghost nodes \
         | neighbours | messages / sweep | values / sweep | KB / sweep | sent / owned values \
         | ghost / owned nodes |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for refinements in 1..=3 {
        // 5 × 3 × 3 Kuhn-split cubes: 10 647 dofs after 2 refinements, 76 875 after 3
        // (the 3-D slider has about 10⁴ at j = 3 and 70 227 at j = 4).
        let bx = ElasticBox::bar(refinements).unwrap();
        let (mesh, a) = (bx.mesh(), &bx.stiffness);
        let colouring = Colouring::new::<D>(a.as_ref()).unwrap();
        let (xadj, adjncy) = node_graph::<D>(a.as_ref()).unwrap();
        let nodes = mesh.num_vertices();
        for parts in [2, 4] {
            let owner = rsf_metis::part_graph_kway(&xadj, &adjncy, parts).unwrap();
            let rows: Vec<_> = std::thread::scope(|s| {
                let handles: Vec<_> = ThreadRanks::group(parts)
                    .into_iter()
                    .map(|mut halo| {
                        let (a, owner, colouring) = (&a, &owner, &colouring);
                        s.spawn(move || {
                            let mut ds =
                                DistributedSweep::<D>::new(a.as_ref(), owner, colouring, &halo)
                                    .unwrap();
                            let mut x = vec![0.0; D * ds.rows().len()];
                            ds.sweep(&mut x, false, &mut halo, |_, p, x| load::<D>(x, p));
                            assert_eq!(ds.counters(), ds.per_sweep());
                            let r = ds.rows();
                            let neighbours = ds.neighbour_ranks().count();
                            (r.owned(), r.ghosts(), neighbours, ds.counters())
                        })
                    })
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap()).collect()
            });
            for (rank, (owned, ghosts, neighbours, c)) in rows.into_iter().enumerate() {
                println!(
                    "| {refinements} | {nodes} | {} | {} | {parts} | {rank} | {owned} | {ghosts} \
                     | {neighbours} | {} | {} | {:.1} | {:.3} | {:.3} |",
                    D * nodes,
                    colouring.num_colours(),
                    c.messages,
                    c.values,
                    c.bytes() as f64 / 1000.0,
                    c.values as f64 / (D * owned) as f64,
                    ghosts as f64 / owned as f64,
                );
            }
        }
    }
}
