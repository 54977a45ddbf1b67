//! The distributed smoother on MPI ranks: the program `distributed_sweep` (linear block
//! Gauss–Seidel on an elastic box partitioned by METIS, the halo exchanged over MPI) under
//! `mpirun -n 1, 2, 4` gives the bits of the one-process coloured sweep computed here, and
//! every rank's counted halo equals its plan's; with `--vcycle`, the linear V-cycle at
//! `mpirun -n 1, 2` gives the bits of the one-process `ColouredVCycle`; with `--tnnmg`,
//! TNNMG on `mpirun -n 1, 2, 4` gives the bits of its solve on 1 and 3 thread ranks.
//! `MpiRanks` alone: its exchanges arrive in order, and its all-gather
//! (`MPI_Allgatherv`) has the bits of rsf-tnnmg's default over point-to-point messages.

use std::path::{Path, PathBuf};

use rsf_fem::ElasticBox;
use rsf_ranks::{ColouredGaussSeidel, Colouring};
use rsf_tnnmg::distributed::{ColouredVCycle, VCycleHierarchy, VCycleShape};

mod common;
use common::mpirun;

const BIN: &str = env!("CARGO_BIN_EXE_distributed_sweep");
const D: usize = 3;

/// A fresh output folder `name` under the target directory's tmp.
fn file(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("halo");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::remove_dir_all(&p).ok();
    p
}

/// The values a run wrote into its folder `out` (`values.bin`, little-endian f64).
fn values(out: &Path) -> Vec<f64> {
    std::fs::read(out.join("values.bin"))
        .unwrap()
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

/// Runs `mpirun -n n` on the program with `args` and `--out out`; asserts that it
/// succeeded (its standard error in the message) and returns the values it wrote and its
/// standard error.
fn run_program(n: usize, args: &[&str], out: &Path) -> (Vec<f64>, String) {
    let run = mpirun(n)
        .arg(BIN)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("mpirun (Open MPI: apt-get install openmpi-bin libopenmpi-dev)");
    let err = String::from_utf8_lossy(&run.stderr).into_owned();
    assert!(run.status.success(), "{n} ranks, {args:?}: {err}");
    (values(out), err)
}

/// Entries whose bits differ.
fn differing_bits(a: &[f64], b: &[f64]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

/// One rank's line of the program's standard error.
#[derive(Debug)]
struct RankLine {
    owned: u64,
    ghosts: u64,
    /// sweeps, exchanges, messages, values, collectives, collective values.
    plan: [u64; 6],
    counted: [u64; 6],
}

fn field<'a>(line: &'a str, key: &str) -> &'a str {
    line.split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        .unwrap_or_else(|| panic!("no {key} in {line}"))
}

/// The `/`-separated counts of a field (`HaloCounters`' form and its parts).
fn numbers<const N: usize>(s: &str) -> [u64; N] {
    let v: Vec<u64> = s.split('/').map(|x| x.parse().unwrap()).collect();
    v.try_into()
        .unwrap_or_else(|v: Vec<u64>| panic!("{N} counts expected in {s}: {v:?}"))
}

/// Rank `r`'s line (`rank r of n: owned=…`) of a run's standard error.
fn rank_line(err: &str, r: usize, n: usize) -> &str {
    err.lines()
        .find(|l| l.starts_with(&format!("rank {r} of {n}: owned=")))
        .unwrap_or_else(|| panic!("no line of rank {r} of {n}:\n{err}"))
}

/// The `rank r of n:` lines, by rank.
fn rank_lines(err: &str, n: usize) -> Vec<RankLine> {
    (0..n)
        .map(|r| {
            let line = rank_line(err, r, n);
            RankLine {
                owned: field(line, "owned").parse().unwrap(),
                ghosts: field(line, "ghosts").parse().unwrap(),
                plan: numbers(field(line, "plan_per_sweep")),
                counted: numbers(field(line, "counted")),
            }
        })
        .collect()
}

/// Six forward and backward sweeps on the box of 10 647 dofs at 1, 2 and 4 MPI ranks: the
/// owned values gathered on rank 0 have the bits of the one-process coloured sweep; per
/// rank the counters over the sweeps are six times the plan's per sweep; the ranks own
/// every node once; the values sent per sweep are `D` per ghost of the receiving ranks
/// (every ghost is sent once per sweep); at several ranks every rank has ghosts and sends.
/// The program's one-process reference (`--reference`) has the same bits.
#[test]
fn distributed_sweeps_on_1_2_and_4_mpi_ranks_have_the_one_process_bits() {
    let bx = ElasticBox::bar(2).unwrap();
    let colouring = Colouring::new::<D>(bx.stiffness.as_ref()).unwrap();
    let sweeps = [false, true, false, true, false, true];
    let start = bx.start();
    let mut gs =
        ColouredGaussSeidel::<D>::new(bx.stiffness.as_ref(), &bx.fixed, &bx.load(), &colouring)
            .unwrap();
    let mut x = start.clone();
    for reverse in sweeps {
        gs.sweep(&mut x, reverse);
    }
    assert!(differing_bits(&x, &start) > bx.dofs() / 2);
    assert!(x.iter().all(|v| v.is_finite()));
    let nodes = bx.mesh().num_vertices() as u64;
    let args = ["--refinements", "2", "--sweeps", "6"];

    let reference = [&args[..], &["--reference"]].concat();
    let (values, _) = run_program(1, &reference, &file("reference.bin"));
    assert_eq!(differing_bits(&values, &x), 0, "--reference");

    for n in [1, 2, 4] {
        let (values, err) = run_program(n, &args, &file(&format!("ranks_{n}.bin")));
        assert_eq!(differing_bits(&values, &x), 0, "{n} ranks");
        let lines = rank_lines(&err, n);
        assert_eq!(lines.iter().map(|l| l.owned).sum::<u64>(), nodes);
        let ghosts: u64 = lines.iter().map(|l| l.ghosts).sum();
        let sent: u64 = lines.iter().map(|l| l.plan[3]).sum();
        assert_eq!(sent, D as u64 * ghosts, "{n} ranks: values per sweep");
        for (r, l) in lines.iter().enumerate() {
            assert_eq!(l.plan[0], 1, "rank {r} of {n}");
            assert_eq!(l.plan[1], colouring.num_colours() as u64);
            let six = l.plan.map(|v| 6 * v);
            assert_eq!(l.counted, six, "rank {r} of {n}: counted against the plan");
            assert_eq!(l.ghosts > 0, n > 1, "rank {r} of {n}: ghosts");
            assert_eq!(l.plan[2] > 0, n > 1, "rank {r} of {n}: messages");
            assert_eq!(l.plan[4..], [0, 0], "rank {r} of {n}: no collective");
        }
    }
}

/// The `rank r of n:` lines of a `--vcycle` run, by rank: owned fine nodes, owned
/// coarsest nodes, the plans' (sweeps, exchanges, messages, values, collectives,
/// collective values) per cycle, and what was counted.
fn vcycle_lines(err: &str, n: usize) -> Vec<(u64, u64, [u64; 6], [u64; 6])> {
    (0..n)
        .map(|r| {
            let line = rank_line(err, r, n);
            (
                field(line, "owned").parse().unwrap(),
                field(line, "coarsest_owned").parse().unwrap(),
                numbers(field(line, "plan_per_cycle")),
                numbers(field(line, "counted")),
            )
        })
        .collect()
}

/// Three linear V(1,1)-cycles on the box of 10 647 dofs (3 levels) with `--vcycle` at 1
/// and 2 MPI ranks: the owned values gathered on rank 0 have the bits of the one-process
/// `ColouredVCycle` computed here, as does the program's `--reference`; per rank the
/// counters over the cycles are three times the plans' per cycle, with 2 sweeps per level
/// above the coarsest; the ranks own every fine and every coarsest node once; at 2 ranks
/// every rank sends.
#[test]
fn vcycles_on_1_and_2_mpi_ranks_have_the_one_process_bits() {
    let bx = ElasticBox::bar(2).unwrap();
    let h = &bx.hierarchy;
    let ps: Vec<_> = (1..=h.finest_level())
        .map(|j| h.vector_prolongation(j).as_ref())
        .collect();
    let vh = VCycleHierarchy::<D>::new(bx.stiffness.as_ref(), &bx.fixed, &ps).unwrap();
    let mut vc = ColouredVCycle::new(&vh, VCycleShape { pre: 1, post: 1 }).unwrap();
    vc.set_rhs(&bx.load()).unwrap();
    let start = bx.start();
    let mut x = start.clone();
    for _ in 0..3 {
        vc.cycle(&mut x);
    }
    assert!(differing_bits(&x, &start) > bx.dofs() / 2);
    assert!(x.iter().all(|v| v.is_finite()));
    let args = ["--refinements", "2", "--sweeps", "3", "--vcycle"];

    let reference = [&args[..], &["--reference"]].concat();
    let (values, _) = run_program(1, &reference, &file("vcycle_reference.bin"));
    assert_eq!(differing_bits(&values, &x), 0, "--reference");

    let levels = vh.num_levels() as u64;
    for n in [1, 2] {
        let (values, err) = run_program(n, &args, &file(&format!("vcycle_ranks_{n}.bin")));
        assert_eq!(differing_bits(&values, &x), 0, "{n} ranks");
        let lines = vcycle_lines(&err, n);
        let owned: u64 = lines.iter().map(|l| l.0).sum();
        let coarsest: u64 = lines.iter().map(|l| l.1).sum();
        assert_eq!(
            (owned, coarsest),
            (bx.mesh().num_vertices() as u64, vh.nodes(0) as u64)
        );
        for (r, (_, _, plan, counted)) in lines.iter().enumerate() {
            assert_eq!(
                plan[0],
                2 * (levels - 1),
                "rank {r} of {n}: sweeps per cycle"
            );
            assert_eq!(*counted, plan.map(|v| 3 * v), "rank {r} of {n}: counted");
            assert_eq!(plan[2] > 0, n > 1, "rank {r} of {n}: messages");
            assert_eq!(plan[4], 1, "rank {r} of {n}: the coarsest gather");
        }
        let gathered: u64 = lines.iter().map(|l| l.2[5]).sum();
        assert_eq!(gathered, D as u64 * vh.nodes(0) as u64, "{n} ranks");
    }
}

/// `exchanges/messages/values/collectives/collective_values` of a rank line's field.
fn five(line: &str, key: &str) -> [u64; 5] {
    numbers(field(line, key))
}

/// TNNMG with Tresca friction on the top face of the box of 10 647 dofs, with V-cycles
/// and with preconditioned CG (`--cg`): the program's solve on 1 and 3 thread ranks (one
/// process) and on 1, 2 and 4 MPI ranks gives the same bits and iteration counts; the
/// solution is finite, moved from the start, and sticks on some frictional nodes and
/// slips on others; per MPI rank the counters over the solve are the iterations times the
/// plans' per iteration plus the solution's all-gather, the first iteration's full update
/// of the hierarchy in place of an incremental one (at most that with CG, whose
/// iterations may stop their cycles early); at several ranks every rank sends
/// point-to-point messages in every iteration, and every iteration makes at least four
/// collectives (the active blocks' two gathers, two reductions), the solve one more.
#[test]
fn tnnmg_on_1_2_and_4_mpi_ranks_has_the_thread_ranks_bits() {
    for cg in [false, true] {
        tnnmg_on_mpi_ranks(cg);
    }
}

fn tnnmg_on_mpi_ranks(cg: bool) {
    let bx = ElasticBox::bar(2).unwrap();
    let mut args = vec!["--refinements", "2", "--tnnmg"];
    if cg {
        args.push("--cg");
    }
    let args = &args[..];
    let mut solutions = Vec::new();
    for threads in [1, 3] {
        let threads_arg = threads.to_string();
        let with_threads = [args, &["--thread-ranks", &threads_arg]].concat();
        let out = file(&format!("tnnmg_threads_{threads}_{cg}.bin"));
        let (values, _) = run_program(1, &with_threads, &out);
        solutions.push((format!("{threads} thread ranks"), values));
    }
    let reference = solutions[0].1.clone();
    assert_eq!(reference.len(), bx.dofs());
    assert!(reference.iter().all(|v| v.is_finite()));
    assert!(differing_bits(&reference, &bx.start()) > bx.dofs() / 2);
    let top: Vec<usize> = (bx.mesh().vertices().iter().enumerate())
        .filter(|(_, v)| v[2] == 1.0)
        .map(|(p, _)| p)
        .collect();
    let stuck = top
        .iter()
        .filter(|&&p| reference[D * p..D * p + D] == [0.0; D])
        .count();
    assert!(
        stuck > 0 && stuck < top.len(),
        "stuck {stuck} of {}",
        top.len()
    );
    let mut iterations = Vec::new();
    for n in [1, 2, 4] {
        let (values, err) = run_program(n, args, &file(&format!("tnnmg_ranks_{n}_{cg}.bin")));
        solutions.push((format!("{n} MPI ranks"), values));
        for r in 0..n {
            let line = rank_line(&err, r, n);
            let it: u64 = field(line, "iterations").parse().unwrap();
            iterations.push(it);
            let (plan, solution) = (five(line, "per_iteration"), five(line, "solution"));
            // The first iteration updates the hierarchy in full, the others
            // incrementally (the plan's).
            let (full, incremental) = (five(line, "full_update"), five(line, "hierarchy"));
            let most: Vec<u64> = (0..5)
                .map(|i| it * plan[i] + solution[i] + full[i] - incremental[i])
                .collect();
            let counted = five(line, "counted");
            if cg {
                assert!(
                    (0..5).all(|i| counted[i] <= most[i]),
                    "rank {r} of {n}: {line}"
                );
            } else {
                assert_eq!(counted.to_vec(), most, "rank {r} of {n}");
            }
            assert_eq!(plan[1] > 0, n > 1, "rank {r} of {n}: {line}");
            assert!(plan[3] >= 4, "rank {r} of {n}: collectives, {line}");
            assert_eq!(solution[3], 1, "rank {r} of {n}: {line}");
        }
    }
    for (name, v) in &solutions {
        assert_eq!(differing_bits(v, &reference), 0, "{name}, cg {cg}");
    }
    assert!(
        iterations.iter().all(|&i| i == iterations[0] && i > 2),
        "{iterations:?}"
    );
}

/// `--reference` is the one-process sweep: on two ranks the program refuses it, and every
/// rank ends.
#[test]
fn the_reference_refuses_two_ranks() {
    let run = mpirun(2)
        .arg(BIN)
        .args(["--refinements", "0", "--reference"])
        .output()
        .unwrap();
    assert!(!run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(err.contains("--reference runs on one rank"), "{err}");
}

/// The program goes through the guard (issue 74): `--sweeps 1e12` (which aborted on a
/// 1 TB allocation) and `--refinements 12` (which hung) are refused at once on every rank,
/// and `--out` into another run's folder is refused, its file unchanged, unless
/// `--overwrite`.
#[test]
fn the_program_refuses_careless_inputs_on_every_rank() {
    for (args, names) in [
        (&["--sweeps", "1e12"][..], "--sweeps"),
        (&["--refinements", "12"][..], "--max-memory-gb"),
    ] {
        let t = std::time::Instant::now();
        let run = mpirun(2).arg(BIN).args(args).output().unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}");
        assert!(err.contains(names), "{args:?}: {err}");
        assert!(
            t.elapsed().as_secs_f64() < 30.0,
            "{args:?}: {:?}",
            t.elapsed()
        );
    }
    let out = file("guarded");
    run_program(1, &["--refinements", "0"], &out);
    let before = std::fs::read(out.join("values.bin")).unwrap();
    let again = mpirun(1)
        .arg(BIN)
        .args(["--refinements", "1", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(
        !again.status.success() && err.contains("--overwrite"),
        "{err}"
    );
    assert_eq!(std::fs::read(out.join("values.bin")).unwrap(), before);
    let replaced = mpirun(1)
        .arg(BIN)
        .args(["--refinements", "1", "--overwrite", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(replaced.status.success());
    assert!(values(&out).len() > before.len() / 8);
}

/// Set in the ranks' environment: run the body of the test (`mpi_ranks_exchange_in_order`,
/// `mpi_all_gather_is_the_default_all_gather`).
const CHILD: &str = "RSF_MPI_HALO_TEST_RANK";

/// `MpiRanks` alone on 3 MPI ranks in a ring: five exchanges of different lengths, no
/// wait between them (a rank may run ahead by any number of exchanges), rank 1 sending
/// nothing in the third: every message arrives at its rank, in order, where its receive
/// entry puts it, and a receive range left out keeps its value.
#[test]
fn mpi_ranks_exchange_in_order() {
    use rsf_ranks::{HaloMessage, RankGroup};
    if std::env::var_os(CHILD).is_some() {
        let (_universe, _ranks) = rsf_mpi::initialize().unwrap();
        let mut halo = rsf_mpi::MpiRanks::world().duplicate();
        let (r, n) = (halo.rank(), halo.size());
        let (next, prev) = ((r + 1) % n, (r + n - 1) % n);
        for round in 0..5 {
            let len = 1 + round;
            let send: Vec<f64> = (0..len)
                .map(|k| (100 * r + 10 * round + k) as f64)
                .collect();
            let mut recv = vec![-1.0; len + 2];
            let silent = |s: usize| round == 2 && s == 1;
            let to = [HaloMessage {
                rank: next,
                start: 0,
                len,
            }];
            let from = [HaloMessage {
                rank: prev,
                start: 2,
                len,
            }];
            halo.exchange(
                if silent(r) { &[] } else { &to },
                &send,
                if silent(prev) { &[] } else { &from },
                &mut recv,
            );
            let mut want = vec![-1.0; len + 2];
            if !silent(prev) {
                for k in 0..len {
                    want[2 + k] = (100 * prev + 10 * round + k) as f64;
                }
            }
            assert_eq!(recv, want, "rank {r}, exchange {round}");
        }
        // One write (the ranks share standard error).
        let line = format!("rank {r} of {n}: five exchanges in order\n");
        std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes()).unwrap();
        return;
    }
    let err = run_as_child(3, "mpi_ranks_exchange_in_order");
    assert_eq!(err.matches("five exchanges in order").count(), 3, "{err}");
}

/// Runs this test binary's test `name` alone on `ranks` MPI ranks, with [`CHILD`] set in
/// their environment (so the test runs its ranks' body); asserts that the job succeeded
/// and returns its standard error.
fn run_as_child(ranks: usize, name: &str) -> String {
    let me = std::env::current_exe().unwrap();
    let out = mpirun(ranks)
        .env(CHILD, "1")
        .arg(&me)
        .args(["--exact", name, "--nocapture", "--test-threads", "1"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{ranks} ranks, {name}: {err}");
    err
}

/// rsf-tnnmg's default all-gather (one exchange of point-to-point messages) on an
/// `MpiRanks`: a transport that only forwards `exchange`.
struct ByExchange<'a>(&'a mut rsf_mpi::MpiRanks);

impl rsf_ranks::RankGroup for ByExchange<'_> {
    fn rank(&self) -> usize {
        self.0.rank()
    }

    fn size(&self) -> usize {
        self.0.size()
    }

    fn exchange(
        &mut self,
        sends: &[rsf_ranks::HaloMessage],
        send: &[f64],
        recvs: &[rsf_ranks::HaloMessage],
        recv: &mut [f64],
    ) {
        self.0.exchange(sends, send, recvs, recv);
    }
}

/// `MpiRanks::all_gather` (`MPI_Allgatherv`) at 2 and 4 MPI ranks, under five count
/// patterns (uneven, some zero, the caller's own zero, all zero, one rank only) with
/// values of every kind (negative zero, NaN payloads, subnormals): the bits of the
/// default all-gather over point-to-point messages on the same ranks, and the
/// concatenation of every rank's values in rank order; exchanges in between still pair
/// up.
#[test]
fn mpi_all_gather_is_the_default_all_gather() {
    use rsf_ranks::RankGroup;
    if std::env::var_os(CHILD).is_some() {
        let (_universe, _ranks) = rsf_mpi::initialize().unwrap();
        let mut halo = rsf_mpi::MpiRanks::world().duplicate();
        let (r, n) = (halo.rank(), halo.size());
        let value = |s: usize, round: usize, k: usize| match k % 4 {
            0 => -0.0,
            1 => f64::from_bits(0x7ff8_0000_0000_0000 | (100 * s + 10 * round + k) as u64),
            2 => f64::from_bits(1 + (s + round) as u64),
            _ => (100 * s + 10 * round + k) as f64 + 0.1,
        };
        let patterns: Vec<Vec<usize>> = vec![
            (0..n).map(|s| 3 * s + 1).collect(),
            (0..n).map(|s| if s % 2 == 0 { 0 } else { 5 + s }).collect(),
            (0..n).map(|s| usize::from(s != 1) * (2 + s)).collect(),
            vec![0; n],
            (0..n).map(|s| usize::from(s + 1 == n) * 1000).collect(),
        ];
        for (round, counts) in patterns.iter().enumerate() {
            let send: Vec<f64> = (0..counts[r]).map(|k| value(r, round, k)).collect();
            let total: usize = counts.iter().sum();
            let (mut collective, mut default) = (vec![7.0; total], vec![-7.0; total]);
            halo.all_gather(&send, counts, &mut collective);
            ByExchange(&mut halo).all_gather(&send, counts, &mut default);
            let want: Vec<u64> = (0..n)
                .flat_map(|s| (0..counts[s]).map(move |k| value(s, round, k).to_bits()))
                .collect();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&collective), want, "rank {r} of {n}, pattern {round}");
            assert_eq!(bits(&default), want, "rank {r} of {n}, pattern {round}");
        }
        let line = format!("rank {r} of {n}: all-gathers agree\n");
        std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes()).unwrap();
        return;
    }
    for n in [2, 4] {
        let err = run_as_child(n, "mpi_all_gather_is_the_default_all_gather");
        assert_eq!(err.matches("all-gathers agree").count(), n, "{err}");
    }
}
