//! The one parallelism parameter (`SolverOptions::parallelism`, docs/design.md,
//! "Parallelism") reaches the parts of a simulation that use threads. That results do not
//! depend on it is tested where the parallel code lives (rsf-tnnmg's direct solver,
//! rsf-time's load operator) on problems above the thresholds.

mod common;

use common::*;
use rsf::method::SolverOptions;
use rsf::{Parallelism, SolverKind};

#[test]
fn the_parallelism_reaches_the_solver_and_the_integrator() {
    assert_eq!(SolverOptions::default().parallelism, Parallelism::default());
    for (solver, par) in [
        (SolverKind::Direct, Parallelism::rayon(3)),
        (SolverKind::Direct, Parallelism::SEQ),
        (SolverKind::Tnnmg, Parallelism::rayon(4)),
    ] {
        let scene = paper(2, solver);
        let options = SolverOptions {
            parallelism: par,
            ..scene.solver_options()
        };
        let mut sim = scene
            .simulation_builder()
            .unwrap()
            .solver_options(options)
            .build()
            .unwrap();
        let method = sim.method();
        assert_eq!(method.options().solver_options.parallelism, par);
        assert_eq!(method.parallelism(), par);
        let expected = (solver == SolverKind::Direct).then_some(par);
        assert_eq!(method.solver_parallelism(), expected, "{solver}");
        sim.step().unwrap();
        assert_eq!(sim.method().solver_parallelism(), expected);
    }
}
