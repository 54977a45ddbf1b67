//! The boundary-element operator of any element set behind the fault ODE's seam
//! (`ElementOperator`, issue 83 item 3, issue 85 item 2): on BP5's fault alone it is the
//! planar `HalfSpaceOperator`'s operator and runs the same trajectory; on a finite-element
//! model's fault its nodes find their elements by position; several faults in one
//! operator are `W K`; a whole space and triangles work the same way.
#![cfg(feature = "halfspace")]

use crate::common::{mixed_slip, relative_product_difference};
use faer::Mat;
use rsf::fault_alone::FaultAlone;
use rsf::fault_operator::FaultOperator;
use rsf::halfspace::{Element, ElementSet, Medium, RectangleElement, Space, Triangle};
use rsf::halfspace_operator::{
    fault_alone_model, ElementOperator, ElementOptions, HalfSpaceOperator, HalfSpaceOperatorError,
    HalfSpaceOptions,
};
use rsf::Stepping;
use rsf_scenes::SeasBp5;

fn max_abs(a: &Mat<f64>) -> f64 {
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

/// BP5's cells as rectangle elements: centre `(0, x₂, −x₃)`, strike along `+y` (φ = 90°),
/// vertical; their strike and dip are the model's free `y` and `z`.
fn bp5_elements(bp5: &SeasBp5, dx: f64) -> ElementSet<RectangleElement> {
    let cells = bp5.cells(dx).unwrap();
    let elements = cells
        .iter()
        .map(|c| RectangleElement::new([0.0, c[0], -c[1]], 90.0, 90.0, dx, dx).unwrap())
        .collect();
    ElementSet::new(bp5.medium().unwrap(), Space::HalfSpace, elements).unwrap()
}

/// BP5's fault alone at 4 km: the element operator is the planar operator (`S` to 1e-12
/// of its largest entry; measured: equal, bit for bit — each element's DC3D call is the
/// planar table's), and the fault ODE with either runs the same steps (40 steps: time and
/// slip rates to 1e-9 relative; measured: the same bits).
#[test]
fn on_bp5_the_element_operator_is_the_planar_operator() {
    let bp5 = SeasBp5::default();
    let dx = 4000.0;
    let model = bp5.model(dx).unwrap();
    let set = bp5_elements(&bp5, dx);
    let mut planar =
        HalfSpaceOperator::fault_alone(&model, &bp5.half_space(1e-6).unwrap()).unwrap();
    let mut elem = ElementOperator::fault_alone(&model, &set, &ElementOptions::default()).unwrap();
    assert_eq!(elem.dim(), planar.dim());
    let (s0, s1) = (planar.dense().unwrap(), elem.dense().unwrap());
    let rel = max_abs(&(&s1 - &s0)) / max_abs(&s0);
    eprintln!("BP5 4 km: element operator against the planar one {rel:.2e}");
    assert!(rel < 1e-12, "{rel:e}");
    // The fault ODE with each.
    let run = |op: Box<dyn FaultOperator>| {
        let plate_velocity = (0..model.vertices.len())
            .flat_map(|_| [bp5.v_p, 0.0])
            .collect();
        let mut ode = bp5
            .problem_builder(model.clone())
            .build_fault_ode_alone(
                bp5.fault_ode_options(1e-6).unwrap(),
                FaultAlone {
                    operator: op,
                    plate_velocity,
                },
            )
            .unwrap();
        for _ in 0..40 {
            ode.advance(None, false).unwrap();
        }
        (ode.state().time, ode.state().kinematics.v.clone())
    };
    let (t0, v0) = run(Box::new(planar));
    let (t1, v1) = run(Box::new(elem));
    let dv = v0
        .iter()
        .zip(&v1)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let vmax = v0.iter().map(|a| a.abs()).fold(0.0, f64::max);
    eprintln!(
        "40 steps: t {t0} s against {t1} s, max |ΔV|/max V = {:.2e}",
        dv / vmax
    );
    assert!((t0 - t1).abs() <= 1e-9 * t0 && dv <= 1e-9 * vmax);
}

/// A finite-element model's buried vertical fault (the model of
/// `halfspace_operator.rs`): a grid of rectangle elements centred on its nodes gives the
/// planar operator's `S` (to 1e-12, measured 1.7e-15; its nodes' frames have `t₂` pointing down, mapped by
/// `A_k`); an element removed, or one turned out of the fault's plane, is refused naming
/// the node or element.
#[test]
fn a_finite_element_faults_nodes_find_their_elements() {
    let model = crate::halfspace_operator::model(6, 4000.0, 1.6, None);
    let medium = Medium::from_shear_poisson(30e9, 0.25).unwrap();
    let a = 1000.0;
    let h = 2.0 * a / 6.0;
    let grid = RectangleElement::grid([0.0, 0.0, -2.0 * a], 90.0, 90.0, [5.0 * h, 5.0 * h], [5, 5])
        .unwrap();
    let set = ElementSet::new(medium, Space::HalfSpace, grid.clone()).unwrap();
    let mut elem = ElementOperator::new(&model, &set, &ElementOptions::default()).unwrap();
    let mut planar = HalfSpaceOperator::new(&model, &HalfSpaceOptions::new(0.0, medium)).unwrap();
    let (s0, s1) = (planar.dense().unwrap(), elem.dense().unwrap());
    let rel = max_abs(&(&s1 - &s0)) / max_abs(&s0);
    eprintln!("FE fault: element operator against the planar one {rel:.2e}");
    assert!(rel < 1e-12, "{rel:e}");
    for m in elem.component_maps() {
        let want = [[1.0, 0.0], [0.0, -1.0]];
        assert!(
            (0..4).all(|k| (m[k / 2][k % 2] - want[k / 2][k % 2]).abs() < 1e-12),
            "{m:?}"
        );
    }
    // One element fewer: a node finds none.
    let fewer = ElementSet::new(medium, Space::HalfSpace, grid[1..].to_vec()).unwrap();
    assert!(matches!(
        ElementOperator::new(&model, &fewer, &ElementOptions::default()),
        Err(HalfSpaceOperatorError::NotAtElement { .. })
    ));
    // One element more: it has no node.
    let mut more = grid.clone();
    more.push(RectangleElement::new([0.0, 3.0 * a, -2.0 * a], 90.0, 90.0, h, h).unwrap());
    let more = ElementSet::new(medium, Space::HalfSpace, more).unwrap();
    assert!(matches!(
        ElementOperator::new(&model, &more, &ElementOptions::default()),
        Err(HalfSpaceOperatorError::NoNodeAt { element: 25, .. })
    ));
    // One element turned by 10° of dip.
    let mut turned = grid.clone();
    let c = turned[7].centre();
    turned[7] = RectangleElement::new(c, 90.0, 80.0, h, h).unwrap();
    let turned = ElementSet::new(medium, Space::HalfSpace, turned).unwrap();
    assert!(matches!(
        ElementOperator::new(&model, &turned, &ElementOptions::default()),
        Err(HalfSpaceOperatorError::NotAligned { element: 7, .. })
    ));
}

/// The model of `set`'s fault alone and its operator (the default options), whose dense
/// `S` is asserted `W K` entry by entry, bit for bit (`W` the weight of each node, scaling
/// its two rows; `K` the set's own dense kernel).
fn weighted_kernel<E: Element>(set: &ElementSet<E>) -> (rsf::Model<3>, ElementOperator) {
    let model = fault_alone_model(set).unwrap();
    let mut op = ElementOperator::fault_alone(&model, set, &ElementOptions::default()).unwrap();
    let (s, k) = (op.dense().unwrap(), set.dense().unwrap());
    let w = &model.frictional_boundary.weights;
    for i in 0..s.nrows() {
        for j in 0..s.ncols() {
            assert_eq!(s[(i, j)], w[i / 2] * k[(i, j)], "{i} {j}");
        }
    }
    (model, op)
}

/// Two faults alone in one operator (two rectangles' grids of different strike and dip,
/// a half-space): `S = W K` entry by entry, bit for bit with the dense kernel; the
/// ℋ-kernel's product within its ε of the dense one; the fault ODE accepts it.
/// Triangles in a whole space go the same way.
#[test]
fn several_faults_alone_in_one_operator() {
    let medium = Medium::from_shear_poisson(30e9, 0.25).unwrap();
    let mut rects =
        RectangleElement::grid([0.0, 0.0, -3000.0], 0.0, 90.0, [16000.0, 3000.0], [32, 6]).unwrap();
    rects.extend(
        RectangleElement::grid(
            [21000.0, 2500.0, -3000.0],
            30.0,
            60.0,
            [12000.0, 3000.0],
            [24, 6],
        )
        .unwrap(),
    );
    let set = ElementSet::new(medium, Space::HalfSpace, rects).unwrap();
    let (model, mut dense) = weighted_kernel(&set);
    let eps = 1e-6;
    let mut h = ElementOperator::fault_alone(
        &model,
        &set,
        &ElementOptions {
            dense_max: 0,
            epsilon: eps,
            leaf_size: 16,
        },
    )
    .unwrap();
    eprintln!("{}", h.report());
    assert!(h.report().low_rank_blocks > 0 && h.report().relative_error <= eps);
    let x = mixed_slip(h.dim());
    let rel = relative_product_difference(&mut dense, &mut h, &x);
    eprintln!("two faults: ‖(S − S_H) x‖/‖S x‖ = {rel:.2e}");
    assert!(rel <= 10.0 * eps, "{rel:e}");
    // Triangles in the whole space: the same operator, W K.
    let tris = vec![
        Triangle::new([[0.0, 0.0, 0.0], [1000.0, 0.0, 200.0], [0.0, 0.0, 1000.0]]).unwrap(),
        Triangle::new([
            [1000.0, 0.0, 200.0],
            [1000.0, 100.0, 1200.0],
            [0.0, 0.0, 1000.0],
        ])
        .unwrap(),
        Triangle::new([
            [3000.0, 500.0, 0.0],
            [4000.0, 900.0, 0.0],
            [3000.0, 500.0, 1000.0],
        ])
        .unwrap(),
    ];
    let tset = ElementSet::new(medium, Space::WholeSpace, tris).unwrap();
    let (tmodel, mut top) = weighted_kernel(&tset);
    let ts = top.dense().unwrap();
    assert_eq!(ts.nrows(), 6);
    for i in 0..6 {
        assert!(ts[(i, i)] > 0.0);
    }
    // A model of another fault is refused.
    assert!(matches!(
        ElementOperator::fault_alone(&tmodel, &set, &ElementOptions::default()),
        Err(HalfSpaceOperatorError::ElementCount { .. })
    ));
    let mut moved = tset.elements().to_vec();
    moved.swap(0, 2);
    let moved = ElementSet::new(medium, Space::WholeSpace, moved).unwrap();
    assert!(matches!(
        ElementOperator::fault_alone(&tmodel, &moved, &ElementOptions::default()),
        Err(HalfSpaceOperatorError::NotAtElement { node: 0, .. })
    ));
    let _ = tset.elements()[0].area();
}

/// Two buried vertical squares of `halfspace_operator.rs`'s fault (side `2A`, centre
/// `DEPTH` deep) side by side across strike at `x = ∓A` (2 km apart), in one box (`n`
/// cells of `h = 2A/n` along each fault, uniform over `|x| ≤ 2A`, `|y| ≤ A` and from the
/// faults' bottom to the surface, graded at `ratio` beyond; the far faces held).
fn two_fault_model(n: usize, far: f64, ratio: f64) -> rsf::Model<3> {
    use crate::halfspace_operator::{symmetric, A, DEPTH, MU, NU};
    use rsf::fem::{cuboid_from_coordinates, geometric_grading};
    let h = 2.0 * A / n as f64;
    let xs = symmetric(h, 2.0 * A, ratio, far);
    let ys = symmetric(h, A, ratio, far);
    let below = geometric_grading(h, DEPTH + A, ratio, far).unwrap();
    let zs: Vec<f64> = below.iter().rev().map(|z| -z).collect();
    let mesh = cuboid_from_coordinates(&xs, &ys, &zs).unwrap();
    let eps = 1e-6 * far;
    let (zb, zt) = (-DEPTH - A, -DEPTH + A);
    let square = |x: f64| [[x, -A, zb], [x, A, zb], [x, A, zt], [x, -A, zt]];
    rsf::ModelBuilder::new(mesh)
        .material(rsf::Material::new(2.0 * (1.0 + NU) * MU, NU, 2700.0))
        .without_mass()
        .dirichlet(
            rsf::Part::predicate("far", move |x| {
                x[0].abs() > far - eps || x[1].abs() > far - eps || x[2] < -far + eps
            }),
            [0.0; 3],
        )
        .fault_tangent([0.0, 1.0, 0.0])
        .internal_fault_polygon("west", &square(-A))
        .internal_fault_polygon("east", &square(A))
        .build()
        .unwrap()
}

/// Relative differences of the finite-element `S` of [`two_fault_model`] and the element
/// operator of the two faults' cells (centred on their nodes): the slip of a uniform
/// stress drop on both, the compliance, and the **cross block** — the traction on the west
/// fault from a smooth slip of the east one alone.
fn two_fault_differences(n: usize, far: f64) -> [f64; 3] {
    use crate::halfspace_operator::{fe_operator, norm2, A, DEPTH, MU, NU};
    use faer::linalg::solvers::{DenseSolveCore, Solve};
    let model = two_fault_model(n, far, 1.3);
    let s = fe_operator(&model);
    let h = 2.0 * A / n as f64;
    let side = (n - 1) as f64 * h;
    let medium = Medium::from_shear_poisson(MU, NU).unwrap();
    let mut cells = Vec::new();
    for x in [-A, A] {
        cells.extend(
            RectangleElement::grid([x, 0.0, -DEPTH], 90.0, 90.0, [side, side], [n - 1, n - 1])
                .unwrap(),
        );
    }
    let set = ElementSet::new(medium, Space::HalfSpace, cells).unwrap();
    let b = ElementOperator::new(&model, &set, &ElementOptions::default())
        .unwrap()
        .dense()
        .unwrap();
    let m = s.nrows();
    assert_eq!(b.nrows(), m);
    let fb = &model.frictional_boundary;
    let west = fb.fault_named("west").unwrap();
    let crack = Mat::<f64>::from_fn(
        m,
        1,
        |i, _| if i % 2 == 0 { fb.weights[i / 2] } else { 0.0 },
    );
    let (s_lu, b_lu) = (s.partial_piv_lu(), b.partial_piv_lu());
    let (xs, xb) = (s_lu.solve(&crack), b_lu.solve(&crack));
    let compliance = norm2(&(&s_lu.inverse() - &b_lu.inverse())) / norm2(&b_lu.inverse());
    let east_smooth = Mat::<f64>::from_fn(m, 1, |i, _| {
        if fb.fault_of[i / 2] == west {
            return 0.0;
        }
        let x = model.vertices[fb.nodes[i / 2]];
        let bump = |t: f64| (std::f64::consts::FRAC_PI_2 * t / A).cos();
        bump(x[1]) * bump(x[2] + DEPTH) * if i % 2 == 0 { 1.0 } else { 0.5 }
    });
    let on_west = |v: Mat<f64>| {
        (0..m)
            .filter(|&i| fb.fault_of[i / 2] == west)
            .map(|i| v[(i, 0)].powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let cross = on_west(&(&s - &b) * &east_smooth) / on_west(&b * &east_smooth);
    [(&xs - &xb).norm_l2() / xb.norm_l2(), compliance, cross]
}

/// Finite elements against boundary elements on a two-fault box (issue 83): as for one
/// fault (`halfspace_operator.rs`, `fe_and_bem_operators_converge_on_a_buried_fault`), the
/// long waves of the two operators — the slip of a uniform stress drop on both faults, the
/// compliance, and the cross block, one fault's traction from the other's smooth slip —
/// converge at first order in `h` (the cells stop half a cell short of the faults' rims).
/// Measured (n = 4, 6, 8): the crack's slip 0.351, 0.247, 0.190 (order 0.87, 0.91), the
/// compliance 0.369, 0.249, 0.191, the cross block 0.882, 0.397, 0.243 (order 1.97, 1.71).
#[test]
fn fe_and_bem_operators_converge_on_two_faults() {
    let rows: Vec<[f64; 3]> = [4, 6, 8]
        .iter()
        .map(|&n| {
            let d = two_fault_differences(n, 6000.0);
            eprintln!(
                "two faults, n = {n}: crack's slip {:.4}, compliance {:.4}, cross block {:.4}",
                d[0], d[1], d[2]
            );
            d
        })
        .collect();
    for k in 0..3 {
        let (n4, n6, n8) = (rows[0][k], rows[1][k], rows[2][k]);
        assert!(n4 > n6 && n6 > n8, "{rows:?}");
        // First order in h, 10 % slack: h(8)/h(6) = 3/4.
        assert!(n8 <= 1.1 * 0.75 * n6, "{rows:?}");
    }
}
