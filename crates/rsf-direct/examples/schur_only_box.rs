//! The condensation without the whole factor against the one that keeps it, on a 3-D
//! elasticity box (docs/three-d.md, "The condensation without the whole factor").
//!
//! A box of `c × c × c` unit cubes of Kuhn tetrahedra (P1 elasticity, λ = μ = 1), clamped
//! at its bottom face `z = 0`, condensed onto a vertical patch: the nodes of the plane
//! `x = c/2` in the upper half `z ≥ c/2` (reaching the free top face, as a strike-slip
//! fault from the surface), two right-hand sides. One method per process, so that the
//! process's peak memory (VmHWM) is the method's:
//!
//! ```text
//! cargo run --release -p rsf-direct --example schur_only_box -- --cubes 24 --method schur-only
//! cargo run --release -p rsf-direct --example schur_only_box -- --cubes 24 --method full
//! cargo run --release -p rsf-direct --features metis --example schur_only_box -- \
//!     --cubes 24 --method schur-only --ordering nested-dissection
//! cargo run --release -p rsf-direct --example schur_only_box -- --cubes 12 --method both
//! cargo run --release -p rsf-direct --example schur_only_box -- --cubes 32 \
//!     --checkpoint /tmp/box.ckpt --every 500
//! ```
//!
//! `full` is `Condensation::with_ordering` then `schur_entries` (what the fault ODE does
//! for a 3-D fault); `schur-only` is `SchurOnly::new` then `eliminate`; `both` runs the
//! two and prints their largest difference (its memory is not either's). Prints one
//! Markdown table row: dofs, kept dofs, method, ordering, factor entries (full) or the
//! plan's bytes (schur-only), wall times, peak resident memory, and trace(S) and ‖g‖ to
//! compare the methods across runs. With `--checkpoint PATH` the Schur-only set-up writes
//! its state every `--every` fronts (default 1000) and resumes from an existing file (kill
//! it and run the same command again); it prints a checksum of the bits of `S` and `g` to
//! compare a resumed run with an uninterrupted one.
//!
//! Inputs are checked before any work: `--cubes` from 2 to 64 (at 64³ the box alone holds
//! about 0.8 million dofs), `--every` at least 1, and `--max-memory-gb G` (default 16):
//! the Schur-only elimination whose plan holds more is refused before it allocates
//! (`rsf_direct::Error::TooLarge`); the whole factor's allocations are fallible (a typed
//! error, not an abort, if the machine runs out).

#[path = "../tests/suite/elasticity_box.rs"]
mod elasticity_box;

use std::time::Instant;

use elasticity_box::ElasticityBox;
use faer::sparse::SparseColMat;
use rsf_direct::{
    CheckpointPolicy, Condensation, InteriorOrdering, KeptSchur, RightHandSide, SchurEntries,
    SchurOnly, SchurOnlyOptions, SchurOnlyPlan,
};

/// The process's peak resident set (VmHWM, bytes) from /proc/self/status (0 elsewhere).
fn peak_rss() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map_or(0, |kb| 1024 * kb)
}

fn gb(bytes: f64) -> String {
    format!("{:.3}", bytes / 1e9)
}

struct Args {
    cubes: usize,
    method: String,
    ordering: InteriorOrdering,
    checkpoint: Option<String>,
    every: usize,
    max_memory_gb: f64,
}

fn parse() -> Result<Args, String> {
    let mut args = Args {
        cubes: 16,
        method: "schur-only".into(),
        ordering: InteriorOrdering::Amd,
        checkpoint: None,
        every: 1000,
        max_memory_gb: 16.0,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--cubes" => args.cubes = value()?.parse().map_err(|e| format!("--cubes: {e}"))?,
            "--method" => args.method = value()?,
            "--ordering" => {
                args.ordering = value()?.parse().map_err(|e| format!("--ordering: {e}"))?
            }
            "--checkpoint" => args.checkpoint = Some(value()?),
            "--every" => args.every = value()?.parse().map_err(|e| format!("--every: {e}"))?,
            "--max-memory-gb" => {
                args.max_memory_gb = value()?
                    .parse()
                    .map_err(|e| format!("--max-memory-gb: {e}"))?
            }
            _ => return Err(format!("unknown argument {a}")),
        }
    }
    if !["schur-only", "full", "both"].contains(&args.method.as_str()) {
        return Err("--method schur-only | full | both".into());
    }
    if !(2..=64).contains(&args.cubes) {
        return Err(format!("--cubes {}: from 2 to 64", args.cubes));
    }
    if args.every == 0 {
        return Err("--every 0: at least one front between checkpoints".into());
    }
    if !(args.max_memory_gb > 0.0) {
        return Err(format!(
            "--max-memory-gb {}: a positive number of gigabytes (inf: no bound)",
            args.max_memory_gb
        ));
    }
    Ok(args)
}

/// The box's problem: the stiffness, the clamped bottom, the patch's nodes, two
/// right-hand sides (a body force and none) and the bottom's prescribed displacement.
struct Problem {
    c: usize,
    n: usize,
    a: SparseColMat<usize, f64>,
    fixed: Vec<bool>,
    blocks: Vec<usize>,
    b: Vec<f64>,
    x: Vec<f64>,
    zeros: Vec<f64>,
}

impl Problem {
    /// The box of `c × c × c` cubes and its vertical patch.
    fn new(c: usize) -> Self {
        let bx = ElasticityBox::new(c, c, c);
        let a = bx.stiffness();
        let n = a.nrows();
        let fixed: Vec<bool> = (0..n).map(|d| bx.coords(d / 3).2 == 0).collect();
        let blocks: Vec<usize> = (0..bx.nodes())
            .filter(|&p| {
                let (i, _, k) = bx.coords(p);
                i == c / 2 && k >= c / 2
            })
            .collect();
        // A body force and a prescribed displacement of the bottom (both smooth).
        let b: Vec<f64> = (0..n)
            .map(|d| {
                let (i, j, k) = bx.coords(d / 3);
                1e-3 * ((i as f64 * 0.3).sin() + (j as f64 * 0.2).cos() + k as f64 * 0.01)
            })
            .collect();
        let x: Vec<f64> = (0..n)
            .map(|d| {
                let (i, j, _) = bx.coords(d / 3);
                if d % 3 == 0 {
                    0.01 * (i as f64 + 2.0 * j as f64) / c as f64
                } else {
                    0.0
                }
            })
            .collect();
        Self {
            c,
            n,
            a,
            fixed,
            blocks,
            b,
            x,
            zeros: vec![0.0; n],
        }
    }
}

/// The Schur-only elimination's result, its analysis and total times (s) and its plan.
type SchurOnlyRun = (KeptSchur, f64, f64, SchurOnlyPlan);

/// The whole factor's entries, the Schur complement's entries, the two condensed
/// right-hand sides, the factorisation's and the total time (s).
type FullRun = (usize, SchurEntries, Vec<Vec<f64>>, f64, f64);

/// The Schur-only elimination of `p` with `args`' ordering, checkpoints and memory bound;
/// prints its analysis, report and the checksum of its bits.
fn run_schur_only(p: &Problem, args: &Args) -> Result<SchurOnlyRun, Box<dyn std::error::Error>> {
    let t = Instant::now();
    let elim = SchurOnly::<3>::new(p.a.as_ref(), &p.fixed, &p.blocks, &[], args.ordering)?;
    let analyse = t.elapsed().as_secs_f64();
    let plan = elim.plan();
    eprintln!(
        "analysis {analyse:.2} s, peak {} GB; plan: {plan:?}",
        gb(peak_rss() as f64)
    );
    let rhs = [
        RightHandSide {
            b: &p.b,
            x_fixed: &p.x,
        },
        RightHandSide {
            b: &p.zeros,
            x_fixed: &p.x,
        },
    ];
    let options = SchurOnlyOptions {
        checkpoint: args.checkpoint.as_ref().map(|path| CheckpointPolicy {
            every_fronts: Some(args.every),
            every_seconds: None,
            ..CheckpointPolicy::new(path)
        }),
        max_bytes: Some((args.max_memory_gb * 1e9).min(usize::MAX as f64) as usize),
    };
    let kept = elim.eliminate(&rhs, &options)?;
    let total = t.elapsed().as_secs_f64();
    eprintln!("report: {:?}", kept.report());
    eprintln!("checksum of the bits of S and g: {:016x}", checksum(&kept));
    Ok((kept, analyse, total, plan))
}

/// FNV-1a over the bits of S and g: equal for equal bits.
fn checksum(kept: &KeptSchur) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let bits = kept
        .schur()
        .packed_rows()
        .iter()
        .chain(kept.condensed_rhs().iter().flatten());
    for v in bits {
        for byte in v.to_bits().to_le_bytes() {
            h = (h ^ byte as u64).wrapping_mul(0x100_0000_01b3);
        }
    }
    h
}

/// The condensation that keeps the whole factor, of `p` with `args`' ordering.
fn run_full(p: &Problem, args: &Args) -> Result<FullRun, Box<dyn std::error::Error>> {
    let t = Instant::now();
    let mut cond =
        Condensation::<3>::with_ordering(p.a.as_ref(), &p.fixed, &p.blocks, args.ordering)?;
    let factor = t.elapsed().as_secs_f64();
    let entries = cond.schur_entries();
    let mut g = vec![vec![0.0; cond.dim()]; 2];
    cond.condense(&p.b, &p.x, &mut g[0])?;
    cond.condense(&p.zeros, &p.x, &mut g[1])?;
    let total = t.elapsed().as_secs_f64();
    Ok((cond.factor_nnz(), entries, g, factor, total))
}

/// Prints the largest differences of the two methods' S and g (`m` kept unknowns).
fn print_differences(m: usize, kept: &KeptSchur, entries: &SchurEntries, g: &[Vec<f64>]) {
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for i in 0..m {
        for j in 0..=i {
            let e = entries.entry(i, j);
            scale = scale.max(e.abs());
            worst = worst.max((kept.schur().entry(i, j) - e).abs());
        }
    }
    let gerr = (0..2)
        .flat_map(|k| (0..m).map(move |i| (k, i)))
        .map(|(k, i)| (kept.condensed_rhs()[k][i] - g[k][i]).abs())
        .fold(0.0, f64::max);
    println!("max |ΔS| = {worst:.3e} (max |S| = {scale:.3e}), max |Δg| = {gerr:.3e}");
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = parse()?;
    let clock = Instant::now();
    let p = Problem::new(args.cubes);
    let (c, n) = (p.c, p.n);
    let model_s = clock.elapsed().as_secs_f64();
    let model_peak = peak_rss();
    eprintln!(
        "box {c}³: {n} dofs, {} blocks, model {model_s:.2} s, peak {} GB",
        p.blocks.len(),
        gb(model_peak as f64)
    );
    let schur_only = if args.method != "full" {
        Some(run_schur_only(&p, &args)?)
    } else {
        None
    };
    let full = if args.method != "schur-only" {
        Some(run_full(&p, &args)?)
    } else {
        None
    };
    let peak = peak_rss();
    let m = schur_only
        .as_ref()
        .map(|s| s.0.dim())
        .or(full.as_ref().map(|f| f.2[0].len()))
        .unwrap_or(0);
    let (trace, gnorm) = if let Some((kept, ..)) = &schur_only {
        (
            (0..m).map(|i| kept.schur().entry(i, i)).sum::<f64>(),
            kept.condensed_rhs()[0]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt(),
        )
    } else {
        let (_, entries, g, ..) = full.as_ref().expect("one method");
        (
            (0..m).map(|i| entries.entry(i, i)).sum::<f64>(),
            g[0].iter().map(|v| v * v).sum::<f64>().sqrt(),
        )
    };
    if let (Some((kept, ..)), Some((_, entries, g, ..))) = (&schur_only, &full) {
        print_differences(m, kept, entries, g);
        return Ok(());
    }
    let ordering = match args.ordering {
        InteriorOrdering::Amd => "AMD",
        _ => "nested dissection",
    };
    if let Some((kept, analyse, total, plan)) = &schur_only {
        let r = kept.report();
        println!(
            "| {c}³ | {n} | {m} | Schur-only | {ordering} | {} fronts: largest {} GB, pending {} GB, S {} GB | {analyse:.1} | {total:.1} | {:.2e} | {} | {} | {trace:.12e} | {gnorm:.12e} |",
            plan.fronts,
            gb(r.largest_front_bytes as f64),
            gb(r.peak_pending_bytes as f64),
            gb(r.result_bytes as f64),
            r.flops,
            gb(model_peak as f64),
            gb(peak as f64),
        );
    }
    if let Some((nnz, _, _, factor, total)) = &full {
        println!(
            "| {c}³ | {n} | {m} | full factor | {ordering} | {nnz:.3e} entries ({} GB) | | {total:.1} (factor {factor:.1}) | | {} | {} | {trace:.12e} | {gnorm:.12e} |",
            gb(8.0 * *nnz as f64),
            gb(model_peak as f64),
            gb(peak as f64),
        );
    }
    Ok(())
}
