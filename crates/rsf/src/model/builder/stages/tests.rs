//! The stages one at a time on small problems: each stage's output invariants, and the
//! errors a stage is the first to see.

use rsf_fem::{rectangle, Diagonal, DofTransform, SimplexMesh, SparseMatrix};
use rsf_numeric::normal_component;

use super::super::part::Part;
use super::super::ModelBuilder;
use super::constraints::{constrain, Constraints};
use super::domain::Domain;
use super::inputs::{check, FaultPart};
use super::matrices::{assemble, Matrices, System};
use super::pairs::share_and_prescribe;
use super::{fault_order, loads, prolongations};
use crate::model::medium::Material;
use crate::Error;

const PHI: f64 = 0.4;

fn rot(phi: f64, x: [f64; 2]) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
}

/// A 2 m × 1 m block turned by `PHI`, refined once, its parts named by their unturned
/// position: clamped top moving along the block, traction on the right end, absorbing
/// left end, frictional bottom (every node of it slanted).
fn slanted_block() -> ModelBuilder<2> {
    let flat = rectangle([0.0; 2], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
    let turned = flat.vertices().iter().map(|&x| rot(PHI, x)).collect();
    let mesh = SimplexMesh::new(turned, flat.cells().to_vec()).unwrap();
    let back = |x: &[f64; 2]| rot(-PHI, *x);
    ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(Material::new(1e8, 0.25, 2.7e3))
        .gravity(rot(PHI, [0.0, -9.81]))
        .dirichlet(
            Part::predicate("top", move |x| back(x)[1] > 1.0 - 1e-9),
            rot(PHI, [1e-4, 0.0]),
        )
        .neumann(
            Part::predicate("right", move |x| back(x)[0] > 2.0 - 1e-9),
            |_| [-1e3, 0.0],
        )
        .absorbing_boundary(Part::predicate("left", move |x| back(x)[0] < 1e-9))
        .frictional_boundary(Part::predicate("bottom", move |x| back(x)[1] < 1e-9))
}

/// A 2 m square with a clamped top and bottom, the bottom's halves `x < 0` and `x > 0`
/// moving with `left` and `right`, cut by a fault from (0, −1) (on the clamped bottom:
/// that pair is prescribed) up to (0, 0.5); its plus side is `x < 0`.
fn square_with_fault_moving(left: [f64; 2], right: [f64; 2]) -> ModelBuilder<2> {
    let square = rectangle([-1.0; 2], [2.0; 2], 5, 5, Diagonal::Forward).unwrap();
    ModelBuilder::refined(square, 1)
        .unwrap()
        .material(Material::new(1e10, 0.25, 2700.0))
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
        .dirichlet(
            Part::predicate("bottom left", |x| x[1] < -1.0 + 1e-9 && x[0] < 0.0),
            left,
        )
        .dirichlet(
            Part::predicate("bottom right", |x| x[1] < -1.0 + 1e-9 && x[0] > 0.0),
            right,
        )
        .internal_fault("fault", [0.0, -1.0], [0.0, 0.5])
}

/// [`square_with_fault_moving`] with the whole bottom at rest.
fn square_with_fault() -> ModelBuilder<2> {
    square_with_fault_moving([0.0; 2], [0.0; 2])
}

/// Stages 1–3 of `b`.
fn constraints_of(b: &ModelBuilder<2>) -> (Domain<'_, 2>, Constraints<2, 2>) {
    let (domain, fault) =
        Domain::cut(&b.hierarchy, b.fault.internal.as_ref(), b.fault.tangent).unwrap();
    let inputs = check(&b.body, &b.boundary, &b.fault, fault.as_ref()).unwrap();
    let c = constrain(
        domain.mesh(),
        &b.boundary.dirichlet,
        &inputs.fault_part,
        fault.as_ref(),
        &b.fault,
    )
    .unwrap();
    (domain, c)
}

fn apply(a: &SparseMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    rsf_fem::spmv_add(a.as_ref(), 1.0, x, &mut y);
    y
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Exactly symmetric, as the solvers demand.
fn assert_symmetric(a: &SparseMatrix) {
    for j in 0..a.ncols() {
        for (i, &v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
            let k = a
                .row_idx_of_col(i)
                .position(|r| r == j)
                .expect("symmetric pattern");
            assert_eq!(v.to_bits(), a.val_of_col(i)[k].to_bits(), "({i}, {j})");
        }
    }
}

/// Stage 2 reports the first missing or contradictory setting, in its order.
#[test]
fn inputs_are_checked_in_order() {
    let name = |e: Error| match e {
        Error::InvalidParameter { name, .. } => name,
        e => panic!("{e}"),
    };
    let run = |b: &ModelBuilder<2>| {
        let (_, fault) =
            Domain::cut(&b.hierarchy, b.fault.internal.as_ref(), b.fault.tangent).unwrap();
        check(&b.body, &b.boundary, &b.fault, fault.as_ref()).map(|i| i.slip_factor)
    };
    let mut b = square_with_fault();
    b.body.material = None;
    assert_eq!(name(run(&b).unwrap_err()), "material");
    let b = square_with_fault().antisymmetric_fault(2.0);
    assert_eq!(name(run(&b).unwrap_err()), "slip_factor");
    let b = square_with_fault().frictional_boundary("bottom");
    assert_eq!(name(run(&b).unwrap_err()), "frictional_boundary");
    let mut b = slanted_block().internal_creep(|_| true, 1e-9);
    assert_eq!(name(run(&b).unwrap_err()), "internal_creep");
    b.fault.creep = None;
    b.fault.frictional_boundary = None;
    assert_eq!(name(run(&b).unwrap_err()), "frictional_boundary");
    assert_eq!(run(&slanted_block().antisymmetric_fault(2.0)).unwrap(), 2.0);
    let b = square_with_fault();
    let (_, fault) = Domain::cut(&b.hierarchy, b.fault.internal.as_ref(), None).unwrap();
    let inputs = check(&b.body, &b.boundary, &b.fault, fault.as_ref()).unwrap();
    assert!(
        matches!(inputs.fault_part, FaultPart::MinusFace(Part::Tag(ref t)) if t == "fault_minus")
    );
}

/// Stage 3 on a slanted Γ_F: every frictional node has a frame whose last column is the
/// inward normal and its normal component fixed in it; the clamped nodes' velocity is in
/// their frame; a prescribed velocity only at a fixed dof.
#[test]
fn constraints_fix_the_normal_in_the_frames_of_a_slanted_fault() {
    let b = slanted_block();
    let (domain, c) = constraints_of(&b);
    let mesh = domain.mesh();
    assert_eq!(
        c.frames.nodes,
        c.gamma_f.nodes(),
        "every node of Γ_F is slanted"
    );
    let inward = rot(PHI, [0.0, 1.0]);
    let top_velocity = rot(PHI, [1e-4, 0.0]);
    for (&p, q) in c.frames.nodes.iter().zip(&c.frames.rotations) {
        let nc = normal_component(2);
        assert!(
            (0..2).all(|r| (q[r][nc] - inward[r]).abs() < 1e-12),
            "{q:?}"
        );
        assert!(c.fixed[2 * p + nc]);
    }
    for (i, w) in c.velocity.iter().enumerate() {
        assert!(w.is_none() || c.fixed[i], "velocity at free dof {i}");
    }
    // A clamped top node off Γ_F keeps its Cartesian velocity.
    let top = (0..mesh.num_vertices())
        .find(|&p| rot(-PHI, mesh.vertices()[p])[1] > 1.0 - 1e-9)
        .unwrap();
    assert_eq!(c.velocity[2 * top], Some(top_velocity[0]));
    // The Dirichlet data of the unknown s·u: zeros dropped, each factor times s.
    let dirichlet = c.dirichlet_velocity(2.0, crate::model::TimeFunction::Constant(1.0));
    assert!(dirichlet.dofs.iter().all(|&i| c.fixed[i]));
    for (&i, &f) in dirichlet.dofs.iter().zip(&dirichlet.factors) {
        assert_eq!(f, 2.0 * c.velocity[i].unwrap());
    }
}

/// A Γ_F node clamped by a Dirichlet part gets its velocity in its frame, `Q_pᵀ w`; one
/// with only some Cartesian components fixed is refused; two parts disagreeing at a node
/// are refused naming it.
#[test]
fn constraints_turn_clamped_fault_nodes_into_their_frame_and_refuse_contradictions() {
    let back = |x: &[f64; 2]| rot(-PHI, *x);
    // The top's velocity (the two parts meet at the top corner).
    let w = rot(PHI, [1e-4, 0.0]);
    let b = slanted_block().dirichlet(Part::predicate("left end", move |x| back(x)[0] < 1e-9), w);
    let (domain, c) = constraints_of(&b);
    let corner = (0..domain.mesh().num_vertices())
        .find(|&p| {
            let y = back(&domain.mesh().vertices()[p]);
            y[0].abs() < 1e-9 && y[1].abs() < 1e-9
        })
        .unwrap();
    let k = c.frames.nodes.binary_search(&corner).unwrap();
    let q = c.frames.rotations[k];
    for col in 0..2 {
        let expected = q[0][col] * w[0] + q[1][col] * w[1];
        assert!((c.velocity[2 * corner + col].unwrap() - expected).abs() < 1e-20);
    }
    let partly = slanted_block().dirichlet_components(
        Part::predicate("left end", move |x| back(x)[0] < 1e-9),
        &[0],
        w,
    );
    let (d, f) = Domain::cut(&partly.hierarchy, None, None).unwrap();
    let inputs = check(&partly.body, &partly.boundary, &partly.fault, f.as_ref()).unwrap();
    let e = constrain(
        d.mesh(),
        &partly.boundary.dirichlet,
        &inputs.fault_part,
        None,
        &partly.fault,
    )
    .err()
    .expect("a partly fixed slanted node");
    assert!(e.to_string().contains("only some"), "{e}");
    let contradicting = slanted_block().dirichlet(
        Part::predicate("top again", move |x| back(x)[1] > 1.0 - 1e-9),
        [0.0, 0.0],
    );
    let (d, f) = Domain::cut(&contradicting.hierarchy, None, None).unwrap();
    let inputs = check(
        &contradicting.body,
        &contradicting.boundary,
        &contradicting.fault,
        f.as_ref(),
    )
    .unwrap();
    let e = constrain(
        d.mesh(),
        &contradicting.boundary.dirichlet,
        &inputs.fault_part,
        None,
        &contradicting.fault,
    )
    .err()
    .expect("two velocities at one dof");
    assert!(e.to_string().contains("an earlier part"), "{e}");
}

/// Stages 4–8 on the slanted block: the matrices share one pattern, the scaling by `s` is
/// exact, and in the frames every matrix is exactly symmetric with the same quadratic
/// form `(Rx)ᵀA(Ry)`; the identity leaves the system as it is, bit for bit.
#[test]
fn the_system_scales_exactly_and_keeps_its_energy_in_the_frames() {
    let b = slanted_block();
    let (domain, c) = constraints_of(&b);
    let mesh = domain.mesh();
    let material = b.body.material.as_deref().unwrap();
    let m = assemble(mesh, material, true, &b.boundary.absorbing, &c).unwrap();
    assert_eq!(
        m.stiffness.symbolic().row_idx(),
        m.energy_norm.symbolic().row_idx()
    );
    let damping = m
        .absorbing
        .as_ref()
        .expect("the left end's dashpots")
        .damping
        .clone();
    let load = loads::load(mesh, material, &b.body, &b.boundary).unwrap();
    let total: f64 = load.iter().skip(1).step_by(2).sum::<f64>();
    assert!(total < 0.0, "gravity pulls down: {total}");
    let cartesian = System {
        matrices: Matrices {
            stiffness: m.stiffness.clone(),
            mass: m.mass.clone(),
            energy_norm: m.energy_norm.clone(),
            absorbing: m.absorbing.clone(),
        },
        load: load.clone(),
    };
    let scaled = System {
        matrices: m,
        load: load.clone(),
    }
    .scaled(2.0)
    .unwrap();
    let quarter: Vec<f64> = cartesian
        .matrices
        .stiffness
        .val()
        .iter()
        .map(|v| v / 4.0)
        .collect();
    assert_eq!(scaled.matrices.stiffness.val(), &quarter[..]);
    assert!(scaled.load.iter().zip(&load).all(|(a, b)| *a == b / 2.0));
    let identity = rsf_fem::NodalFrames::<2>::default();
    let same = scaled.in_unknowns(&identity).unwrap();
    assert_eq!(same.matrices.stiffness.val(), &quarter[..]);

    let (k, mass) = (
        cartesian.matrices.stiffness.clone(),
        cartesian.matrices.mass.clone().unwrap(),
    );
    let framed = cartesian.in_unknowns(&c.frames).unwrap();
    let n = load.len();
    let x: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
    let y: Vec<f64> = (0..n).map(|i| ((i * 5 % 13) as f64) - 6.0).collect();
    let (rx, ry) = (
        c.frames.to_cartesian(&x).unwrap(),
        c.frames.to_cartesian(&y).unwrap(),
    );
    let pairs = [
        (&framed.matrices.stiffness, &k),
        (framed.matrices.mass.as_ref().unwrap(), &mass),
        (
            &framed.matrices.absorbing.as_ref().unwrap().damping,
            &damping,
        ),
    ];
    for (a, cart) in pairs {
        assert_symmetric(a);
        let (lhs, rhs) = (dot(&x, &apply(a, &y)), dot(&rx, &apply(cart, &ry)));
        assert!(
            (lhs - rhs).abs() <= 1e-12 * rhs.abs().max(1.0),
            "{lhs} vs {rhs}"
        );
    }
    let work = (dot(&framed.load, &x), dot(&load, &rx));
    assert!((work.0 - work.1).abs() <= 1e-12 * work.1.abs(), "{work:?}");
}

/// Stages 7 and 9 on a fault inside the body: the pair on the clamped bottom is
/// prescribed (its jump the sides' relative velocity in the pair frame, its mean the
/// stiffness-weighted mean) and not a frictional node; the others are, in order along the
/// fault, with the minus face's weights.
#[test]
fn a_clamped_pair_is_prescribed_and_the_free_pairs_are_the_fault() {
    // The sides slide past each other along the fault (no opening): plus (x < 0) up,
    // minus down.
    let (vp, vm) = ([0.0, 1e-4], [0.0, -1e-4]);
    let b = square_with_fault_moving(vp, vm);
    let (domain, fault) =
        Domain::cut(&b.hierarchy, b.fault.internal.as_ref(), b.fault.tangent).unwrap();
    let fault = fault.unwrap();
    let inputs = check(&b.body, &b.boundary, &b.fault, Some(&fault)).unwrap();
    let mesh = domain.mesh();
    let mut c = constrain(
        mesh,
        &b.boundary.dirichlet,
        &inputs.fault_part,
        Some(&fault),
        &b.fault,
    )
    .unwrap();
    let material = b.body.material.as_deref().unwrap();
    let m = assemble(mesh, material, true, &[], &c).unwrap();
    let shared = share_and_prescribe(fault, &m.stiffness, mesh, None, &mut c).unwrap();
    let pairs = shared.fault.pairs().to_vec();
    let clamped: Vec<usize> = (0..pairs.len()).filter(|&k| shared.prescribed[k]).collect();
    assert_eq!(clamped.len(), 1, "the pair on the clamped bottom");
    let (mi, pl) = pairs[clamped[0]];
    assert!((mesh.vertices()[mi][1] + 1.0).abs() < 1e-12);
    // The jump: tangential t·(v⁺ − v⁻), the normal component tied at 0; the mean of two
    // opposite velocities (the same material on both sides: β = ½) is at rest.
    let q = shared.fault.transform.frames[clamped[0]];
    let slip = q[0][0] * (vp[0] - vm[0]) + q[1][0] * (vp[1] - vm[1]);
    assert!((slip.abs() - 2e-4).abs() < 1e-18, "{slip}");
    assert_eq!(c.velocity[2 * mi..2 * mi + 2], [Some(slip), Some(0.0)]);
    assert_eq!(c.velocity[2 * pl..2 * pl + 2], [Some(0.0), Some(0.0)]);
    assert!((0..2).all(|k| c.fixed[2 * mi + k] && c.fixed[2 * pl + k]));
    let fb = fault_order::frictional_boundary(mesh, &c.gamma_f, 1.0, Some(&shared)).unwrap();
    let free: Vec<usize> = pairs
        .iter()
        .zip(&shared.prescribed)
        .filter(|(_, &p)| !p)
        .map(|(&(mi, _), _)| mi)
        .collect();
    let along: Vec<usize> = fb.along.iter().map(|&k| fb.nodes[k]).collect();
    assert_eq!(along, free);
    let ys: Vec<f64> = along.iter().map(|&p| mesh.vertices()[p][1]).collect();
    assert!(
        ys.windows(2).all(|w| w[0] < w[1]),
        "along the fault: {ys:?}"
    );
    assert!(
        fb.weights.iter().all(|&w| (w - 0.25).abs() < 1e-12),
        "{:?}",
        fb.weights
    );
}

/// Stage 9 on a boundary fault: Γ_F's nodes sorted by their coordinates, weights `w/s`
/// summing to the fault's length over `s`.
#[test]
fn a_boundary_fault_is_in_coordinate_order_with_weights_over_s() {
    let b = slanted_block();
    let (domain, c) = constraints_of(&b);
    let fb = fault_order::frictional_boundary(domain.mesh(), &c.gamma_f, 2.0, None).unwrap();
    let xs: Vec<[f64; 2]> = fb
        .along
        .iter()
        .map(|&k| domain.mesh().vertices()[fb.nodes[k]])
        .collect();
    assert!(xs.windows(2).all(|w| w[0] < w[1]), "{xs:?}");
    assert!((fb.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    assert_eq!(fb.slip_factor, 2.0);
}

/// Stage 10: coarse prolongations stay Cartesian, the finest is `T⁻¹ P` (here `Rᵀ P`),
/// unchanged under the identity.
#[test]
fn only_the_finest_prolongation_takes_the_change_of_variables() {
    let b = slanted_block();
    let (domain, c) = constraints_of(&b);
    let plain =
        prolongations::prolongations::<2, 2>(&domain, &rsf_fem::NodalFrames::<2>::default())
            .unwrap();
    assert_eq!(plain.len(), 1);
    assert_eq!(plain[0].val(), b.hierarchy.vector_prolongation(1).val());
    let framed = prolongations::prolongations::<2, 2>(&domain, &c.frames).unwrap();
    let coarse: Vec<f64> = (0..framed[0].ncols()).map(|j| j as f64).collect();
    let back = c.frames.to_cartesian(&apply(&framed[0], &coarse)).unwrap();
    let direct = apply(&plain[0], &coarse);
    assert!(back.iter().zip(&direct).all(|(a, b)| (a - b).abs() < 1e-12));
}
