//! VTU frames for ParaView: files are written during the run, read back with vtkio, and
//! their point data (u, v, α; on Γ_F slip, shear and normal traction) equal the
//! simulation's state at the frame's step (issues 13, 24).
#![cfg(feature = "vtk")]

use crate::common::*;
use rsf::friction::FrictionLaw;
use rsf::observe::{Every, FileMode, Interval, VtuFrames};

mod point_data;
use point_data::point_data;

#[test]
fn frames_hold_the_state_of_their_step() {
    let dir = temp_dir("vtu");
    // Fast loading: by step 40 Γ_F slides, so u, v differ from node to node and step to step.
    let scene = with_level(fast_loading(2e-2, 40), 1);
    let mut sim = build(&scene);
    let mut frames = Every::new(
        Interval::Steps(20),
        VtuFrames::new(&dir, FileMode::Create).expect("frame folder"),
    )
    .unwrap();
    let mut states = Snapshots {
        every: 20,
        ..Snapshots::default()
    };
    run_until(&mut sim, 0.04, &mut [&mut frames, &mut states]);
    assert_eq!(states.states.len(), 2);
    let model = sim.model();
    let n = model.vertices.len();
    for (step, kin, alpha) in &states.states {
        let path = dir.join(format!("frame_{step:06}.vtu"));
        let vtk = vtkio::Vtk::import(&path).expect("frame is valid VTK XML");
        let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let piece = pieces[0].load_piece_data(None).expect("inline piece");
        assert_eq!(piece.num_points(), n);
        let points = piece
            .points
            .clone()
            .cast_into::<f64>()
            .expect("point coordinates");
        for (p, x) in model.vertices.iter().enumerate() {
            assert_eq!(&points[3 * p..3 * p + 3], &[x[0], x[1], 0.0], "vertex {p}");
        }
        for (name, field) in [("displacement", &kin.u), ("velocity", &kin.v)] {
            let data = point_data(&piece, name);
            assert_eq!(data.len(), 3 * n, "{name}");
            for p in 0..n {
                assert_eq!(
                    &data[3 * p..3 * p + 3],
                    &[field[2 * p], field[2 * p + 1], 0.0],
                    "step {step}: {name} at vertex {p}"
                );
            }
        }
        // α on Γ_F, NaN (no state) elsewhere.
        let state = point_data(&piece, "state_alpha");
        assert_eq!(state.len(), n);
        let mut on_fault = vec![false; n];
        for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
            on_fault[p] = true;
            assert_eq!(state[p], alpha[k], "step {step}: α at frictional node {p}");
        }
        for p in (0..n).filter(|&p| !on_fault[p]) {
            assert!(state[p].is_nan(), "step {step}: α at interior vertex {p}");
        }
        // In slip coordinates on Γ_F (NaN elsewhere): the slip u − u₀, the shear traction
        // σ̄_n μ(V, α) by the law's friction coefficient (the frame evaluates the
        // potential's slope: another code path), the prescribed normal traction σ̄_n.
        let slip = point_data(&piece, "slip");
        let shear = point_data(&piece, "shear_traction");
        let normal = point_data(&piece, "normal_traction");
        let law = friction_law(&scene);
        let sigma_n = params(&scene).sigma_n;
        let mut sliding = 0;
        for (k, &p) in model.frictional_boundary.nodes.iter().enumerate() {
            let u0 = &model.initial_displacement;
            let expected = [
                kin.u[2 * p] - u0[2 * p],
                kin.u[2 * p + 1] - u0[2 * p + 1],
                0.0,
            ];
            assert_eq!(
                &slip[3 * p..3 * p + 3],
                &expected,
                "step {step}: slip at {p}"
            );
            let v = kin.v[2 * p].hypot(kin.v[2 * p + 1]);
            let tau = sigma_n * law.friction_coefficient(v, alpha[k]);
            assert!(
                (shear[p] - tau).abs() <= 1e-12 * tau.abs().max(1.0),
                "step {step}: shear traction at {p}: {} vs σ̄_n μ = {tau}",
                shear[p]
            );
            sliding += usize::from(tau > 0.0);
            assert_eq!(normal[p], sigma_n, "step {step}: normal traction at {p}");
        }
        assert!(sliding > 0, "step {step}: no node slides");
        for p in (0..n).filter(|&p| !on_fault[p]) {
            assert!(shear[p].is_nan() && normal[p].is_nan() && slip[3 * p].is_nan());
        }
        // The frames differ from each other: the data are the step's, not a stale copy.
        let slip_rate = kin.v[2 * model.frictional_boundary.nodes[0]];
        assert!(slip_rate != 0.0, "step {step}: Γ_F at rest");
    }
    assert_ne!(states.states[0].1.u, states.states[1].1.u);
    assert_ne!(
        states.states[0].2, states.states[1].2,
        "α evolves between the frames"
    );
    let pvd = std::fs::read_to_string(dir.join("frames.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 2);
    for (step, ..) in &states.states {
        assert!(pvd.contains(&format!("file=\"frame_{step:06}.vtu\"")));
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A network's frames tell its faults apart (issue 83): the point field `fault` holds each
/// frictional vertex's fault index (0 west, 1 east, from their positions), NaN off the
/// faults, and `frames.pvd` names the indices.
#[test]
fn a_networks_frames_carry_each_vertexs_fault_and_the_names() {
    use crate::greens::{fault_ode, two_faults};
    let dir = temp_dir("vtu_network");
    let mut ode = fault_ode(two_faults(2.0, 4.0), rsf::fault_ode::FaultKernel::Dense);
    let mut frames = VtuFrames::new(&dir, FileMode::Create).expect("frame folder");
    rsf::run_until(&mut ode, rsf::Until::Steps(1), &mut [&mut frames]).unwrap();
    let model = rsf::Stepping::model(&ode);
    let vtk = vtkio::Vtk::import(dir.join("frame_000001.vtu")).expect("frame is valid VTK XML");
    let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).expect("inline piece");
    let fault = point_data(&piece, "fault");
    let on: std::collections::HashSet<usize> =
        model.frictional_boundary.nodes.iter().copied().collect();
    let (mut west, mut east) = (0, 0);
    for (p, x) in model.vertices.iter().enumerate() {
        if !on.contains(&p) {
            assert!(fault[p].is_nan(), "vertex {p} off the faults: {}", fault[p]);
        } else if x[0] < 0.0 {
            assert_eq!(fault[p], 0.0, "{x:?}");
            west += 1;
        } else {
            assert_eq!(fault[p], 1.0, "{x:?}");
            east += 1;
        }
    }
    assert!(west > 0 && east > 0);
    let index = std::fs::read_to_string(dir.join("frames.pvd")).unwrap();
    assert!(
        index.contains("<!-- fault 0: west -->") && index.contains("<!-- fault 1: east -->"),
        "{index}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
