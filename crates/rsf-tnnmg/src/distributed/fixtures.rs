//! The problem of the distributed solvers' tests: a cube's P1 elasticity stiffness with
//! Dirichlet components ([`ElasticBox`]), its right-hand side and start, and the owner
//! vectors they are split by.

use faer::sparse::SparseColMatRef;
use rsf_fem::ElasticBox;

use rsf_ranks::node_graph;

const D: usize = 3;

/// A cube's elasticity problem ([`ElasticBox`]: the face z = 0 clamped, the face x = 0 on
/// rollers), its right-hand side and start.
pub(super) struct Problem {
    pub bx: ElasticBox,
    pub b: Vec<f64>,
    pub x0: Vec<f64>,
}

impl Problem {
    pub fn a(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bx.stiffness.as_ref()
    }
}

/// The box [0, 1.5] × [0, 1] × [0, 1] of 3 × 2 × 2 Kuhn-split cubes, refined
/// `refinements` times.
pub(super) fn cube(refinements: usize) -> Problem {
    let bx = ElasticBox::new([1.5, 1.0, 1.0], [4, 3, 3], refinements).unwrap();
    let (b, x0) = (bx.load(), bx.start());
    Problem { bx, b, x0 }
}

/// The owner vectors tested at `size` ranks: slabs along x, and METIS's partition of the
/// node graph when the workspace is built with METIS.
pub(super) fn owners(pb: &Problem, size: usize) -> Vec<(&'static str, Vec<usize>)> {
    let mut out = vec![("coordinates", pb.bx.slabs(size, 0))];
    if rsf_metis::is_available() {
        let (xadj, adjncy) = node_graph::<D>(pb.a()).unwrap();
        let part = rsf_metis::part_graph_kway(&xadj, &adjncy, size).unwrap();
        out.push(("metis", part));
    }
    out
}
