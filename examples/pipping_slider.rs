//! The paper's model problem (Pipping, Sander & Kornhuber §6.1, Table 6.1): a 5 m × 1 m
//! elastic block, sheared at its top with a ramped velocity, sliding on its rate-and-state
//! frictional bottom. The main job of the workspace.
//!
//! ```sh
//! cargo run --release --example pipping_slider                      # j = 4, N = 1e4, Dieterich, Newmark, TNNMG
//! cargo run --release --example pipping_slider -- --level 3 --law ruina --solver direct
//! cargo run --release --example pipping_slider -- --scene scenes/pipping_slider.toml
//! ```
//!
//! Writes to `out/pipping_slider/` (or `--out DIR`): `timeseries.csv`
//! (`t_s,u_x0_m,v_x0_mps,max_slip_rate_mps,fpi`), `frictional_profile.csv`
//! (`t_s,x_m,slip_rate_mps,alpha` over the window, default [0.6725T, 0.6775T]),
//! `summary.json`, and the figures `displacement_x0.png`, `slip_rate_x0.png`,
//! `slip_rate_map.png`.

use std::path::PathBuf;

use rsf::SliderScene;
use rsf_examples::{
    line_plot, run_slider, space_time_map, stats, write_summary, Args, RunOptions, Series,
};

const USAGE: &str = "pipping_slider [--scene FILE.toml] [--level J] [--steps N] [--end-time T]
  [--law dieterich|ruina] [--integrator newmark|backward-euler|quasistatic] [--solver tnnmg|direct]
  [--window T0,T1 (s; default 0.6725T,0.6775T)] [--out DIR] [--checkpoint-every N] [--resume FILE]";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse(USAGE);
    let mut scene = match args.get("scene") {
        Some(path) => SliderScene::from_toml(&std::fs::read_to_string(path)?)?,
        None => SliderScene::default(),
    };
    scene.level = args.value("level", scene.level);
    scene.steps = args.value("steps", scene.steps);
    scene.end_time_s = args.value("end-time", scene.end_time_s);
    args.apply_scene_choices(&mut scene)?;
    scene.validate()?;
    let t_end = scene.end_time_s;
    let window = match args.get("window") {
        Some(w) => {
            let v: Vec<f64> = w.split(',').map(str::parse).collect::<Result<_, _>>()?;
            if v.len() != 2 {
                return Err("--window takes T0,T1".into());
            }
            (v[0], v[1])
        }
        None => (0.6725 * t_end, 0.6775 * t_end),
    };
    let out = PathBuf::from(args.get("out").unwrap_or("out/pipping_slider"));
    std::fs::create_dir_all(&out)?;
    println!(
        "pipping_slider: level {}, N = {} (τ = {:.3e} s), {:?} law, {:?}, {:?} solver → {}",
        scene.level,
        scene.steps,
        scene.tau(),
        scene.state_law,
        scene.integrator,
        scene.solver,
        out.display()
    );
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        profile_window: Some(window),
        map_samples: 600,
        checkpoint_every: args.value("checkpoint-every", 0),
        resume: args.get("resume").map(PathBuf::from),
        progress: true,
    };
    let run = run_slider(&scene, &opts)?;
    let st = stats(&run, t_end);
    write_summary(&out, &scene, &run, &st)?;

    let disp: Vec<(f64, f64)> = run.u_x0.clone();
    line_plot(
        &out.join("displacement_x0.png"),
        "Displacement u_x at x0 = (2.5, 0)",
        "t (s)",
        "u_x (m)",
        &[Series {
            label: "",
            points: &disp,
        }],
        false,
        false,
    )?;
    let rate: Vec<(f64, f64)> = run
        .v_x0
        .iter()
        .map(|&(t, v)| (t, v.abs().max(1e-40)))
        .collect();
    line_plot(
        &out.join("slip_rate_x0.png"),
        "Slip rate |v| at x0 = (2.5, 0)",
        "t (s)",
        "slip rate (m/s)",
        &[Series {
            label: "",
            points: &rate,
        }],
        true,
        false,
    )?;
    space_time_map(
        &out.join("slip_rate_map.png"),
        "Slip rate along the frictional boundary",
        &run.map.0,
        &run.map.1,
        &run.map.2,
        (-12.0, -2.0),
    )?;
    println!(
        "{} dofs, {} steps in {:.2} s (set-up {:.2} s) on {}",
        run.dofs,
        run.fpi.len(),
        run.seconds,
        run.setup_seconds,
        rsf_examples::machine()
    );
    println!(
        "fixed point iterations: mean {:.2}, max {}; solver iterations {}; relaxed steps {}",
        st.fpi_mean, st.fpi_max, st.solver_iterations, st.relaxed_steps
    );
    println!(
        "first slip event (max V > 1e-3 m/s): {}; slip events: {}; peak slip rate {:.3e} m/s; u_x0 over [0.9T, T]: {:.3e} … {:.3e} m",
        st.first_slip_event_s.map_or("none".into(), |t| format!("{t:.3} s")),
        st.slip_events,
        st.peak_slip_rate_mps,
        st.u_x0_range_last_tenth_m.0,
        st.u_x0_range_last_tenth_m.1
    );
    Ok(())
}
