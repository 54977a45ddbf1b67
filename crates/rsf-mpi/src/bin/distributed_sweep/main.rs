//! The distributed smoother on MPI ranks (docs/scaling.md, "Phase 2"): linear block
//! Gauss–Seidel sweeps of a refined elastic box (`rsf_fem::ElasticBox`, 5 × 3 × 3 cubes)
//! partitioned by METIS, the halo exchanged by [`rsf_mpi::MpiRanks`] (a duplicate of the world communicator).
//!
//! ```text
//! distributed_sweep [--refinements R] [--sweeps N] [--repetitions K] [--out DIR] [--reference]
//!                   [--vcycle [--levels L]] [--tnnmg [--cg] [--thread-ranks N]]
//! ```
//!
//! The program goes through the guard (`rsf_programs::guard::main_on_ranks`: its flags and
//! plan are `rsf_programs::distributed_sweep::Args`): the ranks compare their flags, every
//! flag is checked and the memory estimated before any work, and `--out` is a run folder
//! (locked, another run's refused unless `--overwrite`).
//!
//! Every rank builds the whole problem (the stiffness, the colouring, METIS's partition of
//! the node graph: the same on every rank), keeps its rows and drops the rest, then runs K
//! repetitions of N sweeps from the same start (forward, backward, forward, …), each timed
//! between two barriers. Each rank writes to standard error its owned and ghost nodes, its
//! plan's halo per sweep and what it counted over the last repetition's sweeps, and its
//! resident memory; rank 0 writes each repetition's time and the median to standard
//! output, and with `--out DIR` the owned values of every rank after the last repetition,
//! gathered in global order (node-major, little-endian f64), into `DIR/values.bin`. `--reference` (one rank)
//! runs the one-process coloured sweep (`rsf_tnnmg::distributed::ColouredGaussSeidel`)
//! instead of the distributed one.
//!
//! With `--vcycle` (docs/scaling.md, "Phase 3") N counts linear V(1,1)-cycles
//! (`rsf_tnnmg::distributed::DistributedVCycle`) instead of sweeps, on the box's hierarchy
//! (its L finest levels, all by default), and `--reference` runs the one-process
//! `ColouredVCycle`; see the module `vcycle`.
//!
//! With `--tnnmg` (docs/scaling.md, "Phase 4") the program solves a frictional problem on
//! the box with TNNMG on ranks (`rsf_tnnmg::distributed::DistributedTnnmg`), K times, and
//! writes the solution; `--thread-ranks N` (one MPI rank) solves it on N threads as ranks
//! instead; see the module `tnnmg`.

mod tnnmg;
mod vcycle;

use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

use mpi::collective::{CommunicatorCollectives, Root};
use mpi::datatype::PartitionMut;
use mpi::topology::Communicator;
use rsf_fem::ElasticBox;
use rsf_mpi::MpiRanks;
use rsf_programs::guard::{AnyError, Prepared};
use rsf_ranks::{
    node_graph, BlockGaussSeidel, ColouredGaussSeidel, Colouring, DistributedSweep, LocalRows,
    Processes,
};

const D: usize = 3;

/// The command line (`rsf-programs`', so that the guard judges it like every other
/// program's and the careless-inputs test checks it without MPI).
pub type Flags = rsf_programs::distributed_sweep::Args;

/// This process's resident and peak resident memory in MB (`/proc/self/status`), or 0.
fn memory_mb() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = |key: &str| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (kb("VmRSS:") / 1e3, kb("VmHWM:") / 1e3)
}

/// The median of `t` (sorted in place).
fn median(t: &mut [f64]) -> f64 {
    t.sort_by(f64::total_cmp);
    let n = t.len();
    if n % 2 == 1 {
        t[n / 2]
    } else {
        0.5 * (t[n / 2 - 1] + t[n / 2])
    }
}

/// One rank's part after set-up: its sweep, its update, its start (owned and ghosts).
struct Part {
    sweep: DistributedSweep<D>,
    gs: BlockGaussSeidel<D>,
    x0: Vec<f64>,
    dofs: usize,
    colours: usize,
}

/// METIS's partition of the node graph of the box's stiffness into `parts`
/// (deterministic: the same on every rank).
fn metis_owner(bx: &ElasticBox, parts: usize) -> Result<Vec<usize>, String> {
    let (xadj, adjncy) = node_graph::<D>(bx.stiffness.as_ref()).map_err(|e| e.to_string())?;
    rsf_metis::part_graph_kway(&xadj, &adjncy, parts).map_err(|e| e.to_string())
}

/// Builds the whole problem, partitions it, keeps this rank's part.
fn set_up(f: &Flags, halo: &MpiRanks) -> Result<Part, String> {
    let bx = ElasticBox::bar(f.refinements).map_err(|e| e.to_string())?;
    let a = bx.stiffness.as_ref();
    let colouring = Colouring::new::<D>(a).map_err(|e| e.to_string())?;
    let owner = metis_owner(&bx, halo.size())?;
    let sweep =
        DistributedSweep::<D>::new(a, &owner, &colouring, halo).map_err(|e| e.to_string())?;
    let rows = sweep.rows();
    let len = D * rows.len();
    let (mut b, mut fixed, mut x0) = (vec![0.0; len], vec![false; len], vec![0.0; len]);
    rows.gather(&bx.load(), &mut b);
    rows.gather(&bx.fixed, &mut fixed);
    rows.gather(&bx.start(), &mut x0);
    let gs = BlockGaussSeidel::new(rows, &b, &fixed).map_err(|e| e.to_string())?;
    Ok(Part {
        sweep,
        gs,
        x0,
        dofs: bx.dofs(),
        colours: colouring.num_colours(),
    })
}

/// Forward, backward, forward, …: sweep `k` is backward when `k` is odd.
fn directions(n: usize) -> impl Iterator<Item = bool> {
    (0..n).map(|k| k % 2 == 1)
}

/// The one-process reference on one rank: timed, its result written.
fn reference(f: &Flags) -> Result<(), String> {
    let bx = ElasticBox::bar(f.refinements).map_err(|e| e.to_string())?;
    let a = bx.stiffness.as_ref();
    let colouring = Colouring::new::<D>(a).map_err(|e| e.to_string())?;
    let x0 = bx.start();
    let mut gs = ColouredGaussSeidel::<D>::new(a, &bx.fixed, &bx.load(), &colouring)
        .map_err(|e| e.to_string())?;
    let mut times = Vec::new();
    let mut x = x0.clone();
    for k in 0..f.repetitions {
        x.copy_from_slice(&x0);
        let t = Instant::now();
        for reverse in directions(f.sweeps) {
            gs.sweep(&mut x, reverse);
        }
        let s = t.elapsed().as_secs_f64();
        println!("repetition {k}: {} sweeps in {s:.6} s", f.sweeps);
        times.push(s);
    }
    let (rss, peak) = memory_mb();
    eprintln!("rank 0 of 1: one process, resident={rss:.1} MB peak={peak:.1} MB");
    report(f, bx.dofs(), colouring.num_colours(), 1, &mut times);
    if let Some(out) = f.values_file() {
        write_values(&out, &x)?;
    }
    Ok(())
}

fn report(f: &Flags, dofs: usize, colours: usize, ranks: usize, times: &mut [f64]) {
    let m = median(times);
    println!(
        "dofs={dofs} colours={colours} ranks={ranks} sweeps={} repetitions={} \
         median={m:.6} s sweeps_per_second={:.3}",
        f.sweeps,
        f.repetitions,
        f.sweeps as f64 / m
    );
}

fn write_values(path: &std::path::Path, x: &[f64]) -> Result<(), String> {
    let bytes: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// Gathers every rank's owned values of the local vector `x` of `rows` into global order
/// on rank 0 (`None` elsewhere).
fn gather(halo: &MpiRanks, rows: &LocalRows<D>, x: &[f64]) -> Option<Vec<f64>> {
    let comm = halo.communicator();
    let root = comm.process_at_rank(0);
    let owned = rows.owned();
    let nodes: Vec<u64> = rows.global_nodes()[..owned]
        .iter()
        .map(|&p| p as u64)
        .collect();
    let values = &x[..D * owned];
    let count = i32::try_from(owned).expect("owned nodes fit an int");
    if halo.rank() != 0 {
        root.gather_into(&count);
        root.gather_varcount_into(&nodes[..]);
        root.gather_varcount_into(values);
        return None;
    }
    let mut counts = vec![0i32; halo.size()];
    root.gather_into_root(&count, &mut counts[..]);
    let displs: Vec<i32> = counts
        .iter()
        .scan(0, |at, &c| {
            let d = *at;
            *at += c;
            Some(d)
        })
        .collect();
    let total = counts.iter().map(|&c| c as usize).sum::<usize>();
    let mut all_nodes = vec![0u64; total];
    root.gather_varcount_into_root(
        &nodes[..],
        &mut PartitionMut::new(&mut all_nodes[..], &counts[..], &displs[..]),
    );
    let (vc, vd): (Vec<i32>, Vec<i32>) = counts
        .iter()
        .zip(&displs)
        .map(|(&c, &d)| (D as i32 * c, D as i32 * d))
        .unzip();
    let mut all_values = vec![0.0; D * total];
    root.gather_varcount_into_root(
        values,
        &mut PartitionMut::new(&mut all_values[..], &vc[..], &vd[..]),
    );
    let mut global = vec![f64::NAN; D * total];
    for (k, &p) in all_nodes.iter().enumerate() {
        let p = p as usize;
        global[D * p..D * p + D].copy_from_slice(&all_values[D * k..D * k + D]);
    }
    Some(global)
}

/// The distributed sweeps on every rank.
fn distributed(f: &Flags, root: bool) -> Result<(), String> {
    let mut halo = MpiRanks::world().duplicate();
    let (rank, size) = (halo.rank(), halo.size());
    let t = Instant::now();
    let mut part = set_up(f, &halo)?;
    let set_up_s = t.elapsed().as_secs_f64();
    let (rss, peak) = memory_mb();
    let mut x = part.x0.clone();
    let mut times = Vec::new();
    for k in 0..f.repetitions {
        x.copy_from_slice(&part.x0);
        part.sweep.update_ghosts(&mut x, &mut halo);
        part.sweep.reset_counters();
        halo.communicator().barrier();
        let t = Instant::now();
        for reverse in directions(f.sweeps) {
            let gs = &part.gs;
            part.sweep.sweep(&mut x, reverse, &mut halo, |rows, p, x| {
                gs.update(rows, p, x)
            });
        }
        halo.communicator().barrier();
        let s = t.elapsed().as_secs_f64();
        if root {
            println!("repetition {k}: {} sweeps in {s:.6} s", f.sweeps);
        }
        times.push(s);
    }
    let rows = part.sweep.rows();
    let (plan, counted) = (part.sweep.per_sweep(), part.sweep.counters());
    let neighbours = part.sweep.neighbour_ranks().count();
    // The rows' off-diagonal blocks (72 bytes and a 4-byte column each).
    let blocks: usize = (0..rows.owned()).map(|p| rows.neighbours(p).count()).sum();
    // One write of the whole line (the ranks share standard error: no interleaving).
    let line = format!(
        "rank {rank} of {size}: owned={} ghosts={} neighbours={neighbours} blocks={blocks} \
         plan_per_sweep={plan} counted={counted} set_up={set_up_s:.3} s \
         resident_after_set_up={rss:.1} MB peak_after_set_up={peak:.1} MB\n",
        rows.owned(),
        rows.ghosts(),
    );
    write_line(&line)?;
    if root {
        report(f, part.dofs, part.colours, size, &mut times);
    }
    write_gathered(f, &halo, part.sweep.rows(), &x)
}

/// Writes one rank's `line` to standard error in one write (the ranks share it: no
/// interleaving).
fn write_line(line: &str) -> Result<(), String> {
    std::io::stderr()
        .write_all(line.as_bytes())
        .map_err(|e| e.to_string())
}

/// Gathers the ranks' owned values of `x` on rank 0 ([`gather`]) and writes them to
/// `--out` there (if given).
fn write_gathered(
    f: &Flags,
    halo: &MpiRanks,
    rows: &LocalRows<D>,
    x: &[f64],
) -> Result<(), String> {
    match (gather(halo, rows, x), f.values_file()) {
        (Some(global), Some(out)) => write_values(&out, &global),
        _ => Ok(()),
    }
}

/// The run on the ranks, after the guard: the flags agreed and checked, rank 0's `--out`
/// prepared.
fn run(flags: Flags, _prepared: Prepared, processes: &dyn Processes) -> Result<(), AnyError> {
    let (size, root) = (processes.size(), processes.rank() == 0);
    let result = if flags.tnnmg {
        match flags.thread_ranks {
            Some(_) if size != 1 => Err("--thread-ranks runs on one rank".to_owned()),
            Some(n) => tnnmg::thread_ranks(&flags, n),
            None => tnnmg::distributed(&flags, root),
        }
    } else if flags.reference {
        if size != 1 {
            return Err("--reference runs on one rank".into());
        }
        if flags.vcycle {
            vcycle::reference(&flags)
        } else {
            reference(&flags)
        }
    } else if flags.vcycle {
        vcycle::distributed(&flags, root)
    } else {
        distributed(&flags, root)
    };
    result.map_err(Into::into)
}

fn main() -> ExitCode {
    rsf_mpi::main_on_ranks(|processes| rsf_programs::guard::main_on_ranks(processes, run))
}
