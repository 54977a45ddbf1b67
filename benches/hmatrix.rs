//! The dense product with the condensed fault operator against its ℋ-matrix
//! (rsf-hmatrix, issue 37): `y ← y + S x` for the antiplane half-space kernel of a
//! vertical fault on N = 400 … 3200 cells at ε = 1e-6 (docs/scaling.md, "Compressed fault
//! operator (issue 37)").

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use faer::linalg::matmul::matmul;
use faer::{Accum, Col, Mat, Par};
use rsf_hmatrix::kernels::AntiplaneHalfSpace;
use rsf_hmatrix::{HMatrix, HOptions};
use rsf_programs::fit_exponent;
use std::hint::black_box;

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

criterion_group!(benches, products);
criterion_main!(benches);
