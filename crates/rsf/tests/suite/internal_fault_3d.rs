//! Faults inside a 3-D body (docs/faults-inside.md, "In 3-D"): a planar fault cut into a
//! tetrahedron mesh ([`ModelBuilder::internal_fault_polygon`]), written in the mean–jump
//! unknowns of its split pairs like the 2-D one. A uniform slip on a fault through the
//! whole body is a rigid motion of the two blocks (no stress); TNNMG on the split
//! hierarchy and the direct solver give the same slip history of a partly stuck buried
//! fault, the fault never opens, and the same problem turned by a rotation slips the same;
//! the fault ODE (condensed onto the jumps) and the implicit scheme agree.
use crate::common::{
    assert_first_order, assert_first_order_with_normal_stress, fault_ode_last_slip,
    history_difference, implicit_last_slip, implicit_scheme, implicit_slip_errors,
    internal_fault_displacements, largest_difference, largest_slip, partly_stuck_history,
    run_tresca_steps, slip_and_jump, tight_fault_ode, QuasiDynamic,
};
use rsf::fem::{cuboid, SimplexMesh};
use rsf::normal_stress::NormalStress;
use rsf::{Material, Model, ModelBuilder, Part, SolverKind, StepView};

/// `x` rotated by `q` (row-major).
fn rotate(q: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| (0..3).map(|c| q[r][c] * x[c]).sum())
}

/// `x` rotated back by `qᵀ`.
fn rotate_back(q: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| (0..3).map(|c| q[c][r] * x[c]).sum())
}

/// The rotation about the unit axis `(1, 2, 2)/3` by `angle` (rad).
fn rotation(angle: f64) -> [[f64; 3]; 3] {
    let k = [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    let (s, c) = angle.sin_cos();
    std::array::from_fn(|r| {
        std::array::from_fn(|col| {
            let cross = match (r, col) {
                (0, 1) => -k[2],
                (0, 2) => k[1],
                (1, 0) => k[2],
                (1, 2) => -k[0],
                (2, 0) => -k[1],
                (2, 1) => k[0],
                _ => 0.0,
            };
            let id = if r == col { 1.0 } else { 0.0 };
            c * id + s * cross + (1.0 - c) * k[r] * k[col]
        })
    })
}

/// The cube `[-1, 1]³` of 5 × 5 × 5 coarse vertices rotated by `q`, refined once.
fn cube(q: &[[f64; 3]; 3]) -> SimplexMesh<3> {
    let mesh = cuboid([-1.0; 3], [2.0; 3], [5, 5, 5]).unwrap();
    let moved: Vec<[f64; 3]> = mesh.vertices().iter().map(|&x| rotate(q, x)).collect();
    mesh.with_moved_vertices(moved).unwrap()
}

/// The cube rotated by `q` with the fault `x = 0` over `|y|, |z| ≤ half` (rotated), its
/// faces `x = ±1` moving oppositely along y — simple shear of the fault — no inertia.
fn sheared_cube(q: [[f64; 3]; 3], half: f64) -> rsf::Result<Model<3>> {
    sheared_cube_with_tangent(q, half, [0.0, 1.0, 0.0])
}

/// [`sheared_cube`] with the frames' first tangent along `tangent` (unrotated).
fn sheared_cube_with_tangent(
    q: [[f64; 3]; 3],
    half: f64,
    tangent: [f64; 3],
) -> rsf::Result<Model<3>> {
    let v = 1e-4;
    let corners = [
        [0.0, -half, -half],
        [0.0, half, -half],
        [0.0, half, half],
        [0.0, -half, half],
    ]
    .map(|x| rotate(&q, x));
    ModelBuilder::refined(cube(&q), 1)?
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("plus face", move |x| rotate_back(&q, *x)[0] > 1.0 - 1e-9),
            rotate(&q, [0.0, v, 0.0]),
        )
        .dirichlet(
            Part::predicate("minus face", move |x| rotate_back(&q, *x)[0] < -1.0 + 1e-9),
            rotate(&q, [0.0, -v, 0.0]),
        )
        .fault_tangent(rotate(&q, tangent))
        .internal_fault_polygon("fault", &corners)
        .build()
}

/// A fault through the whole body: moving each block rigidly (the minus side by `−s/2`,
/// the plus side by `+s/2` along a direction in the fault) stresses nothing; in the model's
/// unknowns that field's jump is the tangential `s` at every pair.
#[test]
fn uniform_slip_on_a_fault_through_the_body_is_a_rigid_motion_of_the_two_blocks() {
    for angle in [0.0, 0.7] {
        let q = rotation(angle);
        let model = sheared_cube(q, 1.0).unwrap();
        let f = model.internal_fault.as_ref().unwrap();
        assert!(f.faults()[0].tips().is_empty(), "every fault vertex split");
        assert_eq!(f.pairs().len(), 81, "9 × 9 fine fault vertices");
        // A slip of 1 mm along (0, 0.6, 0.8) in the fault's own coordinates.
        let s = rotate(&q, [0.0, 6e-4, 8e-4]);
        let mut plus = vec![false; model.vertices.len()];
        for &(_, pl) in f.pairs() {
            plus[pl] = true;
        }
        let side = |p: usize| {
            let x = rotate_back(&q, model.vertices[p])[0];
            plus[p] || (x > 1e-9 && !f.pairs().iter().any(|&(mi, _)| mi == p))
        };
        let u: Vec<f64> = (0..model.vertices.len())
            .flat_map(|p| {
                let sign = if side(p) { 0.5 } else { -0.5 };
                s.map(|c| sign * c)
            })
            .collect();
        let t_inv = &f.transform.t_inv;
        let mut u_model = vec![0.0; u.len()];
        for j in 0..t_inv.ncols() {
            for (i, &w) in t_inv.row_idx_of_col(j).zip(t_inv.val_of_col(j)) {
                u_model[i] += w * u[j];
            }
        }
        // The jump blocks hold (s·t₁, s·t₂, 0): the slip is tangential.
        for (k, &(mi, _)) in f.pairs().iter().enumerate() {
            let r = f.transform.frames[k];
            let j: [f64; 3] = std::array::from_fn(|a| (0..3).map(|b| r[b][a] * s[b]).sum());
            for c in 0..3 {
                assert!((u_model[3 * mi + c] - j[c]).abs() < 1e-15, "{k} {c}");
            }
            assert!(j[2].abs() < 1e-15, "the slip is tangential");
        }
        // K' u' = 0 to round-off.
        let k = &model.stiffness;
        let mut ku = vec![0.0; u.len()];
        let mut scale = 0.0f64;
        for j in 0..k.ncols() {
            for (i, &w) in k.row_idx_of_col(j).zip(k.val_of_col(j)) {
                ku[i] += w * u_model[j];
                scale = scale.max((w * u_model[j]).abs());
            }
        }
        let residual = ku.iter().fold(0.0f64, |m, x| m.max(x.abs())) / scale;
        eprintln!("turned by {angle}: |K'u'| / max|K'_ij u'_j| = {residual:e}");
        assert!(residual < 1e-12, "{residual:e}");
    }
}

/// Per step and pair: the slip's length; checks at every step that the observers' slip is
/// the Cartesian jump of the two sides' displacements and that the fault does not open.
struct Slips {
    rows: Vec<Vec<f64>>,
}

impl rsf::Observer<3> for Slips {
    fn observe(&mut self, s: &StepView<'_, 3, 3>) -> rsf::Result<rsf::Flow> {
        let (f, u, u0) = internal_fault_displacements(s)?;
        let mut row = Vec::new();
        for (k, &(mi, pl)) in f.pairs().iter().enumerate() {
            let (slip, jump) = slip_and_jump(s, (&u, &u0), (mi, pl));
            let length = |x: [f64; 3]| x.iter().map(|c| c * c).sum::<f64>().sqrt();
            let scale = length(slip).max(1e-12);
            let d: [f64; 3] = std::array::from_fn(|c| slip[c] - jump[c]);
            assert!(length(d) < 1e-9 * scale, "{k}");
            // Each side's own displacement at a split vertex (Model::vertex_value).
            for side in [mi, pl] {
                let own = s.displacement(side);
                let size = (0..3).fold(1e-300f64, |m, c| m.max(u[3 * side + c].abs()));
                for c in 0..3 {
                    assert!((own[c] - u[3 * side + c]).abs() <= 1e-14 * size, "{k} {c}");
                }
            }
            // No opening: the jump is in the fault's plane (−(last column of R) = n).
            let r = f.transform.frames[k];
            let opening: f64 = (0..3).map(|c| jump[c] * r[c][2]).sum::<f64>().abs();
            assert!(opening < 1e-12 * scale, "opening {opening:e}");
            row.push(length(slip));
        }
        self.rows.push(row);
        Ok(rsf::Flow::Continue(()))
    }
}

/// [`slips_of`] on the sheared cube turned by `angle` with the
/// buried fault `|y|, |z| ≤ 0.5` (its rim tips inside the body): the slip of every pair
/// at every step, pairs in the order of their unrotated coordinates.
fn slip_history(angle: f64, solver: SolverKind) -> Vec<Vec<f64>> {
    let q = rotation(angle);
    let model = sheared_cube(q, 0.5).unwrap();
    let f = model.internal_fault.as_ref().unwrap();
    // Pairs sorted by their position in the unrotated fault.
    let mut order: Vec<usize> = (0..f.pairs().len()).collect();
    let key = |k: usize| {
        let x = rotate_back(&q, model.vertices[f.pairs()[k].0]);
        ((x[1] * 1e6).round() as i64, (x[2] * 1e6).round() as i64)
    };
    order.sort_by_key(|&k| key(k));
    slips_of(model.clone(), solver, q)
        .iter()
        .map(|row| order.iter().map(|&k| row[k]).collect())
        .collect()
}

/// TNNMG (on the two-level hierarchy, both levels split) and the direct solver give the
/// same slip history on a buried fault that is partly stuck (the slip starts at the
/// centre and spreads to all nine pairs), and the problem turned by 0.7 rad about
/// (1, 2, 2) slips the same.
#[test]
fn a_buried_3d_fault_slips_the_same_with_both_solvers_and_turned() {
    let direct = slip_history(0.0, SolverKind::Direct);
    let largest = partly_stuck_history(&direct);
    assert_eq!(
        direct[0].len(),
        9,
        "3 × 3 inner vertices split, the rim's 16 tips"
    );
    let differs = |a: &[Vec<f64>], b: &[Vec<f64>]| history_difference(a, b) / largest;
    let tnnmg = slip_history(0.0, SolverKind::Tnnmg);
    let d = differs(&direct, &tnnmg);
    eprintln!("TNNMG against direct: {d:e} of the largest slip");
    assert!(d < 1e-6, "{d:e}");
    let turned = slip_history(0.7, SolverKind::Direct);
    let d = differs(&direct, &turned);
    eprintln!("turned by 0.7 rad: {d:e} of the largest slip");
    assert!(d < 1e-8, "{d:e}");
}

/// What a 3-D internal fault refuses: a polygon the mesh does not resolve (the splitting's
/// error), a zero tangent.
#[test]
fn a_3d_internal_fault_refuses_what_does_not_fit() {
    let q = rotation(0.0);
    let builder = || {
        ModelBuilder::refined(cube(&q), 1)
            .unwrap()
            .material(Material::new(1e10, 0.25, 2700.0))
            .dirichlet(
                Part::predicate("top", |x| x[2] > 1.0 - 1e-9),
                [1e-4, 0.0, 0.0],
            )
    };
    let off_grid = [
        [0.1, -0.5, -0.5],
        [0.1, 0.5, -0.5],
        [0.1, 0.5, 0.5],
        [0.1, -0.5, 0.5],
    ];
    assert!(matches!(
        builder().internal_fault_polygon("f", &off_grid).build(),
        Err(rsf::Error::Fem(_))
    ));
    let on_grid = off_grid.map(|x| [0.0, x[1], x[2]]);
    match builder()
        .fault_tangent([0.0; 3])
        .internal_fault_polygon("f", &on_grid)
        .build()
    {
        Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, "fault_tangent"),
        other => panic!("expected fault_tangent, got {:?}", other.map(|_| ())),
    }
}

/// The end of a fault ODE's run on the buried 3-D fault to `t_end`, within a stated
/// number of steps: a run that cannot progress (a wrong block minimiser made one take over
/// 16 minutes) ends with `Error::StepSizeCollapse` in seconds. The run of
/// `the_fault_ode_and_the_implicit_scheme_agree_on_a_3d_internal_fault` takes 64 steps.
fn within(t_end: f64) -> rsf::Until {
    rsf::Until::TimeWithin {
        time: t_end,
        max_steps: 1_000,
    }
}

/// The quasi-dynamic problem on the buried 3-D fault (velocity strengthening,
/// a = 0.015 > b = 0.01, f₀ = 0.1, the regularised law, aging law, radiation damping
/// μ/(2c_s)), the state steady at 1e-4 m/s: `normal_stress`'s with the laws' σ̄_n.
pub(crate) fn quasi_dynamic() -> QuasiDynamic<3> {
    crate::normal_stress::quasi_dynamic(
        sheared_cube(rotation(0.0), 0.5).unwrap(),
        NormalStress::Fixed,
    )
}

/// The two engines on a 3-D internal fault: the fault ODE (the volume condensed onto the
/// jump's two tangential components, Runge–Kutta at tolerance 1e-9) and the implicit
/// scheme (backward Euler, fixed steps) agree, the implicit scheme converging to the
/// fault ODE at first order in τ.
#[test]
fn the_fault_ode_and_the_implicit_scheme_agree_on_a_3d_internal_fault() {
    let t_end = 3.0;
    let (reference, steps) = fault_ode_last_slip(quasi_dynamic(), within(t_end));
    eprintln!("the fault ODE: {steps} steps");
    let errors = implicit_slip_errors(quasi_dynamic, t_end, &[25, 50, 100, 200], &reference);
    assert_first_order(&errors);
}

/// Radiation damping that varies along the fault (`SimulationBuilder::radiation_damping_at`:
/// η per node, e.g. `μ/(2c_s)` of the material at each node): the fault ODE and the
/// implicit scheme (backward Euler, direct solver) agree on it as on a uniform η, the
/// implicit scheme converging to the fault ODE as τ halves, and the answer is not the
/// uniform η's (the per-node values are used, not one of them).
#[test]
fn radiation_damping_per_node_is_the_same_physics_in_both_engines() {
    let t_end = 3.0;
    let (mu, c_s) = (1e10 / 2.5, (1e10 / 2.5 / 2700.0f64).sqrt());
    // A hundred times μ/(2c_s), so that ηV is comparable to the frictional stress change.
    let eta0 = 100.0 * mu / (2.0 * c_s);
    let varying = move |x: &[f64; 3]| eta0 * (1.0 + 1.8 * x[1]);
    let options = rsf::fault_ode::FaultOdeOptions {
        tolerance: 1e-9,
        ..Default::default()
    };
    let ode_slip = |builder| fault_ode_last_slip(builder, within(t_end)).0;
    let reference = ode_slip(quasi_dynamic().radiation_damping_at(varying));
    let uniform = ode_slip(quasi_dynamic().radiation_damping(eta0));
    let scale = reference.iter().fold(0.0f64, |m, &x| m.max(x));
    let max_diff = |a: &[f64], b: &[f64]| largest_difference(a, b) / scale;
    let effect = max_diff(&reference, &uniform);
    let implicit_slip = |builder, steps| implicit_last_slip(builder, t_end, steps);
    // Per τ: the implicit scheme's distance from the fault ODE, and the change that the
    // varying η makes in the implicit scheme against the change it makes in the fault ODE.
    let (mut errors, mut effect_errors) = (Vec::new(), Vec::new());
    for steps in [50, 100, 200] {
        let varied = implicit_slip(quasi_dynamic().radiation_damping_at(varying), steps);
        let flat = implicit_slip(quasi_dynamic().radiation_damping(eta0), steps);
        errors.push(max_diff(&varied, &reference));
        let change: Vec<f64> = varied.iter().zip(&flat).map(|(a, b)| a - b).collect();
        let ode_change: Vec<f64> = reference.iter().zip(&uniform).map(|(a, b)| a - b).collect();
        effect_errors.push(max_diff(&change, &ode_change));
    }
    eprintln!(
        "η varying by ±90 %: changes the slip by {effect:e} of the largest {scale:e} m; the \
         implicit scheme at T/50, T/100, T/200 is {errors:?} from the fault ODE, its change \
         by the varying η {effect_errors:?} from the fault ODE's"
    );
    for w in errors.windows(2).chain(effect_errors.windows(2)) {
        assert!(w[1] < 0.7 * w[0], "{errors:?} {effect_errors:?}");
    }
    assert!(
        effect_errors[2] < 0.1 * effect,
        "{effect_errors:?} against {effect:e}"
    );
    // η ≤ 0 at one node is refused by the fault ODE, naming the node.
    let e = quasi_dynamic()
        .radiation_damping_at(|x| if x[1] > 0.2 { 0.0 } else { 1e6 })
        .time_step(1e-3)
        .build_fault_ode(options)
        .map(|_| ())
        .expect_err("refused");
    assert!(
        matches!(e, rsf::Error::InvalidParameter { ref name, ref reason } if name == "radiation_damping" && reason.contains("node")),
        "{e}"
    );
}

/// `[-1, 1]² × [-1, 0]` (the top a free surface; 5 × 5 × 3 coarse vertices refined once)
/// with a fault on the plane `x = z` dipping 45° from its trace `x = z = 0, |y| ≤ 0.5`
/// on the surface to depth 0.5 (its other rim inside the body), the faces `x = ±1`
/// pushed together (left +v, right −v): reverse slip, which changes the normal stress.
fn thrust_block_3d() -> Model<3> {
    crate::normal_stress_3d::dipping_fault([5, 5, 3])
}

/// Per step the last slip lengths and normal stresses of every frictional node.
#[derive(Default)]
struct SlipAndNormalStress(Vec<f64>, Vec<f64>);

impl rsf::Observer<3> for SlipAndNormalStress {
    fn observe(&mut self, s: &StepView<'_, 3, 3>) -> rsf::Result<rsf::Flow> {
        let n = s.model.frictional_boundary.len();
        self.0 = (0..n)
            .map(|k| s.slip(k).iter().map(|c| c * c).sum::<f64>().sqrt())
            .collect();
        self.1 = (0..n).map(|k| s.normal_traction(k).unwrap()).collect();
        Ok(rsf::Flow::Continue(()))
    }
}

/// A normal stress that changes with slip on a dipping 3-D fault under a free surface
/// (`NormalStress::FromSlip`): the implicit scheme (σ̄_n iterated with the state in the
/// fixed point) converges to the fault ODE (the slip → normal-traction operator condensed
/// onto the jumps) at first order, in the slip and in the normal stress; the coupling
/// changes the slip by far more than that error.
#[test]
fn a_dipping_3d_fault_under_a_free_surface_changes_its_normal_stress_in_both_engines() {
    let t_end = 3.0;
    let model = thrust_block_3d();
    let f = model.internal_fault.as_ref().unwrap();
    eprintln!(
        "{} pairs, {} tips, {} frictional nodes",
        f.pairs().len(),
        f.faults()[0].tips().len(),
        model.frictional_boundary.len()
    );
    let params = crate::normal_stress::params();
    let builder = |normal_stress| crate::normal_stress::quasi_dynamic(model.clone(), normal_stress);
    let ode = |normal_stress| {
        let mut ode = tight_fault_ode(builder(normal_stress));
        let mut last = SlipAndNormalStress::default();
        rsf::run_until(&mut ode, within(t_end), &mut [&mut last]).unwrap();
        last
    };
    let reference = ode(NormalStress::FromSlip);
    let slip_scale = reference.0.iter().fold(0.0f64, |m, &x| m.max(x));
    let sigma_change = reference
        .1
        .iter()
        .fold(0.0f64, |m, s| m.max((s - params.sigma_n).abs()));
    eprintln!("largest slip {slip_scale:e} m, largest change of σ̄_n {sigma_change:e} Pa");
    assert!(slip_scale > 0.0 && sigma_change > 1e-3 * params.sigma_n);
    let mut errors = Vec::new();
    for steps in [25, 50, 100, 200] {
        let mut sim = implicit_scheme(builder(NormalStress::FromSlip), t_end, steps);
        let mut last = SlipAndNormalStress::default();
        sim.run(steps, &mut [&mut last]).unwrap();
        let e_slip = largest_difference(&last.0, &reference.0) / slip_scale;
        let e_sigma = largest_difference(&last.1, &reference.1) / sigma_change;
        eprintln!(
            "τ = T/{steps}: implicit against the fault ODE: slip {e_slip:.3e}, normal stress \
             {e_sigma:.3e} of its change"
        );
        errors.push((e_slip, e_sigma));
    }
    let uncoupled = ode(NormalStress::Fixed);
    let effect = largest_difference(&uncoupled.0, &reference.0) / slip_scale;
    eprintln!("fixed σ̄_n against σ̄_n from slip (fault ODE): slip differs by {effect:.3e}");
    assert!(effect > 100.0 * errors[3].0, "{effect:e}");
    assert_first_order_with_normal_stress(&errors);
}

/// The faces of `mesh` whose three vertices satisfy `on` (a convex piece of a plane).
fn faces_where(mesh: &SimplexMesh<3>, on: impl Fn(&[f64; 3]) -> bool) -> Vec<[usize; 3]> {
    mesh.facets()
        .into_iter()
        .filter(|f| f.iter().all(|&v| on(&mesh.vertices()[v])))
        .collect()
}

/// The sheared cube with the fault given as coarse faces (`internal_fault_faces`).
fn sheared_cube_with_faces(faces: &[[usize; 3]]) -> rsf::Result<Model<3>> {
    let v = 1e-4;
    ModelBuilder::refined(cube(&rotation(0.0)), 1)?
        .material(Material::new(1e10, 0.25, 2700.0))
        .without_mass()
        .dirichlet(
            Part::predicate("plus face", |x| x[0] > 1.0 - 1e-9),
            [0.0, v, 0.0],
        )
        .dirichlet(
            Part::predicate("minus face", |x| x[0] < -1.0 + 1e-9),
            [0.0, -v, 0.0],
        )
        .fault_tangent([0.0, 1.0, 0.0])
        .internal_fault_faces("fault", faces)
        .build()
}

/// 16 quasistatic steps of 0.5 s of `model` (its coordinates turned by `q` from the
/// unturned cube's) with Tresca friction weakest at the fault's centre (μ = 0.3 + 0.6·r,
/// r the unturned distance from the x axis, σ̄_n = 5 MPa): the slip of every pair at every
/// step, pairs in the model's order.
fn slips_of(model: Model<3>, solver: SolverKind, q: [[f64; 3]; 3]) -> Vec<Vec<f64>> {
    let mu = |x: &[f64; 3]| {
        let y = rotate_back(&q, *x);
        0.3 + 0.6 * y[1].hypot(y[2])
    };
    let mut slips = Slips { rows: Vec::new() };
    run_tresca_steps(model, mu, solver, 16, &mut slips);
    slips.rows
}

/// A fault given as faces of the coarse mesh (followed down the hierarchy: four children
/// per face and level) gives the polygon's model — the same pairs and stiffness — and
/// slip history; a kinked fault (the plane x = 0 below z = 0, the plane x = z above)
/// given as faces slips the same with TNNMG and the direct solver; bad faces are the
/// splitting's typed errors.
#[test]
fn a_3d_fault_given_as_coarse_faces_follows_the_hierarchy() {
    let coarse = cube(&rotation(0.0));
    let square = |x: &[f64; 3]| x[0] == 0.0 && x[1].abs() <= 0.5 && x[2].abs() <= 0.5;
    let faces = faces_where(&coarse, square);
    assert_eq!(faces.len(), 8);
    let by_faces = sheared_cube_with_faces(&faces).unwrap();
    let by_polygon = sheared_cube(rotation(0.0), 0.5).unwrap();
    assert_eq!(
        by_faces.frictional_boundary.nodes,
        by_polygon.frictional_boundary.nodes
    );
    let (a, b) = (&by_faces.stiffness, &by_polygon.stiffness);
    assert_eq!(a.compute_nnz(), b.compute_nnz());
    let mut largest = 0.0f64;
    let mut differs = 0.0f64;
    for j in 0..a.ncols() {
        for ((i, x), (k, y)) in a
            .row_idx_of_col(j)
            .zip(a.val_of_col(j))
            .zip(b.row_idx_of_col(j).zip(b.val_of_col(j)))
        {
            assert_eq!(i, k);
            largest = largest.max(x.abs());
            differs = differs.max((x - y).abs());
        }
    }
    eprintln!(
        "stiffness by faces against by polygon: {:e}",
        differs / largest
    );
    assert!(differs <= 1e-14 * largest);
    let (s1, s2) = (
        slips_of(by_faces, SolverKind::Direct, rotation(0.0)),
        slips_of(by_polygon, SolverKind::Direct, rotation(0.0)),
    );
    let scale = largest_slip(&s2);
    let d = history_difference(&s1, &s2);
    assert!(scale > 0.0 && d <= 1e-10 * scale, "{d:e}");

    // A kinked fault of two planes, as faces.
    let kinked = |x: &[f64; 3]| {
        x[1].abs() <= 0.5
            && ((x[0] == 0.0 && (-0.5..=0.0).contains(&x[2]))
                || (x[0] == x[2] && (0.0..=0.5).contains(&x[2])))
    };
    let faces = faces_where(&coarse, kinked);
    assert_eq!(faces.len(), 8);
    let model = sheared_cube_with_faces(&faces).unwrap();
    let pairs = model.internal_fault.as_ref().unwrap().pairs().len();
    let direct = slips_of(model.clone(), SolverKind::Direct, rotation(0.0));
    let tnnmg = slips_of(model, SolverKind::Tnnmg, rotation(0.0));
    let scale = largest_slip(&direct);
    let d = history_difference(&direct, &tnnmg);
    eprintln!(
        "kinked: {pairs} pairs, largest slip {scale:e} m, TNNMG against direct {:e}",
        d / scale
    );
    assert!(scale > 0.0 && d <= 1e-6 * scale, "{d:e}");

    // A face that is not a face of the mesh: the splitting's error.
    let mut bad = faces_where(&coarse, square);
    bad[0][2] += 1000;
    assert!(matches!(
        sheared_cube_with_faces(&bad),
        Err(rsf::Error::Fem(_))
    ));
}

/// A fault tangent normal to the fault gives its nodal frames no first tangent: the build
/// fails naming a split vertex on the fault and its position (it used to take a
/// coordinate axis there silently).
#[test]
fn a_fault_tangent_normal_to_the_fault_is_an_error_naming_the_node() {
    let q = rotation(0.7);
    let e = sheared_cube_with_tangent(q, 0.5, [1.0, 0.0, 0.0]).unwrap_err();
    match &e {
        rsf::Error::Fem(rsf::fem::Error::TangentAlongNormal {
            vertex, position, ..
        }) => {
            let x = rotate_back(&q, [position[0], position[1], position[2]]);
            assert!(
                x[0].abs() < 1e-9,
                "vertex {vertex} at {position:?} is on the fault"
            );
            assert!(e.to_string().contains(&format!("vertex {vertex}")), "{e}");
        }
        other => panic!("{other}"),
    }
}
