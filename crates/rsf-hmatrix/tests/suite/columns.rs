//! The set-up from whole columns of a symmetric matrix: accuracy against the dense
//! matrix and the set-up from it, each column asked for once, bits for every thread
//! count, storage growth, the error estimate and bound, and errors.

use std::convert::Infallible;
use std::sync::atomic::{AtomicUsize, Ordering};

use faer::{Mat, MatMut};
use rsf_hmatrix::kernels::AntiplaneHalfSpace;
use rsf_hmatrix::{ColumnsError, Error, ErrorMeasure, HMatrix, HOptions, Points};

/// BP1's shear modulus (Pa) and a 40 km fault.
const MU: f64 = 32.04e9;
const DEPTH: f64 = 40e3;

/// A column oracle from an entry function, counting the requests of each column.
struct Oracle<'a, F> {
    entry: &'a F,
    counts: Vec<AtomicUsize>,
    calls: AtomicUsize,
    /// CPU time spent in the oracle, µs (Linux; 0 elsewhere).
    cpu_micros: AtomicUsize,
}

/// CPU seconds of the calling thread (`thread`) or of the process, from /proc (Linux; 0
/// elsewhere), at the kernel's 100 Hz tick.
fn cpu_seconds(thread: bool) -> f64 {
    let path = if thread {
        "/proc/thread-self/stat"
    } else {
        "/proc/self/stat"
    };
    std::fs::read_to_string(path)
        .ok()
        .and_then(|s| {
            // Fields after the command name (in parentheses): utime and stime are the
            // 12th and 13th.
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<&str> = rest.split(' ').collect();
            let t = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
            Some(t / 100.0)
        })
        .unwrap_or(0.0)
}

impl<'a, F: Fn(usize, usize) -> f64 + Sync> Oracle<'a, F> {
    fn new(entry: &'a F, n: usize) -> Self {
        Self {
            entry,
            counts: (0..n).map(|_| AtomicUsize::new(0)).collect(),
            calls: AtomicUsize::new(0),
            cpu_micros: AtomicUsize::new(0),
        }
    }

    fn columns(&self, js: &[usize], mut out: MatMut<'_, f64>) -> Result<(), Infallible> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        let cpu = cpu_seconds(true);
        assert_eq!(out.ncols(), js.len());
        assert_eq!(out.nrows(), self.counts.len());
        for (k, &j) in js.iter().enumerate() {
            self.counts[j].fetch_add(1, Ordering::Relaxed);
            for i in 0..out.nrows() {
                assert_eq!(out[(i, k)], 0.0);
                out[(i, k)] = (self.entry)(i, j);
            }
        }
        let spent = (cpu_seconds(true) - cpu).max(0.0);
        self.cpu_micros
            .fetch_add((spent * 1e6) as usize, Ordering::Relaxed);
        Ok(())
    }

    /// Every column asked for exactly once.
    fn assert_each_column_once(&self) {
        for (j, c) in self.counts.iter().enumerate() {
            assert_eq!(c.load(Ordering::Relaxed), 1, "column {j}");
        }
    }
}

fn build<'a, F: Fn(usize, usize) -> f64 + Sync>(
    entry: &'a F,
    points: &Points,
    options: &HOptions,
) -> (HMatrix, Oracle<'a, F>) {
    let oracle = Oracle::new(entry, points.len());
    let h = HMatrix::from_symmetric_columns(|js, out| oracle.columns(js, out), points, options)
        .unwrap();
    (h, oracle)
}

/// Checks `S_H` against the dense `S` and against `from_dense`'s compression.
fn check_against_dense<F: Fn(usize, usize) -> f64 + Sync>(
    name: &str,
    entry: &F,
    points: &Points,
    options: &HOptions,
) {
    let n = points.len();
    let eps = options.epsilon;
    let s = Mat::from_fn(n, n, entry);
    let norm = s.norm_l2();
    let (h, oracle) = build(entry, points, options);
    oracle.assert_each_column_once();
    let r = h.report().clone();
    let c = r.columns.clone().unwrap();
    assert_eq!(c.columns_computed, n);
    assert_eq!(c.batches, oracle.calls.load(Ordering::Relaxed));
    let measured = (&h.to_dense() - &s).norm_l2() / norm;
    assert!(measured <= eps, "{name} ε {eps}: measured {measured:.3e}");
    // The bound bounds, the estimate estimates.
    assert!(
        measured <= c.error_bound * (1.0 + 1e-6) + 1e-15,
        "{name}: measured {measured:.3e} above the bound {:.3e}",
        c.error_bound
    );
    assert!(c.error_bound <= eps, "{name}: bound {:.3e}", c.error_bound);
    assert!(matches!(
        r.error_measure,
        ErrorMeasure::SampledColumns { columns: 8 }
    ));
    assert!(
        r.relative_error <= 3.0 * measured + 1e-15 && r.relative_error <= eps,
        "{name}: estimate {:.3e}, measured {measured:.3e}",
        r.relative_error
    );
    // Against the optimal truncation of each block.
    let svd = HMatrix::from_dense(s.as_ref(), points, options).unwrap();
    let between = (&h.to_dense() - &svd.to_dense()).norm_l2() / norm;
    assert!(
        between <= 2.0 * eps,
        "{name}: {between:.3e} from from_dense"
    );
    let (a, b) = (r.stored_entries as f64, svd.stored_entries() as f64);
    assert!(a <= 1.3 * b, "{name}: {a} stored against {b} by SVD");
    assert!(r.low_rank_blocks > 0 && a < (n * n) as f64);
    assert!(c.peak_bytes >= 8 * r.stored_entries);
}

#[test]
fn antiplane_kernel_in_one_dimension() {
    let n = 700;
    let k = AntiplaneHalfSpace::new(n, DEPTH / n as f64, MU).unwrap();
    let entry = |i: usize, j: usize| k.entry(i, j);
    for eps in [1e-4, 1e-6, 1e-8] {
        check_against_dense(
            "antiplane",
            &entry,
            &k.points(),
            &HOptions::with_epsilon(eps),
        );
    }
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// A regularised Kelvin-like kernel with `c` components on points `xyz` (`d` coordinates):
/// `δ_ab/ρ + (x_a − y_a)(x_b − y_b)/ρ³`, `ρ = (r² + h²)^½` (components beyond `d` see
/// only the first term).
fn kelvin(xyz: &[Vec<f64>], c: usize, h: f64, i: usize, j: usize) -> f64 {
    let (p, a, q, b) = (i / c, i % c, j / c, j % c);
    let (x, y) = (&xyz[p], &xyz[q]);
    let rho = (dist(x, y).powi(2) + h * h).sqrt();
    let delta = if a == b { 1.0 } else { 0.0 };
    let da = x.get(a).zip(y.get(a)).map_or(0.0, |(u, v)| u - v);
    let db = x.get(b).zip(y.get(b)).map_or(0.0, |(u, v)| u - v);
    delta / rho + da * db / rho.powi(3)
}

fn unknown_points(xyz: &[Vec<f64>], c: usize) -> Points {
    let d = xyz[0].len();
    let flat: Vec<f64> = xyz
        .iter()
        .flat_map(|p| std::iter::repeat_n(p.clone(), c).flatten())
        .collect();
    Points::new(&flat, d).unwrap()
}

#[test]
fn vector_kernels_on_two_and_three_dimensional_point_sets() {
    // A sheared plane grid with 2 components, and a curved fault surface in 3-D with 3.
    let plane: Vec<Vec<f64>> = (0..24 * 24)
        .map(|p| {
            let (x, y) = ((p % 24) as f64, (p / 24) as f64);
            vec![x + 0.13 * y, y]
        })
        .collect();
    let surface: Vec<Vec<f64>> = (0..18 * 18)
        .map(|p| {
            let (x, z) = ((p % 18) as f64, (p / 18) as f64);
            vec![x, 0.05 * (x - 9.0).powi(2), -z]
        })
        .collect();
    for (name, xyz, c) in [("2-D", &plane, 2), ("3-D", &surface, 3)] {
        let entry = |i: usize, j: usize| kelvin(xyz, c, 0.5, i, j);
        let points = unknown_points(xyz, c);
        check_against_dense(name, &entry, &points, &HOptions::with_epsilon(1e-6));
    }
}

#[test]
fn bit_identical_for_every_thread_count() {
    let surface: Vec<Vec<f64>> = (0..16 * 16)
        .map(|p| {
            let (x, z) = ((p % 16) as f64, (p / 16) as f64);
            vec![x, 0.05 * (x - 8.0).powi(2), -z]
        })
        .collect();
    let entry = |i: usize, j: usize| kelvin(&surface, 3, 0.5, i, j);
    let points = unknown_points(&surface, 3);
    let options = HOptions {
        column_batch: 40,
        ..HOptions::with_epsilon(1e-6)
    };
    let bits = |h: &HMatrix| {
        h.to_dense()
            .col_iter()
            .flat_map(|c| c.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
            .collect::<Vec<_>>()
    };
    let mut first: Option<(Vec<u64>, usize, f64)> = None;
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (h, oracle) = pool.install(|| build(&entry, &points, &options));
        oracle.assert_each_column_once();
        let r = h.report();
        let this = (bits(&h), r.stored_entries, r.relative_error);
        match &first {
            None => first = Some(this),
            Some(f) => {
                assert!(f.0 == this.0, "{threads} threads: other bits");
                assert_eq!((f.1, f.2.to_bits()), (this.1, this.2.to_bits()));
            }
        }
    }
}

#[test]
fn stored_entries_grow_like_n_log_n() {
    crate::assert_stored_entries_grow_like_n_log_n(&[512, 1024, 2048, 4096], |n| {
        let k = AntiplaneHalfSpace::new(n, DEPTH / n as f64, MU).unwrap();
        let entry = |i: usize, j: usize| k.entry(i, j);
        let (h, oracle) = build(&entry, &k.points(), &HOptions::default());
        oracle.assert_each_column_once();
        assert!(h.report().columns.as_ref().unwrap().error_bound <= 1e-6);
        h.stored_entries()
    });
}

#[test]
fn every_column_sampled_makes_the_error_exact() {
    let n = 300;
    let k = AntiplaneHalfSpace::new(n, DEPTH / n as f64, MU).unwrap();
    let entry = |i: usize, j: usize| k.entry(i, j);
    let options = HOptions {
        error_columns: n,
        column_batch: 1,
        leaf_size: 16,
        ..HOptions::with_epsilon(1e-5)
    };
    let (h, oracle) = build(&entry, &k.points(), &options);
    oracle.assert_each_column_once();
    let r = h.report();
    assert_eq!(r.error_measure, ErrorMeasure::Exact);
    let s = Mat::from_fn(n, n, entry);
    let exact = (&h.to_dense() - &s).norm_l2() / s.norm_l2();
    assert!(exact > 0.0);
    assert!((r.relative_error - exact).abs() <= 1e-6 * exact);
    // One leaf cluster per call with a batch of 1.
    assert_eq!(r.columns.as_ref().unwrap().batches, r.leaf_clusters);
}

#[derive(Debug, thiserror::Error, PartialEq)]
#[error("solve failed")]
struct SolveFailed;

#[test]
fn oracle_errors_and_bad_columns_are_typed_errors() {
    let n = 200;
    let k = AntiplaneHalfSpace::new(n, DEPTH / n as f64, MU).unwrap();
    let points = k.points();
    let options = HOptions::default();
    let failing = |js: &[usize], _: MatMut<'_, f64>| {
        if js.contains(&150) {
            Err(SolveFailed)
        } else {
            Ok(())
        }
    };
    match HMatrix::from_symmetric_columns(failing, &points, &options) {
        Err(ColumnsError::Oracle {
            columns, source, ..
        }) => {
            assert!(columns > 0);
            assert_eq!(source, SolveFailed);
        }
        other => panic!("{:?}", other.map(|h| h.dim())),
    }
    let nan = |js: &[usize], mut out: MatMut<'_, f64>| -> Result<(), SolveFailed> {
        for (c, &j) in js.iter().enumerate() {
            for i in 0..n {
                out[(i, c)] = if (i, j) == (3, 150) {
                    f64::NAN
                } else {
                    k.entry(i, j)
                };
            }
        }
        Ok(())
    };
    match HMatrix::from_symmetric_columns(nan, &points, &options) {
        Err(ColumnsError::HMatrix(e)) => {
            assert_eq!(e, Error::NonFiniteEntry { row: 3, col: 150 })
        }
        other => panic!("{:?}", other.map(|h| h.dim())),
    }
    let bad = HOptions {
        column_batch: 0,
        ..HOptions::default()
    };
    assert!(matches!(
        HMatrix::from_symmetric_columns(nan, &points, &bad),
        Err(ColumnsError::HMatrix(Error::Option {
            name: "column_batch",
            ..
        }))
    ));
    // No points: no call.
    let none = Points::new(&[], 3).unwrap();
    let h = HMatrix::from_symmetric_columns(
        |_: &[usize], _: MatMut<'_, f64>| -> Result<(), SolveFailed> { panic!("called") },
        &none,
        &options,
    )
    .unwrap();
    assert_eq!(
        (
            h.dim(),
            h.report().columns.as_ref().unwrap().columns_computed
        ),
        (0, 0)
    );
}

/// The SEAS BP5 fault's sizes: a 100 km × 40 km plane in 3-D, nodes every `h` km (1 and
/// 0.5 km: m = 8 282 and 32 562 unknowns, strike and dip), a regularised Kelvin-like
/// kernel standing in for the Schur complement (an entry costs nanoseconds here, a column
/// of the real S one pair of sparse triangular solves). Prints what the set-up measured;
/// run with `cargo test -p rsf-hmatrix --test suite -- --ignored --nocapture columns::`
/// (`RSF_BP5_SPACINGS=1` for the 1 km fault only; spacings in km, comma-separated).
#[test]
#[ignore = "measurement (a minute or more)"]
fn bp5_sized_faults() {
    let spacings: Vec<f64> = std::env::var("RSF_BP5_SPACINGS")
        .unwrap_or_else(|_| "1,0.5".into())
        .split(',')
        .map(|h| h.trim().parse().expect("spacing in km"))
        .collect();
    for h in spacings {
        let (nx, nz) = ((100.0 / h) as usize + 1, (40.0 / h) as usize + 1);
        let nodes: Vec<Vec<f64>> = (0..nx * nz)
            .map(|p| vec![(p % nx) as f64 * h, 0.0, -((p / nx) as f64) * h])
            .collect();
        // Components: strike (x) and dip (z).
        let plane: Vec<Vec<f64>> = nodes.iter().map(|p| vec![p[0], p[2]]).collect();
        let entry = |i: usize, j: usize| kelvin(&plane, 2, h, i, j);
        let points = unknown_points(&nodes, 2);
        let m = points.len();
        for eps in [1e-4, 1e-6] {
            let (clock, cpu) = (std::time::Instant::now(), cpu_seconds(false));
            let (hm, oracle) = build(&entry, &points, &HOptions::with_epsilon(eps));
            let wall = clock.elapsed().as_secs_f64();
            let cpu = cpu_seconds(false) - cpu;
            let oracle_cpu = oracle.cpu_micros.load(Ordering::Relaxed) as f64 * 1e-6;
            oracle.assert_each_column_once();
            let r = hm.report();
            let c = r.columns.as_ref().unwrap();
            eprintln!(
                "m {m} ε {eps:.0e}: columns {} in {} calls (≤ {}), peak {:.1} MB (dense copy {:.1} MB), \
                 stored {:.1} MB = {:.4} of dense, ranks ≤ {} (mean {:.1}), {} + {} blocks, \
                 error estimate {:.2e} bound {:.2e}, oracle {:.1} s, set-up {:.1} s (wall {wall:.1} s); \
                 CPU: oracle {oracle_cpu:.1} s, the rest {:.1} s",
                c.columns_computed,
                c.batches,
                c.largest_batch,
                c.peak_bytes as f64 / 1e6,
                8.0 * (m * m) as f64 / 1e6,
                8.0 * r.stored_entries as f64 / 1e6,
                r.memory_ratio(),
                r.max_rank,
                r.mean_rank,
                r.dense_blocks,
                r.low_rank_blocks,
                r.relative_error,
                c.error_bound,
                c.oracle_seconds,
                c.setup_seconds,
                cpu - oracle_cpu,
            );
            assert!(c.error_bound <= eps);
        }
    }
}
