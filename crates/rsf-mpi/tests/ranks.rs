//! The fault ODE on MPI ranks: the test starts itself under `mpirun -n 1, 2, 4`
//! (`--oversubscribe`: more ranks than cores), and each rank runs the body below —
//! a small BP1 unshared and shared by the ranks, the two trajectories compared bit for bit
//! on every rank; a rank that finds a difference panics and `mpirun` fails.

use rsf::fault_ode::{FaultKernel, FaultOdeOptions};
use rsf::observe::SECONDS_PER_YEAR;
use rsf::{Flow, Observer, StepView, Until};
use rsf_scenes::{SeasBp1, SeasBp1Grid};

/// Set in the ranks' environment: run the body, not the launcher.
const CHILD: &str = "RSF_MPI_TEST_RANK";

mod common;
use common::mpirun;

/// Every accepted step's time and the bits of the fault's slip and state.
#[derive(Default)]
struct Bits(Vec<Vec<u64>>);

impl Observer<2, 1> for Bits {
    fn observe(&mut self, s: &StepView<'_, 2, 1>) -> rsf::Result<Flow> {
        let mut row = vec![s.state.time.to_bits(), s.state.tau.to_bits()];
        row.extend(
            s.model
                .frictional_boundary
                .nodes
                .iter()
                .map(|&p| s.state.kinematics.u[p].to_bits()),
        );
        row.extend(s.state.alpha.iter().map(|a| a.to_bits()));
        self.0.push(row);
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        false
    }
}

/// BP1 with Δz = 100 m on a 10 km fault (m = 100, leaf size 8) for 20 years.
fn bp1_bits(ranks: Option<rsf_mpi::MpiRanks>) -> Vec<Vec<u64>> {
    let bp1 = SeasBp1 {
        h_top: 2e3,
        h_transition: 1e3,
        w_f: 10e3,
        ..SeasBp1::default()
    };
    let grid = SeasBp1Grid {
        dz: 100.0,
        domain: 20e3,
        ratio: 1.1,
    };
    let model = bp1.model(&grid, false).unwrap();
    let options = FaultOdeOptions {
        kernel: FaultKernel::Hierarchical {
            epsilon: 1e-6,
            leaf_size: 8,
        },
        ..bp1.fault_ode_options(1e-6).unwrap()
    };
    let mut ode = bp1.fault_ode(model, options).unwrap();
    if let Some(r) = ranks {
        ode.share_evaluations(Box::new(r)).unwrap();
    }
    let mut bits = Bits::default();
    ode.run_until(
        Until::TimeWithin {
            time: 20.0 * SECONDS_PER_YEAR,
            max_steps: 500_000,
        },
        &mut [&mut bits],
    )
    .unwrap();
    bits.0
}

#[test]
fn a_bp1_fault_has_the_same_bits_on_1_2_and_4_mpi_ranks() {
    if std::env::var_os(CHILD).is_some() {
        let (_universe, ranks) = rsf_mpi::initialize().unwrap();
        let alone = bp1_bits(None);
        let shared = bp1_bits(Some(ranks.duplicate()));
        assert!(alone.len() > 10);
        assert_eq!(shared.len(), alone.len(), "rank {}: steps", ranks.rank());
        for (k, (a, b)) in shared.iter().zip(&alone).enumerate() {
            assert_eq!(a, b, "rank {} of {}: step {k}", ranks.rank(), ranks.size());
        }
        eprintln!(
            "rank {} of {}: {} steps with the bits of one process",
            ranks.rank(),
            ranks.size(),
            alone.len()
        );
        return;
    }
    let me = std::env::current_exe().unwrap();
    for n in [1, 2, 4] {
        let out = mpirun(n)
            .env(CHILD, "1")
            .arg(&me)
            .args([
                "--exact",
                "a_bp1_fault_has_the_same_bits_on_1_2_and_4_mpi_ranks",
                "--nocapture",
                "--test-threads",
                "1",
            ])
            .output()
            .expect("mpirun (Open MPI: apt-get install openmpi-bin libopenmpi-dev)");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{n} ranks: {}\n{err}", out.status);
        let ok = err.matches("with the bits of one process").count();
        assert_eq!(ok, n, "{n} ranks: every rank reports\n{err}");
    }
}
