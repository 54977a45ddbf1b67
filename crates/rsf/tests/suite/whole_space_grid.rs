//! The whole space's FFT operator of a uniform planar grid (`WholeSpaceGrid`, issue 85
//! item 4): against the dense operator of the same cells as an element set
//! (`ElementOperator` on rectangles in `Space::WholeSpace`, every entry its own DC3D
//! call), in each of the three coordinate planes, with cells that are not square and
//! nodes in a scrambled order; symmetric (reciprocity, `w_k K_kl = w_l K_lk` with equal
//! weights) and positive definite; refusals name the node or cell.
#![cfg(feature = "halfspace")]

use faer::Mat;
use rsf::fault_operator::FaultOperator;
use rsf::halfspace::{ElementSet, Medium, RectangleElement, Space};
use rsf::halfspace_operator::{
    ElementOperator, ElementOptions, HalfSpaceOperatorError, WholeSpaceGrid,
};
use rsf::{Model, Parallelism};

fn max_abs(a: &Mat<f64>) -> f64 {
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

/// Cell centres of an `n[0] × n[1]` grid of `h[0] × h[1]` cells in the plane normal to
/// axis `fixed` (the in-plane axes in increasing order), centred at `(3, −5, 7)` m, listed
/// in a scrambled order.
fn centres(fixed: usize, n: [usize; 2], h: [f64; 2]) -> Vec<[f64; 3]> {
    let axes: Vec<usize> = (0..3).filter(|&a| a != fixed).collect();
    let centre = [3.0, -5.0, 7.0];
    let mut out = Vec::new();
    for j in 0..n[1] {
        for i in 0..n[0] {
            let mut x = centre;
            x[axes[0]] += (i as f64 + 0.5 - 0.5 * n[0] as f64) * h[0];
            x[axes[1]] += (j as f64 + 0.5 - 0.5 * n[1] as f64) * h[1];
            out.push(x);
        }
    }
    // A fixed permutation: k ↦ 7k mod len (len coprime with 7 below).
    let len = out.len();
    (0..len).map(|k| out[(7 * k) % len]).collect()
}

/// The rectangle of each centre whose strike and up-dip directions are the in-plane axes
/// in increasing order (the fault alone's free components).
fn elements(fixed: usize, centres: &[[f64; 3]], h: [f64; 2]) -> Vec<RectangleElement> {
    // (strike φ, dip δ): axis x fixed → strike +y, dip 90 (up dip +z); y fixed → strike
    // +x, dip 90 (+z); z fixed → strike +x, dip 0 (up dip +y).
    let (strike, dip) = match fixed {
        0 => (90.0, 90.0),
        1 => (0.0, 90.0),
        _ => (0.0, 0.0),
    };
    centres
        .iter()
        .map(|&c| RectangleElement::new(c, strike, dip, h[0], h[1]).unwrap())
        .collect()
}

/// The whole space of the grids' tests: μ = 32.04 GPa, ν = 0.25.
fn medium() -> Medium {
    Medium::from_shear_poisson(32.04e9, 0.25).unwrap()
}

/// The [`centres`] of the grid, the fault alone of its cells (each of area `h[0] h[1]`)
/// and its operator in the [`medium`].
fn grid_fault(
    fixed: usize,
    n: [usize; 2],
    h: [f64; 2],
) -> (Vec<[f64; 3]>, Model<3>, WholeSpaceGrid) {
    let c = centres(fixed, n, h);
    let model = Model::fault_only(c.clone(), &vec![h[0] * h[1]; c.len()], fixed).unwrap();
    let grid = WholeSpaceGrid::fault_alone(&model, medium()).unwrap();
    (c, model, grid)
}

#[test]
fn the_fft_operator_is_the_element_operator() {
    let (n, h) = ([12, 9], [10.0, 12.5]);
    for fixed in 0..3 {
        let (c, model, mut fft) = grid_fault(fixed, n, h);
        assert_eq!(fft.cells(), n);
        assert_eq!(fft.spacing(), h);
        let set = ElementSet::new(medium(), Space::WholeSpace, elements(fixed, &c, h)).unwrap();
        let mut dense =
            ElementOperator::fault_alone(&model, &set, &ElementOptions::default()).unwrap();
        let (s0, s1) = (dense.dense().unwrap(), fft.dense().unwrap());
        let scale = max_abs(&s0);
        let rel = max_abs(&(&s1 - &s0)) / scale;
        let asym = max_abs(&(&s1 - s1.transpose())) / scale;
        eprintln!("plane ⟂ axis {fixed}: FFT against dense {rel:.2e}, |S − Sᵀ|/|S| {asym:.2e}");
        assert!(rel < 1e-12, "{rel:e}");
        assert!(asym < 1e-12, "{asym:e}");
        // Positive definite: the symmetric part's Cholesky factorisation exists.
        let sym = Mat::from_fn(s1.nrows(), s1.ncols(), |i, j| {
            0.5 * (s1[(i, j)] + s1[(j, i)])
        });
        assert!(sym.llt(faer::Side::Lower).is_ok());
        // The product subtracts, leaving what was there.
        let x: Vec<f64> = (0..fft.dim())
            .map(|k| ((k * 5) % 13) as f64 - 6.0)
            .collect();
        let mut r = vec![1.0; fft.dim()];
        fft.subtract_product(&x, &mut r, Parallelism::SEQ).unwrap();
        for (i, ri) in r.iter().enumerate() {
            let want = 1.0 - (0..fft.dim()).map(|j| s0[(i, j)] * x[j]).sum::<f64>();
            assert!((ri - want).abs() <= 1e-11 * scale, "{ri} {want}");
        }
    }
}

#[test]
fn grids_that_are_not_grids_are_refused() {
    let medium = Medium::from_shear_poisson(30e9, 0.25).unwrap();
    let (n, h) = ([6, 5], [10.0, 10.0]);
    let c = centres(0, n, h);
    use HalfSpaceOperatorError::{ElementWithoutNode, NotAtCentre, NotPlanar, TooFewNodes};
    // The grid's error for a fault of cells at `centres` of `area` (m²) each matches
    // `error`.
    macro_rules! assert_refused {
        ($centres:expr, $area:expr, $error:pat) => {{
            let model = Model::fault_only($centres, $area, 0).unwrap();
            let e = WholeSpaceGrid::fault_alone(&model, medium).unwrap_err();
            assert!(matches!(e, $error), "{e}");
        }};
    }
    let area = vec![100.0; c.len()];
    // A cell without its node.
    assert_refused!(c[1..].to_vec(), &area[1..], ElementWithoutNode { .. });
    // A node off the grid.
    let mut moved = c.clone();
    moved[3][1] += 3.0;
    assert_refused!(moved, &area, NotAtCentre { node: 3, .. });
    // A node off the plane.
    let mut lifted = c.clone();
    lifted[4][0] += 1.0;
    assert_refused!(lifted, &area, NotPlanar { node: 4, .. });
    // A single row.
    let row: Vec<[f64; 3]> = (0..4).map(|i| [0.0, 10.0 * i as f64, 0.0]).collect();
    assert_refused!(row, &[100.0; 4], TooFewNodes { .. });
}

/// The displacement columns: across a cell's centre the displacement jumps by the cell's
/// own slip (the plus side, where the fixed axis points, moving along `+u` or `+v`
/// relative to the other), in each coordinate plane; a point off the fault sees the
/// slip's field odd across the plane in the in-plane components.
#[test]
fn displacement_jumps_by_the_slip_across_a_cell() {
    let medium = medium();
    let (n, h) = ([6, 5], [10.0, 12.5]);
    for fixed in 0..3 {
        let (c, _, grid) = grid_fault(fixed, n, h);
        let m = grid.dim();
        let axes: Vec<usize> = (0..3).filter(|&a| a != fixed).collect();
        let k = 11;
        // (Okada's DC3D snaps coordinates below 1e-6 m to 0: the plane itself.)
        let eps = 1e-4;
        let mut plus = c[k];
        plus[fixed] += eps;
        let mut minus = c[k];
        minus[fixed] -= eps;
        let cols = grid.displacement_columns(&medium, &[plus, minus]).unwrap();
        for t in 0..2 {
            for comp in 0..3 {
                let jump = cols[0][comp * m + 2 * k + t] - cols[1][comp * m + 2 * k + t];
                let expected = if comp == axes[t] { 1.0 } else { 0.0 };
                assert!(
                    (jump - expected).abs() < 1e-4,
                    "plane ⟂ {fixed}, slip {t}, component {comp}: jump {jump}"
                );
            }
        }
        // Off the fault, mirror points: in-plane components odd, the normal one even.
        let mut a = c[3];
        a[fixed] += 17.0;
        let mut b = c[3];
        b[fixed] -= 17.0;
        let cols = grid.displacement_columns(&medium, &[a, b]).unwrap();
        for j in 0..m {
            for comp in 0..3 {
                let (x, y) = (cols[0][comp * m + j], cols[1][comp * m + j]);
                let d = if comp == fixed { x - y } else { x + y };
                assert!(d.abs() < 1e-12, "plane ⟂ {fixed}: {comp} {j}: {x} {y}");
            }
        }
    }
}
