//! The round trip of a program's run configuration through its command line and TOML
//! (docs/design.md, "One run configuration"), and the slider programs' (whose
//! configuration is their scene, `rsf_scenes::SliderScene` and `Slider3dScene`). The SEAS
//! programs' are in `config_tests`.

use proptest::prelude::*;
use proptest::sample::select;
use rsf::fem::Diagonal;
use rsf::method::{FixedPointScheme, InnerSolves, StateIntegrator};
use rsf::tnnmg::SmootherOrder;
use rsf::{Integrator, SolverKind, StateLawKind};
use rsf_scenes::{
    AdaptiveTimeStep, LateralBoundary, RunConfig, Slider3dScene, SliderScene, TimeStep,
};

use crate::guard::{parse_from, Program};

/// The round trips of `run` through the program `P`'s command line (the settings it
/// parses, `settings` of the parsed program: the same value) and through TOML (the same
/// value, the same fingerprint).
pub(crate) fn round_trip<P: Program, C: RunConfig + std::fmt::Debug>(
    run: &C,
    settings: impl Fn(P) -> C,
) -> Result<(), TestCaseError> {
    round_trip_with(&[], run, settings)
}

/// [`round_trip`] with the program's flags that are no settings `base` (a required
/// `--out`) after the settings' flags.
pub(crate) fn round_trip_with<P: Program, C: RunConfig + std::fmt::Debug>(
    base: &[&str],
    run: &C,
    settings: impl Fn(P) -> C,
) -> Result<(), TestCaseError> {
    prop_assert!(run.validate().is_ok(), "{:?}: {:?}", run, run.validate());
    let mut args = command_line(P::NAME, run);
    args.extend(base.iter().map(|s| (*s).to_owned()));
    let (program, _) =
        parse_from::<P, _, _>(args).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(&settings(program), run);
    let back = C::from_toml(&run.to_toml()).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(&back, run);
    prop_assert_eq!(back.fingerprint(), run.fingerprint());
    Ok(())
}

/// The command line of `run`: every setting as its flag (`--end-years 5`), from the
/// settings' TOML keys.
pub(crate) fn command_line<C: RunConfig>(program: &str, run: &C) -> Vec<String> {
    let table: toml::Table = toml::from_str(&run.to_toml()).unwrap();
    let mut args = vec![program.to_owned()];
    for (key, value) in table {
        let flag = format!("--{}", key.replace('_', "-"));
        match value {
            // A switch: given when true.
            toml::Value::Boolean(b) => {
                if b {
                    args.push(flag);
                }
            }
            toml::Value::String(s) => args.extend([flag, s]),
            toml::Value::Float(x) => args.extend([flag, format!("{x}")]),
            v => args.extend([flag, v.to_string()]),
        }
    }
    args
}

/// A slider scene with every setting the flags give drawn at random (each valid).
fn slider_scene() -> impl Strategy<Value = SliderScene> {
    let choices = (
        select(vec![StateLawKind::Aging, StateLawKind::Slip]),
        select(vec![
            StateIntegrator::BackwardEuler,
            StateIntegrator::ConstantSlipRate,
        ]),
        select(vec![Integrator::Newmark, Integrator::BackwardEuler]),
        select(vec![
            SolverKind::Auto,
            SolverKind::Direct,
            SolverKind::Tnnmg,
        ]),
        select(vec![FixedPointScheme::Anderson, FixedPointScheme::Paper]),
        select(vec![Diagonal::Forward, Diagonal::Backward]),
        prop_oneof![
            Just(InnerSolves::Exact),
            Just(InnerSolves::BySolver),
            (0.01f64..0.9, any::<bool>())
                .prop_map(|(factor, first)| InnerSolves::Inexact { factor, first }),
        ],
        select(vec![
            SmootherOrder::Lexicographic,
            SmootherOrder::MultiColour,
            SmootherOrder::RedBlackChunks,
        ]),
    );
    let numbers = (
        0usize..=6,
        1usize..1_000_000,
        prop_oneof![
            Just(TimeStep::Fixed {}),
            (1e-8f64..0.5).prop_map(|t| TimeStep::Adaptive(AdaptiveTimeStep::new(t))),
        ],
        1e-3f64..1e3,
        (0.2f64..0.45, 1e3f64..1e5, 0.001f64..0.05, 0.0f64..0.05),
        (1e-7f64..1e-4, 1e-6f64..1e-3, -20.0f64..5.0, any::<bool>()),
    );
    (choices, numbers).prop_map(
        |(
            (law, state_integrator, integrator, solver, fixed_point, diagonal, inner, smoother),
            (level, steps, time_step, end_time_s, (nu, sigma_n, a, b), (l, v0, alpha0, absorbing)),
        )| SliderScene {
            level,
            steps,
            time_step,
            end_time_s,
            poisson_ratio: nu,
            sigma_n_pa: sigma_n,
            a,
            b,
            l_m: l,
            v0_m_per_s: v0,
            alpha0,
            absorbing_sides: absorbing,
            state_law: law,
            state_integrator,
            integrator,
            solver,
            fixed_point,
            diagonal,
            fixed_point_inner_solves: inner,
            tnnmg_smoother: smoother,
            ..SliderScene::default()
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Every field of the slider's scene is a flag of `pipping_slider`: a scene → its
    /// command line → the scene the program parses, the same value; through TOML the same
    /// value and fingerprint.
    #[test]
    fn pipping_slider_scene_round_trips(scene in slider_scene()) {
        round_trip(&scene, |p: crate::pipping_slider::Cli| p.slider.scene)?;
    }

    /// The same for `slider_3d`, its defaults the 3-D scene's.
    #[test]
    fn slider_3d_scene_round_trips(
        slider in slider_scene(),
        width_m in 1e-3f64..10.0,
        plane_strain in any::<bool>(),
    ) {
        // The 3-D slider's Kuhn tetrahedra project onto the forward diagonal only.
        let scene = Slider3dScene {
            slider: SliderScene { diagonal: Diagonal::Forward, ..slider },
            width_m,
            lateral: if plane_strain { LateralBoundary::PlaneStrain } else { LateralBoundary::Free },
        };
        round_trip(&scene, |p: crate::slider_3d::Cli| p.slider.scene)?;
    }
}

/// A flag given wins over the scene file's key, the file's key over the program's
/// defaults; the 3-D slider's defaults are its own scene's, not the 2-D scene's.
#[test]
fn a_scene_file_sets_what_no_flag_gives() {
    let dir = std::env::temp_dir().join(format!("rsf-slider-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, "level = 3\nmu0 = 0.5\n").unwrap();
    let path = path.to_str().unwrap();
    let (cli, _) = parse_from::<crate::pipping_slider::Cli, _, _>([
        "pipping_slider",
        "--scene",
        path,
        "--level",
        "2",
    ])
    .unwrap();
    let scene = cli.slider.scene().unwrap();
    assert_eq!((scene.level, scene.mu0), (2, 0.5));
    assert_eq!(scene.a, SliderScene::default().a);
    let (cli, _) =
        parse_from::<crate::slider_3d::Cli, _, _>(["slider_3d", "--config", path]).unwrap();
    let scene = cli.slider.scene().unwrap();
    assert_eq!((scene.slider.level, scene.slider.mu0), (3, 0.5));
    let (cli, _) = parse_from::<crate::slider_3d::Cli, _, _>(["slider_3d"]).unwrap();
    assert_eq!(cli.slider.scene().unwrap(), Slider3dScene::default());
    // A refused value of the file is named as its key, of a flag as the flag.
    std::fs::write(dir.join("bad.toml"), "end_time_s = -1\n").unwrap();
    let bad = dir.join("bad.toml");
    let (cli, _) = parse_from::<crate::pipping_slider::Cli, _, _>([
        "pipping_slider",
        "--scene",
        bad.to_str().unwrap(),
    ])
    .unwrap();
    let e = cli.slider.scene().unwrap_err().to_string();
    assert!(e.contains("key `end_time_s`"), "{e}");
    let (cli, _) =
        parse_from::<crate::pipping_slider::Cli, _, _>(["pipping_slider", "--a", "-0.5"]).unwrap();
    let e = cli.slider.scene().unwrap_err().to_string();
    assert!(e.starts_with("--a "), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
