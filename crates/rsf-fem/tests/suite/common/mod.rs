//! Helpers shared by the integration tests.
#![allow(dead_code)]
use rsf_fem::{spmv_add, NodalFrames, SparseMatrix};

/// `A x`.
pub fn apply(a: &SparseMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    spmv_add(a.as_ref(), 1.0, x, &mut y);
    y
}

/// `aᵀ b`.
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Sum of the entries of a node-major matrix per component; asserts that different
/// components are not coupled (as in a mass matrix).
pub fn component_sums<const D: usize>(m: &SparseMatrix) -> [f64; D] {
    let mut s = [0.0; D];
    for j in 0..m.ncols() {
        for (&i, &v) in m.as_ref().row_idx_of_col_raw(j).iter().zip(m.val_of_col(j)) {
            if i % D == j % D {
                s[j % D] += v;
            } else {
                assert_eq!(v, 0.0);
            }
        }
    }
    s
}

/// Nodal frames change bases consistently: `xᵀ K y = (Rᵀx)ᵀ (RᵀKR) (Rᵀy)` and
/// `to_global ∘ to_local` is the identity.
pub fn check_frames<const D: usize>(k: &SparseMatrix, frames: &NodalFrames<D>) {
    let kt = frames.rotate_matrix(k.as_ref()).unwrap();
    let n = k.nrows();
    let x: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
    let y: Vec<f64> = (0..n).map(|i| (0.11 * i as f64).cos()).collect();
    let kxy = dot(&x, &apply(k, &y));
    let (mut xl, mut yl) = (x.clone(), y.clone());
    frames.to_local(&mut xl).unwrap();
    frames.to_local(&mut yl).unwrap();
    let kxy2 = dot(&xl, &apply(&kt, &yl));
    assert!((kxy - kxy2).abs() < 1e-12 * kxy.abs().max(1.0));
    let mut back = xl;
    frames.to_global(&mut back).unwrap();
    for (a, b) in back.iter().zip(&x) {
        assert!((a - b).abs() < 1e-14);
    }
}

/// The facets in the plane `x = 0` (vertex triples) with their areas.
pub fn plane_facets(m: &rsf_fem::TetrahedronMesh) -> Vec<([usize; 3], f64)> {
    m.facets()
        .into_iter()
        .filter(|f| f.iter().all(|&v| m.vertices()[v][0] == 0.0))
        .map(|f| {
            let [p, q, r] = f.map(|v| m.vertices()[v]);
            let (u, w) = (
                [0, 1, 2].map(|a| q[a] - p[a]),
                [0, 1, 2].map(|a| r[a] - p[a]),
            );
            let n = [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ];
            (f, 0.5 * n.iter().map(|c| c * c).sum::<f64>().sqrt())
        })
        .collect()
}

/// Total area of the boundary facets: the box's surface for a conforming mesh (a hanging
/// vertex leaves facets inside the body that belong to one cell only).
pub fn boundary_area(m: &rsf_fem::TetrahedronMesh) -> f64 {
    (0..m.num_boundary_facets())
        .map(|f| m.boundary_facet_measure(f))
        .sum()
}

/// The distance from the origin to the box `[lo, hi]` (0 inside it).
pub fn distance_to_origin(lo: [f64; 3], hi: [f64; 3]) -> f64 {
    (0..3)
        .map(|a| (lo[a].max(0.0) - hi[a].min(0.0)).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// A size function graded from the origin (m): `h` at the origin, growing by `growth`
/// per metre of [`distance_to_origin`] of the box `[lo, hi]`.
pub fn graded_from_origin(h: f64, growth: f64) -> impl Fn([f64; 3], [f64; 3]) -> f64 {
    move |lo, hi| h + growth * distance_to_origin(lo, hi)
}

/// The Gmsh mesh of `text` read with [`rsf_fem::GmshOptions::interior_facets`], after
/// asserting that the default reading refuses it (a physical group with interior facets).
pub fn parse_with_interior_facets<const D: usize>(text: &str) -> rsf_fem::GmshMesh<D> {
    assert!(matches!(
        rsf_fem::parse_gmsh::<D>(text.as_bytes()),
        Err(rsf_fem::Error::Gmsh { .. })
    ));
    let options = rsf_fem::GmshOptions {
        interior_facets: true,
        ..rsf_fem::GmshOptions::default()
    };
    rsf_fem::parse_gmsh_with::<D>(text.as_bytes(), options).unwrap()
}

/// Cell `cell` of `m`: its vertices, their points (m) and its measure (m², m³).
pub fn cell_geometry<const D: usize>(
    m: &rsf_fem::SimplexMesh<D>,
    cell: usize,
) -> (&[usize], Vec<[f64; D]>, f64) {
    let v = m.cell(cell);
    let x = v.iter().map(|&i| m.vertices()[i]).collect();
    (v, x, m.cell_measure(cell))
}

/// The observed orders of convergence under uniform refinement: `errors(m)` of every
/// level (each a pair of error norms, e.g. L² and energy) and `log₂` of their ratios from
/// one level to the next, both printed.
pub fn observed_rates<const D: usize>(
    levels: &[rsf_fem::SimplexMesh<D>],
    errors: impl Fn(&rsf_fem::SimplexMesh<D>) -> (f64, f64),
) -> Vec<(f64, f64)> {
    let errs: Vec<(f64, f64)> = levels.iter().map(errors).collect();
    let rates: Vec<(f64, f64)> = errs
        .windows(2)
        .map(|w| ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2()))
        .collect();
    eprintln!("errors {errs:?}\nrates {rates:?}");
    rates
}
