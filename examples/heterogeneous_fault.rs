//! A problem built from scratch with the public API (issue 11): an 8 m × 1 m block whose
//! fault is velocity weakening (b > a) only in its middle — b is a Gaussian bump,
//! b > a = 0.01 for |x − 4 m| < 2.35 m — with a user-written state law (the aging law with a
//! finite healing time T_h), loaded at its top and run until its first slip event has
//! ended. Other parameters as the paper's slider.
//!
//! `cargo run --release --example heterogeneous_fault`

use rsf::fem::{rectangle, Diagonal};
use rsf::friction::{DieterichRuina, RateStateParams};
use rsf::observe::StopAt;
use rsf::prelude::*;
use rsf::state::StateLaw;
use rsf_scenes::SliderScene;

/// `θ̇ = 1 − θ/T_h − θV/L`, i.e. `∂ψ/∂α = V/L + 1/T_h − e^{−α}` in `α = ln θ`.
#[derive(Clone)]
struct HealingAging {
    l: f64,
    t_h: f64,
}

impl StateLaw for HealingAging {
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        v / self.l + 1.0 / self.t_h - (-alpha).exp()
    }
}

// The guard every program runs under (`--help`, `--max-memory-gb`; a fixed problem that
// writes nothing but the terminal's lines).
rsf_programs::fixed_size_program! {
    name: "heterogeneous_fault",
    memory_bytes: 2e8,
    what: "an 8 m × 1 m block at level 3 (585 nodes)",
    run: run,
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let block = rectangle([0.0, 0.0], [8.0, 1.0], 9, 2, Diagonal::Forward)?;
    let model = ModelBuilder::refined(block, 3)?
        .material(Material::new(5e7, 0.3, 5e3))
        .gravity([0.0, -9.81])
        .dirichlet(Part::predicate("top", |x| x[1] > 1.0 - 1e-9), [2e-4, 0.0])
        .frictional_boundary(Part::predicate("fault", |x| x[1] < 1e-9))
        .loading(TimeFunction::ramp(3.75))
        .build()?;
    let centre = model.nearest_node(&[4.0, 0.0])?;
    let mut first_event = SlipEvents::new(EventThresholds::default())?
        .slip_at(&model, centre)?
        .stop(StopAt::End(1));
    let p = SliderScene::default().rate_state_params();
    let mut sim = SimulationBuilder::new(model)
        .friction_at(|x| {
            let b = 0.005 + 0.01 * (-(x[0] - 4.0).powi(2) / 8.0).exp(); // a = 0.01
            DieterichRuina::new(RateStateParams { b, ..p })
        })
        .state_law(HealingAging { l: p.l, t_h: 1e3 })
        .initial_state(-10.0)
        .time_step(1.5e-3)
        .build()?;
    sim.run_until(Until::Time(60.0), &mut [&mut first_event])?;
    println!("t = {:.3} s, {:#?}", sim.time(), first_event.events());
    Ok(())
}
