//! The Green's functions of a fault network as a product (`rsf::greens`,
//! docs/fault-networks.md, "Green's functions"): the dense export of the finite-element
//! operator is its products column by column and reads the diagonal the operator stores;
//! it is symmetric to round-off and positive definite; the ℋ-matrix's export differs from
//! the dense one by the error its set-up measured; the unknowns know their fault, weight,
//! position and slip direction; the cross block between two faults is there and falls with
//! their distance as a dislocation's stress does; a dense export above the limit is refused
//! before any product.
use rsf::fault_ode::FaultKernel;
use rsf::fault_operator::OperatorOrigin;
use rsf::greens::{asymmetry, GreensFunctions};
use rsf::Model;

mod faults;
use faults::box_with_faults;
pub(crate) use faults::fault_ode;

/// A `2 half × 2 half` m box in 0.25 m cells, top and bottom held, with two vertical
/// faults 1 m long at `x = ∓d/2`, "west" and "east".
pub(crate) fn two_faults(d: f64, half: f64) -> Model<2> {
    box_with_faults(d, half, 4.0)
}

/// A deterministic vector of `m` entries in (−1, 1).
fn pseudo_random(m: usize, seed: u64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..m)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

fn frobenius(s: &[f64], m: usize, rows: &[usize], cols: &[usize]) -> f64 {
    rows.iter()
        .flat_map(|&i| cols.iter().map(move |&j| s[i * m + j].powi(2)))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn the_dense_export_is_the_operator_symmetric_and_described() {
    let mut ode = fault_ode(two_faults(2.0, 4.0), FaultKernel::Dense);
    let g = ode.greens_functions().unwrap();
    g.validate().unwrap();
    let m = g.dim();
    assert_eq!(m, ode.condensed_dim());
    assert_eq!(g.origin, OperatorOrigin::FiniteElement);
    assert_eq!(g.accuracy.kernel, FaultKernel::Dense);
    assert_eq!(g.fault_names, ["west", "east"]);
    assert_eq!(g.units_s(), "N/m^2");
    let (west, east) = (g.unknowns_of("west"), g.unknowns_of("east"));
    assert_eq!(west.len() + east.len(), m);
    assert!(g.unknowns_of("north").is_empty());
    // Each unknown at its fault's x, a unit direction, the model's weight.
    let model = ode.model().clone();
    for j in 0..m {
        let x = if g.fault[j] == 0 { -1.0 } else { 1.0 };
        assert!(
            (g.positions[j][0] - x).abs() < 1e-12,
            "{:?}",
            g.positions[j]
        );
        let norm: f64 = g.directions[j].iter().map(|v| v * v).sum();
        assert!((norm - 1.0).abs() < 1e-12 && g.directions[j][2] == 0.0);
        let k = g.node[j];
        assert_eq!(g.weights[j], model.frictional_boundary.weights[k]);
    }
    // The tangential unknowns of a vertical fault slip along y (its frame's first axis).
    let tangential = (0..m).filter(|&j| g.component[j] == 0);
    assert!(tangential.clone().count() > 0);
    for j in tangential {
        assert!(g.directions[j][0].abs() < 1e-12, "{:?}", g.directions[j]);
    }

    let s = g.dense(ode.fault_operator_mut(), 10_000).unwrap();
    // The columns read the diagonal the operator stores (another code path).
    let mut diagonal = vec![0.0; m];
    ode.fault_operator_mut().diagonal(&mut diagonal).unwrap();
    for j in 0..m {
        let d = s[j * m + j];
        assert!(d > 0.0);
        assert!(
            (d - diagonal[j]).abs() <= 1e-12 * d,
            "{j}: {d} {}",
            diagonal[j]
        );
    }
    // Symmetric to round-off; reciprocity xᵀ S y = yᵀ S x; positive definite on samples.
    let asym = asymmetry(&s, m);
    eprintln!("m = {m}: ‖S − Sᵀ‖_F/‖S‖_F = {asym:e}");
    assert!(asym < 1e-12, "{asym:e}");
    let (x, y) = (pseudo_random(m, 1), pseudo_random(m, 2));
    let sx = g.apply(ode.fault_operator_mut(), &x).unwrap();
    let sy = g.apply(ode.fault_operator_mut(), &y).unwrap();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    let (xsy, ysx) = (dot(&x, &sy), dot(&y, &sx));
    assert!((xsy - ysx).abs() <= 1e-12 * dot(&x, &sx).abs().max(dot(&y, &sy).abs()));
    assert!(dot(&x, &sx) > 0.0 && dot(&y, &sy) > 0.0);
    // The matrix's product is the operator's.
    for i in 0..m {
        let row: f64 = (0..m).map(|j| s[i * m + j] * x[j]).sum();
        assert!((row - sx[i]).abs() <= 1e-12 * frobenius(&s, m, &[i], &west) + 1e-9);
    }
    // Refused above the limit, by name.
    match g.dense(ode.fault_operator_mut(), m - 1) {
        Err(rsf::Error::GreensTooLarge {
            unknowns, limit, ..
        }) => {
            assert_eq!((unknowns, limit), (m, m - 1));
        }
        other => panic!("{:?}", other.map(|s| s.len())),
    }
    // A fault pair's block is the matrix's entries, bit for bit, from the source's
    // columns alone; names the model has not are refused by name.
    for (r, c) in [("west", "east"), ("east", "west"), ("west", "west")] {
        let (rows, cols) = (g.unknowns_of(r), g.unknowns_of(c));
        let b = g
            .block(ode.fault_operator_mut(), (r, c), cols.len())
            .unwrap();
        assert_eq!(b.len(), rows.len() * cols.len());
        for (ii, &i) in rows.iter().enumerate() {
            for (jj, &j) in cols.iter().enumerate() {
                assert_eq!(b[ii * cols.len() + jj].to_bits(), s[i * m + j].to_bits());
            }
        }
    }
    match g.block(ode.fault_operator_mut(), ("west", "north"), m) {
        Err(rsf::Error::InvalidParameter { name, reason }) => {
            assert!(name == "source" && reason.contains("north"), "{reason}")
        }
        other => panic!("{:?}", other.map(|s| s.len())),
    }
    assert!(matches!(
        g.block(ode.fault_operator_mut(), ("west", "east"), east.len() - 1),
        Err(rsf::Error::GreensTooLarge { .. })
    ));
    assert!(g.apply(ode.fault_operator_mut(), &x[1..]).is_err());
    let mut nan = x.clone();
    nan[3] = f64::NAN;
    assert!(g.apply(ode.fault_operator_mut(), &nan).is_err());
}

#[test]
fn the_cross_block_falls_with_distance_as_a_dislocations_stress() {
    // A 16 m box: faults 2, 4 and 8 m apart stay 3.5 m or more from its sides.
    let mut ratios = Vec::new();
    for d in [2.0, 4.0, 8.0] {
        let mut ode = fault_ode(two_faults(d, 8.0), FaultKernel::Dense);
        let g = ode.greens_functions().unwrap();
        let m = g.dim();
        let s = g.dense(ode.fault_operator_mut(), 10_000).unwrap();
        let (west, east) = (g.unknowns_of("west"), g.unknowns_of("east"));
        let cross = frobenius(&s, m, &west, &east);
        let own = frobenius(&s, m, &west, &west);
        eprintln!("d = {d} m: ‖S_we‖/‖S_ww‖ = {:e}", cross / own);
        assert!(cross > 0.0);
        ratios.push(cross / own);
    }
    // The stress of a slipped segment falls as 1/d² far from it (a factor 4 per doubling
    // in a whole space; the box's held top and bottom bend it).
    for w in ratios.windows(2) {
        let r = w[0] / w[1];
        assert!((3.0..5.0).contains(&r), "{ratios:?}");
    }
}

#[test]
fn the_hierarchical_export_differs_from_the_dense_one_by_its_measured_error() {
    // 1/16 m cells: 15 nodes per fault.
    let model = box_with_faults(2.0, 2.0, 16.0);
    let mut dense = fault_ode(model.clone(), FaultKernel::Dense);
    let kernel = FaultKernel::Hierarchical {
        epsilon: 1e-4,
        leaf_size: 4,
    };
    let mut h = fault_ode(model, kernel);
    let gd = dense.greens_functions().unwrap();
    let gh = h.greens_functions().unwrap();
    assert_eq!(gh.accuracy.kernel, kernel);
    assert_eq!(gd.positions, gh.positions);
    let m = gd.dim();
    let s = gd.dense(dense.fault_operator_mut(), m).unwrap();
    let sh = gh.dense(h.fault_operator_mut(), m).unwrap();
    let diff: Vec<f64> = s.iter().zip(&sh).map(|(a, b)| a - b).collect();
    let all: Vec<usize> = (0..m).collect();
    let error = frobenius(&diff, m, &all, &all) / frobenius(&s, m, &all, &all);
    let reported = gh.accuracy.relative_error;
    eprintln!(
        "m = {m}: ‖S − S_H‖/‖S‖ = {error:e}, reported {reported:e}, low-rank blocks {}, \
         asymmetry of S_H {:e}",
        gh.accuracy.low_rank_blocks,
        asymmetry(&sh, m)
    );
    assert!(gh.accuracy.low_rank_blocks > 0);
    assert!(error > 0.0 && error <= gh.accuracy.tolerance());
    assert!(
        (error - reported).abs() <= 1e-6 * reported + 1e-15,
        "{error:e} {reported:e}"
    );
    assert!(asymmetry(&sh, m) <= 2.0 * gh.accuracy.tolerance());
}

/// Two square faults of 4 × 4 cells of 1 km in a whole space, vertical and striking
/// along y, centred `d` km apart along x: the boundary-element operator's Green's
/// functions.
#[cfg(feature = "halfspace")]
fn element_pair(d: f64) -> (GreensFunctions, Vec<f64>) {
    use rsf::halfspace::{ElementSet, Medium, RectangleElement, Space};
    use rsf::halfspace_operator::{fault_alone_model, ElementOperator, ElementOptions};
    let mut elements = Vec::new();
    for x in [-d / 2.0, d / 2.0] {
        elements.extend(
            RectangleElement::grid([x * 1e3, 0.0, -50e3], 90.0, 90.0, [4e3, 4e3], [4, 4]).unwrap(),
        );
    }
    let medium = Medium::from_shear_poisson(3.2e10, 0.25).unwrap();
    let set = ElementSet::new(medium, Space::WholeSpace, elements).unwrap();
    let mut model = fault_alone_model(&set).unwrap();
    let faults: Vec<usize> = (0..32).map(|e| usize::from(e >= 16)).collect();
    model.frictional_boundary = model
        .frictional_boundary
        .clone()
        .with_faults(vec!["west".into(), "east".into()], &faults)
        .unwrap();
    let mut op = ElementOperator::fault_alone(&model, &set, &ElementOptions::default()).unwrap();
    // The operator's components: each element's strike, then up-dip direction — filled in
    // from the operator (the model's Cartesian labels are not its components).
    let directions: Vec<[f64; 3]> = set.frames().iter().flat_map(|f| [f[0], f[1]]).collect();
    let g = GreensFunctions::new(&model, &op).unwrap();
    assert_eq!(g.directions, directions);
    let s = g.dense(&mut op, 100).unwrap();
    (g, s)
}

/// The boundary-element operator of two faults: described as such (origin, the elements'
/// strike and dip as the unknowns' directions), symmetric, its cross block falling as a
/// dislocation's far-field stress in 3-D, `1/d³` (a factor 8 per doubling).
#[cfg(feature = "halfspace")]
#[test]
fn the_boundary_element_cross_block_falls_as_the_cube_of_the_distance() {
    let mut ratios = Vec::new();
    for d in [16.0, 32.0, 64.0] {
        let (g, s) = element_pair(d);
        let m = g.dim();
        assert_eq!((m, g.origin), (64, OperatorOrigin::BoundaryElements));
        assert_eq!(g.units_s(), "N/m");
        for j in 0..m {
            // Vertical planes striking along y: strike slip along ±y, dip slip along ±z.
            let axis = if g.component[j] == 0 { 1 } else { 2 };
            assert!(
                (g.directions[j][axis].abs() - 1.0).abs() < 1e-12,
                "{:?}",
                g.directions[j]
            );
        }
        let (west, east) = (g.unknowns_of("west"), g.unknowns_of("east"));
        let cross = frobenius(&s, m, &west, &east);
        let own = frobenius(&s, m, &west, &west);
        let asym = asymmetry(&s, m);
        eprintln!(
            "elements, d = {d} km: ‖S_we‖/‖S_ww‖ = {:e}, asymmetry {asym:e}",
            cross / own
        );
        assert!(asym < 1e-12, "{asym:e}");
        ratios.push(cross / own);
    }
    for w in ratios.windows(2) {
        let r = w[0] / w[1];
        assert!((6.0..10.0).contains(&r), "{ratios:?}");
    }
}
