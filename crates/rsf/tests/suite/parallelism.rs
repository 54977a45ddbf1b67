//! The one parallelism parameter (`SolverOptions::parallelism`, docs/design.md,
//! "Parallelism") reaches the parts of a simulation that use threads. That results do not
//! depend on it is tested where the parallel code lives (rsf-tnnmg's direct solver,
//! rsf-time's load operator) on problems above the thresholds.

use crate::common::*;
use rsf::method::SolverOptions;
use rsf::{Parallelism, SolverKind};

#[test]
fn the_parallelism_reaches_the_solver_and_the_integrator() {
    assert_eq!(SolverOptions::default().parallelism, Parallelism::default());
    use rsf::tnnmg::SmootherOrder::{Lexicographic, MultiColour, RedBlackChunks};
    for (solver, par, smoother) in [
        (SolverKind::Direct, Parallelism::rayon(3), Lexicographic),
        (SolverKind::Direct, Parallelism::SEQ, Lexicographic),
        (SolverKind::Tnnmg, Parallelism::rayon(4), Lexicographic),
        (SolverKind::Tnnmg, Parallelism::rayon(3), MultiColour),
        (SolverKind::Tnnmg, Parallelism::rayon(2), RedBlackChunks),
    ] {
        let scene = paper(2, solver);
        let mut options = SolverOptions {
            parallelism: par,
            ..scene.solver_options()
        };
        options.tnnmg.smoother = smoother;
        let mut sim = build_with_options(&scene, options);
        let method = sim.method();
        assert_eq!(method.options().solver_options.parallelism, par);
        assert_eq!(method.parallelism(), par);
        // TNNMG takes the threads in every smoother order (the lexicographic one for its
        // row-parallel parts: quadratic forms, Galerkin products, transfers).
        let expected = Some(par);
        assert_eq!(method.solver_parallelism(), expected, "{solver}");
        sim.step().unwrap();
        assert_eq!(sim.method().solver_parallelism(), expected);
    }
}
