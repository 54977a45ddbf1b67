//! Opening the along-dip files: the checks of a set-up ([`check_setup`]) and the files'
//! state for a new or resumed run ([`open_files`]), the stages of
//! [`SeasOutput::new`](super::SeasOutput::new).

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use rsf::checkpoint::write_atomically;
use rsf::observe::FileMode;

use super::layout::Layout;
use super::resume::{plan_resume, LogState, SEAS_RESUME_LOG};
use crate::error::{invalid, io_at, Result};
use crate::setup::SeasSetup;
use crate::text::is_iso_date;

/// The checks of a set-up for a model of `D` dimensions with `nodes` frictional nodes and
/// `laws` laws: one law per node, a depth axis below `D`, positive finite `sigma_n` and
/// `profile_spacing`, a finite non-negative event quiet time, at least one station, the
/// header's `problem` and `modeler` one non-empty line each, an ISO date.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming the field.
pub(super) fn check_setup<const D: usize>(
    setup: &SeasSetup,
    laws: usize,
    nodes: usize,
) -> Result<()> {
    if laws != nodes {
        return Err(invalid(
            "laws",
            format!("{laws} laws for {nodes} frictional nodes"),
        ));
    }
    if setup.depth_axis >= D {
        return Err(invalid(
            "depth_axis",
            format!("{} must be below the dimension {D}", setup.depth_axis),
        ));
    }
    if !(setup.sigma_n > 0.0 && setup.sigma_n.is_finite()) {
        return Err(invalid("sigma_n", "must be positive and finite"));
    }
    let quiet = setup.sampling.event_quiet_time;
    if !(quiet >= 0.0 && quiet.is_finite()) {
        return Err(invalid(
            "event_quiet_time",
            format!("{quiet} s must be finite and ≥ 0"),
        ));
    }
    if !(setup.profile_spacing > 0.0 && setup.profile_spacing.is_finite()) {
        return Err(invalid("profile_spacing", "must be positive and finite"));
    }
    if setup.stations.is_empty() {
        return Err(invalid("stations", "none given"));
    }
    for (name, value) in [("problem", &setup.problem), ("modeler", &setup.modeler)] {
        if value.trim().is_empty() || value.contains(['\n', '\r']) {
            return Err(invalid(
                name,
                format!(
                    "`{}` must be one non-empty line",
                    rsf_numeric::excerpt(value)
                ),
            ));
        }
    }
    if !is_iso_date(&setup.date) {
        return Err(invalid(
            "date",
            format!(
                "`{}` is not a date YYYY-MM-DD",
                rsf_numeric::excerpt(&setup.date)
            ),
        ));
    }
    Ok(())
}

/// The files' state for `mode`: a new run's folder created (and whether its files replace
/// earlier ones), or a resumed run's files checked against the resume log's step `step`
/// ([`plan_resume`]), then cut to it, and the log opened for appending.
///
/// # Errors
/// Those of [`plan_resume`] (nothing is cut then); I/O errors naming the file.
pub(super) fn open_files(
    dir: &Path,
    setup: &SeasSetup,
    layout: &Layout,
    mode: FileMode,
) -> Result<(bool, LogState, Option<BufWriter<File>>)> {
    Ok(match mode {
        FileMode::Create | FileMode::Overwrite => {
            std::fs::create_dir_all(dir).map_err(io_at("create the folder", dir))?;
            (mode == FileMode::Overwrite, LogState::default(), None)
        }
        FileMode::Resume { step } => {
            let plan = plan_resume(dir, setup, layout, step)?;
            // Everything is checked: now cut.
            for (path, keep, len) in &plan.cuts {
                if keep < len {
                    let bytes = std::fs::read(path).map_err(io_at("read", path))?;
                    write_atomically(path, &bytes[..*keep])?;
                }
            }
            let log = dir.join(SEAS_RESUME_LOG);
            let file = std::fs::OpenOptions::new()
                .append(true)
                .open(&log)
                .map_err(io_at("open for appending", &log))?;
            (false, plan.state, Some(BufWriter::new(file)))
        }
    })
}
