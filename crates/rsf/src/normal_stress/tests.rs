//! Tests of the normal-stress coupling: the dense `S_N` product's bits on the threads, and
//! the measurement of `S_N` dense against compressed.

use super::*;

/// Entries of order 1 with all their bits used (a seeded scramble), so that a sum in
/// another order rounds differently.
fn scrambled(i: usize, seed: u64) -> f64 {
    let mut x = (i as u64 ^ seed).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    x ^= x >> 29;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 32;
    (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// The dense `S_N` product split by rows over 1, 2, 3 and 4 threads (explicit rayon
/// pools) has the bits of the sequential column-by-column loop (the product before it
/// was split: `r = dg a`, then `r_k += S_N,ki du_i` over `i` in order), row by row;
/// rows summed in another order would differ in some rows (checked: the reversed
/// column order differs).
#[test]
fn the_dense_product_has_the_bits_of_the_column_loop_at_every_thread_count() {
    let (rows, m) = (97, 190);
    assert!(rows * m >= MIN_PARALLEL_ENTRIES);
    let s_n = Mat::from_fn(rows, m, |i, j| scrambled(i * m + j, 1) * 1e9);
    let u: Vec<f64> = (0..m).map(|i| scrambled(i, 2) * 1e-3).collect();
    let u0: Vec<f64> = (0..m).map(|i| scrambled(i, 3) * 1e-4).collect();
    let start: Vec<f64> = (0..rows).map(|k| scrambled(k, 4) * 1e5).collect();
    let mut column_loop = start.clone();
    for (i, (u, u0)) in u.iter().zip(&u0).enumerate() {
        let du = u - u0;
        for (s, c) in column_loop.iter_mut().zip(s_n.col(i).iter()) {
            *s += c * du;
        }
    }
    let mut reversed = start.clone();
    for i in (0..m).rev() {
        let du = u[i] - u0[i];
        for (k, s) in reversed.iter_mut().enumerate() {
            *s += s_n[(k, i)] * du;
        }
    }
    assert!(
        reversed
            .iter()
            .zip(&column_loop)
            .any(|(a, b)| a.to_bits() != b.to_bits()),
        "the order of the sum shows in the bits"
    );
    for threads in [1, 2, 3, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let r = pool.install(|| {
            let mut r = start.clone();
            add_dense_product(&s_n, &u, &u0, &mut r, Parallelism::rayon(threads));
            r
        });
        for (k, (a, b)) in r.iter().zip(&column_loop).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "{threads} threads, row {k}");
        }
    }
    // An empty u⁰ is zero.
    let mut r = start.clone();
    add_dense_product(&s_n, &u, &[], &mut r, Parallelism::SEQ);
    let mut expected = start;
    for (i, u) in u.iter().enumerate() {
        for (s, c) in expected.iter_mut().zip(s_n.col(i).iter()) {
            *s += c * u;
        }
    }
    assert_eq!(r, expected);
}

/// CPU seconds of the calling thread from /proc (Linux; 0 elsewhere), at the kernel's
/// 100 Hz tick.
fn thread_cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/stat")
        .ok()
        .and_then(|s| {
            // utime and stime: the 12th and 13th fields after the command name.
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<&str> = rest.split(' ').collect();
            let t = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
            Some(t / 100.0)
        })
        .unwrap_or(0.0)
}

/// Measurement (docs/three-d.md, "The normal-stress operator S_N"): the CPU per
/// evaluation and the memory of a 3-D dipping fault's `S_N`, dense and compressed. A
/// fault dipping 45° (`x = z`, `|y| ≤ 0.5`, from the free surface `z = 0` to depth
/// 0.5) in a box graded from the fault's spacing `h` (`RSF_SN_CELLS` cells per unit
/// length, default 32) at ratio 1.5 to 2 on every side, the faces `x = ±2` pushed
/// together; laws at σ̄_n⁰ = 5 MPa; ε = 1e-6 with the default leaf size.
///
/// `cargo test --release -p rsf --lib -- --ignored --nocapture
/// normal_stress::tests::measure_s_n_dense_and_compressed`
#[test]
#[ignore = "a measurement: minutes and GB"]
fn measure_s_n_dense_and_compressed() {
    use crate::model::{Material, ModelBuilder, Part};
    use rsf_fem::{cuboid_from_coordinates, geometric_grading};
    use rsf_friction::{AsinhLaw, RateStateParams};
    let cells: f64 = std::env::var("RSF_SN_CELLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(32.0);
    let (h, depth, far, ratio) = (1.0 / cells, 0.5, 2.0, 1.5);
    let margin = 4.0 * h;
    let neg = |c: Vec<f64>| -> Vec<f64> { c.iter().rev().map(|x| -x).collect() };
    let mut xs = neg(geometric_grading(h, depth + margin, ratio, far).unwrap());
    xs.extend_from_slice(&geometric_grading(h, margin, ratio, far).unwrap()[1..]);
    let mut ys = neg(geometric_grading(h, 0.5 + margin, ratio, far).unwrap());
    ys.extend_from_slice(&geometric_grading(h, 0.5 + margin, ratio, far).unwrap()[1..]);
    let zs = neg(geometric_grading(h, depth + margin, ratio, far).unwrap());
    let clock = Instant::now();
    let mesh = cuboid_from_coordinates(&xs, &ys, &zs).unwrap();
    let v = 1e-4;
    let model = ModelBuilder::new(mesh)
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("left", move |x| x[0] < -far + 1e-9),
            [v, 0.0, 0.0],
        )
        .dirichlet(
            Part::predicate("right", move |x| x[0] > far - 1e-9),
            [-v, 0.0, 0.0],
        )
        .internal_fault_polygon(
            "fault",
            &[
                [0.0, -0.5, 0.0],
                [-depth, -0.5, -depth],
                [-depth, 0.5, -depth],
                [0.0, 0.5, 0.0],
            ],
        )
        .build()
        .unwrap();
    let fb = &model.frictional_boundary;
    let n = model.num_dofs();
    let mut velocity_factor = vec![0.0; n];
    for (&dof, &f) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
        velocity_factor[dof] = f;
    }
    let mut cond =
        Condensation::<3>::new(model.stiffness.as_ref(), &model.fixed, &fb.nodes).unwrap();
    let m = cond.dim();
    let law = AsinhLaw::new(RateStateParams {
        mu0: 0.1,
        a: 0.015,
        b: 0.01,
        v0: 1e-6,
        l: 1e-4,
        sigma_n: 5e6,
    })
    .unwrap();
    let laws = vec![law; fb.len()];
    let s_n_clock = Instant::now();
    let mut coupling = NormalCoupling::new(
        NormalStress::FromSlip,
        &model,
        &mut cond,
        &laws,
        &velocity_factor,
        0.0,
    )
    .unwrap()
    .unwrap();
    let s_n_seconds = s_n_clock.elapsed().as_secs_f64();
    eprintln!(
        "h = 1/{cells}: {} vertices, {n} dofs, {} frictional nodes, m = {m}, factor \
         {:.3e} entries; model and condensation and S_N in {:.1} s (S_N's columns {:.1} s)",
        model.vertices.len(),
        fb.len(),
        cond.factor_nnz() as f64,
        clock.elapsed().as_secs_f64(),
        s_n_seconds
    );
    // Slips of up to 1 μm: σ̄_n changes by kPa, far from opening.
    let u: Vec<f64> = coupling
        .u_f0
        .iter()
        .enumerate()
        .map(|(i, u0)| u0 + 1e-6 * scrambled(i, 7))
        .collect();
    let mut sigma = vec![0.0; fb.len()];
    // Evaluations for about `seconds` of CPU; CPU and wall seconds per evaluation.
    let time = |c: &mut NormalCoupling, sigma: &mut [f64], par: Parallelism| {
        c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
        let probe = Instant::now();
        c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
        let reps = (2.0 / probe.elapsed().as_secs_f64().max(1e-7)).clamp(3.0, 1e6) as usize;
        let (cpu, wall) = (thread_cpu_seconds(), Instant::now());
        for _ in 0..reps {
            c.evaluate(0.0, 0.0, &u, sigma, par).unwrap();
        }
        (
            (thread_cpu_seconds() - cpu) / reps as f64,
            wall.elapsed().as_secs_f64() / reps as f64,
        )
    };
    let (dense_cpu, dense_wall) = time(&mut coupling, &mut sigma, Parallelism::SEQ);
    let dense_sigma = sigma.clone();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let (_, dense_wall_2) = pool.install(|| time(&mut coupling, &mut sigma, Parallelism::rayon(2)));
    assert_eq!(sigma, dense_sigma, "the same bits on 2 threads");
    let dense_bytes = 8 * fb.len() * m;
    eprintln!(
        "dense S_N: {} × {m} = {} f64 ({:.1} MB); per evaluation {:.3} ms CPU, {:.3} ms \
         wall (1 thread), {:.3} ms wall (2 threads)",
        fb.len(),
        fb.len() * m,
        dense_bytes as f64 / 1e6,
        dense_cpu * 1e3,
        dense_wall * 1e3,
        dense_wall_2 * 1e3
    );
    let report = coupling
        .compress(&model, &cond, FaultKernel::hierarchical(1e-6))
        .unwrap()
        .expect("compressed");
    let (h_cpu, h_wall) = time(&mut coupling, &mut sigma, Parallelism::SEQ);
    let (_, h_wall_2) = pool.install(|| time(&mut coupling, &mut sigma, Parallelism::rayon(2)));
    let change: f64 = dense_sigma
        .iter()
        .map(|s| (s - 5e6).powi(2))
        .sum::<f64>()
        .sqrt();
    let diff: f64 = dense_sigma
        .iter()
        .zip(&sigma)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    eprintln!(
        "compressed S_N: {report}\n  {} f64 ({:.1} MB, {:.2}× fewer than the dense S_N); \
         per evaluation {:.3} ms CPU, {:.3} ms wall (1 thread), {:.3} ms wall (2 threads); \
         ‖Δσ_H − Δσ‖/‖Δσ‖ = {:.2e} at a random slip",
        report.stored_entries,
        report.bytes() as f64 / 1e6,
        (fb.len() * m) as f64 / report.stored_entries as f64,
        h_cpu * 1e3,
        h_wall * 1e3,
        h_wall_2 * 1e3,
        diff / change
    );
}
