//! Scenes of the tests built from the paper's slider.

use rsf_scenes::SliderScene;

/// The paper's slider (`SliderScene::default()`) at refinement level `level` with `steps`
/// time steps over its run.
pub fn slider(level: usize, steps: usize) -> SliderScene {
    SliderScene {
        level,
        steps,
        ..SliderScene::default()
    }
}
