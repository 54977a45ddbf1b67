//! A fault ODE's evaluations shared by ranks (`FaultOde::share_evaluations`, docs/scaling.md
//! "Past one machine"): the same bits at every rank count and as unshared. The ranks here
//! are threads of this process with an all-gather through shared memory (a test double of
//! an MPI communicator; the `rsf-mpi` crate's tests run the same on MPI processes).

use rsf::fault_ode::FaultKernel;
use rsf::observe::SECONDS_PER_YEAR;
use rsf::{Flow, Observer, StepView, Until};
use rsf_ranks::{Processes, ThreadProcess};

use crate::common::{small_bp1_and_fine_grid, within, H_LEAF_8};

/// BP3's grid of the rank tests: Δx = 2 km in a domain of 100 km.
const BP3_2KM: rsf_scenes::SeasBp3Grid = rsf_scenes::SeasBp3Grid {
    dx: 2000.0,
    domain: 100e3,
    ratio: 1.2,
};

/// Every accepted step's time, step size and the bits of the fault's slip and state.
#[derive(Default)]
struct Bits(Vec<Vec<u64>>);

impl<const D: usize, const C: usize> Observer<D, C> for Bits {
    fn observe(&mut self, s: &StepView<'_, D, C>) -> rsf::Result<Flow> {
        let mut row = vec![s.state.time.to_bits(), s.state.tau.to_bits()];
        for &p in &s.model.frictional_boundary.nodes {
            row.extend((0..C).map(|c| s.state.kinematics.u[C * p + c].to_bits()));
        }
        row.extend(s.state.alpha.iter().map(|a| a.to_bits()));
        self.0.push(row);
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

/// `ode` shared by `ranks` (if any) run to `until`: every accepted step's bits.
fn run_shared<const D: usize, L, S, const C: usize>(
    mut ode: rsf::FaultOde<D, L, S, C>,
    ranks: Option<ThreadProcess>,
    until: Until,
) -> Vec<Vec<u64>>
where
    L: rsf::friction::FrictionLaw,
    S: rsf::state::StateLaw,
{
    if let Some(ranks) = ranks {
        let (rank, size) = (ranks.rank(), ranks.size());
        ode.share_evaluations(ranks.group()).unwrap();
        assert_eq!(ode.rank_and_size(), (rank, size));
    }
    let mut bits = Bits::default();
    ode.run_until(until, &mut [&mut bits]).unwrap();
    bits.0
}

/// Runs `run` unshared, then on 1, 2, 3 and 4 thread ranks (each rank its own run), and
/// checks that every rank's rows have the unshared bits; returns the unshared rows.
fn same_bits_on_ranks(run: impl Fn(Option<ThreadProcess>) -> Vec<Vec<u64>> + Sync) -> usize {
    let alone = run(None);
    assert!(alone.len() > 10, "{} steps", alone.len());
    for size in 1..=4 {
        let rows: Vec<Vec<Vec<u64>>> = std::thread::scope(|s| {
            let handles: Vec<_> = ThreadProcess::job(size)
                .into_iter()
                .map(|ranks| s.spawn(|| run(Some(ranks))))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (rank, r) in rows.iter().enumerate() {
            assert_eq!(r.len(), alone.len(), "rank {rank} of {size}: steps");
            for (k, (a, b)) in r.iter().zip(&alone).enumerate() {
                assert_eq!(a, b, "rank {rank} of {size}: step {k} differs");
            }
        }
    }
    alone.len()
}

/// BP1 at Δz = 100 m (m = 100) for 20 years with the ℋ-kernel at leaf size 8 (up to 4
/// parts of the rows) and with the dense kernel (its rows in blocks of 8).
#[test]
fn a_bp1_fault_has_the_same_bits_on_1_to_4_ranks() {
    let (bp1, _, grid) = small_bp1_and_fine_grid();
    for kernel in [H_LEAF_8, FaultKernel::Dense] {
        let steps = same_bits_on_ranks(|ranks| {
            let model = bp1.model(&grid, false).unwrap();
            let options = rsf::fault_ode::FaultOdeOptions {
                kernel,
                ..bp1.fault_ode_options(1e-6).unwrap()
            };
            let ode = bp1.fault_ode(model, options).unwrap();
            run_shared(ode, ranks, within(20.0 * SECONDS_PER_YEAR))
        });
        eprintln!("BP1, m = 100, {kernel:?}: {steps} steps with the same bits on 1–4 ranks");
    }
}

/// The quasi-dynamic buried 3-D fault of `internal_fault_3d` with the ℋ-kernel at leaf size
/// 4 (two slip components per node, kept in one leaf and so in one part) for 3 s.
#[test]
fn a_3d_fault_has_the_same_bits_on_1_to_4_ranks() {
    let steps = same_bits_on_ranks(|ranks| {
        let ode = crate::internal_fault_3d::quasi_dynamic()
            .time_step(1e-3)
            .build_fault_ode(rsf::fault_ode::FaultOdeOptions {
                tolerance: 1e-9,
                kernel: FaultKernel::Hierarchical {
                    epsilon: 1e-2,
                    leaf_size: 4,
                },
                ..Default::default()
            })
            .unwrap();
        run_shared(ode, ranks, within(3.0))
    });
    eprintln!("3-D internal fault: {steps} steps with the same bits on 1–4 ranks");
}

/// SEAS BP3 (a thrust fault dipping 60° under the free surface: the normal stress changes
/// with slip, each rank summing its rows of `S_N`) at Δx = 2 km with the ℋ-kernel at leaf
/// size 8 (`S_N` an ℋ-matrix too, its rows by leaf clusters) and with the dense kernel
/// (its rows in contiguous blocks), for 1500 steps; every shared evaluation makes two
/// all-gathers, the reactions' (one per node) and the rates'.
#[test]
fn a_bp3_thrust_fault_with_a_normal_stress_from_slip_has_the_same_bits_on_1_to_4_ranks() {
    use rsf_scenes::SeasBp3;
    let bp3 = SeasBp3::thrust();
    let grid = BP3_2KM;
    let hierarchical = FaultKernel::Hierarchical {
        epsilon: 1e-7,
        leaf_size: 8,
    };
    for kernel in [hierarchical, FaultKernel::Dense] {
        let steps = same_bits_on_ranks(|ranks| {
            let model = bp3.model(&grid).unwrap();
            let mut options = bp3.params.fault_ode_options(1e-7).unwrap();
            options.runge_kutta.dt_min = 1e-8;
            options.kernel = kernel;
            let mut ode = bp3.fault_ode(model, options).unwrap();
            let nodes = ode.model().frictional_boundary.len();
            let Some(ranks) = ranks else {
                return run_shared(ode, None, Until::Steps(1500));
            };
            let size = ranks.size();
            ode.share_evaluations(ranks.group()).unwrap();
            let mut bits = Bits::default();
            ode.run_until(Until::Steps(1500), &mut [&mut bits]).unwrap();
            let e = ode.exchanges().unwrap();
            let evaluations = ode.evaluations() as u64;
            assert_eq!(e.ranks, size);
            assert_eq!(
                e.all_gathers,
                2 * evaluations,
                "{e:?}, {evaluations} evaluations"
            );
            // Each rank receives every rate and every reaction.
            assert!(e.values > nodes as u64 * evaluations, "{e:?}");
            bits.0
        });
        eprintln!("BP3 thrust, 2 km, {kernel:?}: {steps} steps with the same bits on 1–4 ranks");
    }
}

/// The mesh of `bp3` on `grid` with its vertices numbered in a scrambled order (vertex
/// `i` becomes `(i · 7919) mod n`): the frictional nodes, in vertex order, are then not in
/// the order of their positions along the fault — nor in the ℋ-matrix's cluster order.
fn scrambled_bp3_model(bp3: &rsf_scenes::SeasBp3, grid: &rsf_scenes::SeasBp3Grid) -> rsf::Model<2> {
    let mesh = bp3.mesh(grid).unwrap();
    let n = mesh.num_vertices();
    assert!(n % 7919 != 0);
    let new = |i: usize| (i * 7919) % n;
    let mut vertices = vec![[0.0; 2]; n];
    for (i, v) in mesh.vertices().iter().enumerate() {
        vertices[new(i)] = *v;
    }
    let cells = mesh.cells().iter().map(|&i| new(i)).collect();
    let mesh = rsf::fem::TriangleMesh::new(vertices, cells).unwrap();
    bp3.model_on(mesh, grid).unwrap()
}

/// BP3's normal stress from slip shared by ranks where the frictional nodes are not in
/// the ℋ-matrix's cluster order (the mesh numbered in a scrambled order): each rank's
/// reactions read the loading at their own nodes (node order), not at their rows'
/// positions in cluster order — the unshared bits on 1–4 ranks. (Issue 74: with the nodes
/// in cluster order, as in the test above, reading the loading in cluster order went
/// unnoticed.)
#[test]
fn bp3_with_its_nodes_out_of_cluster_order_has_the_same_bits_on_1_to_4_ranks() {
    use rsf_scenes::SeasBp3;
    let bp3 = SeasBp3::thrust();
    let grid = BP3_2KM;
    let model = scrambled_bp3_model(&bp3, &grid);
    // The nodes out of order along the fault (not monotone in x_d): the ℋ-matrix's cluster
    // order, by position, is not theirs.
    let x_d: Vec<f64> = model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| bp3.x_d(&model.vertices[p]))
        .collect();
    let ups = x_d.windows(2).filter(|w| w[1] > w[0]).count();
    assert!(ups > 0 && ups + 1 < x_d.len(), "{x_d:?}");
    let steps = same_bits_on_ranks(|ranks| {
        let mut options = bp3.params.fault_ode_options(1e-7).unwrap();
        options.runge_kutta.dt_min = 1e-8;
        options.kernel = FaultKernel::Hierarchical {
            epsilon: 1e-7,
            leaf_size: 8,
        };
        let ode = bp3.fault_ode(model.clone(), options).unwrap();
        run_shared(ode, ranks, Until::Steps(300))
    });
    eprintln!("BP3 thrust, scrambled nodes: {steps} steps with the same bits on 1–4 ranks");
}

/// A slip that opens the fault (the thrust block of `normal_stress` pulled apart, `S_N`
/// dense): each rank sums its rows of `S_N`, every rank finds the same first node with
/// σ̄_n ≤ 0, refuses the same stages and ends with the unshared run's error, after the
/// unshared run's steps.
#[test]
fn an_opening_fault_ends_every_rank_with_the_unshared_error() {
    use rsf::normal_stress::NormalStress;
    let run = |ranks: Option<ThreadProcess>| {
        let model = crate::normal_stress::pulled_apart_block();
        let mut ode = crate::normal_stress::fault_ode(model, NormalStress::FromSlip).unwrap();
        if let Some(ranks) = ranks {
            ode.share_evaluations(ranks.group()).unwrap();
        }
        let mut bits = Bits::default();
        let e = ode.run_until(within(10.0), &mut [&mut bits]).unwrap_err();
        let text = format!("{e}: {}", e.error);
        (bits.0, text, ode.exchanges())
    };
    let (alone, error, _) = run(None);
    assert!(error.contains("normal stress"), "{error}");
    for size in 1..=4 {
        let runs: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = ThreadProcess::job(size)
                .into_iter()
                .map(|ranks| s.spawn(|| run(Some(ranks))))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (rank, (bits, text, exchanges)) in runs.iter().enumerate() {
            assert_eq!(bits, &alone, "rank {rank} of {size}: steps");
            assert_eq!(text, &error, "rank {rank} of {size}");
            assert!(exchanges.unwrap().all_gathers > 0, "rank {rank} of {size}");
        }
    }
    eprintln!("{} steps, then on every rank: {error}", alone.len());
}

/// SEAS BP5 at Δx = 4 km (a fault alone, 500 cells, two slip components each) with
/// Okada's half-space operator, dense (its rows in blocks of 8) and as an ℋ-matrix of leaf
/// size 16 (an element's two rows in one leaf), for 150 steps.
#[test]
fn a_bp5_fault_with_the_half_space_operator_has_the_same_bits_on_1_to_4_ranks() {
    use rsf_scenes::SeasBp5;
    let bp5 = SeasBp5::default();
    for dense_max in [usize::MAX, 0] {
        let steps = same_bits_on_ranks(|ranks| {
            let model = bp5.model(4000.0).unwrap();
            let half_space = rsf::halfspace_operator::HalfSpaceOptions {
                dense_max,
                leaf_size: 16,
                ..bp5.half_space(1e-6).unwrap()
            };
            let options = bp5.fault_ode_options(1e-6).unwrap();
            let ode = bp5.fault_ode(model, options, &half_space).unwrap();
            run_shared(ode, ranks, Until::Steps(150))
        });
        eprintln!("BP5 at 4 km, dense_max {dense_max}: {steps} steps with the same bits");
    }
}

/// BP5 at Δx = 4 km with the ℋ-matrix half-space operator built on the ranks, each rank
/// holding only the blocks of its rows (`fault_ode_on_ranks`: the back-slip loading at
/// set-up is the operator's whole product, each rank's rows and an all-gather): every
/// accepted step's bits those of one process with the whole operator at 1–4 ranks; on
/// more than one rank each holds less than the whole and says which part.
#[test]
fn a_bp5_operator_held_in_parts_by_the_ranks_has_the_same_bits_as_one_process() {
    use rsf_scenes::SeasBp5;
    let bp5 = SeasBp5::default();
    let half_space = rsf::halfspace_operator::HalfSpaceOptions {
        dense_max: 0,
        leaf_size: 16,
        ..bp5.half_space(1e-6).unwrap()
    };
    let whole = bp5
        .fault_ode(
            bp5.model(4000.0).unwrap(),
            bp5.fault_ode_options(1e-6).unwrap(),
            &half_space,
        )
        .unwrap()
        .kernel_report()
        .stored_entries;
    let steps = same_bits_on_ranks(|ranks| {
        let model = bp5.model(4000.0).unwrap();
        let options = bp5.fault_ode_options(1e-6).unwrap();
        let group = ranks.as_ref().map(|r| r.group());
        let (ode, _) = bp5
            .fault_ode_on_ranks(model, options, &half_space, &[], group)
            .unwrap();
        let report = ode.kernel_report();
        match &ranks {
            Some(r) if r.size() > 1 => {
                assert_eq!(report.part, Some((r.rank(), r.size())));
                assert!(report.stored_entries < whole);
            }
            _ => assert_eq!(report.part, None),
        }
        run_shared(ode, ranks, Until::Steps(150))
    });
    eprintln!("BP5 at 4 km, operator held in parts: {steps} steps with the same bits");
}

/// An operator that cannot compute its rows apart (the trait's default) is refused with a
/// typed error naming `ranks`, and the run stays unshared.
#[test]
fn an_operator_without_parts_is_refused() {
    use rsf::fault_operator::{FaultOperator, KernelReport};
    use rsf_scenes::SeasBp5;
    /// The half-space operator without its parts.
    struct Whole(rsf::halfspace_operator::HalfSpaceOperator);
    impl FaultOperator for Whole {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn subtract_product(
            &mut self,
            x: &[f64],
            r: &mut [f64],
            par: rsf::Parallelism,
        ) -> rsf::Result<()> {
            self.0.subtract_product(x, r, par)
        }
        fn report(&self) -> &KernelReport {
            self.0.report()
        }
    }
    let bp5 = SeasBp5::default();
    let model = bp5.model(4000.0).unwrap();
    let half_space = bp5.half_space(1e-6).unwrap();
    let operator =
        rsf::halfspace_operator::HalfSpaceOperator::fault_alone(&model, &half_space).unwrap();
    let alone = rsf::fault_alone::FaultAlone {
        plate_velocity: (0..model.vertices.len())
            .flat_map(|_| [bp5.v_p, 0.0])
            .collect(),
        operator: Box::new(Whole(operator)),
    };
    let mut ode = bp5
        .problem_builder(model)
        .build_fault_ode_alone(bp5.fault_ode_options(1e-6).unwrap(), alone)
        .unwrap();
    let ranks = ThreadProcess::job(1).pop().unwrap();
    match ode.share_evaluations(ranks.group()) {
        Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, "ranks"),
        other => panic!("expected a refusal, got {other:?}"),
    }
    assert_eq!(ode.rank_and_size(), (0, 1));
}
