//! `--tnnmg`: TNNMG on MPI ranks (docs/scaling.md, "Phase 4").
//!
//! Every rank builds the box, its hierarchy (all levels) and METIS's partition of the fine
//! node graph, and sets up `DistributedTnnmg` (each rank its rows of every level);
//! the nonlinearity is Tresca friction (`BlockTresca`, bound 1, viscous weight 0.1) on the
//! nodes of the top face z = 1. K repetitions solve from the box's start to 1e-10 in the
//! energy norm (one nonlinear sweep and one V(2,2)-cycle per iteration; with `--cg`
//! conjugate gradients preconditioned by V(2,2)-cycles, at most 4 per iteration, stopping
//! at a residual reduction of 0.01: the one-process TNNMG's defaults), each timed between
//! two barriers. Each rank writes its owned and ghost nodes, the iterations, what one
//! iteration sends by the plans per part (smoother, cycles, gathers, reductions, the
//! hierarchy's incremental update: exchanges/messages/values point to point, then
//! collectives/values contributed to them) and in total, what a full update of the
//! hierarchy sends (a solve's first iteration), and what it counted over the last solve
//! (including the solution's all-gather); rank 0 the median and, with `--out`, the
//! solution (every rank holds it whole after the solve). `--thread-ranks N` (one MPI rank)
//! runs the same solve on N threads as ranks (`ThreadRanks`, METIS's partition into N)
//! and writes thread rank 0's solution: the reference the MPI runs must reproduce.

use std::time::Instant;

use mpi::collective::CommunicatorCollectives;
use mpi::topology::Communicator;
use rsf_fem::ElasticBox;
use rsf_mpi::MpiRanks;
use rsf_nonsmooth::{NonsmoothSolver, Stopping};
use rsf_ranks::halo::HaloCounters;
use rsf_ranks::{RankGroup, ThreadRanks};
use rsf_tnnmg::distributed::{BlockTresca, DistributedTnnmg, DistributedTnnmgOptions, VCycleShape};
use rsf_tnnmg::LinearCorrection;

use super::{median, memory_mb, metis_owner, write_line, write_values, Flags, D};

/// The box of `f` and its friction on the top face.
fn problem(f: &Flags) -> Result<(ElasticBox, BlockTresca<D>), String> {
    let bx = ElasticBox::bar(f.refinements).map_err(|e| e.to_string())?;
    let nodes: Vec<usize> = (bx.mesh().vertices().iter().enumerate())
        .filter(|(_, v)| v[2] == 1.0)
        .map(|(p, _)| p)
        .collect();
    let k = nodes.len();
    let nl = BlockTresca::new(nodes, vec![1.0; k], vec![0.1; k]).map_err(|e| e.to_string())?;
    Ok((bx, nl))
}

fn options(f: &Flags) -> DistributedTnnmgOptions {
    let classical = DistributedTnnmgOptions {
        stopping: Stopping {
            absolute: 1e-10,
            relative: 0.0,
            max_iterations: 200,
        },
        nonlinear_sweeps: 1,
        v_cycles: 1,
        linear_correction: LinearCorrection::Cycles,
        linear_reduction: None,
        smoothing: VCycleShape { pre: 2, post: 2 },
        record_energy: false,
    };
    if f.cg {
        DistributedTnnmgOptions {
            v_cycles: 4,
            linear_correction: LinearCorrection::PreconditionedCg,
            linear_reduction: Some(0.01),
            ..classical
        }
    } else {
        classical
    }
}

/// The solver of `halo`'s rank on the box under `owner`.
fn solver(
    f: &Flags,
    bx: &ElasticBox,
    owner: &[usize],
    halo: Box<dyn RankGroup>,
) -> Result<DistributedTnnmg<D>, String> {
    let h = &bx.hierarchy;
    let ps: Vec<_> = (1..=h.finest_level())
        .map(|j| h.vector_prolongation(j).as_ref())
        .collect();
    DistributedTnnmg::new(
        bx.stiffness.as_ref(),
        &bx.fixed,
        &ps,
        None,
        options(f),
        owner,
        halo,
    )
    .map_err(|e| e.to_string())
}

/// `exchanges/messages/values/collectives/collective_values`.
fn counts(c: HaloCounters) -> String {
    format!(
        "{}/{}/{}/{}/{}",
        c.exchanges, c.messages, c.values, c.collectives, c.collective_values
    )
}

/// The solve on `n` thread ranks in this process: thread rank 0's solution written.
pub fn thread_ranks(f: &Flags, n: usize) -> Result<(), String> {
    let (bx, nl) = problem(f)?;
    let owner = metis_owner(&bx, n)?;
    let (bx, nl, owner) = (&bx, &nl, &owner);
    let results: Vec<Result<(Vec<f64>, usize), String>> = std::thread::scope(|s| {
        let handles: Vec<_> = ThreadRanks::group(n)
            .into_iter()
            .map(|halo| {
                s.spawn(move || {
                    let mut t = solver(f, bx, owner, Box::new(halo))?;
                    let mut v = bx.start();
                    let report = t.solve(&bx.load(), nl, &mut v).map_err(|e| e.to_string())?;
                    Ok((v, report.iterations))
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("a thread rank panicked".into()))
            })
            .collect()
    });
    let mut first = None;
    for (r, res) in results.into_iter().enumerate() {
        let (v, iterations) = res?;
        eprintln!("thread rank {r} of {n}: iterations={iterations}");
        first.get_or_insert(v);
    }
    if let (Some(out), Some(v)) = (f.values_file(), first) {
        write_values(&out, &v)?;
    }
    Ok(())
}

/// The solves on every MPI rank.
pub fn distributed(f: &Flags, root: bool) -> Result<(), String> {
    let halo = MpiRanks::world().duplicate();
    let (rank, size) = (halo.rank(), halo.size());
    let comm = halo.communicator().duplicate();
    let t = Instant::now();
    let (bx, nl) = problem(f)?;
    let owner = metis_owner(&bx, size)?;
    let mut tnnmg = solver(f, &bx, &owner, Box::new(halo))?;
    let set_up_s = t.elapsed().as_secs_f64();
    let (rss, peak) = memory_mb();
    let (b, start) = (bx.load(), bx.start());
    let mut v = start.clone();
    let mut times = Vec::new();
    let mut iterations = 0;
    for k in 0..f.repetitions {
        v.copy_from_slice(&start);
        tnnmg.reset_counters();
        comm.barrier();
        let t = Instant::now();
        let report = tnnmg.solve(&b, &nl, &mut v).map_err(|e| e.to_string())?;
        comm.barrier();
        let s = t.elapsed().as_secs_f64();
        iterations = report.iterations;
        if root {
            println!("repetition {k}: {iterations} TNNMG iterations in {s:.6} s");
        }
        times.push(s);
    }
    let rows = tnnmg.rows();
    let plan = tnnmg
        .per_iteration()
        .ok_or("no solve: no per-iteration plan")?;
    let counted = tnnmg.counters();
    // One write of the whole line (the ranks share standard error: no interleaving).
    let line = format!(
        "rank {rank} of {size}: owned={} ghosts={} iterations={iterations} \
         per_iteration={} bytes_per_iteration={} smoother={} cycles={} gathers={} \
         reductions={} hierarchy={} full_update={} solution={} counted={} \
         set_up={set_up_s:.3} s \
         resident_after_set_up={rss:.1} MB peak_after_set_up={peak:.1} MB\n",
        rows.owned(),
        rows.ghosts(),
        counts(plan.total()),
        plan.total().bytes(),
        counts(plan.smoother),
        counts(plan.cycles),
        counts(plan.gathers),
        counts(plan.reductions),
        counts(plan.hierarchy),
        counts(tnnmg.per_full_update()),
        counts(tnnmg.per_solution()),
        counts(counted.total()),
    );
    write_line(&line)?;
    if root {
        let m = median(&mut times);
        println!(
            "dofs={} frictional_nodes={} ranks={size} iterations={iterations} \
             repetitions={} median={m:.6} s",
            bx.dofs(),
            rsf_nonsmooth::BlockNonlinearity::<D>::active_blocks(&nl).len(),
            f.repetitions
        );
        if let Some(out) = f.values_file() {
            write_values(&out, &v)?;
        }
    }
    Ok(())
}
