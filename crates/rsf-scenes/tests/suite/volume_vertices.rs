//! A run condensed onto the fault computes the few vertices off Γ_F that observers ask
//! for (`Observer::volume_vertices`) from precomputed rows of the extension operator; the
//! values must be those of the whole field's sparse solves (an observer reading the
//! volume), and the rest of the field must stay uncomputed.
use crate::within;
use rsf::observe::StepView;
use rsf::{Flow, Observer};
use rsf_scenes::{SeasBp3, SeasBp3Grid};
use rsf_seas::SECONDS_PER_YEAR;

const GRID: SeasBp3Grid = SeasBp3Grid {
    dx: 2000.0,
    domain: 100e3,
    ratio: 1.2,
};

/// The Cartesian displacement and velocity of `vertices` at every step; `volume` says
/// whether it asks for the whole field or only for its vertices.
struct Stations {
    vertices: Vec<usize>,
    volume: bool,
    rows: Vec<Vec<[f64; 4]>>,
    /// Interior values seen that were not computed (NaN) at a vertex not asked for.
    nan_elsewhere: bool,
    other: usize,
}

impl Observer<2> for Stations {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        self.rows.push(
            self.vertices
                .iter()
                .map(|&p| {
                    let (u, v) = (s.displacement(p), s.velocity(p));
                    [u[0], u[1], v[0], v[1]]
                })
                .collect(),
        );
        self.nan_elsewhere |= s.displacement(self.other)[0].is_nan();
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        self.volume
    }
    fn volume_vertices(&self) -> Vec<usize> {
        self.vertices.clone()
    }
}

#[test]
fn watched_vertices_equal_the_whole_fields_values() {
    let bp3 = SeasBp3::thrust();
    let model = bp3.model(&GRID).unwrap();
    // Surface vertices at x = -32, -8, 0 (both copies of the split vertex), 8, 32 km, and
    // one inside the body 10 km below x = 20 km.
    let nearest = |x: [f64; 2]| {
        (0..model.vertices.len())
            .min_by(|&a, &b| {
                let d = |p: usize| {
                    let v = model.vertices[p];
                    (v[0] - x[0]).hypot(v[1] - x[1])
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let top = nearest([0.0, 0.0]);
    let (minus, plus) = model
        .internal_fault
        .as_ref()
        .unwrap()
        .pair_of(top)
        .expect("the fault's top vertex is split");
    let mut vertices = vec![
        nearest([-32e3, 0.0]),
        nearest([-8e3, 0.0]),
        minus,
        plus,
        nearest([8e3, 0.0]),
        nearest([32e3, 0.0]),
        nearest([20e3, -10e3]),
    ];
    vertices.sort_unstable();
    let other = nearest([-20e3, -10e3]);
    let run = |volume: bool| {
        let options = bp3.params.fault_ode_options(1e-7).unwrap();
        let mut ode = bp3.fault_ode(model.clone(), options).unwrap();
        let mut obs = Stations {
            vertices: vertices.clone(),
            volume,
            rows: Vec::new(),
            nan_elsewhere: false,
            other,
        };
        ode.run_until(within(150.0 * SECONDS_PER_YEAR), &mut [&mut obs])
            .unwrap();
        obs
    };
    let watched = run(false);
    let whole = run(true);
    assert_eq!(watched.rows.len(), whole.rows.len(), "the same steps");
    assert!(
        watched.nan_elsewhere,
        "the rest of the field is not computed"
    );
    assert!(!whole.nan_elsewhere);
    let mut scale = [0.0f64; 4];
    for row in &whole.rows {
        for x in row {
            for c in 0..4 {
                assert!(x[c].is_finite());
                scale[c] = scale[c].max(x[c].abs());
            }
        }
    }
    let mut worst = [0.0f64; 4];
    for (a, b) in watched.rows.iter().zip(&whole.rows) {
        for (x, y) in a.iter().zip(b) {
            for c in 0..4 {
                worst[c] = worst[c].max((x[c] - y[c]).abs() / scale[c]);
            }
        }
    }
    eprintln!(
        "{} steps; largest |u| {:.3e} m, |v| {:.3e} m/s; relative differences {:?}",
        whole.rows.len(),
        scale[0].max(scale[1]),
        scale[2].max(scale[3]),
        worst.map(|w| format!("{w:.1e}"))
    );
    // The slip rate peaks during the event: velocities span many orders of magnitude.
    assert!(scale[2].max(scale[3]) > 1e-3, "{scale:?}");
    for w in worst {
        assert!(w < 1e-10, "{worst:?}");
    }
}

/// Whether a vertex off the fault was computed at each step.
struct Computed {
    vertex: usize,
    volume: bool,
    finite: Vec<bool>,
}

impl Observer<2> for Computed {
    fn observe(&mut self, s: &StepView<'_, 2, 2>) -> rsf::Result<Flow> {
        let (u, v) = (s.displacement(self.vertex), s.velocity(self.vertex));
        self.finite.push(u.iter().chain(&v).all(|x| x.is_finite()));
        Ok(Flow::Continue(()))
    }
    fn reads_volume(&self) -> bool {
        self.volume
    }
}

/// A vertex off the fault is computed exactly when an observer reads the volume (or the
/// caller asks for it), and is uncomputed (NaN) again at every step after that, however
/// runs with and without the volume follow each other.
#[test]
fn the_field_off_the_fault_is_computed_only_when_asked_for() {
    let bp3 = SeasBp3::thrust();
    let model = bp3.model(&GRID).unwrap();
    let vertex = (0..model.vertices.len())
        .min_by(|&a, &b| {
            let d = |p: usize| (model.vertices[p][0] + 20e3).hypot(model.vertices[p][1] + 10e3);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let options = bp3.params.fault_ode_options(1e-7).unwrap();
    let mut ode = bp3.fault_ode(model, options).unwrap();
    assert!(ode.state().kinematics.u[2 * vertex].is_nan());
    let run = |ode: &mut rsf::FaultOde<2, _, _, 2>, volume: bool| {
        let mut obs = Computed {
            vertex,
            volume,
            finite: Vec::new(),
        };
        ode.run_until(rsf::Until::Steps(5), &mut [&mut obs])
            .unwrap();
        assert_eq!(obs.finite.len(), 5);
        obs.finite
    };
    assert_eq!(run(&mut ode, false), [false; 5]);
    assert_eq!(run(&mut ode, true), [true; 5]);
    assert_eq!(run(&mut ode, false), [false; 5]);
    let state = ode.state_with_volume().unwrap();
    assert!(state.kinematics.u[2 * vertex].is_finite());
    assert_eq!(run(&mut ode, false), [false; 5]);
    // A restored state (here one with the whole field) is not kept off the fault either.
    let checkpoint = {
        ode.state_with_volume().unwrap();
        ode.checkpoint()
    };
    assert_eq!(run(&mut ode, false), [false; 5]);
    ode.restore(&checkpoint).unwrap();
    assert!(ode.state().kinematics.u[2 * vertex].is_nan());
    assert_eq!(run(&mut ode, false), [false; 5]);
}
