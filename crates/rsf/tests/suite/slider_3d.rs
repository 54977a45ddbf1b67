//! The 3-D slider (issue 12; docs/math.md §10): with `u_z = 0` on its lateral faces it
//! reproduces the 2-D main job, TNNMG and the direct solver agree on its velocity
//! problems, and its VTU frames hold tetrahedra.

use crate::common::{
    apply, dot, first_crossing, newmark_rhs, newmark_velocity_matrix, steady_shear_strain,
    tnnmg_on, uniform_friction, with_dirichlet_values,
};
use rsf::direct::{DirectOptions, DirectSolver};
use rsf::fem::SparseMatrix;
use rsf::friction::DieterichRuina;
use rsf::method::FrictionBlocks;
use rsf::nonsmooth::{NonsmoothSolver, Stopping};
use rsf::tnnmg::{Tnnmg, TnnmgOptions};
use rsf::{Model, Observer, SolverKind, StepView};
use rsf_scenes::{LateralBoundary, Slider3dScene, SliderScene, SLIDER_CENTRE};

/// Time, `u_x` at one node and the largest slip rate of every step, until the largest slip
/// rate exceeds `stop` (m/s).
struct Trace {
    node: usize,
    stop: f64,
    t: Vec<f64>,
    u_x: Vec<f64>,
    max_slip_rate: Vec<f64>,
}

impl Trace {
    fn new(node: usize, stop: f64) -> Self {
        Self {
            node,
            stop,
            t: Vec::new(),
            u_x: Vec::new(),
            max_slip_rate: Vec::new(),
        }
    }

    /// `u_x` at time `t` (linear interpolation between steps).
    fn u_x_at(&self, t: f64) -> f64 {
        let i = self
            .t
            .partition_point(|&s| s < t)
            .clamp(1, self.t.len() - 1);
        let w = (t - self.t[i - 1]) / (self.t[i] - self.t[i - 1]);
        self.u_x[i - 1] + w * (self.u_x[i] - self.u_x[i - 1])
    }
}

impl<const D: usize> Observer<D> for Trace {
    fn observe(&mut self, s: &StepView<'_, D>) -> rsf::Result<rsf::Flow> {
        self.t.push(s.report.time);
        self.u_x.push(s.state.kinematics.u[D * self.node]);
        self.max_slip_rate.push(s.report.max_slip_rate);
        Ok(if s.report.max_slip_rate > self.stop {
            rsf::Flow::Break(())
        } else {
            rsf::Flow::Continue(())
        })
    }
}

/// Issue 12's plane-strain check. The 3-D slider with `u_z = 0` on both lateral faces
/// (W = 1 m) against the 2-D main job (Table 6.1, N = 10⁴, Newmark, Dieterich) at the same
/// level j = 2: the first slip event (the largest slip rate crossing 1e-3 m/s,
/// interpolated in ln V between steps) within 0.5 %, and u_x(x0) before it within 1 %:
/// over the whole run up to `t_ev − 0.1 s` (the fault creeps a few µm by then), the
/// largest difference is at most 1 % of the 2-D `u_x(x0, t_ev − 0.1 s)`.
///
/// Level: j = 2 is the cheapest level where both comparisons are meaningful: the static
/// `u_x(x0)` before the creep (≈ −3e-7 m, an artefact of the meshes' diagonals that
/// vanishes under refinement) differs by 1.9 % at j = 2 and 0.6 % at j = 3 between the
/// Kuhn tetrahedra and the triangles, small against the creep; `u_x(x0, t_ev − 0.1 s)`
/// differs by about 0.15 % at j = 2 and 0.05 % at j = 3; both levels give the same event
/// time to the step (10.086 s at j = 2, 10.0875 s at j = 3, the value). j = 3 costs
/// ten times more (≈ 10⁴ dofs).
#[test]
fn plane_strain_reproduces_the_2d_main_job() {
    let slider = SliderScene {
        level: 2,
        solver: SolverKind::Direct,
        ..SliderScene::default()
    };
    let stop = 1e-3;
    let mut sim2 = slider.build().expect("2-D slider");
    let x0 = sim2.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let mut trace2 = Trace::new(x0, stop);
    sim2.run(slider.steps, &mut [&mut trace2]).unwrap();

    let scene = Slider3dScene {
        slider,
        width_m: 1.0,
        lateral: LateralBoundary::PlaneStrain,
    };
    let mut sim3 = scene.build().expect("3-D slider");
    let x0 = sim3.model().nearest_node(&scene.centre()).unwrap();
    assert_eq!(sim3.model().vertices[x0], scene.centre(), "x0 is a node");
    let mut trace3 = Trace::new(x0, stop);
    sim3.run(scene.slider.steps, &mut [&mut trace3]).unwrap();

    let event = |t: &Trace| first_crossing(&t.t, &t.max_slip_rate, stop, 0.0).expect("an event");
    let (ev2, ev3) = (event(&trace2), event(&trace3));
    let before = ev2 - 0.1;
    let u2 = trace2.u_x_at(before);
    let max_diff = trace2
        .t
        .iter()
        .take_while(|&&t| t <= before)
        .map(|&t| (trace3.u_x_at(t) - trace2.u_x_at(t)).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "plane strain, j = 2: first event 2-D {ev2:.5} s, 3-D {ev3:.5} s; u_x(x0, {before:.4} s) \
         2-D {u2:.6e} m, 3-D {:.6e} m; largest difference before it {max_diff:.3e} m",
        trace3.u_x_at(before)
    );
    assert!((ev3 - ev2).abs() <= 5e-3 * ev2, "event {ev3} vs {ev2}");
    assert!(u2 > 1e-6, "the fault has crept before the event: {u2:e}");
    assert!(max_diff <= 1e-2 * u2, "u_x(x0): {max_diff:e} vs {u2:e}");
}

/// Post-ramp loading velocity of Γ_D (m/s).
const V_TOP: f64 = 2e-4;

/// Direction of the previous sliding velocity in the fault plane (x, z): 30° off x, so
/// that both tangential components of every friction block are active.
const SLIDE_DIRECTION: [f64; 3] = [0.866_025_403_784_438_6, 0.0, 0.5];

/// One Newmark velocity problem of the 3-D slider (free lateral faces) at a level.
struct Problem {
    scene: Slider3dScene,
    model: Model<3>,
    a: SparseMatrix,
    /// Dofs of Γ_D (the top face), all three components.
    top: Vec<bool>,
}

impl Problem {
    fn new(level: usize) -> Self {
        let scene = Slider3dScene {
            slider: SliderScene {
                level,
                ..SliderScene::default()
            },
            ..Slider3dScene::default()
        };
        let tau = scene.slider.tau();
        let model = scene.build_model().expect("3-D slider model");
        let a = newmark_velocity_matrix(&model, tau);
        let top = (0..model.num_dofs())
            .map(|i| model.vertices[i / 3][1] > 1.0 - 1e-9)
            .collect();
        Self {
            scene,
            model,
            a,
            top,
        }
    }

    fn n(&self) -> usize {
        self.model.num_dofs()
    }

    /// `v_prev`: `V · SLIDE_DIRECTION` below the top, the loading velocity on it.
    fn previous_velocity(&self, v_slide: f64) -> Vec<f64> {
        (0..self.n())
            .map(|i| match (self.top[i], i % 3) {
                (true, 0) => V_TOP,
                (true, _) => 0.0,
                (false, c) => v_slide * SLIDE_DIRECTION[c],
            })
            .collect()
    }

    /// Newmark right-hand side ℓ from `(u_0 + prestress, v_prev, 0)`.
    fn rhs(&self, v_slide: f64) -> Vec<f64> {
        let s = &self.scene.slider;
        // Shear prestress u_t += γ y along the sliding direction with G γ = μ_ss(V) σ̄_n:
        // the elastic traction on Γ_F balances steady-state friction (a slip phase).
        let mut u = self.model.initial_displacement.clone();
        if v_slide > 0.0 {
            let gamma = steady_shear_strain(s, v_slide);
            for (i, u) in u.iter_mut().enumerate() {
                *u += gamma * self.model.vertices[i / 3][1] * SLIDE_DIRECTION[i % 3];
            }
        }
        newmark_rhs(&self.model, s.tau(), u, self.previous_velocity(v_slide))
    }

    /// Warm start: `v_prev` with the Dirichlet values on the fixed dofs.
    fn start(&self, v_slide: f64) -> Vec<f64> {
        let v = self.previous_velocity(v_slide);
        with_dirichlet_values(&self.model, &self.top, V_TOP, v)
    }

    fn dieterich_ruina(&self, alpha: f64) -> FrictionBlocks<DieterichRuina> {
        let law = DieterichRuina::new(self.scene.slider.rate_state_params()).unwrap();
        uniform_friction(&self.model, law, alpha)
    }

    /// TNNMG on this problem's hierarchy, stopping norm `K + M`.
    fn tnnmg(&self, opts: TnnmgOptions) -> Tnnmg<3> {
        tnnmg_on(&self.a, &self.model, opts)
    }

    /// `‖x − y‖_E / ‖y‖_E` in the energy norm `K + M`.
    fn relative_difference(&self, x: &[f64], y: &[f64]) -> f64 {
        let d: Vec<f64> = x.iter().zip(y).map(|(a, b)| a - b).collect();
        let norm = |x: &[f64]| dot(x, &apply(&self.model.energy_norm, x)).max(0.0).sqrt();
        norm(&d) / norm(y)
    }
}

/// Issue 12: on the 3-D slider's Newmark velocity problems TNNMG and the direct solver
/// agree to 1e-9 relative in the energy norm `K + M`, at levels j = 1, 2, 3 (297, 1 575 and
/// 9 963 dofs), for Dieterich–Ruina at the paper's initial state α = −10 from rest and at
/// steady state α = ln(L/V) while sliding at V ∈ {1e-6, 1e-3} m/s 30° off the x axis (both
/// tangential components of every block active). TNNMG (default options) stops at 1e-12
/// relative in the energy norm, tighter than the paper's 1e-10 absolute, so that the
/// agreement measures the solvers and not the stopping test. Its iteration counts are
/// printed (measured: 5 5 5 at j = 1, 7 5 6 at j = 2, 5 5 5 at j = 3); the band asserted:
/// at most 25 per solve, and at j = 3 at most twice the count at j = 1 plus 2 (multigrid:
/// no growth with the level beyond that).
#[test]
fn tnnmg_and_direct_agree_on_3d_velocity_problems() {
    let cases: [(&str, f64, Option<f64>); 3] = [
        ("alpha=-10, from rest", 0.0, Some(-10.0)),
        ("steady, V=1e-6", 1e-6, None),
        ("steady, V=1e-3", 1e-3, None),
    ];
    let mut counts = Vec::new();
    for level in 1..=3 {
        let p = Problem::new(level);
        let opts = TnnmgOptions {
            stopping: Stopping {
                absolute: 0.0,
                relative: 1e-12,
                max_iterations: 200,
            },
            ..TnnmgOptions::default()
        };
        let mut tn = p.tnnmg(opts);
        let mut direct =
            DirectSolver::<3>::new(p.a.as_ref(), &p.model.fixed, DirectOptions::default()).unwrap();
        let mut row = Vec::new();
        for (name, v_slide, alpha) in cases {
            let alpha = alpha.unwrap_or_else(|| (p.scene.slider.l_m / v_slide).ln());
            let b = p.rhs(v_slide);
            let nl = p.dieterich_ruina(alpha);
            let mut v_d = p.start(v_slide);
            direct.solve(&b, &nl, &mut v_d).unwrap();
            let mut v_tn = p.start(v_slide);
            let rep = tn.solve(&b, &nl, &mut v_tn).unwrap();
            let d = p.relative_difference(&v_tn, &v_d);
            let slip: Vec<f64> = p
                .model
                .frictional_boundary
                .nodes
                .iter()
                .map(|&q| v_d[3 * q].hypot(v_d[3 * q + 2]))
                .collect();
            let (lo, hi) = slip
                .iter()
                .fold((f64::INFINITY, 0.0_f64), |(l, h), &s| (l.min(s), h.max(s)));
            eprintln!(
                "j={level} ({} dofs) {name:22} tnnmg {:2} its, vs direct {d:.1e}; slip rates {lo:.1e} … {hi:.1e} m/s",
                p.n(),
                rep.iterations
            );
            assert!(d < 1e-9, "j={level} {name}: tnnmg vs direct {d:.3e}");
            assert!(
                rep.iterations <= 25,
                "j={level} {name}: {} its",
                rep.iterations
            );
            row.push(rep.iterations);
        }
        counts.push(row);
    }
    for (k, (name, _, _)) in cases.iter().enumerate() {
        assert!(
            counts[2][k] <= 2 * counts[0][k] + 2,
            "{name}: iterations grow with the level: {:?}",
            counts.iter().map(|r| r[k]).collect::<Vec<_>>()
        );
    }
}

/// CPU time of the calling thread (s): the first field of `/proc/thread-self/schedstat`
/// (Linux); NaN elsewhere.
fn thread_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// Thread CPU time (s) per call of `solve`, each call from `start`: the mean over repeated
/// calls for at least 0.2 s (the clock advances in scheduler ticks of a few ms).
fn seconds_per_solve(start: &[f64], mut solve: impl FnMut(&mut Vec<f64>)) -> f64 {
    let mut v = start.to_vec();
    let t0 = thread_seconds();
    let mut calls = 0;
    while calls == 0 || thread_seconds() - t0 < 0.2 {
        v.copy_from_slice(start);
        solve(&mut v);
        calls += 1;
    }
    (thread_seconds() - t0) / calls as f64
}

/// Measurement for docs/three-d.md, not a check: the cost of one TNNMG solve of the 3-D
/// slider's velocity problem (DR at steady state, sliding at 1e-6 m/s) against linear
/// multigrid on the same `A` and `b` (the TNNMG machinery with `NoNonlinearity`), both
/// with the scene's options (default TNNMG, 1e-10 absolute in the energy norm), from the
/// same warm start; thread CPU time per solve, median of 5 alternating rounds. Levels from
/// `RSF_3D_COST_LEVELS` (default `1,2,3`).
///
/// `cargo test --release -p rsf --test suite -- --ignored --nocapture slider_3d::solve_cost`
#[test]
#[ignore = "measurement; run with --ignored --nocapture"]
fn solve_cost_tnnmg_against_linear_multigrid() {
    let levels: Vec<usize> = std::env::var("RSF_3D_COST_LEVELS")
        .unwrap_or_else(|_| "1,2,3".into())
        .split(',')
        .map(|l| l.trim().parse().expect("a level"))
        .collect();
    for level in levels {
        let p = Problem::new(level);
        let v_slide = 1e-6;
        let b = p.rhs(v_slide);
        let nl = p.dieterich_ruina((p.scene.slider.l_m / v_slide).ln());
        let start = p.start(v_slide);
        let SolverKind::Auto = p.scene.slider.solver else {
            unreachable!("the default scene's solver is Auto")
        };
        let opts = p.scene.slider.solver_options().tnnmg;
        let mut tn = p.tnnmg(opts);
        let its = |tn: &mut Tnnmg<3>, linear: bool| {
            let mut v = start.clone();
            if linear {
                tn.solve(&b, &rsf::nonsmooth::NoNonlinearity, &mut v)
            } else {
                tn.solve(&b, &nl, &mut v)
            }
            .unwrap()
            .iterations
        };
        let (its_tn, its_lin) = (its(&mut tn, false), its(&mut tn, true));
        let (mut t_tn, mut t_lin) = (Vec::new(), Vec::new());
        for _round in 0..5 {
            t_tn.push(seconds_per_solve(&start, |v| {
                tn.solve(&b, &nl, v).unwrap();
            }));
            t_lin.push(seconds_per_solve(&start, |v| {
                tn.solve(&b, &rsf::nonsmooth::NoNonlinearity, v).unwrap();
            }));
        }
        t_tn.sort_by(f64::total_cmp);
        t_lin.sort_by(f64::total_cmp);
        let (t_tn, t_lin) = (t_tn[2], t_lin[2]);
        eprintln!(
            "j={level} n={} frictional nodes={}: TNNMG {its_tn} its {:.3} ms, linear MG {its_lin} its {:.3} ms, TNNMG / linear MG {:.2}",
            p.n(),
            p.model.frictional_boundary.nodes.len(),
            t_tn * 1e3,
            t_lin * 1e3,
            t_tn / t_lin
        );
    }
}

/// VTU frames of the 3-D slider hold its tetrahedra: ParaView's cell type 10 (tetra) for
/// every cell, the model's connectivity and vertices, and the 3 components of the state.
#[cfg(feature = "vtk")]
#[test]
fn vtu_frames_of_the_3d_slider_are_tetrahedra() {
    use vtkio::model::{CellType, DataSet, VertexNumbers};
    let dir = crate::common::temp_dir("vtu-3d");
    let scene = Slider3dScene {
        slider: SliderScene {
            level: 0,
            steps: 100,
            ..SliderScene::default()
        },
        ..Slider3dScene::default()
    };
    let mut sim = scene.build().unwrap();
    let mut frames = rsf::observe::Every::new(
        rsf::observe::Interval::Steps(2),
        rsf::observe::VtuFrames::new(&dir, rsf::observe::FileMode::Create).unwrap(),
    )
    .unwrap();
    sim.run(2, &mut [&mut frames]).unwrap();
    let vtk = vtkio::Vtk::import(dir.join("frame_000002.vtu")).expect("valid VTK XML");
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).expect("inline piece");
    let m = sim.model();
    assert_eq!(piece.num_points(), m.num_nodes());
    let points = piece.points.clone().cast_into::<f64>().unwrap();
    let flat: Vec<f64> = m.vertices.iter().flatten().copied().collect();
    assert_eq!(points, flat);
    assert_eq!(piece.cells.types.len(), m.cells.len() / 4);
    assert!(piece.cells.types.iter().all(|&t| t == CellType::Tetra));
    let VertexNumbers::XML { connectivity, .. } = &piece.cells.cell_verts else {
        panic!("XML connectivity")
    };
    let cells: Vec<u64> = m.cells.iter().map(|&c| c as u64).collect();
    assert_eq!(connectivity, &cells);
    let _ = std::fs::remove_dir_all(&dir);
}
