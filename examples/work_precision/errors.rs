//! The errors (a), (b), (c) of a run against the reference, and a run's row of a table.

use rsf_scenes::SliderScene;

use crate::common::log;
use crate::plot::Point;
use crate::trace::{trace, Trace};

/// Errors (a), (b), (c) of `run` against `reference` (relative; None if undefined).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Errors {
    pub(crate) u: Option<f64>,
    u_value: Option<f64>,
    pub(crate) ts: Option<f64>,
    ts_value: Option<f64>,
    pub(crate) lnv: Option<f64>,
}

impl Errors {
    /// `err a … b … c …` and the run's failure, for the log.
    pub(crate) fn describe(&self, run: &Trace) -> String {
        format!(
            "err a {} b {} c {} {}",
            opt(self.u),
            opt(self.ts),
            opt(self.lnv),
            run.failure.as_deref().unwrap_or("")
        )
    }

    /// The point of `run` in a study's figure: `label`, its CPU time (s) and these errors.
    pub(crate) fn point(&self, label: String, run: &Trace) -> Point {
        (label, run.cpu_s, [self.u, self.ts, self.lnv])
    }
}

/// The run of `scene` recorded over `(t_min, t_max)` ([`trace`], to its first slip event)
/// and its errors against `reference`; `None` where the run fails, logged as
/// `  {what}: {error}`.
pub(crate) fn traced(
    scene: &SliderScene,
    (t_min, t_max): (f64, f64),
    reference: &Trace,
    what: std::fmt::Arguments<'_>,
) -> Option<(Trace, Errors)> {
    match trace(scene, t_min, t_max, true) {
        Ok(run) => {
            let e = errors(&run, reference, scene);
            Some((run, e))
        }
        Err(e) => {
            log(&format!("  {what}: {e}"));
            None
        }
    }
}

pub(crate) fn errors(run: &Trace, reference: &Trace, scene: &SliderScene) -> Errors {
    let t_end = scene.end_time_s;
    let ta = 0.6 * t_end;
    let ramp = scene.ramp_fraction * t_end;
    let u = run.ux_at(ta).map(|u| u - run.u_init);
    let u_ref = reference.ux_at(ta).map(|u| u - reference.u_init);
    let ts = run.first_slip(ramp);
    let ts_ref = reference.first_slip(ramp);
    let ref_lnv: Vec<f64> = reference
        .vx
        .iter()
        .map(|v| v.abs().max(1e-300).ln())
        .collect();
    let (mut sum, mut n) = (0.0, 0usize);
    for (k, &t) in run.t.iter().enumerate() {
        if t < ramp - 1e-12 || t > ta + 1e-12 {
            continue;
        }
        if let Some(r) = reference.at(&ref_lnv, t) {
            let d = run.vx[k].abs().max(1e-300).ln() - r;
            sum += d * d;
            n += 1;
        }
    }
    Errors {
        u: u.zip(u_ref).map(|(a, b)| ((a - b) / b).abs()),
        u_value: u,
        ts: ts.zip(ts_ref).map(|(a, b)| ((a - b) / b).abs()),
        ts_value: ts,
        lnv: (n > 0).then(|| (sum / n as f64).sqrt()),
    }
}

pub(crate) fn opt(x: Option<f64>) -> String {
    x.map_or_else(|| "nan".into(), |v| format!("{v:.6e}"))
}

pub(crate) const ROW_HEAD: &str =
    "cpu_s,seconds,setup_s,step_s,record_s,steps,dofs,fpi_mean,solver_its,\
du_x0_ta_m,err_u_rel,t_slip_s,err_tslip_rel,err_lnv_rms,failure";

pub(crate) fn row(tr: &Trace, e: &Errors) -> String {
    format!(
        "{:.4},{:.4},{:.4},{:.4},{:.4},{},{},{:.3},{},{},{},{},{},{},{}",
        tr.cpu_s,
        tr.seconds(),
        tr.setup_s,
        tr.step_s,
        tr.record_s,
        tr.steps(),
        tr.dofs,
        tr.fpi as f64 / tr.steps().max(1) as f64,
        tr.solver_its,
        opt(e.u_value),
        opt(e.u),
        opt(e.ts_value),
        opt(e.ts),
        opt(e.lnv),
        tr.failure.as_deref().unwrap_or("")
    )
}
