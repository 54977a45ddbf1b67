//! The pore-pressure fields: BP6's closed form at the check points of the benchmark's
//! restatement (values computed there independently, to the 4 digits printed), the
//! numerical diffusion against it and its no-flux ends.

use super::*;

const DAY: f64 = 86_400.0;

/// BP6's injection: q₀ = 1.25e-6 m/s, shut-in after 100 days; βφ = 1e-9 /Pa, α = 0.1 m²/s.
fn bp6() -> (Injection, f64, f64) {
    (
        Injection {
            rate: 1.25e-6,
            shut_in: 100.0 * DAY,
        },
        1e-9,
        0.1,
    )
}

fn closed_form() -> InjectionPressure<2> {
    let (inj, storage, alpha) = bp6();
    InjectionPressure::new(inj, storage, alpha, [0.0, 0.0], [0.0, 1.0]).unwrap()
}

#[test]
fn closed_form_matches_the_check_values_of_the_description() {
    // docs/seas-bp6.md "Pore pressure": p (MPa) at z (km) and t (days).
    let days = [50.0, 100.0, 200.0, 365.0, 730.0];
    let table: [(f64, [f64; 5]); 5] = [
        (0.0, [4.635, 6.555, 2.715, 1.853, 1.258]),
        (0.5, [2.165, 3.899, 2.580, 1.810, 1.244]),
        (1.0, [0.836, 2.116, 2.215, 1.688, 1.205]),
        (2.5, [0.013, 0.181, 0.780, 1.037, 0.963]),
        (5.0, [0.000, 0.000, 0.025, 0.185, 0.433]),
    ];
    let p = closed_form();
    for (z, row) in table {
        for (d, want) in days.iter().zip(row) {
            for sign in [1.0, -1.0] {
                let got = p.pressure(&[3.0, sign * z * 1e3], d * DAY) / 1e6;
                assert!(
                    (got - want).abs() <= 5.0001e-4,
                    "z = {z} km, t = {d} d: {got} MPa, table {want}"
                );
            }
        }
    }
    // p(·, 0) = 0; continuous at shut-in; the Darcy velocity is odd in z, q₀/2 at the
    // source's side just after injection starts.
    assert_eq!(p.pressure(&[0.0, 100.0], 0.0), 0.0);
    let t = 100.0 * DAY;
    let jump = p.pressure(&[0.0, 300.0], t * (1.0 + 1e-12)) - p.pressure(&[0.0, 300.0], t);
    assert!(jump.abs() < 1e-3, "{jump}");
    let q = p.darcy_velocity(&[0.0, 1e-3], 10.0 * DAY).unwrap();
    assert!((q - 0.625e-6).abs() < 1e-9, "{q}");
    assert_eq!(
        p.darcy_velocity(&[0.0, -700.0], 20.0 * DAY).unwrap(),
        -p.darcy_velocity(&[0.0, 700.0], 20.0 * DAY).unwrap()
    );
}

/// The diffusion of BP6 on ±20 km with `cells` cells.
fn diffusion(cells: usize, ends: [f64; 2]) -> FaultDiffusion<2> {
    let (inj, storage, alpha) = bp6();
    // k/η_f = 1e-13/1e-3.
    FaultDiffusion::new(
        inj,
        (storage, alpha, 1e-10),
        [0.0, 0.0],
        [0.0, 1.0],
        ends,
        cells,
    )
    .unwrap()
}

#[test]
fn numerical_diffusion_converges_to_the_closed_form_far_from_the_ends() {
    let exact = closed_form();
    // Away from the source (|z| ≥ 300 m: second order) and at it (the kink of p, where
    // the cells' centres h/2 away interpolate it: first order).
    let (mut away, mut at_source) = (Vec::new(), Vec::new());
    for cells in [400, 800, 1600] {
        let d = diffusion(cells, [-20e3, 20e3]);
        let (mut worst, mut source) = (0.0_f64, 0.0_f64);
        for t in [50.0 * DAY, 100.0 * DAY, 200.0 * DAY, 730.0 * DAY] {
            let peak = exact.at(0.0, t);
            for i in 0..=100 {
                let z = -5e3 + 100.0 * i as f64;
                let x = [0.0, z];
                let e = (d.pressure(&x, t) - exact.pressure(&x, t)).abs() / peak;
                if z.abs() >= 300.0 {
                    worst = worst.max(e);
                } else if z == 0.0 {
                    source = source.max(e);
                }
            }
        }
        away.push(worst);
        at_source.push(source);
    }
    eprintln!(
        "max |p_h − p| / p(0, t) at h = 100, 50, 25 m: {away:?} for |z| ≥ 300 m, \
         {at_source:?} at z = 0"
    );
    assert!(away[2] < 1e-3, "{away:?}");
    for w in away.windows(2) {
        assert!(
            w[1] < 0.3 * w[0],
            "second order away from the source: {away:?}"
        );
    }
    assert!(at_source[2] < 0.02, "{at_source:?}");
    for w in at_source.windows(2) {
        assert!(
            w[1] < 0.6 * w[0],
            "first order at the source: {at_source:?}"
        );
    }
}

#[test]
fn numerical_diffusion_conserves_the_injected_volume_through_no_flux_ends() {
    // A short fault: after a long time the pressure is uniform, the whole volume kept.
    let (inj, storage, _) = bp6();
    let d = diffusion(200, [-1e3, 3e3]);
    let h = d.cell_width();
    for t in [10.0 * DAY, 100.0 * DAY, 400.0 * DAY, 20_000.0 * DAY] {
        let volume = storage * h * d.cells(t).iter().sum::<f64>();
        let injected = inj.rate * t.min(inj.shut_in);
        assert!(
            (volume - injected).abs() <= 1e-12 * injected,
            "t = {t}: {volume} against {injected}"
        );
    }
    // After many diffusion times L²/α = 1850 days: uniform.
    let late = d.cells(20_000.0 * DAY);
    let uniform = inj.rate * inj.shut_in / (storage * 4e3);
    for p in &late {
        assert!(
            (p - uniform).abs() < 1e-6 * uniform,
            "{p} against {uniform}"
        );
    }
    // The Darcy velocity vanishes at and beyond the ends, and the closed form (no ends)
    // has lost volume by then.
    assert_eq!(d.darcy_velocity(&[0.0, 3e3], 50.0 * DAY), Some(0.0));
    assert_eq!(d.darcy_velocity(&[0.0, -1e3 - 5.0], 50.0 * DAY), Some(0.0));
    let exact = closed_form();
    assert!(exact.pressure(&[0.0, 3e3], 20_000.0 * DAY) < 0.9 * uniform);
}

#[test]
fn invalid_fields_are_typed_errors() {
    let (inj, storage, alpha) = bp6();
    let bad = |r: crate::Result<InjectionPressure<2>>, name: &str| match r {
        Err(crate::Error::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
        other => panic!("{other:?}"),
    };
    bad(
        InjectionPressure::new(inj, -1.0, alpha, [0.0; 2], [0.0, 1.0]),
        "storage",
    );
    bad(
        InjectionPressure::new(inj, storage, f64::NAN, [0.0; 2], [0.0, 1.0]),
        "diffusivity",
    );
    bad(
        InjectionPressure::new(inj, storage, alpha, [0.0; 2], [0.0, 2.0]),
        "direction",
    );
    bad(
        InjectionPressure::new(
            Injection {
                rate: -1.0,
                shut_in: 1.0,
            },
            storage,
            alpha,
            [0.0; 2],
            [0.0, 1.0],
        ),
        "injection.rate",
    );
    assert!(matches!(
        FaultDiffusion::<2>::new(inj, (storage, alpha, 1e-10), [0.0; 2], [0.0, 1.0], [1.0, 2.0], 10),
        Err(crate::Error::InvalidParameter { ref name, .. }) if name == "ends"
    ));
    assert!(matches!(
        FaultDiffusion::<2>::new(inj, (storage, alpha, 1e-10), [0.0; 2], [0.0, 1.0], [-1.0, 2.0], 1),
        Err(crate::Error::InvalidParameter { ref name, .. }) if name == "cells"
    ));
}
