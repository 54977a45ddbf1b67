//! Runs you can trust (issue 26, docs/reliability.md): every mistake is a typed error that
//! leaves every file byte-identical; corrupted checkpoints are refused, untouched ones
//! resume bit-identically; implausible scenes are refused naming the field.

use std::path::Path;
use std::sync::OnceLock;

use crate::common::{snapshot, temp_dir};
use proptest::prelude::*;
use rsf::checkpoint::{write_atomically, Fingerprint};
use rsf::observe::{FileMode, FrictionalProfile, PointSeries};
use rsf::{Checkpoint, Error, StateLawKind};
use rsf_scenes::{SliderScene, SLIDER_CENTRE};

fn scene() -> SliderScene {
    SliderScene {
        level: 1,
        steps: 40,
        end_time_s: 0.04,
        loading_velocity_m_per_s: 1e-2,
        ramp_fraction: 0.0,
        ..SliderScene::default()
    }
}

/// A run of 40 steps: the bytes of its checkpoint at step 20 (with the scene's
/// fingerprint) and its final state.
fn reference() -> &'static (Vec<u8>, rsf::SimulationState) {
    static R: OnceLock<(Vec<u8>, rsf::SimulationState)> = OnceLock::new();
    R.get_or_init(|| {
        let mut sim = scene().build().unwrap();
        sim.run(20, &mut []).unwrap();
        let mut c = sim.checkpoint();
        c.fingerprint = scene().fingerprint();
        let bytes = c.to_bytes();
        sim.run(20, &mut []).unwrap();
        (bytes, sim.state().clone())
    })
}

#[test]
fn an_untouched_checkpoint_resumes_bit_identically() {
    let (bytes, end) = reference();
    let dir = temp_dir("reliability-untouched");
    let path = dir.join("checkpoint.bin");
    std::fs::write(&path, bytes).unwrap();
    let c = Checkpoint::read(&path).unwrap();
    c.fingerprint.check(&scene().fingerprint(), &[]).unwrap();
    let mut sim = scene().build().unwrap();
    sim.restore(&c).unwrap();
    sim.run(20, &mut []).unwrap();
    assert_eq!(sim.state(), end);
}

/// The ways a checkpoint file is damaged.
#[derive(Debug, Clone)]
enum Damage {
    /// One bit flipped.
    Flip(usize),
    /// Cut to this fraction of its length.
    Truncate(f64),
    /// A header word (0..11: sizes, step, times, τ, wall time, fingerprint length)
    /// replaced.
    EditHeader(usize, u64),
    /// Bytes appended.
    Append(Vec<u8>),
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        any::<usize>().prop_map(Damage::Flip),
        (0.0..1.0f64).prop_map(Damage::Truncate),
        (0usize..11, any::<u64>()).prop_map(|(i, w)| Damage::EditHeader(i, w)),
        proptest::collection::vec(any::<u8>(), 1..16).prop_map(Damage::Append),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A damaged checkpoint is a typed error naming the file, never a silent different
    /// run; the file itself is left as it is.
    #[test]
    fn a_damaged_checkpoint_is_refused(d in damage()) {
        let (bytes, _) = reference();
        let mut b = bytes.clone();
        match &d {
            Damage::Flip(i) => {
                let i = i % (8 * b.len());
                b[i / 8] ^= 1 << (i % 8);
            }
            Damage::Truncate(f) => b.truncate((f * bytes.len() as f64) as usize),
            Damage::EditHeader(i, w) => {
                b[8 + 8 * i..16 + 8 * i].copy_from_slice(&w.to_le_bytes());
            }
            Damage::Append(extra) => b.extend_from_slice(extra),
        }
        prop_assume!(&b != bytes);
        let dir = temp_dir("reliability-damaged");
        let path = dir.join(format!("c{}.bin", std::process::id()));
        std::fs::write(&path, &b).unwrap();
        let e = Checkpoint::read(&path).unwrap_err();
        prop_assert!(matches!(&e, Error::CheckpointCorrupt { path: p, .. } if p.contains(".bin")), "{e}");
        prop_assert_eq!(std::fs::read(&path).unwrap(), b);
    }
}

#[test]
fn a_checkpoint_of_other_physics_or_method_is_refused_naming_the_field() {
    let (bytes, _) = reference();
    let c = Checkpoint::from_bytes(bytes).unwrap();
    let other = |s: SliderScene| c.fingerprint.check(&s.fingerprint(), &[]).unwrap_err();
    let field = |e: Error| match e {
        Error::CheckpointMismatch { field, .. } => field,
        e => panic!("{e}"),
    };
    let cases = [
        (
            SliderScene {
                state_law: StateLawKind::Slip,
                ..scene()
            },
            "state_law",
        ),
        (
            SliderScene {
                steps: 41,
                ..scene()
            },
            "steps",
        ),
        (
            SliderScene {
                end_time_s: 0.05,
                ..scene()
            },
            "end_time_s",
        ),
        (
            SliderScene {
                level: 2,
                ..scene()
            },
            "level",
        ),
        (
            SliderScene {
                time_step: rsf_scenes::TimeStep::Adaptive(rsf_scenes::AdaptiveTimeStep::new(1e-3)),
                ..scene()
            },
            "time_step.kind",
        ),
    ];
    for (s, name) in cases {
        assert_eq!(field(other(s)), name);
    }
    // A deliberate change is allowed explicitly.
    let later = SliderScene {
        end_time_s: 0.05,
        ..scene()
    };
    c.fingerprint
        .check(&later.fingerprint(), &["end_time_s"])
        .unwrap();
    // A checkpoint of the earlier format (no fingerprint, no checksum) is read, and
    // refused as the field `format`.
    let mut v2 = b"RSFCKPT2".to_vec();
    let s = &c.state;
    for w in [2, s.step, s.kinematics.u.len(), s.alpha.len(), 0, 0] {
        v2.extend_from_slice(&(w as u64).to_le_bytes());
    }
    for x in [0.0, s.time, s.tau] {
        v2.extend_from_slice(&f64::to_le_bytes(x));
    }
    let k = &s.kinematics;
    for x in k.u.iter().chain(&k.v).chain(&k.a).chain(&s.alpha) {
        v2.extend_from_slice(&x.to_le_bytes());
    }
    let old = Checkpoint::from_bytes(&v2).unwrap();
    assert_eq!(old.state, c.state);
    assert_eq!(
        field(
            old.fingerprint
                .check(&scene().fingerprint(), &[])
                .unwrap_err()
        ),
        "format"
    );
}

#[test]
fn a_new_file_never_replaces_results_and_a_failed_resume_cuts_nothing() {
    let dir = temp_dir("reliability-files");
    let sim = scene().build().unwrap();
    let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
    let series = dir.join("timeseries.csv");
    let profile = dir.join("profile.csv");
    std::fs::write(
        &series,
        format!(
            "{}\n1,2,3,4,1,0.001,1,1,0,5,6\n1,2,3,4,1,0.001,2,1,0,5,6\n",
            PointSeries::<2>::header()
        ),
    )
    .unwrap();
    std::fs::write(&profile, "another,header\n1,2\n").unwrap();
    let before = snapshot(&dir);
    let e = PointSeries::new(&series, sim.model(), x0, FileMode::Create)
        .err()
        .unwrap();
    assert!(matches!(e, Error::FileExists { .. }), "{e}");
    // The checkpoint's step after the last row: rows are missing.
    let e = PointSeries::new(&series, sim.model(), x0, FileMode::Resume { step: 5 })
        .err()
        .unwrap();
    assert!(matches!(e, Error::Resume { .. }), "{e}");
    assert!(PointSeries::<2>::check_resume(&series, 5).is_err());
    let e = FrictionalProfile::<2>::new(&profile, (0.0, 1.0), FileMode::Resume { step: 1 })
        .err()
        .unwrap();
    assert!(e.to_string().contains("header"), "{e}");
    assert_eq!(snapshot(&dir), before);
    // What may be continued is cut atomically to the checkpoint's step; Overwrite starts
    // anew.
    PointSeries::<2>::check_resume(&series, 1).unwrap();
    drop(PointSeries::new(&series, sim.model(), x0, FileMode::Resume { step: 1 }).unwrap());
    let text = std::fs::read_to_string(&series).unwrap();
    assert_eq!(text.lines().count(), 2, "{text}");
    assert!(!dir.join("timeseries.csv.tmp").exists());
    drop(PointSeries::new(&series, sim.model(), x0, FileMode::Overwrite).unwrap());
    assert_eq!(
        std::fs::read_to_string(&series).unwrap(),
        PointSeries::<2>::header() + "\n"
    );
}

#[test]
fn io_errors_name_the_path_and_the_action_and_keep_the_old_file() {
    let dir = temp_dir("reliability-io");
    let missing = dir.join("no-such-checkpoint.bin");
    let e = Checkpoint::read(&missing).unwrap_err();
    let Error::File { path, action, .. } = &e else {
        panic!("{e}")
    };
    assert!(path.ends_with("no-such-checkpoint.bin") && action.contains("read"));
    // A folder where the checkpoint should be: refused, the folder untouched.
    let folder = dir.join("a-folder");
    std::fs::create_dir_all(folder.join("inside")).unwrap();
    let e = Checkpoint::read(&folder).unwrap_err();
    assert!(e.to_string().contains("a-folder"), "{e}");
    let e = write_atomically(&folder, b"new").unwrap_err();
    assert!(
        matches!(&e, Error::File { path, .. } if path.contains("a-folder")),
        "{e}"
    );
    assert!(folder.join("inside").is_dir() && !dir.join("a-folder.tmp").exists());
    // A very long path is quoted in at most about 100 characters.
    let long = dir.join("x".repeat(5000));
    let e = Checkpoint::read(&long).unwrap_err();
    assert!(e.to_string().len() < 400, "{}", e.to_string().len());
}

#[test]
fn implausible_scenes_are_refused_naming_the_field() {
    let s = scene;
    let cases: Vec<(SliderScene, &str)> = vec![
        (SliderScene { mu0: -0.1, ..s() }, "mu0"),
        (SliderScene { b: -1e-3, ..s() }, "b"),
        (
            SliderScene {
                alpha0: 1e300,
                ..s()
            },
            "alpha0",
        ),
        (
            SliderScene {
                alpha0: -800.0,
                ..s()
            },
            "alpha0",
        ),
        (
            SliderScene {
                youngs_modulus_pa: 1e-300,
                ..s()
            },
            "youngs_modulus_pa",
        ),
        (
            SliderScene {
                density_kg_per_m2: 1e300,
                ..s()
            },
            "density_kg_per_m2",
        ),
        (
            SliderScene {
                end_time_s: 1e300,
                ..s()
            },
            "end_time_s",
        ),
        (
            SliderScene {
                loading_velocity_m_per_s: -1e9,
                ..s()
            },
            "loading_velocity_m_per_s",
        ),
        (
            SliderScene {
                fixed_point_tolerance: 2.0,
                ..s()
            },
            "fixed_point_tolerance",
        ),
        (
            SliderScene {
                solver_tolerance: 1e-300,
                ..s()
            },
            "solver_tolerance",
        ),
    ];
    for (scene, name) in cases {
        let e = scene.validate().unwrap_err();
        match &e {
            Error::InvalidParameter { name: n, reason } => {
                assert_eq!(n, name);
                assert!(reason.contains("admissible range"), "{e}");
            }
            e => panic!("{name}: {e}"),
        }
    }
    // The bounds themselves are admissible: μ₀ = 0, b = 0, the α₀ range.
    for ok in [
        SliderScene { mu0: 0.0, ..s() },
        SliderScene { b: 0.0, ..s() },
        SliderScene {
            alpha0: rsf_scenes::ALPHA_RANGE.1,
            ..s()
        },
        SliderScene {
            alpha0: rsf_scenes::ALPHA_RANGE.0,
            ..s()
        },
    ] {
        ok.validate().unwrap();
    }
    assert!(Fingerprint::default().0.is_empty());
}

/// `b < 0` only by explicit opt-in: refused with the reason and the name of the opt-in by
/// default; with `allow_negative_b = true` (TOML) accepted, run finite, and part of the
/// fingerprint, so that a checkpoint of such a run does not continue a default run and
/// vice versa. Without the opt-in the fingerprint has no such field (earlier checkpoints
/// keep theirs).
#[test]
fn negative_b_only_by_explicit_opt_in() {
    let s = || SliderScene {
        b: -1e-3,
        ..scene()
    };
    let e = s().validate().unwrap_err();
    match &e {
        Error::InvalidParameter { name, reason } => {
            assert_eq!(name, "b");
            assert!(reason.contains("allow_negative_b = true"), "{e}");
            assert!(reason.contains("admissible range"), "{e}");
        }
        e => panic!("{e}"),
    }
    // The opt-in from TOML.
    let opted = SliderScene::from_toml("b = -1e-3\nallow_negative_b = true\nlevel = 1").unwrap();
    assert!(opted.allow_negative_b);
    opted.validate().unwrap();
    let explicit = SliderScene {
        allow_negative_b: true,
        ..s()
    };
    explicit.validate().unwrap();
    // It runs (velocity strengthening: b − a < 0), finite.
    let mut sim = explicit.build().unwrap();
    sim.run(10, &mut []).unwrap();
    assert!(sim.kinematics().v.iter().all(|v| v.is_finite()));
    // Fingerprints: the field is present only when true, and differs from a default run.
    assert_eq!(scene().fingerprint().get("allow_negative_b"), None);
    let with_b = SliderScene {
        allow_negative_b: true,
        ..scene()
    };
    assert_eq!(with_b.fingerprint().get("allow_negative_b"), Some("true"));
    match with_b.fingerprint().check(&scene().fingerprint(), &[]) {
        Err(Error::CheckpointMismatch { field, .. }) => assert_eq!(field, "allow_negative_b"),
        other => panic!("{other:?}"),
    }
    match scene().fingerprint().check(&with_b.fingerprint(), &[]) {
        Err(Error::CheckpointMismatch { field, .. }) => assert_eq!(field, "allow_negative_b"),
        other => panic!("{other:?}"),
    }
    // An unknown spelling is refused, not ignored.
    assert!(SliderScene::from_toml("allow_negative_B = true").is_err());
}

/// The scales of `model`'s problem (its stiffness, mass, load, initial displacement and
/// fixed dofs).
fn problem_scales(model: &rsf::Model<2>) -> rsf::model::ProblemScales {
    rsf::model::ProblemScales::new(
        &model.stiffness,
        model.mass.as_ref(),
        &model.load,
        &model.initial_displacement,
        &model.fixed,
    )
}

/// The conditioning estimate (docs/reliability.md, "Conditioning"): the scene defaults and
/// the bounds of the per-field checks pass; a scene whose values are each admissible but
/// whose problem is not representable (gravity 1e200 m/s²: |u₀| ≈ 1e195 m) or whose slip
/// distance is lost in the displacements (L = 1e-20 m against |u₀| ≈ 1e-3 m; a loading
/// displacement of 1e13 m) is refused naming the fields; the resolution threshold is tested
/// on both sides at the measured displacement scale.
#[test]
fn conditioning_estimate_refuses_unresolvable_scenes_naming_the_fields() {
    let ill_fields = |scene: &SliderScene| match scene.build_model() {
        Err(Error::IllConditioned { fields, reason }) => {
            assert!(reason.len() < 400, "{reason}");
            fields
        }
        Ok(_) => panic!("accepted: {scene:?}"),
        Err(e) => panic!("{e}"),
    };
    // Defaults (level 1 and the paper's level 4), and each per-field bound, pass.
    for ok in [
        scene(),
        SliderScene::default(),
        SliderScene {
            youngs_modulus_pa: 1e3,
            ..scene()
        },
        SliderScene {
            youngs_modulus_pa: 1e13,
            ..scene()
        },
        SliderScene {
            density_kg_per_m2: 1e7,
            ..scene()
        },
        SliderScene {
            density_kg_per_m2: 1e-3,
            ..scene()
        },
    ] {
        let model = ok.build_model().unwrap_or_else(|e| panic!("{e}: {ok:?}"));
        let s = problem_scales(&model);
        println!("level {}: {s:?}", ok.level);
    }
    // Not representable: the gravity sag overflows the squares.
    let f = ill_fields(&SliderScene {
        gravity_m_per_s2: 1e200,
        ..scene()
    });
    assert!(f.contains(&"gravity_m_per_s2".to_string()), "{f:?}");
    // Not resolvable: slip distance against the gravity sag, and against the loading.
    let f = ill_fields(&SliderScene {
        l_m: 1e-20,
        ..scene()
    });
    assert!(f.contains(&"l_m".to_string()), "{f:?}");
    let f = ill_fields(&SliderScene {
        loading_velocity_m_per_s: 1e3,
        end_time_s: 1e10,
        steps: 1_000_000,
        ..scene()
    });
    assert_eq!(
        f,
        ["l_m", "loading_velocity_m_per_s", "end_time_s"],
        "the loading displacement 1e13 m is the largest"
    );
    // The threshold on both sides, at the measured displacement scale D of this scene.
    let model = scene().build_model().unwrap();
    let d = [
        model
            .initial_displacement
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs())),
        scene().loading_velocity_m_per_s * scene().end_time_s,
    ]
    .into_iter()
    .fold(0.0_f64, f64::max);
    let estimate = problem_scales(&model).displacement_estimate;
    let d = d.max(estimate);
    SliderScene {
        l_m: 2.0 * rsf::model::SLIP_RESOLUTION * d,
        ..scene()
    }
    .build_model()
    .unwrap();
    ill_fields(&SliderScene {
        l_m: 0.5 * rsf::model::SLIP_RESOLUTION * d,
        ..scene()
    });
    // The time-step matrix: a step so small that c_M M overflows the squares (fixed steps
    // of 1e-150 s at ρ = 1e7) names the steps.
    let f = ill_fields(&SliderScene {
        end_time_s: 1e-144,
        steps: 1_000_000,
        density_kg_per_m2: 1e7,
        ..scene()
    });
    assert!(f.contains(&"steps".to_string()), "{f:?}");
}

/// A checkpoint of another model is refused with a typed error naming what differs (node
/// count, lengths, dimension), and the simulation is left as it was.
/// A model edited by hand (no scene fields to blame) is checked for magnitudes by
/// `Model::validate` when a simulation is built: each edit names the model field.
#[test]
fn hand_edited_models_with_unrepresentable_magnitudes_name_the_field() {
    let build = |edit: &dyn Fn(&mut rsf::Model<2>)| {
        let mut model = scene().build_model().unwrap();
        edit(&mut model);
        rsf::SimulationBuilder::new(model)
            .friction(rsf::friction::Tresca::new(0.5, 1e5).unwrap())
            .initial_state(0.0)
            .integrator(rsf::time::Newmark)
            .time_step(1e-3)
            .build()
            .map(|_| ())
    };
    let field = |edit: &dyn Fn(&mut rsf::Model<2>)| match build(edit) {
        Err(Error::IllConditioned { fields, reason }) => (fields, reason),
        Ok(()) => panic!("accepted"),
        Err(e) => panic!("{e}"),
    };
    build(&|_| {}).expect("the unedited model builds");
    let (f, r) = field(&|m| m.stiffness.val_mut().iter_mut().for_each(|x| *x *= 1e-300));
    assert!(
        f.contains(&"stiffness".to_string()) && r.contains("K_ii"),
        "{f:?}: {r}"
    );
    let (f, r) = field(&|m| {
        let mass = m.mass.as_mut().unwrap();
        mass.val_mut().iter_mut().for_each(|x| *x *= 1e200);
    });
    assert!(f == ["mass"] && r.contains("M_ii"), "{f:?}: {r}");
    let (f, r) = field(&|m| m.load.iter_mut().for_each(|x| *x *= 1e200));
    assert!(
        f.contains(&"load".to_string()) && r.contains("|F|"),
        "{f:?}: {r}"
    );
    let (f, r) = field(&|m| {
        let free = m.fixed.iter().position(|&x| !x).unwrap();
        m.initial_displacement[free] = f64::NAN;
    });
    assert!(
        f.contains(&"initial_displacement".to_string()),
        "{f:?}: {r}"
    );
    // A negative mass (not positive semi-definite) is refused by name too.
    let e = build(&|m| {
        let mass = m.mass.as_mut().unwrap();
        mass.val_mut().iter_mut().for_each(|x| *x = -*x);
    })
    .unwrap_err();
    assert!(
        matches!(&e, Error::InvalidParameter { name, .. } if name == "mass"),
        "{e}"
    );
}

#[test]
fn restore_names_what_differs() {
    let mut coarse = scene().build().unwrap();
    coarse.run(2, &mut []).unwrap();
    let c = coarse.checkpoint();
    let mut fine = SliderScene {
        level: 2,
        ..scene()
    }
    .build()
    .unwrap();
    let before = fine.checkpoint();
    let nodes = |s: &rsf_scenes::SceneSimulation<2>| s.model().num_nodes();
    match fine.restore(&c) {
        Err(Error::CheckpointSize {
            what,
            checkpoint,
            simulation,
        }) => {
            assert_eq!(what, "number of nodes");
            assert_eq!((checkpoint, simulation), (nodes(&coarse), nodes(&fine)));
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(fine.checkpoint(), before, "unchanged");
    type Edit = fn(&mut Checkpoint);
    let edits: [(Edit, &str); 5] = [
        (|c| c.dim = 3, "space dimension"),
        (|c| c.state.kinematics.u.truncate(1), "length of u"),
        (|c| c.state.kinematics.v.truncate(1), "length of v"),
        (|c| c.state.kinematics.a.push(0.0), "length of a"),
        (
            |c| c.state.alpha.truncate(1),
            "number of frictional nodes (length of alpha)",
        ),
    ];
    for (edit, name) in edits {
        let mut e = c.clone();
        edit(&mut e);
        match coarse.restore(&e) {
            Err(err @ Error::CheckpointSize { what, .. }) => {
                assert_eq!(what, name, "{err}");
                assert!(err.to_string().contains(name), "{err}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
    coarse.restore(&c).unwrap();
}

/// A row that cannot be written mid-run (the reader of a FIFO went away: EPIPE) is an
/// `Error::File` naming the file and the action, for the time series and the profile.
#[cfg(target_os = "linux")]
#[test]
fn a_row_that_cannot_be_written_names_the_file() {
    use std::os::unix::fs::OpenOptionsExt;
    let dir = temp_dir("fifo-rows");
    for name in ["series.csv", "profile.csv"] {
        let fifo = dir.join(name);
        let _ = std::fs::remove_file(&fifo);
        let ok = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        if !ok {
            eprintln!("mkfifo unavailable: skipped");
            return;
        }
        // A non-blocking reader (O_NONBLOCK), so that opening the writer does not block.
        let reader = std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(0o4000)
            .open(&fifo)
            .unwrap();
        let mut sim = scene().build().unwrap();
        let x0 = sim.model().nearest_node(&SLIDER_CENTRE).unwrap();
        let result = if name == "series.csv" {
            let mut obs = PointSeries::new(&fifo, sim.model(), x0, FileMode::Overwrite).unwrap();
            drop(reader);
            sim.run(1, &mut [&mut obs]).map(|_| ())
        } else {
            let mut obs = FrictionalProfile::new(&fifo, (0.0, 1.0), FileMode::Overwrite).unwrap();
            drop(reader);
            sim.run(1, &mut [&mut obs]).map(|_| ())
        };
        match result.map_err(Error::from) {
            Err(Error::File { path, action, .. }) => {
                assert!(path.ends_with(name), "{path}");
                assert!(action == "flush" || action.starts_with("write"), "{action}");
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// The peak resident set of this process (`VmHWM`, bytes).
fn peak_resident_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let kb: u64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap();
    kb * 1024
}

/// Checks before reads (issue 87: a 2 GB data file was read whole before "not an rsf
/// checkpoint"). A 2 GB file that is not a checkpoint (sparse: `File::set_len`, no disk
/// used) is refused after its first bytes with the process's resident set below 100 MB —
/// measured in a child process that runs only this test (this binary re-run with
/// `--exact`), so that no other test's memory counts.
#[test]
fn a_large_file_of_another_kind_is_refused_as_a_checkpoint_without_reading_it() {
    const CHILD: &str = "RSF_TEST_LARGE_NOT_A_CHECKPOINT";
    let dir = temp_dir(&format!("large-{}", std::env::var_os(CHILD).is_some()));
    let big = dir.join("data.bin");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(2 << 30)
        .unwrap();
    if std::env::var_os(CHILD).is_some() {
        let e = Checkpoint::read(&big).unwrap_err();
        println!("refused: {e}");
        println!("peak_resident_bytes={}", peak_resident_bytes());
        return;
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "reliability::a_large_file_of_another_kind_is_refused_as_a_checkpoint_without_reading_it",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env(CHILD, "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("not an rsf checkpoint") && stdout.contains("data.bin"),
        "{stdout}"
    );
    let peak: f64 = stdout
        .lines()
        .find_map(|l| l.strip_prefix("peak_resident_bytes="))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("no peak in {stdout}"));
    assert!(peak < 100e6, "peak resident set {peak} B");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Non-files where a file is read whole are refused by their type, at once (issue 87:
/// `--resume /dev/zero` grew to 8.2 GB before "out of memory"; a FIFO where a file was
/// expected blocked forever): a checkpoint or a scene file that is a device, a FIFO or a
/// folder.
#[cfg(unix)]
#[test]
fn a_device_a_fifo_or_a_folder_is_refused_where_a_file_is_read() {
    let dir = temp_dir("not-files");
    let fifo = dir.join("fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    let mut cases = vec![
        (Path::new("/dev/zero").to_path_buf(), "a device"),
        (dir.clone(), "a folder"),
    ];
    if made {
        cases.push((fifo, "a FIFO"));
    }
    for (path, kind) in cases {
        let e = Checkpoint::read(&path).unwrap_err().to_string();
        assert!(e.contains(kind) && e.contains("not a regular file"), "{e}");
        let e = SliderScene::read(&path).unwrap_err().to_string();
        assert!(
            e.contains(kind) && e.contains(&path.display().to_string()),
            "{e}"
        );
        // A Gmsh mesh (`--mesh FILE.msh` of the programs, `Mesh.read_gmsh` in Python)
        // goes through the same open: the FIFO must not block, /dev/zero not be read.
        for e in [
            rsf::fem::read_gmsh::<2>(&path).map(|_| ()),
            rsf::fem::read_gmsh::<3>(&path).map(|_| ()),
        ] {
            let e = e.unwrap_err().to_string();
            assert!(
                e.contains(kind)
                    && e.contains("not a regular file")
                    && e.contains(&path.display().to_string()),
                "{e}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
