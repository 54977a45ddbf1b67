//! Faults of any orientation (issue 24; docs/math.md §10): nodal frames on slanted
//! frictional boundaries, the model rotated block-diagonally at build time.
//!
//! - Rotation invariance: the fast-loading slider (level 2, τ = 1e-3 s, 300 steps through
//!   its first slip event) with mesh, gravity and loading velocity rotated by 30° gives the
//!   unrotated trajectory: first-slip time, slip at x₀ (the tangential displacement, in slip
//!   coordinates), peak slip rate and fixed point iterations. In exact arithmetic the two
//!   discrete problems are the same (the rotated one is the unrotated one with the non-fault
//!   nodes' blocks rotated by an orthogonal `G`, which nodal block smoothers, truncation and
//!   Galerkin coarsening all commute with), so they differ by round-off amplified through
//!   the fixed point's stopping test (tolerance 1e-10 on the velocity correction in the
//!   energy norm): compared to 1e-6 relative (as TNNMG against direct in slip_event.rs).
//! - With the angle 0 the builder takes the axis-aligned path: the model equals the scene's
//!   bit for bit, without frames.
//! - The same in 3-D: the fast-loading slider extruded (level 1, 300 steps) and rotated by
//!   30° about (1, 2, 3)/√14 (mesh, gravity, loading, and the fault's reference tangent
//!   `fault_tangent` = the rotated e_x): the unrotated trajectory.
//! - TNNMG and the direct solver agree on one velocity problem of the rotated slider to
//!   1e-9 relative in the energy norm, in 2-D and on the rotated 3-D slider (level 2).
//! - Closed form on an incline: a block on a base inclined by θ under vertical gravity, with
//!   velocity-strengthening friction (a > b) and a prescribed σ̄_n, settles to steady
//!   sliding down the slope at `V_ss` with `σ̄_n (μ0 + (a − b) ln(V_ss/V0)) = ρ g H sin θ`
//!   (the lumped weights sum to the fault length and the consistent gravity load to ρ g
//!   times the area, so the discrete steady state has the same `V_ss`); two angles, both
//!   state laws. Backward Euler (its numerical damping removes the elastic waves the
//!   release of the initial equilibrium starts; Newmark keeps them ringing for seconds)
//!   and steady sliding is an exact solution of the discrete scheme too.
//! - Bad frames: a fault around a corner of the block, a kink limit out of range, a
//!   partially fixed Dirichlet node on the slanted fault, a fault folding back at a crack
//!   tip (coincident facets, opposite normals), a facet of (numerically) zero length: typed
//!   errors naming the node.

use crate::common::*;
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::{
    pipping_slider_coarse, rectangle, Diagonal, SimplexMesh, TriangleMesh, TAG_DIRICHLET,
    TAG_FRICTIONAL, TAG_NEUMANN,
};
use rsf::friction::DieterichRuina;
use rsf::method::FrictionBlocks;
use rsf::nonsmooth::NonsmoothSolver;
use rsf::time::{Kinematics, Newmark, SystemMatrices, VelocityIntegrator};
use rsf::tnnmg::Tnnmg;
use rsf::{Error, Model, ModelBuilder, Observer, Part, SolverKind, StateLawKind, StepView};
use rsf_scenes::{
    onto_arc, skew_rotation, slider_3d_coarse, Slider3dScene, SliderScene, ARC_BLOCK_MESH,
    ARC_CENTRE, ARC_RADIUS_M, SLIDER_CENTRE,
};

/// The rotation by `phi` (rad) about the origin.
fn rot(phi: f64, x: [f64; 2]) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [c * x[0] - s * x[1], s * x[0] + c * x[1]]
}

/// `mesh` rotated by `phi`, its boundary re-tagged by `tag` applied to the unrotated
/// facet midpoints.
fn rotated_mesh(
    mesh: &TriangleMesh,
    phi: f64,
    tag: impl Fn(&mut TriangleMesh, &dyn Fn(&[f64; 2]) -> [f64; 2]),
) -> TriangleMesh {
    let vertices = mesh.vertices().iter().map(|&x| rot(phi, x)).collect();
    let mut m = SimplexMesh::new(vertices, mesh.cells().to_vec()).expect("a rotated mesh");
    tag(&mut m, &|x: &[f64; 2]| rot(-phi, *x));
    m
}

/// The model of `scene` (the paper's slider) with mesh, gravity and loading rotated by
/// `phi`.
fn rotated_slider(scene: &SliderScene, phi: f64) -> Model<2> {
    let coarse = rotated_mesh(&pipping_slider_coarse(scene.diagonal), phi, |m, back| {
        m.tag_boundary(TAG_NEUMANN, |x| {
            let y = back(x);
            y[0] < 1e-9 || y[0] > 5.0 - 1e-9
        });
        m.tag_boundary(TAG_DIRICHLET, |x| back(x)[1] > 1.0 - 1e-9);
        m.tag_boundary(TAG_FRICTIONAL, |x| back(x)[1] < 1e-9);
    });
    ModelBuilder::refined(coarse, scene.level)
        .unwrap()
        .material(scene.material())
        .gravity(rot(phi, [0.0, -scene.gravity_m_per_s2]))
        .dirichlet(
            TAG_DIRICHLET,
            rot(phi, [scene.loading_velocity_m_per_s, 0.0]),
        )
        .frictional_boundary(TAG_FRICTIONAL)
        .loading(scene.loading())
        .build()
        .expect("the rotated slider builds")
}

/// Per step: time, largest slip rate, fixed point iterations, the displacement of node `x0`
/// in model coordinates (slip coordinates on the fault), and the Cartesian velocity of x0.
#[derive(Default)]
struct Track<const D: usize> {
    x0: usize,
    t: Vec<f64>,
    max_v: Vec<f64>,
    fpi: Vec<usize>,
    u_x0: Vec<[f64; D]>,
    v_x0: Vec<[f64; D]>,
}

impl<const D: usize> Observer<D> for Track<D> {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<rsf::Flow> {
        self.t.push(s.report.time);
        self.max_v.push(s.report.max_slip_rate);
        self.fpi.push(s.report.fixed_point_iterations);
        self.u_x0.push(s.displacement_in_frame(self.x0));
        self.v_x0.push(s.velocity(self.x0));
        Ok(rsf::Flow::Continue(()))
    }
}

impl<const D: usize> Track<D> {
    /// The first step where the largest slip rate crosses 1e-3 m/s (interpolated).
    fn first_slip(&self) -> f64 {
        first_crossing(&self.t, &self.max_v, 1e-3, 0.0).expect("a slip event")
    }
    /// The largest slip rate of the run (m/s).
    fn peak(&self) -> f64 {
        self.max_v.iter().copied().fold(0.0, f64::max)
    }
    /// The change of the first model component of x0's displacement over the run (on the
    /// fault: the slip along the first tangent, m).
    fn slip(&self) -> f64 {
        self.u_x0.last().unwrap()[0] - self.u_x0[0][0]
    }
    /// Asserts that the run holds a slip event (its peak slip rate above 1e-3 m/s) and that
    /// `other`'s first slip (to 1e-6 s), peak slip rate and slip (each to 1e-6 of its own)
    /// are this run's.
    fn assert_same_event(&self, other: &Self) {
        let (t1, t2) = (self.first_slip(), other.first_slip());
        let (p1, p2) = (self.peak(), other.peak());
        let (s1, s2) = (self.slip(), other.slip());
        assert!(p1 > 1e-3, "the window holds a slip event (peak {p1:e} m/s)");
        assert!((t1 - t2).abs() <= 1e-6, "first slip {t1} vs {t2} s");
        assert!((p1 - p2).abs() <= 1e-6 * p1, "peak slip rate {p1} vs {p2}");
        assert!(
            (s1 - s2).abs() <= 1e-6 * s1.abs(),
            "slip at x0 {s1} vs {s2}"
        );
    }
    /// Steps whose fixed point iteration counts differ, and whether any differs by more
    /// than one.
    fn fpi_differences(&self, other: &Self) -> (usize, bool) {
        let pairs = || self.fpi.iter().zip(&other.fpi);
        (
            pairs().filter(|(a, b)| a != b).count(),
            pairs().any(|(a, b)| a.abs_diff(*b) > 1),
        )
    }
    /// The largest `|Δ ln V|` of the largest slip rate over the steps.
    fn worst_ln_v(&self, other: &Self) -> f64 {
        self.max_v
            .iter()
            .zip(&other.max_v)
            .map(|(a, b)| (a.ln() - b.ln()).abs())
            .fold(0.0, f64::max)
    }
}

fn track(scene: &SliderScene, model: Model<2>, x0: [f64; 2], t_end: f64) -> Track<2> {
    let mut tr = Track {
        x0: model.nearest_node(&x0).unwrap(),
        ..Track::default()
    };
    let mut sim = scene
        .build_with_model(model)
        .expect("the simulation builds");
    run_until(&mut sim, t_end, &mut [&mut tr]);
    tr
}

#[test]
fn the_angle_zero_is_the_axis_aligned_model_bit_for_bit() {
    let scene = fast_loading(2e-2, 300);
    let a = scene.build_model().unwrap();
    let b = rotated_slider(&scene, 0.0);
    assert!(b.frames.nodes.is_empty());
    assert_eq!(a.stiffness.val(), b.stiffness.val());
    assert_eq!(a.load, b.load);
    assert_eq!(a.initial_displacement, b.initial_displacement);
    assert_eq!(a.fixed, b.fixed);
}

#[test]
fn the_slider_rotated_by_30_degrees_slips_as_the_unrotated_one() {
    let phi = 30f64.to_radians();
    let scene = fast_loading(2e-2, 300);
    let t_end = 0.3;
    let rotated_model = rotated_slider(&scene, phi);
    // Every node of Γ_F has a frame whose normal is the rotated −e_y.
    let fb = &rotated_model.frictional_boundary;
    assert_eq!(rotated_model.frames.nodes, fb.nodes);
    for q in &rotated_model.frames.rotations {
        let n_in = rot(phi, [0.0, 1.0]);
        assert!((q[0][1] - n_in[0]).abs() < 1e-12 && (q[1][1] - n_in[1]).abs() < 1e-12);
    }
    let straight = track(&scene, scene.build_model().unwrap(), SLIDER_CENTRE, t_end);
    let turned = track(&scene, rotated_model, rot(phi, SLIDER_CENTRE), t_end);
    assert_eq!(straight.x0, turned.x0, "x0 is the same node");
    assert_eq!(straight.t.len(), 300);
    assert_eq!(straight.t, turned.t);

    let (t1, t2) = (straight.first_slip(), turned.first_slip());
    let (p1, p2) = (straight.peak(), turned.peak());
    let (s1, s2) = (straight.slip(), turned.slip());
    println!(
        "first slip {t1:.9} / {t2:.9} s, peak V {p1:.9e} / {p2:.9e} m/s, slip at x0 {s1:.9e} / \
         {s2:.9e} m, FPI {} / {}",
        straight.fpi.iter().sum::<usize>(),
        turned.fpi.iter().sum::<usize>()
    );
    straight.assert_same_event(&turned);
    // ln V of the largest slip rate at every step, to 1e-6.
    let worst_ln_v = straight.worst_ln_v(&turned);
    assert!(worst_ln_v <= 1e-6, "max |Δ ln V| = {worst_ln_v:e}");
    // The Cartesian velocity of x0 is the rotated one (StepView rotates back).
    for (a, b) in straight.v_x0.iter().zip(&turned.v_x0) {
        let ra = rot(phi, *a);
        let scale = a[0].hypot(a[1]).max(1e-12);
        assert!((ra[0] - b[0]).hypot(ra[1] - b[1]) <= 1e-6 * scale);
    }
    // Fixed point iterations: the same count at (almost) every step; a step whose last
    // correction sits at the tolerance may take one more or less.
    let (differ, off_by_more) = straight.fpi_differences(&turned);
    println!("FPI differ at {differ} of 300 steps");
    assert!(
        differ <= 3 && !off_by_more,
        "{differ} steps differ in FPI count"
    );
}

/// One Newmark velocity problem of `model` (the paper's material, `scene`'s τ and
/// friction): the body moved at the Cartesian velocity `v_slide` (along the fault) the
/// step before, the state at steady state of that rate, so that the inertia near the fault
/// exceeds friction and the fault slides against rate-and-state friction. Solved by TNNMG
/// (relative 1e-12) and by the direct solver; returns their relative difference in the
/// energy norm and the largest slip rate (m/s), after checking that the normal
/// components on the fault stay 0.
fn tnnmg_against_direct<const D: usize>(
    scene: &SliderScene,
    model: &Model<D>,
    v_slide: [f64; D],
) -> (f64, f64) {
    let tau = scene.tau();
    let mass = model.mass.as_ref().unwrap();
    let a = rsf::fem::combine(2.0 / tau, mass, tau / 2.0, &model.stiffness).unwrap();
    let n = model.num_dofs();
    let mut v_prev = vec![0.0; n];
    for p in 0..model.num_nodes() {
        v_prev[D * p..D * p + D].copy_from_slice(&model.to_model(p, v_slide));
    }
    let mut v = v_prev.clone();
    for (i, &f) in model.fixed.iter().enumerate() {
        if f {
            v[i] = 0.0;
        }
    }
    for (&i, &w) in model.dirichlet.dofs.iter().zip(&model.dirichlet.factors) {
        v[i] = w;
    }
    let kin = Kinematics {
        u: model.initial_displacement.clone(),
        v: v_prev,
        a: vec![0.0; n],
    };
    let mut b = vec![0.0; n];
    Newmark
        .right_hand_side(
            tau,
            SystemMatrices::new(model.mass.as_ref(), &model.stiffness),
            &model.load,
            &kin,
            &mut b,
        )
        .unwrap();
    let nf = model.frictional_boundary.len();
    let law = DieterichRuina::new(scene.rate_state_params()).unwrap();
    // α at steady state of the previous slip rate.
    let speed = v_slide.iter().map(|c| c * c).sum::<f64>().sqrt();
    let alpha = (scene.l_m / speed).ln();
    let blocks = FrictionBlocks::new(
        model.frictional_boundary.nodes.clone(),
        model.frictional_boundary.weights.clone(),
        vec![law; nf],
        &vec![alpha; nf],
    );
    let mut v_direct = v.clone();
    DirectSolver::<D>::new(a.as_ref(), &model.fixed, DirectOptions::default())
        .unwrap()
        .solve(&b, &blocks, &mut v_direct)
        .unwrap();
    let mut v_tnnmg = v;
    Tnnmg::<D>::new(
        a.as_ref(),
        &model.fixed,
        &model.prolongations,
        Some(model.energy_norm.as_ref()),
        crate::common::tight_tnnmg(),
    )
    .unwrap()
    .solve(&b, &blocks, &mut v_tnnmg)
    .unwrap();
    let e = |x: &[f64]| dot(x, &apply(&model.energy_norm, x)).max(0.0).sqrt();
    let d: Vec<f64> = v_tnnmg.iter().zip(&v_direct).map(|(a, b)| a - b).collect();
    let rel = e(&d) / e(&v_direct);
    let vmax = model
        .frictional_boundary
        .nodes
        .iter()
        .map(|&p| {
            let w = &v_direct[D * p..D * p + D];
            w.iter().map(|c| c * c).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max);
    // The normal component on the fault is fixed at 0: the last model component at a
    // frame node, the Cartesian one along the normal elsewhere.
    for &p in &model.frictional_boundary.nodes {
        for c in 0..D {
            if model.fixed[D * p + c] {
                assert!(v_direct[D * p + c] == 0.0 && v_tnnmg[D * p + c] == 0.0);
            }
        }
        if model.frame(p).is_some() {
            assert!(
                model.fixed[D * p + rsf::fem::normal_component(D)],
                "node {p}: normal fixed"
            );
        }
    }
    (rel, vmax)
}

/// The slider rotated by 25° at level 3, the block sliding along the fault at 0.5 m/s the
/// step before: TNNMG and the direct solver agree to 1e-9 in the energy norm.
#[test]
fn tnnmg_and_direct_agree_on_a_slanted_fault() {
    let phi = 25f64.to_radians();
    let scene = SliderScene {
        level: 3,
        ..fast_loading(2e-2, 300)
    };
    let model = rotated_slider(&scene, phi);
    let (rel, vmax) = tnnmg_against_direct(&scene, &model, rot(phi, [0.5, 0.0]));
    println!("TNNMG vs direct on a 25° fault: {rel:e} (largest slip rate {vmax:e} m/s)");
    assert!(vmax > 1e-3, "the fault slides");
    assert!(rel <= 1e-9, "relative energy-norm difference {rel:e}");
}

/// A `w × h` block on a base inclined by `theta` (rising to the right), gravity vertical,
/// no Dirichlet part; the initial equilibrium is taken with the top-left node pinned, and
/// the pin is then released.
fn incline_model(theta: f64, w: f64, h: f64, level: usize, scene: &SliderScene) -> Model<2> {
    let flat = rectangle([0.0, 0.0], [w, h], 5, 3, Diagonal::Forward).unwrap();
    let coarse = rotated_mesh(&flat, theta, |m, back| {
        m.tag_boundary("base", |x| back(x)[1] < 1e-9);
        m.tag_boundary("pin", |x| {
            let y = back(x);
            y[0] < 1e-9 && y[1] > 0.5 * h
        });
    });
    let mut model = ModelBuilder::refined(coarse, level)
        .unwrap()
        .material(scene.material())
        .gravity([0.0, -scene.gravity_m_per_s2])
        .dirichlet("pin", [0.0, 0.0])
        .frictional_boundary("base")
        .build()
        .expect("the incline builds");
    // Release the pin: only the fault's normal components stay fixed.
    let on_fault: std::collections::HashSet<usize> =
        model.frictional_boundary.nodes.iter().copied().collect();
    for (i, f) in model.fixed.iter_mut().enumerate() {
        if !(on_fault.contains(&(i / 2)) && i % 2 == 1) {
            *f = false;
        }
    }
    model.validate().unwrap();
    model
}

#[test]
fn a_block_on_an_incline_slides_steadily_at_the_closed_form_rate() {
    let (w, h) = (2.0, 0.5);
    let weight = |scene: &SliderScene| scene.density_kg_per_m2 * scene.gravity_m_per_s2 * h;
    for law in [StateLawKind::Aging, StateLawKind::Slip] {
        for theta_deg in [19.0f64, 20.0] {
            let theta = theta_deg.to_radians();
            let scene = SliderScene {
                level: 1,
                steps: 1500,
                end_time_s: 3.0,
                integrator: rsf::Integrator::BackwardEuler,
                mu0: 0.3,
                a: 0.015,
                b: 0.010,
                ramp_fraction: 0.0,
                state_law: law,
                solver: SolverKind::Direct,
                ..SliderScene::default()
            };
            // σ̄_n = ρ g H (the weight per unit length, as in the paper): then
            // μ_ss(V_ss) = sin θ.
            let scene = SliderScene {
                sigma_n_pa: weight(&scene),
                ..scene
            };
            let p = scene.rate_state_params();
            let rho_g_h = scene.density_kg_per_m2 * scene.gravity_m_per_s2 * h;
            let v_ss =
                p.v0 * ((rho_g_h * theta.sin() / scene.sigma_n_pa - p.mu0) / (p.a - p.b)).exp();
            let model = incline_model(theta, w, h, scene.level, &scene);
            let nodes = model.frictional_boundary.nodes.clone();
            let mut sim = scene
                .simulation_builder_with_model(model)
                .unwrap()
                .initial_state((scene.l_m / v_ss).ln())
                .build()
                .unwrap();
            run_until(&mut sim, scene.end_time_s, &mut []);
            let down = [-theta.cos(), -theta.sin()];
            let mut worst = 0.0f64;
            for &p in &nodes {
                let vm = &sim.kinematics().v[2 * p..2 * p + 2];
                let vg = sim.model().to_global(p, [vm[0], vm[1]]);
                let speed = vg[0].hypot(vg[1]);
                let along = (vg[0] * down[0] + vg[1] * down[1]) / speed;
                assert!(
                    along > 1.0 - 1e-9,
                    "node {p} slides down the slope ({vg:?})"
                );
                worst = worst.max((speed / v_ss - 1.0).abs());
            }
            println!(
                "{law:?} θ = {theta_deg}°: V_ss = {v_ss:.6e} m/s, worst |V/V_ss − 1| = {worst:.3e}"
            );
            // The approach is exponential (measured: |V/V_ss − 1| ≈ 3e-3 at 1 s, ≤ 1e-7 at 3 s).
            assert!(worst < 1e-6, "{law:?} θ = {theta_deg}°: {worst:e}");
        }
    }
}

/// Asserts that `err` is a fault's corner at `node` of `angle` (°, to 1e-9).
fn assert_fault_corner(err: &Error, node: usize, angle: f64) {
    match err {
        Error::FaultCorner {
            node: n,
            angle_degrees,
            ..
        } => {
            assert_eq!(*n, node);
            assert!((angle_degrees - angle).abs() < 1e-9, "{angle_degrees}");
        }
        e => panic!("expected FaultCorner, got {e}"),
    }
}

#[test]
fn a_fault_around_a_corner_is_a_typed_error_naming_the_node() {
    let mesh = rectangle([0.0, 0.0], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
    // Bottom and right side: the corner (2, 0) is node 4, facets at 90°.
    let builder = || {
        ModelBuilder::new(mesh.clone())
            .material(rsf::Material::new(1e8, 0.25, 2.7e3))
            .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
            .frictional_boundary(Part::predicate("L", |x| x[1] < 1e-9 || x[0] > 2.0 - 1e-9))
    };
    let err = builder().build().unwrap_err();
    assert_fault_corner(&err, 4, 90.0);
    assert!(err.to_string().contains("node 4"), "{err}");
    // A limit above 90° accepts the corner (its normal is the diagonal, a frame node).
    let model = builder().max_fault_kink(91.0).build().unwrap();
    assert_eq!(model.frames.nodes, vec![4]);
    let q = model.frame(4).unwrap();
    let s = 0.5f64.sqrt();
    // Inward normal −(1, −1)/√2 in the last column, tangent (1, 1)/√2 in the first.
    assert!((q[0][1] + s).abs() < 1e-12 && (q[1][1] - s).abs() < 1e-12);
    assert!((q[0][0] - s).abs() < 1e-12 && (q[1][0] - s).abs() < 1e-12);
    // Out-of-range limit.
    let err = ModelBuilder::new(mesh.clone())
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .frictional_boundary(Part::predicate("bottom", |x| x[1] < 1e-9))
        .max_fault_kink(f64::NAN)
        .build()
        .unwrap_err();
    assert!(matches!(&err, Error::InvalidParameter { name, .. } if name == "max_fault_kink"));
}

#[test]
fn a_partly_fixed_node_on_a_slanted_fault_is_a_typed_error() {
    let phi = 10f64.to_radians();
    let flat = rectangle([0.0, 0.0], [2.0, 1.0], 5, 3, Diagonal::Forward).unwrap();
    let mesh = rotated_mesh(&flat, phi, |m, back| {
        m.tag_boundary("base", |x| back(x)[1] < 1e-9);
        m.tag_boundary("left", |x| back(x)[0] < 1e-9);
    });
    // A roller on the left side fixes x only; its bottom node (0) is on the slanted fault.
    let err = ModelBuilder::new(mesh.clone())
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .dirichlet_components("left", &[0], [0.0, 0.0])
        .frictional_boundary("base")
        .build()
        .unwrap_err();
    assert!(
        matches!(&err, Error::InvalidParameter { name, reason } if name == "dirichlet" && reason.contains("node 0")),
        "{err}"
    );
    // Clamping it fully is fine: the node's prescribed velocity is rotated into its frame.
    let model = ModelBuilder::new(mesh)
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .dirichlet("left", [1e-3, 0.0])
        .frictional_boundary("base")
        .build()
        .unwrap();
    let q = model.frame(0).unwrap();
    let k = model.dirichlet.dofs.iter().position(|&i| i == 0).unwrap();
    assert!((model.dirichlet.factors[k] - 1e-3 * q[0][0]).abs() < 1e-18);
    assert!(model.fixed[0] && model.fixed[1]);
}

/// A 2 m × 2 m square with a crack along y = 1 from the left side to its tip at (1, 1)
/// (node 4): the crack's two faces have their own copies of (0, 1) (node 3 below, node 9
/// above) and meet at the tip, where the frictional boundary (both faces) folds back:
/// two coincident facets with opposite outer normals (+y below, −y above).
fn cracked_square() -> TriangleMesh {
    let mut vertices: Vec<[f64; 2]> = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64]).collect();
    vertices.push([0.0, 1.0]);
    // Squares (a, b, c, d) counter-clockwise from the lower left, split along a–c.
    let squares = [[0, 1, 4, 3], [1, 2, 5, 4], [9, 4, 7, 6], [4, 5, 8, 7]];
    let cells = squares
        .iter()
        .flat_map(|&[a, b, c, d]| [a, b, c, a, c, d])
        .collect();
    SimplexMesh::new(vertices, cells).unwrap()
}

#[test]
fn a_fault_folding_back_at_a_crack_tip_is_a_typed_error_naming_the_node() {
    let mesh = cracked_square();
    let crack = || Part::predicate("crack", |x| (x[1] - 1.0).abs() < 1e-9);
    let builder = |kink: f64| {
        ModelBuilder::new(mesh.clone())
            .material(rsf::Material::new(1e8, 0.25, 2.7e3))
            .dirichlet(Part::predicate("top", |x| x[1] > 2.0 - 1e-9), [1e-4, 0.0])
            .frictional_boundary(crack())
            .max_fault_kink(kink)
            .build()
    };
    // Under the default kink limit the tip is a corner of 180°.
    let err = builder(rsf::model::DEFAULT_MAX_FAULT_KINK_DEGREES).unwrap_err();
    assert_fault_corner(&err, 4, 180.0);
    // Admitting any kink, the normals still cancel: no frame exists.
    let err = builder(180.0).unwrap_err();
    match &err {
        Error::FaultFoldsBack { node, position, .. } => {
            assert_eq!(*node, 4);
            assert_eq!(position, &vec![1.0, 1.0]);
        }
        e => panic!("expected FaultFoldsBack, got {e}"),
    }
    assert!(err.to_string().contains("node 4"), "{err}");
    // One face alone (the lower body's: the two faces share their midpoints, so select by
    // the cell) is a flat fault.
    let mut mesh = mesh;
    let lower: Vec<usize> = (0..mesh.num_boundary_facets())
        .filter(|&f| {
            let cell = mesh.cell(mesh.boundary_facet_cell(f));
            (mesh.boundary_facet_midpoint(f)[1] - 1.0).abs() < 1e-9
                && cell.iter().all(|&v| mesh.vertices()[v][1] <= 1.0)
        })
        .collect();
    assert_eq!(lower.len(), 1);
    mesh.tag_boundary_facets("lower face", &lower).unwrap();
    let model = ModelBuilder::new(mesh)
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .dirichlet(Part::predicate("top", |x| x[1] > 2.0 - 1e-9), [1e-4, 0.0])
        .frictional_boundary("lower face")
        .build();
    assert!(model.is_ok(), "{:?}", model.err());
}

/// A bottom facet of 1e-11 m among ten of 100 m (a valid mesh: the sliver cell under it
/// has area 5e-12 m², above the mesh's degeneracy test at its 1 m longest edge): the
/// facet's normal is numerically undefined, a typed error naming the facet and a node.
#[test]
fn a_zero_length_fault_facet_is_a_typed_error_naming_the_node() {
    let mut xs: Vec<f64> = (0..=10).map(|i| 100.0 * i as f64).collect();
    xs.push(1000.0 + 1e-11);
    let mesh = rsf::fem::rectangle_from_coordinates(&xs, &[0.0, 1.0], Diagonal::Forward).unwrap();
    let err = ModelBuilder::new(mesh.clone())
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
        .frictional_boundary(Part::predicate("base", |x| x[1] < 1e-9))
        .build()
        .unwrap_err();
    match &err {
        Error::DegenerateFaultFacet {
            node,
            facet,
            measure,
            ..
        } => {
            assert!(mesh.boundary_facet(*facet).contains(node));
            assert!([10, 11].contains(node), "node {node}");
            assert!((measure - 1e-11).abs() < 1e-13, "{measure}");
        }
        e => panic!("expected DegenerateFaultFacet, got {e}"),
    }
    assert!(err.to_string().contains("node 1"), "{err}");
    // Without the sliver the base is fine.
    let mesh =
        rsf::fem::rectangle_from_coordinates(&xs[..11], &[0.0, 1.0], Diagonal::Forward).unwrap();
    assert!(ModelBuilder::new(mesh)
        .material(rsf::Material::new(1e8, 0.25, 2.7e3))
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [1e-4, 0.0])
        .frictional_boundary(Part::predicate("base", |x| x[1] < 1e-9))
        .build()
        .is_ok());
}

fn track_3d(scene: &Slider3dScene, model: Model<3>, x0: [f64; 3]) -> Track<3> {
    let mut tr = Track {
        x0: model.nearest_node(&x0).unwrap(),
        ..Track::default()
    };
    let mut sim = scene.build_with_model(model).unwrap();
    sim.run(scene.slider.steps, &mut [&mut tr]).unwrap();
    tr
}

/// The fast-loading slider (v_load 2e-2 m/s, 300 steps) extruded to 3-D at `level`
/// (W = 1 m, free lateral faces).
fn fast_slider_3d(level: usize) -> Slider3dScene {
    Slider3dScene {
        slider: SliderScene {
            level,
            ..fast_loading(2e-2, 300)
        },
        ..Slider3dScene::default()
    }
}

/// The fast-loading slider extruded to 3-D (level 1, W = 1 m, free lateral faces, τ = 1e-3
/// s, 300 steps through its first slip event) rotated by 30° about (1, 2, 3)/√14 gives the
/// unrotated trajectory (as the 2-D test above): the rotated fault's frames are
/// `(R e_x, −R e_z, R e_y)` with `fault_tangent = R e_x`, the unrotated fault's Cartesian
/// basis `(e_x, e_y, e_z)`, the same basis up to an orthogonal change per node.
#[test]
fn the_3d_slider_rotated_about_a_skew_axis_slips_as_the_unrotated_one() {
    let phi = 30f64.to_radians();
    let scene = fast_slider_3d(1);
    // The turned construction at angle 0 rebuilds the scene's model bit for bit (same
    // refinement, no frames).
    let straight_model = scene.build_model().unwrap();
    let zero = scene.build_turned_model(0.0).unwrap();
    assert!(zero.frames.nodes.is_empty());
    assert_eq!(straight_model.stiffness.val(), zero.stiffness.val());
    assert_eq!(straight_model.load, zero.load);
    assert_eq!(straight_model.fixed, zero.fixed);

    let turned_model = scene.build_turned_model(phi).unwrap();
    assert_eq!(
        turned_model.frames.nodes,
        turned_model.frictional_boundary.nodes
    );
    let (t1, n_in) = (
        skew_rotation(phi, [1.0, 0.0, 0.0]),
        skew_rotation(phi, [0.0, 1.0, 0.0]),
    );
    for q in &turned_model.frames.rotations {
        for r in 0..3 {
            assert!((q[r][0] - t1[r]).abs() < 1e-12 && (q[r][2] - n_in[r]).abs() < 1e-12);
        }
    }
    let straight = track_3d(&scene, straight_model, scene.centre());
    let turned = track_3d(&scene, turned_model, skew_rotation(phi, scene.centre()));
    assert_eq!(straight.x0, turned.x0, "x0 is the same node");
    assert_eq!(straight.t, turned.t);
    let (f1, f2) = (straight.first_slip(), turned.first_slip());
    let (p1, p2) = (straight.peak(), turned.peak());
    let (s1, s2) = (straight.slip(), turned.slip());
    let (differ, off_by_more) = straight.fpi_differences(&turned);
    let worst_ln_v = straight.worst_ln_v(&turned);
    println!(
        "3-D: first slip {f1:.9} / {f2:.9} s, peak V {p1:.9e} / {p2:.9e} m/s, slip at x0 \
         {s1:.9e} / {s2:.9e} m, FPI {} / {} (differ at {differ} of {} steps), max |Δ ln V| \
         {worst_ln_v:.2e}",
        straight.fpi.iter().sum::<usize>(),
        turned.fpi.iter().sum::<usize>(),
        straight.t.len()
    );
    straight.assert_same_event(&turned);
    assert!(worst_ln_v <= 1e-6, "max |Δ ln V| = {worst_ln_v:e}");
    // The Cartesian velocity of x0 is the rotated one.
    for (a, b) in straight.v_x0.iter().zip(&turned.v_x0) {
        let ra = skew_rotation(phi, *a);
        let scale = a.iter().map(|c| c * c).sum::<f64>().sqrt().max(1e-12);
        let d = (0..3).map(|r| (ra[r] - b[r]).powi(2)).sum::<f64>().sqrt();
        assert!(d <= 1e-6 * scale, "{a:?} rotated vs {b:?}");
    }
    assert!(
        differ <= 3 && !off_by_more,
        "{differ} steps differ in FPI count"
    );
}

/// The 3-D slider rotated by 30° about the skew axis at level 2, the block sliding along
/// the fault at 0.5 m/s (rotated `e_x`) the step before: TNNMG and the direct solver agree
/// to 1e-9 in the energy norm on the slanted 3-D fault.
#[test]
fn tnnmg_and_direct_agree_on_a_slanted_3d_fault() {
    let phi = 30f64.to_radians();
    let scene = fast_slider_3d(2);
    let model = scene.build_turned_model(phi).unwrap();
    assert!(!model.frames.nodes.is_empty());
    let (rel, vmax) =
        tnnmg_against_direct(&scene.slider, &model, skew_rotation(phi, [0.5, 0.0, 0.0]));
    println!(
        "TNNMG vs direct on a slanted 3-D fault ({} dofs): {rel:e} (largest slip rate {vmax:e} \
         m/s)",
        model.num_dofs()
    );
    assert!(vmax > 1e-3, "the fault slides");
    assert!(rel <= 1e-9, "relative energy-norm difference {rel:e}");
}

/// The fixture's coarse mesh (`rsf_scenes::ARC_BLOCK_MESH`: the block x ∈ [0, 5], y ≤ 1
/// on the lower branch of the circle of radius `ARC_RADIUS_M` about `ARC_CENTRE`), read
/// through the Gmsh reader.
fn arc_block_coarse() -> TriangleMesh {
    rsf::fem::read_gmsh::<2>(ARC_BLOCK_MESH).unwrap().mesh
}

/// The block on the arc at `level`: the fixture refined with new base nodes moved onto the
/// arc, the paper's material, the top clamped (moving at the loading velocity), the arc
/// frictional.
fn arc_block(scene: &SliderScene, level: usize) -> Model<2> {
    let hierarchy = rsf::fem::MeshHierarchy::try_refine_uniformly_onto(
        arc_block_coarse(),
        level,
        TAG_FRICTIONAL,
        onto_arc,
    )
    .unwrap();
    ModelBuilder::from_hierarchy(hierarchy)
        .material(scene.material())
        .gravity([0.0, -scene.gravity_m_per_s2])
        .dirichlet(TAG_DIRICHLET, [scene.loading_velocity_m_per_s, 0.0])
        .frictional_boundary(TAG_FRICTIONAL)
        .loading(scene.loading())
        .build()
        .expect("the block on the arc builds")
}

/// The frames of the curved fault: their inward normals (last columns) converge to the
/// exact normals of the arc, `(centre − x)/R`, at O(h²). The area-weighted mean of the two
/// chord normals at a node is the normal of the central difference `x_{p+1} − x_{p−1}`,
/// second order where the spacing varies smoothly (here: equally spaced in x on every
/// level), with the leading term (h²/6) |y'''|/(1 + y'²) checked to 1 % on every level.
/// (A radial projection of the refined nodes would halve the angles of each coarse
/// interval, keep the coarse spacing's jumps at the coarse nodes and give O(h) there.)
/// Measured at the arc's interior nodes (at its two ends Γ_F has one facet, a
/// one-sided O(h) normal); the fixture's own nodes lie on the arc (checked).
#[test]
fn the_frames_of_a_curved_fault_converge_to_the_arc_normals_at_second_order() {
    let coarse = arc_block_coarse();
    let on_arc: Vec<usize> = coarse
        .facets_with_tag(TAG_FRICTIONAL)
        .iter()
        .flat_map(|&f| coarse.boundary_facet(f).to_vec())
        .collect();
    assert_eq!(coarse.facets_with_tag(TAG_FRICTIONAL).len(), 10);
    for &p in &on_arc {
        let x = coarse.vertices()[p];
        let r = (x[0] - ARC_CENTRE[0]).hypot(x[1] - ARC_CENTRE[1]);
        assert!(
            (r - ARC_RADIUS_M).abs() < 1e-12,
            "fixture node {p} off the arc: {r}"
        );
    }
    let scene = fast_loading(2e-2, 300);
    let mut errors = Vec::new();
    for level in 0..=4 {
        let model = arc_block(&scene, level);
        let h = 0.5 / f64::from(1u32 << level);
        let mut worst = 0.0f64;
        let mut predicted = 0.0f64;
        let mut framed = 0;
        for &p in &model.frictional_boundary.nodes {
            let x = model.vertices[p];
            if x[0] < 1e-9 || x[0] > 5.0 - 1e-9 {
                continue;
            }
            let exact = [
                (ARC_CENTRE[0] - x[0]) / ARC_RADIUS_M,
                (ARC_CENTRE[1] - x[1]) / ARC_RADIUS_M,
            ];
            // The inward normal: the frame's last column, or +e_y where the normal is along
            // the axis (no frame: only the arc's lowest point x = 2.5).
            let n = match model.frame(p) {
                Some(q) => {
                    framed += 1;
                    [q[0][1], q[1][1]]
                }
                None => {
                    assert!((x[0] - 2.5).abs() < 1e-12, "node {p} at {x:?} has no frame");
                    [0.0, 1.0]
                }
            };
            // The arc is below the centre: every node's normal points up into the block.
            assert!(n[1] > 0.9);
            worst = worst.max((n[0] - exact[0]).hypot(n[1] - exact[1]));
            // The leading error term: the normal is that of the central difference
            // (2h, y(x+h) − y(x−h)) = 2h (1, y' + h² y'''/6 + O(h⁴)), off by the angle
            // (h²/6) y'''/(1 + y'²), with y = c_y − √(R² − u²), u = x − c_x:
            // y' = u/s, y''' = 3R²u/s⁵, s = √(R² − u²).
            let u = x[0] - ARC_CENTRE[0];
            let s = (ARC_RADIUS_M * ARC_RADIUS_M - u * u).sqrt();
            let (d1, d3) = (u / s, 3.0 * ARC_RADIUS_M * ARC_RADIUS_M * u / s.powi(5));
            predicted = predicted.max(h * h / 6.0 * d3.abs() / (1.0 + d1 * d1));
        }
        println!(
            "level {level}: h = {h:.4} m along x, {framed} frames, max |n − n_arc| = \
             {worst:.3e} (leading term {predicted:.3e})"
        );
        errors.push(worst);
        assert!(
            (worst / predicted - 1.0).abs() < 0.01,
            "level {level}: error {worst:e}, leading term {predicted:e}"
        );
    }
    let rates: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("observed orders: {rates:.3?}");
    assert!(
        rates.iter().all(|&r| r > 1.8),
        "normals converge at O(h²): orders {rates:?}"
    );
}

/// TNNMG and the direct solver agree to 1e-9 relative in the energy norm on the curved
/// fault (level 3), the block moving along x at 0.5 m/s the step before.
#[test]
fn tnnmg_and_direct_agree_on_a_curved_fault() {
    let scene = SliderScene {
        level: 3,
        ..fast_loading(2e-2, 300)
    };
    let model = arc_block(&scene, scene.level);
    assert!(model.frames.nodes.len() + 1 == model.frictional_boundary.len());
    let (rel, vmax) = tnnmg_against_direct(&scene, &model, [0.5, 0.0]);
    println!("TNNMG vs direct on the arc: {rel:e} (largest slip rate {vmax:e} m/s)");
    assert!(vmax > 1e-3, "the fault slides");
    assert!(rel <= 1e-9, "relative energy-norm difference {rel:e}");
}

/// Curvature of the 3-D curved base `y = CURVED_3D_C (x − 2.5)²` (1/m²): 0.125 m higher at
/// the ends of the 5 m block than at its middle.
const CURVED_3D_C: f64 = 0.02;

/// The 3-D slider (level 2, W = 1 m) on a base curved in x, the parabolic cylinder
/// `y = c (x − 2.5)²`: the coarse mesh's vertices moved by `(1 − y) c (x − 2.5)²` in y (top
/// fixed), then refined with the new base vertices moved onto the cylinder. Every base
/// node off x = 2.5 gets a nodal frame.
fn curved_slider_3d(scene: &Slider3dScene, level: usize) -> Model<3> {
    let bump = |x: f64| CURVED_3D_C * (x - 2.5).powi(2);
    let flat = slider_3d_coarse(scene.width_m).unwrap();
    let moved = flat
        .vertices()
        .iter()
        .map(|x| [x[0], x[1] + (1.0 - x[1]) * bump(x[0]), x[2]])
        .collect();
    let coarse = flat.with_moved_vertices(moved).unwrap();
    let hierarchy =
        rsf::fem::MeshHierarchy::try_refine_uniformly_onto(coarse, level, TAG_FRICTIONAL, |x| {
            [x[0], bump(x[0]), x[2]]
        })
        .unwrap();
    let s = &scene.slider;
    ModelBuilder::from_hierarchy(hierarchy)
        .material(s.material())
        .gravity([0.0, -s.gravity_m_per_s2, 0.0])
        .dirichlet(TAG_DIRICHLET, [s.loading_velocity_m_per_s, 0.0, 0.0])
        .frictional_boundary(TAG_FRICTIONAL)
        .fault_tangent([1.0, 0.0, 0.0])
        .loading(s.loading())
        .build()
        .expect("the 3-D block on the curved base builds")
}

/// TNNMG and the direct solver agree to 1e-9 relative in the energy norm on a curved 3-D
/// fault (the block moving along x at 0.5 m/s the step before).
#[test]
fn tnnmg_and_direct_agree_on_a_curved_3d_fault() {
    let scene = fast_slider_3d(2);
    let model = curved_slider_3d(&scene, 2);
    let with_frames = model.frames.nodes.len();
    assert!(
        with_frames + 20 >= model.frictional_boundary.len() && with_frames > 0,
        "{with_frames} of {} base nodes have frames",
        model.frictional_boundary.len()
    );
    let (rel, vmax) = tnnmg_against_direct(&scene.slider, &model, [0.5, 0.0, 0.0]);
    println!(
        "TNNMG vs direct on a curved 3-D fault ({} dofs, {with_frames} frames): {rel:e} \
         (largest slip rate {vmax:e} m/s)",
        model.num_dofs()
    );
    assert!(vmax > 1e-3, "the fault slides");
    assert!(rel <= 1e-9, "relative energy-norm difference {rel:e}");
}

/// A [`PointSeries`](rsf::observe::PointSeries) at a vertex with a nodal frame writes its slip
/// coordinates (tangent, inward normal) and its header names them so; at a vertex without
/// a frame (and on the axis-aligned slider, the main job's files) the header is the
/// Cartesian one, byte for byte as before (issue 34).
#[test]
fn a_point_series_at_a_framed_vertex_names_slip_coordinates() {
    use rsf::observe::{FileMode, PointSeries};
    let cartesian = "t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,\
                     relaxed_iterations,u_y0_m,v_y0_mps";
    assert_eq!(PointSeries::<2>::header(), cartesian);
    let scene = fast_loading(2e-2, 300);
    let straight = scene.build_model().unwrap();
    let x0 = straight.nearest_node(&SLIDER_CENTRE).unwrap();
    assert_eq!(PointSeries::header_at(&straight, x0), cartesian);

    let phi = 30f64.to_radians();
    let model = rotated_slider(&scene, phi);
    let x0 = model.nearest_node(&rot(phi, SLIDER_CENTRE)).unwrap();
    assert!(model.frame(x0).is_some());
    let framed = "t_s,u_t_m,v_t_mps,max_slip_rate_mps,fpi,tau_s,step,solver_iterations,\
                  relaxed_iterations,u_n_m,v_n_mps";
    assert_eq!(PointSeries::header_at(&model, x0), framed);
    let top = model.nearest_node(&rot(phi, [2.5, 1.0])).unwrap();
    assert!(model.frame(top).is_none());
    assert_eq!(PointSeries::header_at(&model, top), cartesian);

    let dir = temp_dir("framed-series");
    let path = dir.join("x0.csv");
    let mut series = PointSeries::new(&path, &model, x0, FileMode::Overwrite).unwrap();
    let mut tr = Track {
        x0,
        ..Track::default()
    };
    let mut sim = scene.build_with_model(model).unwrap();
    sim.run(3, &mut [&mut series, &mut tr]).unwrap();
    drop(series);
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().next(), Some(framed));
    // The columns hold the slip coordinates: what `displacement_in_frame` shows, the
    // normal velocity (fixed by bilateral contact) zero.
    let rows = PointSeries::<2>::read(&path).unwrap();
    assert_eq!(rows.len(), 3);
    for (row, u) in rows.iter().zip(&tr.u_x0) {
        assert_eq!(
            row.u.map(|x| format!("{x:.12e}")),
            u.map(|x| format!("{x:.12e}"))
        );
        assert_eq!(row.v[1], 0.0);
    }
    PointSeries::<2>::check_resume(&path, 3).unwrap();
    std::fs::remove_dir_all(&dir).ok();
}
