//! Throughput of the pointwise kernels of rsf-friction and rsf-state:
//! state updates per second (closed form vs the generic safeguarded Newton/bisection) and
//! exact local-minimiser calls per second for each potential.
//!
//! Run: `cargo bench --bench friction_state`; numbers in `docs/friction-state.md`.

use criterion::measurement::WallTime;
use criterion::{
    criterion_group, criterion_main, BenchmarkGroup, BenchmarkId, Criterion, Throughput,
};
use rsf_friction::{
    AsinhLaw, ConvexPotential, DieterichRuina, FrictionLaw, RateStateParams, Tresca,
};
use rsf_state::{generic_update, Aging, Discontinuous, Slip, StateLaw};
use std::hint::black_box;
use std::time::Duration;

const N: usize = 1024;

/// Deterministic pseudo-random numbers in [0, 1) (no extra dependency).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// (α_prev, V, τ): α ∈ [−20, 20], V log-uniform in [1e-12, 1e-1] m/s, τ log-uniform in
/// [1e-6, 1e-2] s — the range a simulation of the paper's model visits.
fn state_inputs() -> Vec<(f64, f64, f64)> {
    let mut s = 7;
    (0..N)
        .map(|_| {
            let alpha = -20.0 + 40.0 * lcg(&mut s);
            let v = 10f64.powf(-12.0 + 11.0 * lcg(&mut s));
            let tau = 10f64.powf(-6.0 + 4.0 * lcg(&mut s));
            (alpha, v, tau)
        })
        .collect()
}

fn bench_law<S: StateLaw>(c: &mut Criterion, name: &str, law: &S, inputs: &[(f64, f64, f64)]) {
    let mut group = c.benchmark_group("state_update");
    group.throughput(Throughput::Elements(inputs.len() as u64));
    group.bench_function(BenchmarkId::new(name, "closed_form"), |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &(a, v, t) in inputs {
                acc += law.update(black_box(a), v, t).unwrap();
            }
            acc
        })
    });
    group.bench_function(BenchmarkId::new(name, "generic"), |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &(a, v, t) in inputs {
                acc += generic_update(law, black_box(a), v, t).unwrap();
            }
            acc
        })
    });
    group.finish();
}

fn state_updates(c: &mut Criterion) {
    let inputs = state_inputs();
    bench_law(c, "aging", &Aging::new(1e-5).unwrap(), &inputs);
    bench_law(c, "slip", &Slip::new(1e-5).unwrap(), &inputs);
    // Discontinuous law: α = θ around 1/V.
    let disc: Vec<_> = inputs
        .iter()
        .map(|&(a, v, t)| ((1.0 + 0.1 * a) / v, v, t))
        .collect();
    bench_law(c, "discontinuous", &Discontinuous, &disc);
}

/// The local problems `(ϕ, a, r, w)` of `cases` `(α, a, r, w)`, `ϕ` `law`'s potential at
/// `α`.
fn problems<L: FrictionLaw>(
    law: &L,
    cases: &[(f64, f64, f64, f64)],
) -> Vec<(L::Potential, f64, f64, f64)> {
    cases
        .iter()
        .map(|c| (law.potential(c.0), c.1, c.2, c.3))
        .collect()
}

/// The benchmark `name` of `group`: the exact local minimiser on every one of `problems`
/// (their minimisers summed).
fn bench_minimize<P: ConvexPotential>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    problems: &[(P, f64, f64, f64)],
) {
    group.bench_function(name, |b| {
        b.iter(|| {
            problems
                .iter()
                .map(|(p, a, r, w)| p.minimize(*a, black_box(*r), *w))
                .sum::<f64>()
        })
    });
}

/// Local problems `argmin ½ a s² − r s + w ϕ(s)` with the paper's parameters: α ∈ [−20, 20],
/// `a` ∈ [1e6, 1e12], `r` log-uniform in [1e-3, 1e5] Pa (sticking and slipping nodes).
fn minimizers(c: &mut Criterion) {
    let p = RateStateParams {
        mu0: 0.6,
        a: 0.010,
        b: 0.015,
        v0: 1e-6,
        l: 1e-5,
        sigma_n: 49_050.0,
    };
    let dr = DieterichRuina::new(p).unwrap();
    let asl = AsinhLaw::new(p).unwrap();
    let tr = Tresca::new(0.6, 49_050.0).unwrap();
    let mut s = 11;
    let cases: Vec<(f64, f64, f64, f64)> = (0..N)
        .map(|_| {
            let alpha = -20.0 + 40.0 * lcg(&mut s);
            let a = 10f64.powf(6.0 + 6.0 * lcg(&mut s));
            let r = 10f64.powf(-3.0 + 8.0 * lcg(&mut s));
            (alpha, a, r, 0.2)
        })
        .collect();
    let dr_p = problems(&dr, &cases);

    let mut group = c.benchmark_group("local_minimizer");
    group.throughput(Throughput::Elements(N as u64));
    bench_minimize(&mut group, "dieterich_ruina", &dr_p);
    bench_minimize(&mut group, "asinh", &problems(&asl, &cases));
    bench_minimize(&mut group, "tresca", &problems(&tr, &cases));
    group.bench_function("dieterich_ruina_vector_2d", |b| {
        b.iter(|| {
            dr_p.iter()
                .map(|(p, a, r, w)| p.minimize_vector(*a, [black_box(*r) * 0.6, *r * 0.8], *w)[0])
                .sum::<f64>()
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = state_updates, minimizers
}
criterion_main!(benches);
