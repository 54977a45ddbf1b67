//! `SliderScene::absorbing_sides`: the block's ends x = 0 and x = 5 m absorb waves
//! (Lysmer–Kuhlemeyer dashpots). The dashpot matrix is checked against the impedances
//! computed here from E, ν and ρ; the paper's scene (flag off) keeps its fingerprint.

use crate::within;
use rsf::fem::{quadratic_form, SparseMatrix, TAG_NEUMANN};
use rsf::{Error, Integrator};
use rsf_scenes::{Slider3dScene, SliderScene};

/// `eᵀ C e` for the uniform unit velocity `e` along `axis` (`dim` components per node):
/// the power per unit velocity² the dashpots take from a rigid motion of the ends.
fn rigid_power(c: &SparseMatrix, dim: usize, axis: usize) -> f64 {
    let e: Vec<f64> = (0..c.nrows())
        .map(|i| f64::from(u8::from(i % dim == axis)))
        .collect();
    quadratic_form(c.as_ref(), &e)
}

/// `(ρc_p, ρc_s)` of plane strain from the scene's E, ν, ρ (the textbook formulas).
fn impedances(s: &SliderScene) -> (f64, f64) {
    let (e, nu, rho) = (s.youngs_modulus_pa, s.poisson_ratio, s.density_kg_per_m2);
    let mu = e / (2.0 * (1.0 + nu));
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let c_p = ((lambda + 2.0 * mu) / rho).sqrt();
    let c_s = (mu / rho).sqrt();
    (rho * c_p, rho * c_s)
}

/// The two ends are 1 m high, with normal ±x: a rigid motion along x meets the impedance
/// `ρc_p` over 2 m, along y `ρc_s` over 2 m, and the two do not couple.
#[test]
fn the_ends_carry_the_plane_strain_impedances() {
    let scene = SliderScene {
        level: 2,
        absorbing_sides: true,
        ..SliderScene::default()
    };
    let model = scene.build_model().unwrap();
    let absorbing = model.absorbing.as_ref().expect("absorbing ends");
    assert_eq!(absorbing.parts, vec![TAG_NEUMANN.to_string()]);
    let (zp, zs) = impedances(&scene);
    let c = &absorbing.damping;
    let xx = rigid_power(c, 2, 0);
    let yy = rigid_power(c, 2, 1);
    // e_xᵀ C e_y from the quadratic form of e_x + e_y.
    let xy = 0.5 * (quadratic_form(c.as_ref(), &vec![1.0; c.nrows()]) - xx - yy);
    assert!(
        (xx / (2.0 * zp) - 1.0).abs() < 1e-13,
        "{xx} against {}",
        2.0 * zp
    );
    assert!(
        (yy / (2.0 * zs) - 1.0).abs() < 1e-13,
        "{yy} against {}",
        2.0 * zs
    );
    assert!(xy.abs() < 1e-13 * xx, "coupling {xy}");
    // The paper's scene has none.
    let paper = SliderScene {
        level: 2,
        ..SliderScene::default()
    };
    assert!(paper.build_model().unwrap().absorbing.is_none());
}

/// In 3-D the ends are 1 m × W: `ρc_p · 2W` along x, `ρc_s · 2W` along y and z.
#[test]
fn the_3d_slider_has_absorbing_ends_too() {
    let mut scene = Slider3dScene::default();
    scene.slider.level = 0;
    scene.slider.absorbing_sides = true;
    let model = scene.build_model().unwrap();
    let c = &model.absorbing.as_ref().expect("absorbing ends").damping;
    let (zp, zs) = impedances(&scene.slider);
    let w = scene.width_m;
    for (axis, z) in [(0, zp), (1, zs), (2, zs)] {
        let s = rigid_power(c, 3, axis);
        assert!((s / (2.0 * w * z) - 1.0).abs() < 1e-13, "axis {axis}: {s}");
    }
}

/// Without inertia there are no waves to absorb: refused, naming the field.
#[test]
fn absorbing_ends_need_inertia() {
    let scene = SliderScene {
        absorbing_sides: true,
        integrator: Integrator::Quasistatic(Default::default()),
        ..SliderScene::default()
    };
    match scene.validate() {
        Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "absorbing_sides"),
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

/// The flag is written only when set: the paper's scene file and fingerprint do not
/// change; a file that sets it reads back.
#[test]
fn the_flag_leaves_the_papers_fingerprint_alone() {
    let paper = SliderScene::default();
    let text = toml::to_string(&paper).unwrap();
    assert!(!text.contains("absorbing_sides"), "{text}");
    let on = SliderScene::from_toml("absorbing_sides = true").unwrap();
    assert!(on.absorbing_sides);
    assert_ne!(on.fingerprint(), paper.fingerprint());
    assert_eq!(
        SliderScene::from_toml("").unwrap().fingerprint(),
        paper.fingerprint()
    );
}

/// Per step: time (s), max slip rate on Γ_F (m/s), kinetic energy (J/m).
struct Energies(Vec<[f64; 3]>);

impl rsf::Observer<2> for Energies {
    fn observe(&mut self, s: &rsf::StepView<'_, 2, 2>) -> rsf::Result<rsf::Flow> {
        let max_v = (0..s.model.frictional_boundary.len())
            .map(|k| s.slip_rate(k))
            .fold(0.0, f64::max);
        let kinetic = s.model.kinetic_energy(&s.state.kinematics.v)?;
        self.0.push([s.state.time, max_v, kinetic]);
        Ok(rsf::Flow::Continue(()))
    }
}

/// The first event (max V ≥ 1e-3 m/s) of the main job at j = 2 with traction-free and
/// with absorbing ends: it starts within two steps of 1.5 ms (the dashpots' force before it is
/// ρc·v ≤ 1e4 · 2e-4 N/m², far below the friction's), and afterwards the block with
/// absorbing ends keeps much less kinetic energy: the waves that stay in the paper's
/// block are reflections from its ends (here 0.020 of the traction-free energy; at j = 3 and 4
/// `examples/slider_absorbing.rs` measured 0.10 and 0.06).
#[test]
fn absorbing_ends_take_the_ringing_out_of_the_block() {
    let run = |absorbing_sides: bool| {
        let scene = SliderScene {
            level: 2,
            absorbing_sides,
            ..SliderScene::default()
        };
        let mut sim = scene.build().unwrap();
        let mut rows = Energies(Vec::new());
        sim.run_until(within(11.0), &mut [&mut rows]).unwrap();
        rows.0
    };
    let (free, absorbing) = (run(false), run(true));
    // The first event: onset and end (first step back below 1e-3 m/s).
    let event = |rows: &[[f64; 3]]| {
        let on = rows.iter().position(|r| r[1] >= 1e-3).expect("an event");
        let off = on + rows[on..].iter().position(|r| r[1] < 1e-3).unwrap();
        (on, off)
    };
    let ((on_f, off_f), (on_a, off_a)) = (event(&free), event(&absorbing));
    assert!(
        on_f.abs_diff(on_a) <= 2,
        "the first event starts within two steps (3 ms): {on_f}, {on_a}"
    );
    let mean_after = |rows: &[[f64; 3]], off: usize| {
        let t1 = rows[off][0];
        let e: Vec<f64> = rows
            .iter()
            .filter(|r| r[0] >= t1 + 0.1 && r[0] <= t1 + 0.6)
            .map(|r| r[2])
            .collect();
        e.iter().sum::<f64>() / e.len() as f64
    };
    let (ef, ea) = (mean_after(&free, off_f), mean_after(&absorbing, off_a));
    println!("kinetic energy 0.1–0.6 s after the first event: free {ef:e}, absorbing {ea:e} J/m");
    assert!(
        ea < 0.3 * ef,
        "absorbing {ea:e} against traction-free {ef:e}"
    );
}

/// `Model::kinetic_energy` of a rigid translation is `½ m v²` with the block's mass
/// `m = ρ · 5 m · 1 m`; a velocity of the wrong length and a model without mass are refused.
#[test]
fn kinetic_energy_of_a_translation_is_half_the_mass_times_the_speed_squared() {
    let scene = SliderScene {
        level: 2,
        ..SliderScene::default()
    };
    let model = scene.build_model().unwrap();
    let (vx, vy) = (0.3, -0.4);
    let v: Vec<f64> = (0..model.num_dofs())
        .map(|i| if i % 2 == 0 { vx } else { vy })
        .collect();
    let mass = scene.density_kg_per_m2 * 5.0 * 1.0;
    let expected = 0.5 * mass * (vx * vx + vy * vy);
    let e = model.kinetic_energy(&v).unwrap();
    assert!((e / expected - 1.0).abs() < 1e-12, "{e} against {expected}");
    assert!(matches!(
        model.kinetic_energy(&v[1..]),
        Err(Error::InvalidParameter { .. })
    ));
    let quasistatic = SliderScene {
        level: 2,
        integrator: Integrator::Quasistatic(Default::default()),
        ..SliderScene::default()
    };
    assert!(matches!(
        quasistatic.build_model().unwrap().kinetic_energy(&v),
        Err(Error::InvalidParameter { .. })
    ));
}
