//! The flags' checks of the guard: the error type of the programs, the bounds every
//! program takes ([`Limits`]), and the helpers that refuse a flag naming it as the user
//! wrote it.

use std::error::Error;

/// The error type of the programs.
pub type AnyError = Box<dyn Error>;

/// The bounds every program takes: `--max-memory-gb` and `--max-output-gb`.
#[derive(Debug, Clone, Copy, PartialEq, clap::Args)]
pub struct Limits {
    /// Refuse, before anything is allocated, a run whose memory is estimated above this
    /// many gigabytes, in (0, inf] (`inf`: no bound; docs/reliability.md lists each
    /// program's estimate).
    #[arg(long, default_value_t = 16.0, value_name = "GB", value_parser = gigabytes)]
    pub max_memory_gb: f64,
    /// Refuse, before anything is written, a run whose files are estimated above this many
    /// gigabytes, in (0, inf] (`inf`: no bound).
    #[arg(long, default_value_t = 10.0, value_name = "GB", value_parser = gigabytes)]
    pub max_output_gb: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_memory_gb: 16.0,
            max_output_gb: 10.0,
        }
    }
}

/// Parses a size limit in gigabytes: a positive number, `inf` for none (a clap value
/// parser: `nan`, 0 and negative values are refused where the flag is read).
///
/// # Errors
/// A message naming the value.
pub fn gigabytes(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x > 0.0 => Ok(x),
        Ok(_) => Err(format!(
            "`{s}` GB must be a positive number (inf: no bound)"
        )),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

/// An error naming the flag the user wrote: `--out a_file: cannot create …`.
#[derive(Debug)]
pub struct FlagError {
    /// The flag as written (`--out`) or the scene key.
    pub flag: String,
    /// What is wrong.
    pub source: AnyError,
}

impl std::fmt::Display for FlagError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.flag, self.source)
    }
}

impl Error for FlagError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        // The wrapped error's own causes (its message is already in ours).
        self.source.source()
    }
}

/// `result`'s error named after `flag` (e.g. `--scene`).
///
/// # Errors
/// The error of `result`, prefixed with `flag`.
pub fn flag<T, E: Into<AnyError>>(flag: &str, result: Result<T, E>) -> Result<T, AnyError> {
    result.map_err(|e| {
        Box::new(FlagError {
            flag: flag.to_owned(),
            source: e.into(),
        }) as AnyError
    })
}

/// The message `--flag value: why` of a refused flag, as an error.
pub fn refuse(flag: &str, value: impl std::fmt::Display, why: &str) -> AnyError {
    format!("{flag} {}: {why}", excerpt(&value.to_string())).into()
}

/// A value as the user wrote it, at most about 100 characters (`1e300`, not 301 digits).
pub(super) fn excerpt(s: &str) -> String {
    rsf_numeric::excerpt(s)
}

/// A computed number for a message as a user would write it: `300`, `0.025`, `1e300`
/// (never 301 digits), `NaN`, four digits where the shortest form is longer
/// ([`rsf_numeric::number`]). A flag's value is shown by [`written`] instead.
pub fn number(x: f64) -> String {
    rsf_numeric::number(x)
}

/// A flag's value as the user wrote it, up to notation: the shorter of the shortest
/// round-trip texts `{x}` and `{x:e}` ([`rsf_numeric::written`]: `1e-300`, never 300
/// digits; `2000.0000001`, never rounded to look like its bound `2000`).
pub fn written(x: f64) -> String {
    rsf_numeric::written(x)
}

/// Checks that `x` (the value of `flag`) lies in `[lo, hi]` (NaN is refused).
///
/// # Errors
/// `--flag x: must be in [lo, hi] (why)`, `x` as written ([`written`]), the bounds as
/// [`bound`] shows them.
pub fn in_range(flag: &str, x: f64, (lo, hi): (f64, f64), why: &str) -> Result<f64, AnyError> {
    if x >= lo && x <= hi {
        Ok(x)
    } else {
        Err(refuse(
            flag,
            written(x),
            &format!("must be in [{}, {}] ({why})", bound(lo), bound(hi)),
        ))
    }
}

/// A bound of a range for a message: [`number`]'s short form where it is the bound
/// exactly (`2000`, `1e-9`, `0.025`), else the bound's every digit ([`written`]), so that
/// a value refused for lying just beyond it never reads as the bound itself.
pub fn bound(x: f64) -> String {
    rsf_scenes::run_config::bound(x)
}

/// Checks that the values of the list flag `flag` are distinct: a size listed twice
/// (`--dz 1000,1000`) runs the same case twice and leaves a fit of the cost against the
/// size without two sizes (it printed `m^NaN`).
///
/// # Errors
/// `--flag a,b,…: `x` is listed twice`.
pub fn distinct<T: PartialEq + std::fmt::Display>(
    flag: &str,
    values: &[T],
) -> Result<(), AnyError> {
    for (i, v) in values.iter().enumerate() {
        if values[..i].contains(v) {
            let all = values.iter().map(ToString::to_string).collect::<Vec<_>>();
            return Err(refuse(
                flag,
                all.join(","),
                &format!(
                    "`{}` is listed twice: every value is a case of its own (a fit across \
                     them needs distinct values)",
                    excerpt(&v.to_string())
                ),
            ));
        }
    }
    Ok(())
}

/// A flag's range and its `--help` text from one pair of literals, so that the two cannot
/// drift: `flag_range!(END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 100])`
/// defines `const END_YEARS: (f64, f64) = (1e-9, 100.0)` for [`in_range`] and `const
/// END_YEARS_HELP: &str = "End time (years), in [1e-9, 100]."` for the flag's
/// `#[arg(help = END_YEARS_HELP)]` (the test `flag_ranges` reads the range back from
/// `--help` and probes the check at its bounds): the run configurations' macro
/// ([`rsf_scenes::setting_range`]). The SEAS programs' (feature `seas`).
#[cfg_attr(not(feature = "seas"), allow(unused_imports))]
pub(crate) use rsf_scenes::setting_range as flag_range;
