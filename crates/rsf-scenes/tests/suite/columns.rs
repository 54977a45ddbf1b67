//! The 3-D slider built on some columns (`Slider3dScene::build_model_columns`, what one
//! process of several holds): every kept column of K, M, E and the absorbing dashpots has
//! the whole model's bits, the other columns are empty, and the vectors, the
//! prolongations and the frictional boundary are the whole model's — with free and
//! plane-strain lateral faces, absorbing sides, and turned (nodal frames at every fault
//! node); the parts' conditioning scales combine to the whole model's.
use rsf::model::ProblemScales;
use rsf::Model;
use rsf_scenes::{LateralBoundary, Slider3dScene};

/// The first half of the vertices, a pseudo-random half, and one vertex.
fn keep_sets(n: usize) -> Vec<Vec<bool>> {
    let mut x = 57u64;
    let mut random = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        x >> 63 == 1
    };
    vec![
        (0..n).map(|p| p < n / 2).collect(),
        (0..n).map(|_| random()).collect(),
        (0..n).map(|p| p == n / 3).collect(),
    ]
}

/// `build(keep, equilibrium)` of every keep-set against `whole`, the equilibrium the whole
/// model's `u₀` (the system it is given checked against the whole model).
fn check(
    what: &str,
    whole: &Model<3>,
    build: impl Fn(
        &[bool],
        &dyn Fn(&rsf::model::EquilibriumSystem<'_>) -> rsf::Result<Vec<f64>>,
    ) -> rsf::Result<Model<3>>,
) {
    for keep in keep_sets(whole.num_nodes()) {
        let equilibrium = |s: &rsf::model::EquilibriumSystem<'_>| {
            assert_eq!(s.columns, Some(&keep[..]));
            assert_eq!(s.load, &whole.load[..]);
            assert_eq!(s.stiffness.compute_nnz() > 0, keep.iter().any(|&k| k));
            Ok(whole.initial_displacement.clone())
        };
        let part = build(&keep, &equilibrium).unwrap();
        assert_eq!(part.columns.as_deref(), Some(&keep[..]), "{what}");
        // The scales of this part and of the complementary one combine to the whole
        // model's (what the processes of a job check together).
        let others: Vec<bool> = keep.iter().map(|&k| !k).collect();
        let rest = build(&others, &|_| Ok(whole.initial_displacement.clone())).unwrap();
        assert_eq!(
            ProblemScales::combined(&[
                ProblemScales::of_model(&rest),
                ProblemScales::of_model(&part)
            ]),
            ProblemScales::of_model(whole),
            "{what}"
        );
        part.validate().unwrap();
        part.check_part_of(whole)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let held = part.stiffness.compute_nnz() as f64 / whole.stiffness.compute_nnz() as f64;
        println!(
            "{what}: {} of {} nodes kept, {:.3} of K's entries",
            keep.iter().filter(|&&k| k).count(),
            keep.len(),
            held
        );
    }
}

fn scene(level: usize, lateral: LateralBoundary, absorbing: bool) -> Slider3dScene {
    let mut s = Slider3dScene::default();
    s.slider.level = level;
    s.lateral = lateral;
    s.slider.absorbing_sides = absorbing;
    s
}

#[test]
fn the_slider_on_columns_has_the_whole_models_columns() {
    for (level, lateral, absorbing) in [
        (2, LateralBoundary::Free, false),
        (2, LateralBoundary::PlaneStrain, false),
        (1, LateralBoundary::Free, true),
        (1, LateralBoundary::PlaneStrain, true),
    ] {
        let s = scene(level, lateral, absorbing);
        let whole = s.build_model().unwrap();
        assert_eq!(whole.absorbing.is_some(), absorbing);
        let what = format!("level {level}, {lateral:?}, absorbing {absorbing}");
        check(&what, &whole, |keep, eq| s.build_model_columns(keep, eq));
    }
}

#[test]
fn the_turned_slider_on_columns_has_the_whole_models_columns() {
    for (level, absorbing) in [(1, false), (2, false)] {
        let s = scene(level, LateralBoundary::Free, absorbing);
        let phi = 0.3;
        let whole = s.build_turned_model(phi).unwrap();
        assert!(!whole.frames.nodes.is_empty());
        let what = format!("turned, level {level}, absorbing {absorbing}");
        check(&what, &whole, |keep, eq| {
            s.build_turned_model_columns(phi, keep, eq)
        });
    }
}

#[test]
fn the_slider_on_columns_refuses_a_keep_set_of_another_length() {
    let s = scene(1, LateralBoundary::Free, false);
    let e = s
        .build_model_columns(&[true; 3], |_| unreachable!())
        .unwrap_err();
    assert!(
        matches!(&e, rsf::Error::InvalidParameter { name, .. } if name == "keep"),
        "{e}"
    );
}

/// The 3-D slider at `level` (the default scene otherwise) built by `how` — `whole`
/// (`build_model`, its equilibrium solved), `all` (`build_model_columns` keeping every
/// node), `half` (keeping the first half of the vertices) — its peak resident memory
/// (VmHWM of /proc/self/status) printed; the column builds' equilibrium is `u₀ = 0` (not
/// solved: what is measured is the assembly and the stages). Ignored (seconds, GB); run
/// each in its own process, e.g.
/// `cargo test --release -p rsf-scenes --test suite columns::peak_level_4_half -- --ignored --nocapture`.
fn print_peak(level: usize, how: &str) {
    let s = scene(level, LateralBoundary::Free, false);
    // The finest mesh's vertices (the hierarchy dropped before the build).
    let nv = rsf_fem::MeshHierarchy::refine_uniformly(
        rsf_scenes::slider_3d_coarse(s.width_m).unwrap(),
        s.slider.level,
    )
    .finest()
    .num_vertices();
    let zero = |s: &rsf::model::EquilibriumSystem<'_>| Ok(vec![0.0; s.load.len()]);
    let model = match how {
        "whole" => s.build_model().unwrap(),
        "all" => s.build_model_columns(&vec![true; nv], zero).unwrap(),
        "half" => {
            let keep: Vec<bool> = (0..nv).map(|p| p < nv / 2).collect();
            s.build_model_columns(&keep, zero).unwrap()
        }
        _ => unreachable!("{how}"),
    };
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let peak = status
        .lines()
        .find(|l| l.starts_with("VmHWM"))
        .unwrap_or("?");
    println!(
        "level {level}, {how}: {} nodes, K {} entries, M {:?}, {peak}",
        model.num_nodes(),
        model.stiffness.compute_nnz(),
        model.mass.as_ref().map(|m| m.compute_nnz())
    );
}

#[test]
#[ignore = "memory measurement: level 4, seconds and GB"]
fn peak_level_4_whole() {
    print_peak(4, "whole");
}

#[test]
#[ignore = "memory measurement: level 4, seconds and GB"]
fn peak_level_4_all() {
    print_peak(4, "all");
}

#[test]
#[ignore = "memory measurement: level 4, seconds and GB"]
fn peak_level_4_half() {
    print_peak(4, "half");
}

#[test]
#[ignore = "memory measurement: level 5, seconds and GB"]
fn peak_level_5_whole() {
    print_peak(5, "whole");
}

#[test]
#[ignore = "memory measurement: level 5, seconds and GB"]
fn peak_level_5_all() {
    print_peak(5, "all");
}

#[test]
#[ignore = "memory measurement: level 5, seconds and GB"]
fn peak_level_5_half() {
    print_peak(5, "half");
}
