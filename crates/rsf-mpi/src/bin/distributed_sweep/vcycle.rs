//! `--vcycle`: the distributed linear V-cycle on MPI ranks (docs/scaling.md, "Phase 3").
//!
//! Every rank builds the box and its whole V-cycle hierarchy (`VCycleHierarchy`: the
//! Galerkin coarse operators, masks and colourings of every level) and METIS's partition of
//! the fine node graph, keeps its rows of each level (`DistributedVCycle`) and drops the
//! rest, then times K repetitions of N V(1,1)-cycles from the box's start between two
//! barriers. Each rank writes its fine owned and ghost nodes, its owned coarsest nodes, the
//! plans' halo per cycle (sweeps, exchanges, messages, values) and what it counted over the
//! last repetition; rank 0 the median and, with `--out`, the owned fine values gathered in
//! global order.

use std::time::Instant;

use mpi::collective::CommunicatorCollectives;
use rsf_fem::ElasticBox;
use rsf_mpi::MpiRanks;
use rsf_tnnmg::distributed::{ColouredVCycle, DistributedVCycle, VCycleHierarchy, VCycleShape};

use super::{median, memory_mb, metis_owner, write_gathered, write_line, write_values, Flags, D};

/// One pre- and one post-smoothing sweep.
const SHAPE: VCycleShape = VCycleShape { pre: 1, post: 1 };

/// The box of `f` and the hierarchy of its `f.levels` finest levels (all by default).
fn hierarchy(f: &Flags) -> Result<(ElasticBox, VCycleHierarchy<D>), String> {
    let bx = ElasticBox::bar(f.refinements).map_err(|e| e.to_string())?;
    let h = &bx.hierarchy;
    let finest = h.finest_level();
    let levels = f.levels.unwrap_or(finest + 1);
    if !(2..=finest + 1).contains(&levels) {
        return Err(format!(
            "--levels {levels}: the box refined {} times has 2 to {} levels",
            f.refinements,
            finest + 1
        ));
    }
    let ps: Vec<_> = (finest + 2 - levels..=finest)
        .map(|j| h.vector_prolongation(j).as_ref())
        .collect();
    let vh =
        VCycleHierarchy::new(bx.stiffness.as_ref(), &bx.fixed, &ps).map_err(|e| e.to_string())?;
    Ok((bx, vh))
}

/// The levels' sizes (nodes, coarsest first) and colours, as `a/b/c`.
fn sizes(h: &VCycleHierarchy<D>) -> (String, String) {
    let join = |f: &dyn Fn(usize) -> usize| {
        (0..h.num_levels())
            .map(|l| f(l).to_string())
            .collect::<Vec<_>>()
            .join("/")
    };
    (join(&|l| h.nodes(l)), join(&|l| h.num_colours(l)))
}

fn report(f: &Flags, dofs: usize, levels: &(String, String), ranks: usize, times: &mut [f64]) {
    let m = median(times);
    println!(
        "dofs={dofs} level_nodes={} colours={} ranks={ranks} cycles={} repetitions={} \
         median={m:.6} s cycles_per_second={:.3}",
        levels.0,
        levels.1,
        f.sweeps,
        f.repetitions,
        f.sweeps as f64 / m
    );
}

/// The one-process reference on one rank: timed, its result written.
pub fn reference(f: &Flags) -> Result<(), String> {
    let (bx, h) = hierarchy(f)?;
    let mut vc = ColouredVCycle::new(&h, SHAPE).map_err(|e| e.to_string())?;
    vc.set_rhs(&bx.load()).map_err(|e| e.to_string())?;
    let x0 = bx.start();
    let mut x = x0.clone();
    let mut times = Vec::new();
    for k in 0..f.repetitions {
        x.copy_from_slice(&x0);
        let t = Instant::now();
        for _ in 0..f.sweeps {
            vc.cycle(&mut x);
        }
        let s = t.elapsed().as_secs_f64();
        println!("repetition {k}: {} cycles in {s:.6} s", f.sweeps);
        times.push(s);
    }
    let (rss, peak) = memory_mb();
    eprintln!("rank 0 of 1: one process, resident={rss:.1} MB peak={peak:.1} MB");
    report(f, bx.dofs(), &sizes(&h), 1, &mut times);
    if let Some(out) = f.values_file() {
        write_values(&out, &x)?;
    }
    Ok(())
}

/// The distributed V-cycles on every rank.
pub fn distributed(f: &Flags, root: bool) -> Result<(), String> {
    let mut halo = MpiRanks::world().duplicate();
    let (rank, size) = (halo.rank(), halo.size());
    let t = Instant::now();
    let (mut vc, x0, dofs, levels) = {
        let (bx, h) = hierarchy(f)?;
        let owner = metis_owner(&bx, size)?;
        let mut vc =
            DistributedVCycle::<D>::new(&h, &owner, SHAPE, &halo).map_err(|e| e.to_string())?;
        let rows = vc.rows();
        let (mut b, mut x0) = (vec![0.0; D * rows.len()], vec![0.0; D * rows.len()]);
        rows.gather(&bx.load(), &mut b);
        rows.gather(&bx.start(), &mut x0);
        vc.set_rhs(&b).map_err(|e| e.to_string())?;
        (vc, x0, bx.dofs(), sizes(&h))
    };
    let set_up_s = t.elapsed().as_secs_f64();
    let (rss, peak) = memory_mb();
    let mut x = x0.clone();
    let mut times = Vec::new();
    for k in 0..f.repetitions {
        x.copy_from_slice(&x0);
        vc.update_ghosts(&mut x, &mut halo);
        vc.reset_counters();
        halo.communicator().barrier();
        let t = Instant::now();
        for _ in 0..f.sweeps {
            vc.cycle(&mut x, &mut halo);
        }
        halo.communicator().barrier();
        let s = t.elapsed().as_secs_f64();
        if root {
            println!("repetition {k}: {} cycles in {s:.6} s", f.sweeps);
        }
        times.push(s);
    }
    let rows = vc.rows();
    let (plan, counted) = (vc.per_cycle(), vc.counters());
    // One write of the whole line (the ranks share standard error: no interleaving).
    let line = format!(
        "rank {rank} of {size}: owned={} ghosts={} coarsest_owned={} \
         plan_per_cycle={plan} bytes_per_cycle={} counted={counted} \
         set_up={set_up_s:.3} s resident_after_set_up={rss:.1} MB \
         peak_after_set_up={peak:.1} MB\n",
        rows.owned(),
        rows.ghosts(),
        vc.coarsest_owned(),
        plan.bytes(),
    );
    write_line(&line)?;
    if root {
        report(f, dofs, &levels, size, &mut times);
    }
    write_gathered(f, &halo, vc.rows(), &x)
}
