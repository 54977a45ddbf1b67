//! The programs of `rsf-programs` with HDF5 output (feature `programs`): their fields with
//! `--hdf5 N` ([`Hdf5Writers`], the writers these binaries supply through
//! `rsf_programs::fields::FieldWriters`) — the binaries `slider_3d` and `pipping_slider`
//! (the body's fields, [`Hdf5Fields`]) and `seas_bp1`, `seas_bp3`, `seas_bp5` (the fault's
//! fields, [`Hdf5FaultFields`]) — and the SEAS programs' time series in one HDF5 file:
//! [`main_with_series`] runs a program and writes `seas.h5` into its `--out` folder when it
//! ends (`seas_bp1`, `seas_bp3`, `seas_bp5`, `seas_bp6`).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use rsf::observe::{Every, Interval};
use rsf::Observer;
use rsf_programs::fields::{FieldWriters, FieldsTarget};

use crate::series::{write_seas_series, SEAS_SERIES_FILE};
use crate::{Hdf5FaultFields, Hdf5Fields};

/// The HDF5 writers of `--hdf5 N`: the body's fields of the sliders ([`Hdf5Fields`]) and
/// the fault's fields of the SEAS programs ([`Hdf5FaultFields`]) into `OUT/fields.h5` with
/// the index `OUT/fields.xmf`, a frame every N steps. A new file records the run's
/// fingerprint and N; a resumed run continues the file once it shows that it holds the
/// checkpoint's run, with the same N.
#[derive(Debug, Clone, Copy, Default)]
pub struct Hdf5Writers;

impl Hdf5Writers {
    /// The writers, as the programs' `main_with_fields` take them.
    pub fn shared() -> Arc<dyn FieldWriters> {
        Arc::new(Self)
    }
}

/// `fields` (the body's or the fault's, new or continued) for `target`, a frame every
/// `target.every` steps.
fn sampled<const D: usize, const C: usize, O: Observer<D, C> + 'static>(
    target: &FieldsTarget<'_>,
    new: impl FnOnce() -> crate::Result<O>,
    resumed: impl FnOnce(&rsf::Checkpoint, &[&str]) -> crate::Result<O>,
) -> rsf::Result<Box<dyn Observer<D, C>>> {
    let fields = match target.resumed {
        Some(c) => {
            crate::frames::check_every(target.path, target.every)?;
            let allowed: Vec<&str> = target.allow_change.iter().map(String::as_str).collect();
            resumed(c, &allowed)?
        }
        None => new()?,
    };
    Ok(Box::new(Every::new(Interval::Steps(target.every), fields)?))
}

/// [`sampled`] of the writer `$fields` ([`Hdf5Fields`] or [`Hdf5FaultFields`]) for
/// `$target`: a new file with the run's fingerprint and interval, or the file continued.
macro_rules! sampled_file {
    ($fields:ident, $target:expr) => {{
        let target = $target;
        sampled(
            target,
            || {
                Ok($fields::new(target.path, target.mode)?
                    .fingerprint(target.fingerprint.clone())
                    .every(target.every))
            },
            |c, allowed| $fields::continue_run(target.path, c, allowed),
        )
    }};
}

/// The body's fields for `target`.
fn volume<const D: usize>(target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<D>>>
where
    Hdf5Fields: Observer<D>,
{
    sampled_file!(Hdf5Fields, target)
}

/// The fault's fields for `target`.
fn fault<const D: usize, const C: usize>(
    target: &FieldsTarget<'_>,
) -> rsf::Result<Box<dyn Observer<D, C>>> {
    sampled_file!(Hdf5FaultFields, target)
}

impl FieldWriters for Hdf5Writers {
    fn volume_2d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>> {
        volume(target)
    }

    fn volume_3d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>> {
        volume(target)
    }

    fn fault_antiplane(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2, 1>>> {
        fault(target)
    }

    fn fault_2d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<2>>> {
        fault(target)
    }

    fn fault_3d(&self, target: &FieldsTarget<'_>) -> rsf::Result<Box<dyn Observer<3>>> {
        fault(target)
    }
}

/// Runs the SEAS program `program` (its `main`: the same flags, guard and
/// files, e.g. `rsf_programs::seas_bp1::main`) and, when it ends successfully, writes the
/// time series of its `--out` folder (`default_out` where the program has a default and
/// the flag is not given) into `seas.h5` there ([`write_seas_series`]), holding the
/// folder's lock while it does (as a run does: no other run writes into it meanwhile).
///
/// A run that fails or stops at `--max-steps` (an error exit) leaves the folder's `seas.h5`
/// as it was: the run resumed to its end writes it, or the program `seas_hdf5 DIR` at any
/// time. So does a run of the program itself in the folder (a resume,
/// `--overwrite`), which knows nothing of `seas.h5`: `seas_hdf5 DIR` rebuilds it. Returns the program's exit code, or failure (the error printed) if the HDF5 file
/// cannot be written.
pub fn main_with_series(program: fn() -> ExitCode, default_out: Option<&str>) -> ExitCode {
    let out = out_flag(std::env::args_os().skip(1)).or_else(|| default_out.map(PathBuf::from));
    let code = program();
    match out {
        Some(dir) if code == ExitCode::SUCCESS => match write_series_locked(&dir) {
            Ok(()) => code,
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        },
        _ => code,
    }
}

/// Writes `dir/seas.h5` under the folder's lock; tells what it wrote.
///
/// # Errors
/// Another run holds the folder's lock, or [`write_seas_series`]'s.
pub fn write_series_locked(dir: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let _lock = rsf_programs::guard::lock(dir)?;
    let path = dir.join(SEAS_SERIES_FILE);
    let summary = write_seas_series(dir, &path)?;
    let rows: usize = summary.groups.iter().map(|g| g.1).sum();
    eprintln!(
        "{}: {} groups, {rows} rows (the SEAS files of the folder)",
        path.display(),
        summary.groups.len()
    );
    Ok(())
}

/// The value of the flag `--out` (`--out DIR` or `--out=DIR`) among `args` (before a
/// `--`), the last if given more than once (the program refuses that itself).
pub fn out_flag(args: impl IntoIterator<Item = OsString>) -> Option<PathBuf> {
    let mut args = args.into_iter();
    let mut out = None;
    while let Some(a) = args.next() {
        if a == "--" {
            break;
        } else if a == "--out" {
            out = args.next().map(PathBuf::from);
        } else if let Some(dir) = a.to_str().and_then(|a| a.strip_prefix("--out=")) {
            out = Some(PathBuf::from(dir));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::out_flag;
    use std::path::PathBuf;

    #[test]
    fn the_out_folder_is_found_as_clap_reads_it() {
        let flag = |args: &[&str]| out_flag(args.iter().map(Into::into));
        let dir = Some(PathBuf::from("run"));
        assert_eq!(flag(&["--dz", "400", "--out", "run"]), dir);
        assert_eq!(flag(&["--out=run", "--threads", "1"]), dir);
        assert_eq!(flag(&["--output", "x", "--out", "run"]), dir);
        assert_eq!(flag(&["--dz", "400"]), None);
        assert_eq!(flag(&["--", "--out", "run"]), None);
        assert_eq!(flag(&["--out"]), None);
    }
}
