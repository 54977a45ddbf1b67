//! rsf-fem on the paper's slider mesh (5 m × 1 m, levels 4..8; level 8 ≈ 330 000 vertices):
//! pattern construction, numeric assembly of M and K (shared pattern, no per-element
//! allocation), and one sparse Cholesky factorisation + solve of the Newmark matrix
//! A = (2/τ)M + (τ/2)K with Dirichlet conditions on the top edge.
//!
//! Run: `cargo bench --bench fem_assembly` (optionally a filter, e.g. `level8`).
//! Each level also prints one-shot wall times and the process's peak resident memory
//! (VmHWM) to stderr. Numbers and machine: `docs/fem.md`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rsf_fem::{
    combine, pipping_slider_coarse, Assembler, BoundarySegment, ConstrainedSystem, Constraints,
    Diagonal, LinearElasticity, MeshHierarchy, SparseMatrix, TriangleMesh, TAG_DIRICHLET,
};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// The process's peak resident memory (MiB; NaN where the system does not say).
fn peak_rss_mib() -> f64 {
    rsf_programs::memory::peak_bytes().map_or(f64::NAN, |b| b as f64 / (1024.0 * 1024.0))
}

/// Assembles the mass `m` (density `rho`) and the stiffness `k` (material `mat`) of `mesh`
/// into their shared pattern.
fn assemble_mass_and_stiffness(
    asm: &Assembler<2>,
    mesh: &TriangleMesh,
    (rho, mat): (f64, &LinearElasticity),
    (m, k): (&mut SparseMatrix, &mut SparseMatrix),
) {
    asm.assemble_into(mesh, m, |_, vol, loc| {
        rsf_fem::element::p1_mass::<2>(vol, rho, loc)
    })
    .unwrap();
    asm.assemble_into(mesh, k, |gr, vol, loc| {
        rsf_fem::element::p1_stiffness::<2>(gr, vol, mat, loc)
    })
    .unwrap();
}

fn levels() -> std::ops::RangeInclusive<usize> {
    let max = std::env::var("RSF_BENCH_MAX_LEVEL")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(8);
    4..=max
}

fn bench(c: &mut Criterion) {
    let max = *levels().end();
    let t = Instant::now();
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), max);
    eprintln!(
        "hierarchy 0..={max}: {:.3} s, peak RSS {:.0} MiB",
        t.elapsed().as_secs_f64(),
        peak_rss_mib()
    );
    let mat = LinearElasticity::plane_strain(5e7, 0.3).unwrap();
    let (rho, tau) = (5e3, 15.0 / 1e4);
    let mut g = c.benchmark_group("fem");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for level in levels() {
        let mesh = h.level(level);
        let nv = mesh.num_vertices();
        g.throughput(Throughput::Elements(nv as u64));
        let id = |name: &str| BenchmarkId::new(name, format!("level{level}"));

        let t = Instant::now();
        let asm = Assembler::new(mesh).unwrap();
        let t_pattern = t.elapsed().as_secs_f64();
        let mut m = asm.zeros();
        let mut k = asm.zeros();
        let t = Instant::now();
        assemble_mass_and_stiffness(&asm, mesh, (rho, &mat), (&mut m, &mut k));
        let t_assembly = t.elapsed().as_secs_f64();
        let top = BoundarySegment::from_tag(mesh, TAG_DIRICHLET).unwrap();
        let mut con = Constraints::<2>::new(nv);
        con.fix_nodes(top.nodes(), &[0, 1], [0.0, 0.0]).unwrap();
        let a = combine(2.0 / tau, &m, 0.5 * tau, &k).unwrap();
        let b: Vec<f64> = (0..2 * nv).map(|i| (i as f64 * 0.37).sin()).collect();
        let t = Instant::now();
        let mut sys = ConstrainedSystem::new(a.as_ref(), con.fixed()).unwrap();
        let t_analyze_factor = t.elapsed().as_secs_f64();
        let mut x = vec![0.0; 2 * nv];
        let t = Instant::now();
        sys.refactorize(a.as_ref()).unwrap();
        let t_factor = t.elapsed().as_secs_f64();
        let t = Instant::now();
        sys.solve(&b, &mut x).unwrap();
        let t_solve = t.elapsed().as_secs_f64();
        eprintln!(
            "level {level}: {nv} vertices, {} cells, {} dofs, nnz(A) {}, nnz(L) {}; one-shot: \
             pattern {t_pattern:.4} s, M+K {t_assembly:.4} s, analyse+factor {t_analyze_factor:.4} s, \
             refactor {t_factor:.4} s, solve {t_solve:.4} s; peak RSS {:.0} MiB",
            mesh.num_cells(),
            2 * nv,
            a.val().len(),
            sys.cholesky().factor_nnz(),
            peak_rss_mib()
        );

        g.bench_function(id("pattern"), |bch| {
            bch.iter(|| black_box(Assembler::new(mesh).unwrap()))
        });
        g.bench_function(id("assemble_M_K"), |bch| {
            bch.iter(|| {
                assemble_mass_and_stiffness(&asm, mesh, (rho, &mat), (&mut m, &mut k));
                black_box((&m, &k));
            })
        });
        g.bench_function(id("cholesky_analyse_factor_solve"), |bch| {
            bch.iter(|| {
                let mut s = ConstrainedSystem::new(a.as_ref(), con.fixed()).unwrap();
                s.solve(&b, &mut x).unwrap();
                black_box(&x);
            })
        });
        g.bench_function(id("cholesky_refactor_solve"), |bch| {
            bch.iter(|| {
                sys.refactorize(a.as_ref()).unwrap();
                sys.solve(&b, &mut x).unwrap();
                black_box(&x);
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
