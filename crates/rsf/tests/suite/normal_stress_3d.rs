//! The slip → normal-traction operator `S_N` of a 3-D fault inside the body
//! (`NormalStress::FromSlip`, docs/faults-inside.md "Normal stress", docs/three-d.md):
//! compressed with a hierarchical kernel (embedded in `m × m`, one point per slip
//! unknown) against the dense one, entry by entry and along a run, and the dense product
//! on 1, 2 and 4 threads.
use crate::common::within;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions};
use rsf::fem::cuboid;
use rsf::friction::AsinhLaw;
use rsf::normal_stress::NormalStress;
use rsf::state::Aging;
use rsf::{FaultOde, Flow, Material, Model, ModelBuilder, Observer, Part, StepView, Stepping};

use crate::normal_stress::SIGMA_N;

/// `[-1, 1]² × [-1, 0]` (the top a free surface) of `cells` coarse vertices per axis
/// (`x` and `z` at the same spacing, so that the plane `x = z` runs along faces) refined
/// once, with a fault on `x = z` dipping 45° from its trace `x = z = 0, |y| ≤ 0.5` on the
/// surface to depth 0.5, the faces `x = ±1` pushed together (left +v, right −v): reverse
/// slip, which changes the normal stress.
pub(crate) fn dipping_fault(cells: [usize; 3]) -> Model<3> {
    let v = 1e-4;
    let mesh = cuboid([-1.0, -1.0, -1.0], [2.0, 2.0, 1.0], cells).unwrap();
    ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("left", |x| x[0] < -1.0 + 1e-9),
            [v, 0.0, 0.0],
        )
        .dirichlet(
            Part::predicate("right", |x| x[0] > 1.0 - 1e-9),
            [-v, 0.0, 0.0],
        )
        .internal_fault_polygon(
            "fault",
            &[
                [0.0, -0.5, 0.0],
                [-0.5, -0.5, -0.5],
                [-0.5, 0.5, -0.5],
                [0.0, 0.5, 0.0],
            ],
        )
        .build()
        .unwrap()
}

/// The fault ODE on `model` (regularised law, aging law, steady state at 1e-4 m/s,
/// radiation damping μ/(2c_s), σ̄_n from slip) at tolerance 1e-9 with `kernel` on
/// `threads` threads.
pub(crate) fn fault_ode(
    model: Model<3>,
    kernel: FaultKernel,
    threads: usize,
) -> FaultOde<3, AsinhLaw, Aging> {
    crate::normal_stress::quasi_dynamic(model, NormalStress::FromSlip)
        .time_step(1e-3)
        .build_fault_ode(FaultOdeOptions {
            tolerance: 1e-9,
            kernel,
            parallelism: rsf::Parallelism::rayon(threads),
            ..Default::default()
        })
        .unwrap()
}

/// The dofs of the condensed slip unknowns: every frictional node's free components, node
/// by node (the condensation's order).
fn slip_dofs(model: &Model<3>) -> Vec<usize> {
    model
        .frictional_boundary
        .nodes
        .iter()
        .flat_map(|&p| (3 * p..3 * p + 3).filter(|&d| !model.fixed[d]))
        .collect()
}

/// `S_N` (`nodes × m`, N/m, row-major) as the fault ODE applies it, column by column: the
/// change of the reactions `w_k (σ̄_n⁰ − σ̄_n,k)` at `t = 0` (no loading) when slip
/// unknown `j` moves by `delta` (m) from the initial state, divided by `delta`.
fn probed_s_n(ode: &mut FaultOde<3, AsinhLaw, Aging>, delta: f64) -> Vec<Vec<f64>> {
    let model = ode.model().clone();
    let weights = &model.frictional_boundary.weights;
    let dofs = slip_dofs(&model);
    assert_eq!(dofs.len(), ode.condensed_dim());
    let start = ode.state().clone();
    let mut s_n = vec![vec![0.0; dofs.len()]; weights.len()];
    for (j, &dof) in dofs.iter().enumerate() {
        let mut state = start.clone();
        state.kinematics.u[dof] += delta;
        ode.restart_from(&state, 1e-3).unwrap();
        let tractions = ode.fault_tractions();
        for (k, row) in s_n.iter_mut().enumerate() {
            let sigma = tractions.normal_traction(k).unwrap();
            row[j] = (SIGMA_N - sigma) * weights[k] / delta;
        }
    }
    s_n
}

/// The hierarchical kernel at accuracy `epsilon`, leaves of 8 nodes.
fn hierarchical(epsilon: f64) -> FaultKernel {
    FaultKernel::Hierarchical {
        epsilon,
        leaf_size: 8,
    }
}

/// On a dipping 3-D fault the compressed `S_N` (the ℋ-matrix of its `m × m` embedding,
/// node `k`'s row read back from its first slip unknown's) is the dense `S_N` to ε:
/// `‖S_N,H − S_N‖_F/‖S_N‖_F` measured over every entry (each column probed through the
/// fault ODE's normal stress) is at most 2ε and matches the set-up's sampled estimate.
/// A row read back from the wrong unknown (another node's, or the zero row of the second
/// component) is an error of order 1.
#[test]
fn a_compressed_3d_normal_stress_operator_is_the_dense_one_to_its_accuracy() {
    let model = dipping_fault([9, 65, 5]);
    let epsilon = 1e-6;
    let kernel = hierarchical(epsilon);
    let mut dense = fault_ode(model.clone(), FaultKernel::Dense, 1);
    let mut compressed = fault_ode(model.clone(), kernel, 1);
    assert!(dense.normal_kernel_report().is_none());
    let report = compressed
        .normal_kernel_report()
        .expect("S_N compressed")
        .clone();
    let m = compressed.condensed_dim();
    let nodes = model.frictional_boundary.len();
    eprintln!("{nodes} frictional nodes, m = {m}; S_N: {report}");
    assert_eq!(m, 2 * nodes);
    assert_eq!(report.dim, m);
    assert!(report.low_rank_blocks > 0, "nothing compressed: {report}");
    assert!(report.relative_error <= epsilon, "{report}");
    // Slips of 1 μm change σ̄_n by at most a few kPa of 5 MPa: far from opening, and the
    // reactions come back with ~1e-16 · 5 MPa / (kPa) relative round-off.
    let delta = 1e-6;
    let exact = probed_s_n(&mut dense, delta);
    let approx = probed_s_n(&mut compressed, delta);
    let (mut e2, mut s2, mut largest) = (0.0, 0.0, 0.0f64);
    for (a, b) in exact.iter().flatten().zip(approx.iter().flatten()) {
        e2 += (a - b) * (a - b);
        s2 += a * a;
        largest = largest.max(a.abs());
    }
    let error = (e2 / s2).sqrt();
    let change = largest * delta / model.frictional_boundary.weights[0];
    eprintln!(
        "‖S_N,H − S_N‖_F/‖S_N‖_F = {error:.3e} (ε = {epsilon:e}, estimated {:.3e}); \
         largest entry {largest:.3e} N/m (a change of σ̄_n near {change:.1e} Pa)",
        report.relative_error
    );
    assert!(s2 > 0.0);
    assert!(error <= 2.0 * epsilon, "{error:e}");
    // The set-up's estimate (sampled entries of each component's block) is of the same
    // size: the blocks' errors are weighed as they should be.
    let estimate = report.relative_error;
    assert!(
        error <= 10.0 * estimate && estimate <= 10.0 * error,
        "{estimate:e}"
    );
}

/// Per stop: the normal stress of every frictional node.
#[derive(Default)]
struct NormalStresses(Vec<Vec<f64>>);

impl Observer<3> for NormalStresses {
    fn observe(&mut self, s: &StepView<'_, 3, 3>) -> rsf::Result<Flow> {
        let n = s.model.frictional_boundary.len();
        let sigma = (0..n).map(|k| s.normal_traction(k).unwrap()).collect();
        match self.0.last_mut() {
            Some(last) => *last = sigma,
            None => self.0.push(sigma),
        }
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

/// σ̄_n of every frictional node at `stops` (s), one row per stop.
fn normal_stress_at(ode: &mut FaultOde<3, AsinhLaw, Aging>, stops: &[f64]) -> Vec<Vec<f64>> {
    let mut rows = Vec::new();
    for &t in stops {
        let mut record = NormalStresses::default();
        rsf::run_until(ode, within(t), &mut [&mut record]).unwrap();
        rows.push(record.0.pop().unwrap());
    }
    rows
}

/// A fault-ODE run on a dipping 3-D fault with the hierarchical kernel (S and S_N
/// compressed at ε) follows the dense kernel's normal stress to within a multiple of ε
/// of its change, which is far larger: σ̄_n at five times over 3 s.
#[test]
fn a_3d_run_with_compressed_operators_follows_the_dense_normal_stress() {
    let model = dipping_fault([9, 65, 5]);
    let epsilon = 1e-6;
    let kernel = hierarchical(epsilon);
    let stops = [0.6, 1.2, 1.8, 2.4, 3.0];
    let dense = normal_stress_at(&mut fault_ode(model.clone(), FaultKernel::Dense, 1), &stops);
    let mut ode = fault_ode(model, kernel, 1);
    assert!(ode.normal_kernel_report().is_some());
    let compressed = normal_stress_at(&mut ode, &stops);
    let (mut change, mut difference) = (0.0f64, 0.0f64);
    for (d, c) in dense.iter().flatten().zip(compressed.iter().flatten()) {
        change = change.max((d - SIGMA_N).abs());
        difference = difference.max((d - c).abs());
    }
    eprintln!(
        "largest change of σ̄_n {change:.3e} Pa; largest difference compressed − dense \
         {difference:.3e} Pa ({:.2e} of the change, ε = {epsilon:e})",
        difference / change
    );
    assert!(change > 1e-3 * SIGMA_N, "{change:e}");
    assert!(difference <= 100.0 * epsilon * change, "{difference:e}");
}

/// With the dense `S_N` (split by rows over the threads) the normal stress of a run on a
/// dipping 3-D fault has the same bits at 1, 2 and 4 threads (explicit rayon pools), and
/// the run the same evaluations. (The subtraction `σ̄_n⁰ − r/w` often absorbs the last
/// bit of a reaction `r` summed in another order: the product's own bits are checked
/// against the column-by-column loop in rsf's unit test
/// `normal_stress::tests::the_dense_product_has_the_bits_of_the_column_loop_at_every_thread_count`.)
#[test]
fn the_dense_3d_normal_stress_has_the_same_bits_at_1_2_and_4_threads() {
    let model = dipping_fault([9, 17, 5]);
    let nodes = model.frictional_boundary.len();
    // Large enough for the product to split (4096 entries and more).
    assert!(nodes * 2 * nodes >= 4096, "{nodes}");
    let stops = [0.5, 1.0];
    let run = |threads: usize| {
        crate::common::on_threads(threads, || {
            let mut ode = fault_ode(model.clone(), FaultKernel::Dense, threads);
            let rows = normal_stress_at(&mut ode, &stops);
            (rows, ode.evaluations())
        })
    };
    let (one, evaluations) = run(1);
    for threads in [2, 4] {
        let (other, e) = run(threads);
        assert_eq!(e, evaluations, "{threads} threads");
        for (a, b) in one.iter().flatten().zip(other.iter().flatten()) {
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "{threads} threads: {a:e} against {b:e}"
            );
        }
    }
}
