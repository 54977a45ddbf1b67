use rsf::{EventDetector, EventThresholds, Flow, Observer, Slider3dScene, SliderScene, SolverChoice, StepState, LateralBoundary, SLIDER_CENTRE};

struct Rec { x0: usize, d: usize, t: Vec<f64>, ux: Vec<f64>, maxv: Vec<f64>, fpi: Vec<usize>, it: Vec<usize> }
impl<const D: usize> Observer<D> for Rec {
    fn observe(&mut self, s: &StepState<'_, D>) -> rsf::Result<Flow> {
        self.t.push(s.report.time); self.ux.push(s.kinematics.u[D*self.x0]); self.maxv.push(s.report.max_slip_rate);
        self.fpi.push(s.report.fixed_point_iterations); self.it.push(s.report.solver_iterations);
        let _ = self.d;
        Ok(if s.report.max_slip_rate > 1e-3 { Flow::Break(()) } else { Flow::Continue(()) })
    }
}

#[test]
fn explore() {
    let level: usize = std::env::var("LEVEL").map(|s| s.parse().unwrap()).unwrap_or(2);
    let solver = match std::env::var("SOLVER").as_deref() { Ok("tnnmg") => SolverChoice::Tnnmg, _ => SolverChoice::Direct };
    let s2 = SliderScene { level, solver, ..SliderScene::default() };
    let t0 = std::time::Instant::now();
    let mut sim2 = s2.build().unwrap();
    let x0 = sim2.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let mut r2 = Rec { x0, d: 2, t: vec![], ux: vec![], maxv: vec![], fpi: vec![], it: vec![] };
    sim2.run(8000, &mut [&mut r2]).unwrap();
    eprintln!("2D: {} dofs, {:.1} s, last t {} ux {:e}", sim2.model().num_dofs(), t0.elapsed().as_secs_f64(), r2.t.last().unwrap(), r2.ux.last().unwrap());
    let s3 = Slider3dScene { slider: s2.clone(), lateral: LateralBoundary::PlaneStrain, ..Slider3dScene::default() };
    let t0 = std::time::Instant::now();
    let mut sim3 = s3.build().unwrap();
    eprintln!("3D setup {:.1} s, {} dofs, solver {}", t0.elapsed().as_secs_f64(), sim3.model().num_dofs(), sim3.solver_name());
    let x0 = sim3.model().nearest_node(&s3.centre()).unwrap();
    let mut r3 = Rec { x0, d: 3, t: vec![], ux: vec![], maxv: vec![], fpi: vec![], it: vec![] };
    let t0 = std::time::Instant::now();
    sim3.run(8000, &mut [&mut r3]).unwrap();
    eprintln!("3D: {:.1} s, last t {} ux {:e}, fpi mean {:.2}, it mean {:.2}", t0.elapsed().as_secs_f64(), r3.t.last().unwrap(), r3.ux.last().unwrap(),
      r3.fpi.iter().sum::<usize>() as f64 / r3.fpi.len() as f64, r3.it.iter().sum::<usize>() as f64 / r3.it.len() as f64);
    for k in [1000, 3000, 5000, 6000, 6500] { if k < r3.t.len() && k < r2.t.len() { eprintln!("t {} ux2 {:e} ux3 {:e} rel {:e}", r2.t[k], r2.ux[k], r3.ux[k], (r3.ux[k]-r2.ux[k])/r2.ux[k]); } }
    let _ = (EventDetector::new(EventThresholds::default()),);
}
