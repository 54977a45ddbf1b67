//! The dense product with the condensed fault operator against its ℋ-matrix
//! (rsf-hmatrix, issue 37): `y ← y + S x` for the antiplane half-space kernel of a
//! vertical fault on N = 400 … 3200 cells at ε = 1e-6 (docs/scaling.md, "Compressed fault
//! operator (issue 37)"); and the ℋ-product of a fault plane the size of SEAS BP5's at
//! 1 km (101 × 41 nodes, two slip components, ε = 1e-4) on one and two threads
//! (docs/performance.md, "Row panels").

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, Par};
use rsf_hmatrix::kernels::AntiplaneHalfSpace;
use rsf_hmatrix::{HMatrix, HOptions, Points};
use rsf_programs::fit_exponent;
use std::hint::black_box;
use std::num::NonZeroUsize;

fn products(c: &mut Criterion) {
    let mut group = c.benchmark_group("fault_operator_product");
    let mut stored = Vec::new();
    for n in [400usize, 800, 1600, 3200] {
        // 40 km of fault, as in BP1 (Δz = 25 m at N = 1600).
        let kernel = AntiplaneHalfSpace::new(n, 40e3 / n as f64, 32.04e9).expect("kernel");
        let s = Mat::from_fn(n, n, |i, j| kernel.entry(i, j));
        let points = kernel.points();
        let mut h = HMatrix::from_dense(s.as_ref(), &points, &HOptions::with_epsilon(1e-6))
            .expect("compression");
        let r = h.report().clone();
        println!(
            "N = {n}: error {:.2e}, stored {} = {:.3} n², blocks {} dense + {} low-rank, rank max {} mean {:.1}",
            r.relative_error,
            r.stored_entries,
            r.memory_ratio(),
            r.dense_blocks,
            r.low_rank_blocks,
            r.max_rank,
            r.mean_rank
        );
        stored.push((n as f64, r.stored_entries as f64));
        let x = Col::from_fn(n, |i| ((i * 7919) % 1000) as f64 / 1000.0 - 0.5);
        let mut y = Col::<f64>::zeros(n);
        group.bench_with_input(BenchmarkId::new("dense", n), &n, |b, _| {
            b.iter(|| {
                matmul(
                    y.as_mat_mut(),
                    Accum::Add,
                    s.as_ref(),
                    x.as_mat(),
                    1.0,
                    Par::Seq,
                );
                black_box(&y);
            })
        });
        let xs: Vec<f64> = x.iter().copied().collect();
        let mut ys = vec![0.0; n];
        group.bench_with_input(BenchmarkId::new("hmatrix", n), &n, |b, _| {
            b.iter(|| {
                h.apply_add(&xs, &mut ys, 1.0, Par::Seq).expect("product");
                black_box(&ys);
            })
        });
    }
    group.finish();
    let slope = fit_exponent(&stored);
    println!("stored entries ~ N^{slope:.3} (least squares on log–log, N = 400 … 3200)");
}

/// A regularised `1/r³` interaction of two slip components on a 101 × 41 grid of nodes
/// 1 km apart (the BP5 fault's 100 km × 40 km at 1 km): `m = 8282` unknowns, each node's
/// two components interleaved, as the condensed operator of BP5's volume is held.
fn plane_products(c: &mut Criterion) {
    let (nx, nz, h) = (101usize, 41usize, 1e3);
    let nodes: Vec<[f64; 2]> = (0..nz)
        .flat_map(|k| (0..nx).map(move |i| [i as f64 * h, k as f64 * h]))
        .collect();
    let coords: Vec<f64> = nodes
        .iter()
        .flat_map(|p| [p[0], p[1], p[0], p[1]])
        .collect();
    let points = Points::new(&coords, 2).expect("points");
    let entry = |i: usize, j: usize| {
        let (p, q) = (nodes[i / 2], nodes[j / 2]);
        let r = [p[0] - q[0], p[1] - q[1]];
        let d2 = r[0] * r[0] + r[1] * r[1] + h * h;
        let (a, b) = (i % 2, j % 2);
        let delta = if a == b { 1.0 } else { 0.0 };
        3.2e10 / (4.0 * std::f64::consts::PI) * (delta - 1.5 * r[a] * r[b] / d2) / d2.powf(1.5)
    };
    let options = HOptions {
        components: 2,
        ..HOptions::with_epsilon(1e-4)
    };
    let mut h_mat = HMatrix::from_entries(entry, &points, &options).expect("compression");
    let r = h_mat.report().clone();
    let m = h_mat.dim();
    println!(
        "plane m = {m}: error {:.2e}, stored {} = {:.3} m², blocks {} dense + {} low-rank",
        r.relative_error,
        r.stored_entries,
        r.memory_ratio(),
        r.dense_blocks,
        r.low_rank_blocks
    );
    let x: Vec<f64> = (0..m)
        .map(|i| ((i * 7919) % 1000) as f64 / 1000.0 - 0.5)
        .collect();
    let mut y = vec![0.0; m];
    let mut group = c.benchmark_group("fault_plane_product");
    group.sample_size(30);
    for threads in [1usize, 2] {
        let par = match NonZeroUsize::new(threads) {
            Some(k) if threads > 1 => Par::Rayon(k),
            _ => Par::Seq,
        };
        group.bench_with_input(BenchmarkId::new("hmatrix", threads), &threads, |b, _| {
            b.iter(|| {
                h_mat.apply_add(&x, &mut y, 1.0, par).expect("product");
                black_box(&y);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, products, plane_products);
criterion_main!(benches);
