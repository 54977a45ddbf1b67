//! Our DC3D against Okada's own FORTRAN routine: `tests/fixtures/dc3d.csv`, made by
//! `tests/fixtures/make_dc3d_fixture.sh` (9 sources: buried and surface-breaking, dips
//! 0°, 15°, 30°, 45°, 60°, 75°, 90°, 120°, three values of α; 36 points each — random,
//! near the fault, on the free surface, in the fault's plane beyond its end, and on an
//! edge — and the three unit dislocations at each).
//!
//! Tolerance: both codes evaluate the same closed forms in double precision. They differ
//! in the order of operations, and where DC3D forms `R + ξ` (or `R + η`) for a negative
//! `ξ` as a plain sum it loses `log₁₀(ξ²/(η² + q²))` digits, which we avoid
//! (`b²/(R − ξ)`); the corner sums amplify either by the ratio of the corner terms to the
//! result (at most about 10³ at these distances). Measured: 2.5·10⁻¹² (displacements)
//! and 3.2·10⁻¹¹ (derivatives) relative to the field's scale at the point — the largest
//! 0.18 below a horizontal fault, beyond its down-dip end, where DC3D's `R + η` has lost
//! three digits (2·10⁻¹³ and 2·10⁻¹⁴ when we formed the sums as DC3D does). We ask
//! 10⁻¹⁰ relative to the field's scale at the point — the largest displacement component
//! for `u`, the largest derivative for `∇u` — which catches any wrong term.
use rsf_halfspace::okada::{dc3d, Rectangle};
use rsf_halfspace::Error;

struct Row {
    alpha: f64,
    point: [f64; 3],
    depth: f64,
    dip: f64,
    al: [f64; 2],
    aw: [f64; 2],
    disl: [f64; 3],
    iret: i32,
    values: [f64; 12],
}

fn rows() -> Vec<Row> {
    let text = include_str!("../fixtures/dc3d.csv");
    // The fixture's `#` lines are comments; the header names the 28 columns.
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader.headers().unwrap().clone();
    assert_eq!(header.len(), 28);
    assert_eq!(&header[2], "alpha");
    assert_eq!(&header[15], "iret");
    assert_eq!(&header[16], "ux");
    assert_eq!(&header[27], "uzz");
    reader
        .records()
        .map(|record| {
            let f: Vec<f64> = record.unwrap().iter().map(|v| v.parse().unwrap()).collect();
            assert_eq!(f.len(), 28);
            let mut values = [0.0; 12];
            values.copy_from_slice(&f[16..28]);
            Row {
                alpha: f[2],
                point: [f[3], f[4], f[5]],
                depth: f[6],
                dip: f[7],
                al: [f[8], f[9]],
                aw: [f[10], f[11]],
                disl: [f[12], f[13], f[14]],
                iret: f[15] as i32,
                values,
            }
        })
        .collect()
}

#[test]
fn dc3d_matches_okadas_routine() {
    let rows = rows();
    assert_eq!(rows.len(), 972);
    let (mut worst_u, mut worst_g, mut singular) = (0.0f64, 0.0f64, 0);
    let mut worst_row = (0, 0);
    for (n, r) in rows.iter().enumerate() {
        let got = dc3d(
            r.alpha,
            r.point,
            Rectangle::new(r.depth, r.dip, r.al, r.aw).unwrap(),
            r.disl,
        );
        if r.iret == 1 {
            assert!(
                matches!(got, Err(Error::OnEdge { .. })),
                "row {n}: DC3D says singular, we gave {got:?}"
            );
            singular += 1;
            continue;
        }
        assert_eq!(r.iret, 0);
        let d = got.unwrap_or_else(|e| panic!("row {n}: {e}"));
        // DC3D's order: u, then the x, y and z derivatives of (ux, uy, uz).
        let mut ours = [0.0; 12];
        ours[..3].copy_from_slice(&d.u);
        for j in 0..3 {
            for i in 0..3 {
                ours[3 + 3 * j + i] = d.grad[i][j];
            }
        }
        let scale_u = r.values[..3].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let scale_g = r.values[3..].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale_u > 0.0 && scale_g > 0.0, "row {n}: zero field");
        for k in 0..12 {
            let scale = if k < 3 { scale_u } else { scale_g };
            let rel = (ours[k] - r.values[k]).abs() / scale;
            if k < 3 {
                if rel > worst_u {
                    worst_row.0 = n;
                }
                worst_u = worst_u.max(rel);
            } else {
                if rel > worst_g {
                    worst_row.1 = n;
                }
                worst_g = worst_g.max(rel);
            }
            assert!(
                rel <= 1e-10,
                "row {n} value {k}: ours {} DC3D {} (relative to the scale {rel:.2e})",
                ours[k],
                r.values[k]
            );
        }
    }
    assert_eq!(singular, 27);
    println!(
        "largest differences: displacement {worst_u:.2e} (row {}), gradient {worst_g:.2e} (row {}), relative",
        worst_row.0, worst_row.1
    );
}
