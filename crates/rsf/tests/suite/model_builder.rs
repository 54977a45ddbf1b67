//! The model builder: it reproduces the paper's slider as assembled by hand (bit for bit),
//! builds 3D models and non-paper problems, and reports every inadmissible description as
//! a typed error naming the part or parameter — never a panic (proptest).

use proptest::prelude::*;
use rsf::fem::{
    body_force_load, cuboid, lumped_weights, pipping_slider_coarse, rectangle, Assembler,
    BoundarySegment, ConstrainedSystem, Diagonal, LinearElasticity, MeshHierarchy, SimplexMesh,
    SparseMatrix,
};
use rsf::friction::{DieterichRuina, RateStateParams, Tresca};
use rsf::model::FrictionalBoundary;
use rsf::state::Aging;
use rsf::{Error, Material, Model, ModelBuilder, Part, SimulationBuilder, TimeFunction};
use rsf_scenes::SliderScene;

const ROCK: Material = Material {
    youngs_modulus: 5e7,
    poisson_ratio: 0.3,
    density: 5e3,
};

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// The slider assembled step by step as `SliderScene::build_model` did before the builder
/// existed (Γ_D = top with velocity (v_max min(t/t_ramp, 1), 0), Γ_F = bottom with the
/// normal fixed, u₀ from K u₀ = F).
struct HandModel {
    model_parts: (
        Vec<[f64; 2]>,
        SparseMatrix,
        SparseMatrix,
        SparseMatrix,
        Vec<f64>,
    ),
    fixed: Vec<bool>,
    u0: Vec<f64>,
    prolongations: Vec<SparseMatrix>,
    frictional_boundary: FrictionalBoundary,
    dirichlet_dofs: Vec<usize>,
}

fn by_hand(s: &SliderScene) -> HandModel {
    let h = MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), s.level);
    let mesh = h.finest();
    let asm = Assembler::new(mesh).unwrap();
    let mat = LinearElasticity::plane_strain(s.youngs_modulus_pa, s.poisson_ratio).unwrap();
    let k = asm.stiffness(mesh, &mat).unwrap();
    let m = asm.mass(mesh, s.density_kg_per_m2).unwrap();
    let e = asm.energy(mesh, s.density_kg_per_m2, &mat).unwrap();
    let rho_g = s.density_kg_per_m2 * s.gravity_m_per_s2;
    let load = body_force_load(mesh, |_| [0.0, -rho_g]).unwrap();
    let gd = BoundarySegment::from_tag(mesh, "dirichlet").unwrap();
    let gf = BoundarySegment::from_tag(mesh, "frictional").unwrap();
    let n = 2 * mesh.num_vertices();
    let mut fixed = vec![false; n];
    let mut dofs = Vec::new();
    for &p in gd.nodes() {
        fixed[2 * p] = true;
        fixed[2 * p + 1] = true;
        dofs.push(2 * p);
    }
    for &p in gf.nodes() {
        fixed[2 * p + 1] = true;
    }
    let frictional = FrictionalBoundary::new(gf.nodes(), &lumped_weights(mesh, &gf)).unwrap();
    let mut u0 = vec![0.0; n];
    ConstrainedSystem::new(k.as_ref(), &fixed)
        .unwrap()
        .solve(&load, &mut u0)
        .unwrap();
    dofs.sort_unstable();
    HandModel {
        model_parts: (mesh.vertices().to_vec(), k, m, e, load),
        fixed,
        u0,
        prolongations: (1..=s.level)
            .map(|j| h.vector_prolongation(j).clone())
            .collect(),
        frictional_boundary: frictional,
        dirichlet_dofs: dofs,
    }
}

/// The velocity the old model prescribed on its Dirichlet dofs: 1 · V_D(t).
fn old_speed(s: &SliderScene, t: f64) -> f64 {
    let (v_max, t_ramp) = (s.loading_velocity_m_per_s, s.ramp_fraction * s.end_time_s);
    let speed = if t_ramp > 0.0 && t < t_ramp {
        v_max * (t / t_ramp)
    } else {
        v_max
    };
    1.0 * speed
}

#[test]
fn the_paper_slider_is_the_hand_assembled_model_bit_for_bit() {
    for level in [0, 2] {
        let scene = SliderScene {
            level,
            ..SliderScene::default()
        };
        let model = scene.build_model().unwrap();
        let hand = by_hand(&scene);
        let (vertices, k, m, e, load) = &hand.model_parts;
        assert_eq!(&model.vertices, vertices);
        assert!(
            crate::common::same_bits(&model.stiffness, k),
            "stiffness, level {level}"
        );
        assert!(
            crate::common::same_bits(model.mass.as_ref().unwrap(), m),
            "mass"
        );
        assert!(
            crate::common::same_bits(&model.energy_norm, e),
            "energy norm"
        );
        assert_eq!(bits(&model.load), bits(load), "load");
        assert_eq!(model.fixed, hand.fixed, "constraints");
        assert_eq!(bits(&model.initial_displacement), bits(&hand.u0), "u0");
        assert_eq!(model.prolongations.len(), hand.prolongations.len());
        for (a, b) in model.prolongations.iter().zip(&hand.prolongations) {
            assert!(crate::common::same_bits(a, b), "prolongation");
        }
        assert_eq!(
            model.frictional_boundary.nodes,
            hand.frictional_boundary.nodes
        );
        assert_eq!(
            bits(&model.frictional_boundary.weights),
            bits(&hand.frictional_boundary.weights)
        );
        assert_eq!(
            model.frictional_boundary.along,
            hand.frictional_boundary.along
        );
        assert_eq!(model.dirichlet.dofs, hand.dirichlet_dofs);
        for t in [0.0, 1e-3, 1.7, 3.75, 3.7500001, 10.0] {
            let speed = model.dirichlet.speed(t);
            for f in &model.dirichlet.factors {
                assert_eq!(
                    (f * speed).to_bits(),
                    old_speed(&scene, t).to_bits(),
                    "t = {t}"
                );
            }
        }
    }
}

#[test]
fn a_three_dimensional_block_on_its_bottom_face_runs() {
    let mesh = cuboid([0.0; 3], [2.0, 1.0, 1.0], [3, 2, 2]).unwrap();
    let model = ModelBuilder::refined(mesh, 1)
        .unwrap()
        .material(ROCK)
        .gravity([0.0, 0.0, -9.81])
        .dirichlet(
            Part::predicate("top", |x| x[2] > 1.0 - 1e-9),
            [1e-4, 0.0, 0.0],
        )
        .frictional_boundary(Part::predicate("bottom", |x| x[2] < 1e-9))
        .build()
        .unwrap();
    // 5 × 3 nodes on the bottom face after one refinement, the z component fixed.
    assert_eq!(model.frictional_boundary.len(), 15);
    assert!(model
        .frictional_boundary
        .nodes
        .iter()
        .all(|&p| model.fixed[3 * p + 2] && !model.fixed[3 * p]));
    assert!((model.frictional_boundary.weights.iter().sum::<f64>() - 2.0).abs() < 1e-12);
    let sigma_n = 5e3 * 9.81;
    let mut sim = SimulationBuilder::new(model)
        .friction(Tresca::new(0.6, sigma_n).unwrap())
        .time_step(1e-3)
        .build()
        .unwrap();
    sim.run(3, &mut []).unwrap();
    assert!(sim.kinematics().v.iter().all(|v| v.is_finite()));
}

#[test]
fn a_vertical_fault_fixes_the_x_component_and_orders_by_y() {
    let mesh = rectangle([0.0, 0.0], [1.0, 3.0], 2, 4, Diagonal::Forward).unwrap();
    let model = ModelBuilder::new(mesh)
        .material(ROCK)
        .dirichlet(Part::predicate("right", |x| x[0] > 1.0 - 1e-9), [0.0, 1e-4])
        .frictional_boundary(Part::predicate("left", |x| x[0] < 1e-9))
        .without_mass()
        .build()
        .unwrap();
    let fb = &model.frictional_boundary;
    assert!(model.mass.is_none());
    assert!(fb
        .nodes
        .iter()
        .all(|&p| model.fixed[2 * p] && !model.fixed[2 * p + 1]));
    let ys: Vec<f64> = fb
        .along
        .iter()
        .map(|&k| model.vertices[fb.nodes[k]][1])
        .collect();
    assert_eq!(ys, [0.0, 1.0, 2.0, 3.0]);
}

fn block() -> ModelBuilder<2> {
    let mesh = rectangle([0.0, 0.0], [4.0, 1.0], 5, 2, Diagonal::Forward).unwrap();
    ModelBuilder::new(mesh)
        .material(ROCK)
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
}

fn names(e: &Error, words: &[&str]) {
    let msg = e.to_string();
    for w in words {
        assert!(msg.contains(w), "`{msg}` does not mention `{w}`");
    }
}

#[test]
fn inadmissible_descriptions_are_named_errors() {
    let mesh = || rectangle([0.0, 0.0], [4.0, 1.0], 5, 2, Diagonal::Forward).unwrap();
    names(
        &ModelBuilder::new(mesh())
            .frictional_boundary("x")
            .build()
            .unwrap_err(),
        &["material"],
    );
    names(
        &ModelBuilder::new(mesh())
            .material(ROCK)
            .build()
            .unwrap_err(),
        &["frictional"],
    );
    names(
        &block()
            .frictional_boundary("no-such-tag")
            .build()
            .unwrap_err(),
        &["no-such-tag", "selects no boundary facet"],
    );
    // No Dirichlet part: the block can slide away, K u0 = F is singular.
    let free = ModelBuilder::new(mesh())
        .material(ROCK)
        .gravity([0.0, -9.81])
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
        .build()
        .unwrap_err();
    assert!(matches!(free, Error::Equilibrium(_)), "{free}");
    // The message carries the solver's cause, not only `source()` (issue 34).
    let cause = std::error::Error::source(&free).unwrap().to_string();
    assert!(free.to_string().ends_with(&cause), "{free}");
    // Two parts prescribing different velocities to the corner nodes they share.
    let e = block()
        .dirichlet(Part::predicate("left", |x| x[0] < 1e-9), [0.0, 0.0])
        .build()
        .unwrap_err();
    names(&e, &["left", "component 0"]);
    names(
        &block()
            .dirichlet_components("top", &[2], [0.0, 0.0])
            .build()
            .unwrap_err(),
        &["components"],
    );
    names(
        &block()
            .dirichlet("top", [f64::NAN, 0.0])
            .build()
            .unwrap_err(),
        &["velocity"],
    );
    names(
        &block().gravity([0.0, f64::INFINITY]).build().unwrap_err(),
        &["gravity"],
    );
    names(
        &block()
            .loading(TimeFunction::PiecewiseLinear(vec![(1.0, 0.0), (0.5, 1.0)]))
            .build()
            .unwrap_err(),
        &["loading"],
    );
    assert!(block()
        .neumann(Part::predicate("right", |x| x[0] > 4.0 - 1e-9), |_| [
            f64::NAN,
            0.0
        ])
        .build()
        .is_err());
    let other = rectangle([0.0, 0.0], [1.0, 1.0], 3, 3, Diagonal::Forward).unwrap();
    let foreign = rsf::fem::BoundaryPart::from_predicate(&other, "foreign", |x| x[1] < 1e-9);
    names(
        &block()
            .frictional_boundary(foreign.unwrap())
            .build()
            .unwrap_err(),
        &["foreign", "another mesh"],
    );
    names(
        &ModelBuilder::refined(mesh(), 40).err().unwrap(),
        &["levels"],
    );
}

/// `fault_tangent` only orients the 3-D frames: in 2-D (`t = (−n_y, n_x)`) it would be
/// ignored, so `build` refuses it rather than silently dropping the user's choice.
#[test]
fn a_fault_tangent_in_two_dimensions_is_refused() {
    let e = block().fault_tangent([1.0, 0.0]).build().unwrap_err();
    assert!(
        matches!(&e, Error::InvalidParameter { name, .. } if name == "fault_tangent"),
        "{e}"
    );
    names(&e, &["fault_tangent", "3-D", "(-n_y, n_x)"]);
    // Without it the same block builds.
    assert!(block().build().is_ok());
}

#[test]
fn a_slanted_fault_gets_nodal_frames() {
    // The block rotated by 30°: its bottom is not along a coordinate axis, so every node
    // of it gets a nodal frame (issue 24; more in tests/suite/nodal_frames.rs).
    let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let m = rectangle([0.0, 0.0], [4.0, 1.0], 5, 2, Diagonal::Forward).unwrap();
    let rotated: Vec<[f64; 2]> = m
        .vertices()
        .iter()
        .map(|x| [c * x[0] - s * x[1], s * x[0] + c * x[1]])
        .collect();
    let mesh = SimplexMesh::new(rotated, m.cells().to_vec()).unwrap();
    let on_bottom = move |x: &[f64; 2]| (-s * x[0] + c * x[1]).abs() < 1e-9;
    let model = ModelBuilder::new(mesh)
        .material(ROCK)
        .dirichlet(
            Part::predicate("top", move |x| (-s * x[0] + c * x[1] - 1.0).abs() < 1e-9),
            [0.0, 0.0],
        )
        .frictional_boundary(Part::predicate("slanted", on_bottom))
        .build()
        .unwrap();
    assert_eq!(model.frames.nodes, model.frictional_boundary.nodes);
    for &p in &model.frictional_boundary.nodes {
        // The normal is model component 1, fixed; the tangent is free.
        assert!(model.fixed[2 * p + 1] && !model.fixed[2 * p]);
        // Its frame maps the model's tangent to the rotated e_x.
        let t = model.to_global(p, [1.0, 0.0]);
        assert!(
            (t[0] - c).abs() < 1e-12 && (t[1] - s).abs() < 1e-12,
            "{t:?}"
        );
    }
}

#[test]
fn friction_given_by_position_follows_the_nodes() {
    let model = block().build().unwrap();
    let p = RateStateParams {
        mu0: 0.6,
        a: 0.01,
        b: 0.015,
        v0: 1e-6,
        l: 1e-5,
        sigma_n: 5e4,
    };
    let sim = SimulationBuilder::new(model.clone())
        .friction_at(|x| {
            DieterichRuina::new(RateStateParams {
                mu0: 0.5 + 0.01 * x[0],
                ..p
            })
        })
        .state_law(Aging::new(p.l).unwrap())
        .initial_state_at(|x| -10.0 - x[0])
        .time_step(1e-3)
        .build()
        .unwrap();
    for (k, &node) in model.frictional_boundary.nodes.iter().enumerate() {
        assert_eq!(sim.alpha()[k], -10.0 - model.vertices[node][0]);
    }
    // An invalid parameter at one position is the friction crate's error.
    let e = SimulationBuilder::new(model)
        .friction_at(|x| DieterichRuina::new(RateStateParams { a: 2.0 - x[0], ..p }))
        .state_law(Aging::new(p.l).unwrap())
        .initial_state(-10.0)
        .time_step(1e-3)
        .build()
        .err()
        .unwrap();
    names(&e, &["a"]);
    assert!(matches!(e, Error::Friction(_)));
}

/// Mostly admissible values in `range`, sometimes NaN, ∞, 0 or huge negative.
fn sometimes_bad(range: std::ops::Range<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => range,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(0.0),
        1 => Just(-1e300),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Arbitrary (mostly inadmissible) descriptions: the builders return `Ok` or an
    /// error, never panic; an `Ok` model is consistent (its validation fails, if at all,
    /// only on the magnitudes of the user's data, `IllConditioned`, which the simulation
    /// builder refuses) and its simulation builds or errs.
    #[test]
    fn builders_never_panic(
        e in sometimes_bad(0.1..2.0), nu in sometimes_bad(-2.2..2.2), rho in sometimes_bad(0.1..2.0),
        g in sometimes_bad(-2.0..2.0), vx in sometimes_bad(-2.0..2.0), comp in 0usize..3,
        y_fault in prop_oneof![Just(0.0), Just(0.5), Just(1.0)],
        levels in 0usize..2, mass in any::<bool>(), duration in sometimes_bad(0.0..2.0),
        tau in sometimes_bad(1e-4..1e-2), alpha0 in sometimes_bad(-20.0..20.0),
        mu in sometimes_bad(-0.1..1.0),
    ) {
        let mesh = rectangle([0.0, 0.0], [2.0, 1.0], 3, 2, Diagonal::Forward).unwrap();
        let mut b = ModelBuilder::refined(mesh, levels).unwrap()
            .material(Material { youngs_modulus: 1e7 * e, poisson_ratio: nu / 4.0, density: 1e3 * rho })
            .gravity([0.0, 9.81 * g])
            .dirichlet_components(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), &[comp], [vx, 0.0])
            .frictional_boundary(Part::predicate("fault", move |x| (x[1] - y_fault).abs() < 1e-9))
            .loading(TimeFunction::ramp(duration));
        if !mass {
            b = b.without_mass();
        }
        if let Ok(model) = b.build() {
            match model.validate() {
                Ok(()) | Err(rsf::Error::IllConditioned { .. }) => {}
                Err(e) => prop_assert!(false, "an Ok model is inconsistent: {e}"),
            }
            let _ = SimulationBuilder::new(model)
                .friction_at(|_| Tresca::new(mu, 1e4))
                .initial_state(alpha0)
                .time_step(tau)
                .build()
                .map(|mut sim| sim.step());
        }
    }
}

#[test]
fn a_model_is_its_own_description() {
    // The doc example's problem on the public fields: constraints and the equilibrium.
    let model: Model<2> = block().gravity([0.0, -9.81]).build().unwrap();
    let mut r = model.load.clone();
    rsf::fem::spmv_add(
        model.stiffness.as_ref(),
        -1.0,
        &model.initial_displacement,
        &mut r,
    );
    let free_residual = r
        .iter()
        .zip(&model.fixed)
        .filter(|(_, &f)| !f)
        .map(|(x, _)| x.abs())
        .fold(0.0, f64::max);
    let scale = model.load.iter().map(|x| x.abs()).fold(0.0, f64::max);
    assert!(
        free_residual <= 1e-9 * scale,
        "K u0 = F off by {free_residual:e}"
    );
    assert!(model
        .initial_displacement
        .iter()
        .zip(&model.fixed)
        .all(|(u, &f)| !f || *u == 0.0));
}
