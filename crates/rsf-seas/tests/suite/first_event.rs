//! A coarse SEAS BP1 run (the antiplane model of rsf-scenes) to its first event with the
//! benchmark's files and catalogue, resumed from a checkpoint bit-identically (issue 23,
//! docs/seas-bp1.md).

use rsf::friction::AsinhLaw;
use rsf::observe::FileMode;
use rsf::{Checkpoint, Flow, Observer, StepView};
use rsf_scenes::{SeasBp1, SeasBp1Grid, SeasBp1Simulation};
use rsf_seas::{SeasOutput, SeasSampling, SeasSetup, SECONDS_PER_YEAR};

fn coarse_bp1() -> (SeasBp1, SeasBp1Simulation) {
    let bp1 = SeasBp1::default();
    let grid = SeasBp1Grid {
        dz: 500.0,
        domain: 50e3,
        ratio: 1.05,
    };
    let model = bp1.model(&grid, false).unwrap();
    let sim = bp1
        .simulation_builder(model, false, 1e-2, bp1.step_control(1e-2).unwrap())
        .unwrap()
        .build()
        .unwrap();
    (bp1, sim)
}

fn output(dir: &std::path::Path, bp1: &SeasBp1, sim: &SeasBp1Simulation) -> SeasOutput<AsinhLaw> {
    SeasOutput::new(
        dir,
        sim.model(),
        sim.problem().friction_laws(),
        SeasSetup {
            problem: "BP1-QD (coarse test)".into(),
            modeler: "test".into(),
            date: "2026-11-24".into(),
            ..bp1.seas_setup(500.0, false, SeasSampling::default())
        },
        FileMode::Overwrite,
    )
    .unwrap()
}

/// Stops a run at the first step after the first event (max slip rate ≥ 1e-3 m/s, then
/// below again).
#[derive(Default)]
struct UntilFirstEventEnds {
    started: bool,
}

impl Observer<2, 1> for UntilFirstEventEnds {
    fn observe(&mut self, s: &StepView<'_, 2, 1>) -> rsf::Result<Flow> {
        let fast = s.report.max_slip_rate >= 1e-3;
        self.started |= fast;
        Ok(if self.started && !fast {
            Flow::Break(())
        } else {
            Flow::Continue(())
        })
    }
}

/// Runs `sim` with `out` until the first event has ended; returns the steps.
fn to_first_event_end(sim: &mut SeasBp1Simulation, out: &mut SeasOutput<AsinhLaw>) -> usize {
    let mut stop = UntilFirstEventEnds::default();
    let summary = sim.run(200_000, &mut [out, &mut stop]).unwrap();
    assert!(summary.steps < 200_000, "no event");
    summary.steps
}

/// A coarse BP1 (Δz = 500 m, 50 km domain, tolerance 1e-2) reaches its first event near
/// the spec's depth and time scale, writes the benchmark's files and catalogue; a
/// checkpoint taken in the interseismic period resumes to the same event and the same
/// final state, bit for bit.
#[test]
fn coarse_bp1_reaches_its_first_event_and_resumes_bit_identically() {
    let dir = std::env::temp_dir().join(format!("rsf_bp1_{}", std::process::id()));
    let (bp1, mut sim) = coarse_bp1();
    let mut out = output(&dir.join("a"), &bp1, &sim);
    let steps = to_first_event_end(&mut sim, &mut out);
    let first = out.events()[0];
    eprintln!("first event after {steps} steps: {first:?}");
    // Nucleation in the velocity-weakening zone, after decades of loading.
    assert!(first.hypocentre_depth > 5e3 && first.hypocentre_depth < 18e3);
    assert!(first.t_start > 50.0 * SECONDS_PER_YEAR && first.t_start < 400.0 * SECONDS_PER_YEAR);
    assert!(first.peak_slip_rate >= 1e-3 && first.t_end > first.t_start);
    let csv = std::fs::read_to_string(dir.join("a/events.csv")).unwrap();
    assert!(csv.starts_with(
        "event,t_start_s,t_end_s,hypocentre_depth_m,peak_slip_rate_mps,surface_slip_m\n1,"
    ));
    let station = std::fs::read_to_string(dir.join("a/fltst_dp075")).unwrap();
    assert!(station.contains("# num_time_steps="));
    assert!(station.contains("\nt slip slip_rate shear_stress state\n"));
    let rows: Vec<&str> = station
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .collect();
    assert!(rows.len() > 10 && rows.iter().all(|r| r.split_whitespace().count() == 5));
    let devol = std::fs::read_to_string(dir.join("a/devol.dat")).unwrap();
    let mut body = devol.lines().skip_while(|l| l.starts_with('#'));
    // The description's two field-list lines, then the row of depths.
    assert_eq!(body.next(), Some("z"));
    assert_eq!(body.next(), Some("t max_slip_rate slip"));
    let depths = body.next().unwrap();
    assert!(depths.starts_with("0 0 "), "{depths}");
    let columns = depths.split_whitespace().count();
    assert_eq!(columns, 2 + 81, "surface to W_f = 40 km every 500 m");
    assert!(body.all(|l| l.split_whitespace().count() == columns));

    // Resume from a checkpoint halfway through the interseismic period.
    let (_, mut sim_b) = coarse_bp1();
    let half = steps / 2;
    sim_b.run(half, &mut []).unwrap();
    let bytes = sim_b.checkpoint().to_bytes();
    let (_, mut sim_c) = coarse_bp1();
    sim_c
        .restore(&Checkpoint::from_bytes(&bytes).unwrap())
        .unwrap();
    let mut out_c = output(&dir.join("c"), &bp1, &sim_c);
    let rest = to_first_event_end(&mut sim_c, &mut out_c);
    assert_eq!(half + rest, steps);
    assert_eq!(out_c.events()[0], first);
    let (a, c) = (&sim.state().kinematics, &sim_c.state().kinematics);
    assert!(a
        .u
        .iter()
        .zip(&c.u)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(sim
        .alpha()
        .iter()
        .zip(sim_c.alpha())
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    let _ = std::fs::remove_dir_all(&dir);
}
