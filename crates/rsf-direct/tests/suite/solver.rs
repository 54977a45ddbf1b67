//! The direct solver on a synthetic stick–slip problem.

use crate::common::*;
use rsf_direct::{DirectOptions, DirectSolver};
use rsf_nonsmooth::NonsmoothSolver;

/// A direct solver set up for another matrix of the same pattern by reusing an existing
/// one's analysis (`for_matrix`, as at a change of the time step) solves exactly as one set
/// up from scratch: the same bits.
#[test]
fn direct_solver_for_another_matrix_equals_a_fresh_one() {
    let m = 16;
    let (a1, a2) = (square(m, 10.0), square(m, 3.0));
    let fixed = left_edge_fixed(m);
    let b = stick_slip_load(m);
    let nl = stick_slip_tresca(m);
    let mut first = DirectSolver::<1>::new(a1.as_ref(), &fixed, DirectOptions::default()).unwrap();
    first.prepare(&nl.nodes).unwrap();
    let mut reused = first.for_matrix(a2.as_ref()).unwrap();
    let mut fresh = DirectSolver::<1>::new(a2.as_ref(), &fixed, DirectOptions::default()).unwrap();
    let (mut v_r, mut v_f) = (vec![0.0; b.len()], vec![0.0; b.len()]);
    reused.solve(&b, &nl, &mut v_r).unwrap();
    fresh.solve(&b, &nl, &mut v_f).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&v_r), bits(&v_f));
    // And the first solver still solves its own problem.
    let mut v1 = vec![0.0; b.len()];
    first.solve(&b, &nl, &mut v1).unwrap();
    assert_ne!(bits(&v1), bits(&v_r));
}
