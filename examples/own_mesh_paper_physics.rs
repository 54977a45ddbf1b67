//! The paper's slider physics (Table 6.1: material, gravity, loading ramp, Dieterich–Ruina
//! friction, aging law, α₀, τ, solver) on a mesh of your own — here the Gmsh fixture
//! `arc_block.msh` (a block on a circular-arc base, physical groups `dirichlet` on top and
//! `frictional` on the arc) — through `SliderScene::simulation_builder_on`, run until the
//! first slip event starts. `cargo run --release --example own_mesh_paper_physics`

use rsf::fem::read_gmsh;
use rsf::observe::{EventThresholds, SlipEvents, StopAt};
use rsf::{ModelBuilder, Until};
use rsf_scenes::SliderScene;
use rsf_scenes::ARC_BLOCK_MESH; // crates/rsf-fem/tests/fixtures/arc_block.msh

// The guard every program runs under (`--help`, `--max-memory-gb`; a fixed problem that
// writes nothing but the terminal's lines).
rsf_programs::fixed_size_program! {
    name: "own_mesh_paper_physics",
    memory_bytes: 2e8,
    what: "the arc block refined twice",
    run: run,
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let scene = SliderScene::default(); // the paper's physics and method
    let mesh = ModelBuilder::refined(read_gmsh::<2>(ARC_BLOCK_MESH)?.mesh, 2)?; // your mesh, refined twice
    let mut sim = scene
        .simulation_builder_on(mesh, "dirichlet", "frictional")? // Γ_D and Γ_F by tag
        .build()?;
    let mut events = SlipEvents::new(EventThresholds::default())?.stop(StopAt::Onset(1));
    sim.run_until(Until::Time(scene.end_time_s), &mut [&mut events])?;
    match events.events().first() {
        Some(e) => println!(
            "first slip: step {}, t = {:.4} s (max slip rate > 1e-3 m/s; crossing {:.4} s)",
            e.onset_step, e.onset_s, e.crossing_s
        ),
        None => println!("no slip event before T = {} s", scene.end_time_s),
    }
    Ok(())
}
