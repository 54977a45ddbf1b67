//! Any value of any key of a scene file (the main job's `SliderScene`, the 3-D slider's
//! `Slider3dScene`) is either accepted and the scene runs a step, or refused with an error
//! that names the key (issue 38) — never a panic, a NaN state or an error about something
//! else.

use proptest::prelude::*;
use rsf_scenes::{Slider3dScene, SliderScene};

/// Values a careless user writes: numbers at and beyond every range, of every TOML type.
const VALUES: &[&str] = &[
    "0",
    "1",
    "2",
    "-1",
    "1000000000000",
    "0.0",
    "0.5",
    "-0.5",
    "1e-300",
    "1e300",
    "-1e300",
    "nan",
    "inf",
    "-inf",
    "1e-9",
    "1e9",
    "\"x\"",
    "\"aging\"",
    "true",
    "[1, 2]",
    "{ a = 1 }",
];

/// The scalar keys of a scene serialised as TOML (nested tables' keys excluded).
fn keys(table: &toml::Table) -> Vec<String> {
    table
        .iter()
        .filter(|(_, v)| !v.is_table())
        .map(|(k, _)| k.clone())
        .collect()
}

/// The scene text: a small, fast base (`base`) with `key = value` on top.
fn text(base: &str, key: &str, value: &str) -> String {
    let kept: Vec<&str> = base
        .lines()
        .filter(|l| !l.starts_with(&format!("{key} ")))
        .collect();
    format!("{}\n{key} = {value}\n", kept.join("\n"))
}

/// `error` names `key`: the key as a whole word of its message (an invalid parameter named
/// after it, a scene-file error at its key, a conditioning check listing it).
fn names(error: &rsf::Error, key: &str) -> bool {
    let m = error.to_string();
    let word = |c: char| c.is_alphanumeric() || c == '_';
    m.match_indices(key).any(|(i, _)| {
        let before = m[..i].chars().next_back();
        let after = m[i + key.len()..].chars().next();
        !before.is_some_and(word) && !after.is_some_and(word)
    })
}

fn check_2d(key: &str, value: &str) -> Result<(), TestCaseError> {
    // Level 0, 5 steps: a step takes milliseconds; `level` itself only up to 2.
    let base = "level = 0\nsteps = 5";
    if key == "level" && value.parse::<f64>().is_ok_and(|l| l > 2.0) {
        return Ok(());
    }
    let scene = match SliderScene::from_toml(&text(base, key, value)) {
        Err(e) => {
            prop_assert!(names(&e, key), "{key} = {value}: {e}");
            return Ok(());
        }
        Ok(s) => s,
    };
    match scene.build() {
        Err(e) => prop_assert!(names(&e, key), "{key} = {value}: {e}"),
        Ok(mut sim) => match sim.run(1, &mut []) {
            Ok(_) => {
                let s = sim.state();
                prop_assert!(
                    s.kinematics
                        .u
                        .iter()
                        .chain(&s.kinematics.v)
                        .chain(&s.alpha)
                        .all(|x| x.is_finite()),
                    "{key} = {value}: a non-finite state"
                );
            }
            // A step may fail on physics the key made impossible; it says so, typed.
            Err(e) => prop_assert!(!e.to_string().is_empty(), "{key} = {value}"),
        },
    }
    Ok(())
}

fn check_3d(key: &str, value: &str) -> Result<(), TestCaseError> {
    let base = "level = 0\nsteps = 3";
    if key == "level" && value.parse::<f64>().is_ok_and(|l| l > 1.0) {
        return Ok(());
    }
    if key == "width_m" && value.parse::<f64>().is_ok_and(|w| w > 4.0) {
        return Ok(()); // accepted up to 1000 m; a wide block is slow, not wrong
    }
    match Slider3dScene::from_toml(&text(base, key, value)) {
        Err(e) => prop_assert!(names(&e, key), "{key} = {value}: {e}"),
        Ok(scene) => {
            if let Err(e) = scene.validate() {
                prop_assert!(names(&e, key), "{key} = {value}: {e}");
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn any_value_of_a_2d_scene_key_runs_a_step_or_names_the_key(
        k in 0usize..1000,
        v in proptest::sample::select(VALUES),
    ) {
        let keys = keys(&toml::Table::try_from(SliderScene::default()).unwrap());
        check_2d(&keys[k % keys.len()], v)?;
    }

    #[test]
    fn any_value_of_a_3d_scene_key_is_accepted_or_names_the_key(
        k in 0usize..1000,
        v in proptest::sample::select(VALUES),
    ) {
        let mut keys = keys(&toml::Table::try_from(SliderScene::default()).unwrap());
        keys.extend(["width_m".to_string(), "lateral".to_string()]);
        check_3d(&keys[k % keys.len()], v)?;
    }
}
