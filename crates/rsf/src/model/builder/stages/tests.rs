//! The stages one at a time on small problems: each stage's output invariants, and the
//! errors a stage is the first to see.

use rsf_fem::{rectangle, Diagonal, DofTransform, SimplexMesh, SparseMatrix};
use rsf_numeric::normal_component;

use super::super::part::Part;
use super::super::ModelBuilder;
use super::constraints::{constrain, Constraints};
use super::domain::Domain;
use super::inputs::check;
use super::matrices::{assemble, Matrices, System};
use super::pairs::{share_and_prescribe, Kinematics};
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
    let (domain, fault) = Domain::cut(&b.hierarchy, &b.fault).unwrap();
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
        let (_, fault) = Domain::cut(&b.hierarchy, &b.fault).unwrap();
        check(&b.body, &b.boundary, &b.fault, fault.as_ref()).map(|i| i.slip_factor)
    };
    let mut b = square_with_fault();
    b.body.material = None;
    assert_eq!(name(run(&b).unwrap_err()), "material");
    let b = square_with_fault().antisymmetric_fault(2.0);
    assert_eq!(name(run(&b).unwrap_err()), "slip_factor");
    // A frictional boundary beside a fault inside the body is Γ_F with it.
    let b = square_with_fault().frictional_boundary("bottom");
    assert_eq!(run(&b).unwrap(), 1.0);
    let mut b = slanted_block().internal_creep(|_| true, 1e-9);
    assert_eq!(name(run(&b).unwrap_err()), "internal_creep");
    b.fault.creep = None;
    b.fault.frictional_boundary = None;
    assert_eq!(name(run(&b).unwrap_err()), "frictional_boundary");
    assert_eq!(run(&slanted_block().antisymmetric_fault(2.0)).unwrap(), 2.0);
    let b = square_with_fault();
    let (_, fault) = Domain::cut(&b.hierarchy, &b.fault).unwrap();
    let inputs = check(&b.body, &b.boundary, &b.fault, fault.as_ref()).unwrap();
    assert!(inputs.fault_part.given.is_none() && inputs.fault_part.minus_faces == ["fault_minus"]);
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
    let (d, f) = Domain::cut(&partly.hierarchy, &Default::default()).unwrap();
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
    let (d, f) = Domain::cut(&contradicting.hierarchy, &Default::default()).unwrap();
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
    let m = assemble(mesh, material, true, &b.boundary.absorbing, &c, None).unwrap();
    assert_eq!(
        m.stiffness.symbolic().row_idx(),
        m.energy_norm
            .as_ref()
            .expect("with mass")
            .symbolic()
            .row_idx()
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
    let (domain, fault) = Domain::cut(&b.hierarchy, &b.fault).unwrap();
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
    let m = assemble(mesh, material, true, &[], &c, None).unwrap();
    let shared = share_and_prescribe(
        fault,
        &m.stiffness,
        mesh,
        Kinematics {
            creep: None,
            slip: None,
        },
        &mut c,
    )
    .unwrap();
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
    let fb = fault_order::frictional_boundary(mesh, &c.gamma_f, 1.0, Some(&shared), None).unwrap();
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
    let fb =
        fault_order::frictional_boundary(domain.mesh(), &c.gamma_f, 2.0, None, c.boundary.as_ref())
            .unwrap();
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

/// Every kept node's columns of `part` have the rows and bits of `whole`'s, every other
/// column is empty; the shapes agree.
pub(crate) fn assert_node_columns(
    what: &str,
    whole: &SparseMatrix,
    part: &SparseMatrix,
    keep: &[bool],
) {
    assert_eq!(
        (part.nrows(), part.ncols()),
        (whole.nrows(), whole.ncols()),
        "{what}"
    );
    let c = whole.ncols() / keep.len();
    for j in 0..whole.ncols() {
        if keep[j / c] {
            assert_eq!(
                part.row_idx_of_col_raw(j),
                whole.row_idx_of_col_raw(j),
                "{what} {j}"
            );
            let bits = |a: &SparseMatrix| -> Vec<u64> {
                a.val_of_col(j).iter().map(|x| x.to_bits()).collect()
            };
            assert_eq!(bits(part), bits(whole), "{what}: column {j}");
        } else {
            assert!(part.row_idx_of_col_raw(j).is_empty(), "{what}: column {j}");
        }
    }
}

/// A model of some columns against the whole model ([`crate::Model::check_part_of`]).
pub(crate) fn assert_columns_of<const D: usize, const C: usize>(
    whole: &crate::Model<D, C>,
    part: &crate::Model<D, C>,
    keep: &[bool],
) {
    assert_eq!(part.columns.as_deref(), Some(keep));
    part.validate().unwrap();
    part.check_part_of(whole).unwrap();
    assert!(whole.check_part_of(part).is_err() || keep.iter().all(|&k| k));
}

/// The models of every keep-set's columns of `builder()`'s model (the equilibrium given:
/// the whole model's) against the whole model.
fn assert_every_keep_set<const C: usize>(builder: impl Fn() -> ModelBuilder<2, C>) {
    let whole = builder().build().unwrap();
    for keep in keep_sets(whole.num_nodes()) {
        let part = builder()
            .build_columns(&keep, |_| Ok(whole.initial_displacement.clone()))
            .unwrap();
        assert_columns_of(&whole, &part, &keep);
    }
}

/// All, none, the first half and a pseudo-random half of `n` nodes.
pub(crate) fn keep_sets(n: usize) -> Vec<Vec<bool>> {
    let mut x = 57u64;
    let mut random = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        x >> 63 == 1
    };
    vec![
        vec![true; n],
        vec![false; n],
        (0..n).map(|p| p < n / 2).collect(),
        (0..n).map(|_| random()).collect(),
    ]
}

/// The slanted block (nodal frames at every fault node, an absorbing end, a traction),
/// with and without inertia and with an antisymmetric fault's scaling: every keep-set's
/// model has the whole model's columns and vectors, the equilibrium given the kept
/// columns of `K`.
#[test]
fn a_model_of_some_columns_has_the_whole_models_columns() {
    type Variant = fn(ModelBuilder<2>) -> ModelBuilder<2>;
    let variants: [(&str, Variant); 3] = [
        ("slanted", |b| b),
        ("antisymmetric", |b| b.antisymmetric_fault(2.0)),
        ("quasistatic", |b| {
            // No inertia: no absorbing parts either.
            let flat = rectangle([0.0; 2], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
            let _ = b;
            ModelBuilder::refined(flat, 1)
                .unwrap()
                .material(Material::new(1e8, 0.25, 2.7e3))
                .gravity([0.0, -9.81])
                .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
                .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
                .without_mass()
        }),
    ];
    for (name, variant) in variants {
        let whole = variant(slanted_block()).build().unwrap();
        for keep in keep_sets(whole.num_nodes()) {
            let part = variant(slanted_block())
                .build_columns(&keep, |system| {
                    assert_eq!(system.columns, Some(&keep[..]));
                    assert_node_columns("K given", &whole.stiffness, system.stiffness, &keep);
                    assert_eq!(system.load, &whole.load[..]);
                    assert_eq!(system.fixed, &whole.fixed[..]);
                    assert_eq!(system.prolongations.len(), whole.prolongations.len());
                    Ok(whole.initial_displacement.clone())
                })
                .unwrap();
            println!(
                "{name}: {} of {} nodes",
                keep.iter().filter(|&&k| k).count(),
                keep.len()
            );
            assert_columns_of(&whole, &part, &keep);
        }
    }
}

/// A user's medium that only assembles whole matrices gets the default
/// `assemble_columns` (the whole matrices' columns, the same bits); the antiplane medium
/// assembles its columns itself.
#[test]
fn a_user_medium_and_the_antiplane_medium_on_columns() {
    struct Plain(Material);
    impl crate::model::Medium<2, 2> for Plain {
        fn density(&self) -> f64 {
            self.0.density
        }
        fn assemble(
            &self,
            mesh: &SimplexMesh<2>,
            with_mass: bool,
        ) -> crate::Result<crate::model::MediumMatrices> {
            crate::model::Medium::<2, 2>::assemble(&self.0, mesh, with_mass)
        }
    }
    let plain = || {
        let flat = rectangle([0.0; 2], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
        ModelBuilder::refined(flat, 1)
            .unwrap()
            .material(Plain(Material::new(1e8, 0.25, 2.7e3)))
            .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
            .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
    };
    assert_every_keep_set(plain);
    let antiplane = || {
        let flat = rectangle([0.0; 2], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
        ModelBuilder::scalar_refined(flat, 1)
            .unwrap()
            .material(crate::model::AntiplaneMaterial::new(3e10, 2670.0))
            .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4])
            .absorbing_boundary(Part::predicate("right", |x| x[0] > 2.0 - 1e-9))
            .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
    };
    assert_every_keep_set(antiplane);
}

/// `build_columns` refuses a keep-set of another length, a fault inside the body and an
/// equilibrium of another length, each by name; a model whose column flags or matrices
/// disagree is refused by `validate`.
#[test]
fn a_model_of_some_columns_refuses_what_it_cannot_build() {
    let name = |e: Error| match e {
        Error::InvalidParameter { name, .. } => name,
        e => panic!("{e}"),
    };
    let n = slanted_block().mesh().num_vertices();
    let e = slanted_block().build_columns(&vec![true; n + 1], |_| unreachable!());
    assert_eq!(name(e.unwrap_err()), "keep");
    let nf = square_with_fault().mesh().num_vertices();
    let e = square_with_fault().build_columns(&vec![true; nf], |_| unreachable!());
    assert_eq!(name(e.unwrap_err()), "internal_fault");
    let e = slanted_block().build_columns(&vec![true; n], |s| Ok(vec![0.0; s.load.len() - 1]));
    assert_eq!(name(e.unwrap_err()), "equilibrium");
    let e = slanted_block().build_columns(&vec![true; n], |_| {
        Err(Error::Equilibrium(rsf_fem::Error::PatternMismatch))
    });
    assert!(matches!(e, Err(Error::Equilibrium(_))));
    let keep: Vec<bool> = (0..n).map(|p| p < n / 2).collect();
    let whole = slanted_block().build().unwrap();
    let mut part = slanted_block()
        .build_columns(&keep, |_| Ok(whole.initial_displacement.clone()))
        .unwrap();
    // `check_part_of` finds the first field that differs.
    part.check_part_of(&whole).unwrap();
    let mut other = part.clone();
    other.load[3] = f64::from_bits(other.load[3].to_bits() ^ 1);
    assert_eq!(name(other.check_part_of(&whole).unwrap_err()), "load");
    let mut other = part.clone();
    let j = 2 * keep.iter().position(|&k| k).unwrap();
    let k = other.stiffness.symbolic().col_ptr()[j];
    let v = &mut other.stiffness.val_mut()[k];
    *v = f64::from_bits(v.to_bits() ^ 1);
    assert_eq!(name(other.check_part_of(&whole).unwrap_err()), "stiffness");
    let mut other = part.clone();
    other.columns = Some(vec![true; n]);
    assert_eq!(name(other.check_part_of(&whole).unwrap_err()), "stiffness");
    assert_eq!(name(whole.check_part_of(&part).unwrap_err()), "columns");
    let mut other = part.clone();
    other.initial_displacement[0] += 1.0;
    assert_eq!(
        name(other.check_part_of(&whole).unwrap_err()),
        "initial_displacement"
    );
    // A column model whose flags do not match its matrices.
    part.columns = Some(vec![false; n]);
    assert_eq!(name(part.validate().unwrap_err()), "stiffness");
    part.columns = Some(vec![true; n - 1]);
    assert_eq!(name(part.validate().unwrap_err()), "columns");
}
