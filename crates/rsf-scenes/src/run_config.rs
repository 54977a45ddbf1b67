//! A program's run configuration as one typed value (docs/reliability.md, "One run
//! configuration"): a struct of settings whose field names are at once the command line's
//! flags (`dx` is `--dx`; clap derives the flags from the struct under the feature
//! `clap`), the keys of a TOML file (`dx = 20`), Python's keyword arguments (`dx=20`),
//! the fields of a checkpoint's fingerprint and the keys of `summary.json`'s `settings`.
//! Nothing is listed twice: the defaults are the struct's [`Default`], the ranges and
//! rules its [`RunConfig::validate`], the fingerprint and the summary its serde
//! serialisation.
//!
//! ```
//! # #[cfg(feature = "seas")] {
//! use rsf_scenes::{RunConfig, SeasBp7Run};
//! let run = SeasBp7Run::from_toml("law = \"slip\"\ndx = 20")?;
//! assert_eq!(run.dx, 20.0);
//! assert_eq!(run.end_years, SeasBp7Run::default().end_years);
//! assert_eq!(SeasBp7Run::from_toml(&run.to_toml())?, run);
//! assert!(SeasBp7Run::from_toml("dx = 3").is_err()); // 800 m is not a whole number of cells
//! # }
//! # Ok::<(), rsf::Error>(())
//! ```

use rsf::checkpoint::Fingerprint;
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::invalid;

/// The range of a numeric setting and its help text, written once: `$range` (a closed
/// interval `(lo, hi)`) and `$help` (`"text, in [lo, hi]."`, what clap's `--help` shows
/// and what the programs' range test reads back).
#[macro_export]
macro_rules! setting_range {
    ($vis:vis $range:ident, $help:ident = $text:literal, [$lo:literal, $hi:literal]) => {
        #[doc = concat!("The range of the setting of [`", stringify!($help), "`].")]
        $vis const $range: (f64, f64) = ($lo as f64, $hi as f64);
        #[doc = concat!("`--help` of a setting: ", $text, ", in [", stringify!($lo), ", ", stringify!($hi), "].")]
        $vis const $help: &str = concat!($text, ", in [", stringify!($lo), ", ", stringify!($hi), "].");
    };
}

/// A run configuration: the settings of one program's run (module docs).
///
/// Implementors derive `serde::Serialize` and `serde::Deserialize` with
/// `#[serde(default, deny_unknown_fields)]` (a file sets some keys, the others keep their
/// defaults; an unknown key is refused by name).
pub trait RunConfig: Serialize + DeserializeOwned + Default + Clone + PartialEq {
    /// Checks every setting against its range and the rules between settings.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting's field (the TOML key and
    /// the Python keyword; the flag is `--` and the name with dashes).
    fn validate(&self) -> rsf::Result<()>;

    /// The fingerprint of a checkpoint of the run: every setting by value
    /// ([`Fingerprint::of_serialized`]), after the scene's parameters where the run has a
    /// scene.
    fn fingerprint(&self) -> Fingerprint {
        Fingerprint::of_serialized(self)
    }

    /// The settings as `summary.json` records them (a JSON object of the fields).
    fn summary(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    /// The settings of a TOML text (keys the fields; a missing key keeps its default),
    /// validated.
    ///
    /// # Errors
    /// [`rsf::Error::SceneFile`] for a text that does not parse, an unknown key or a
    /// value of the wrong type (line, column and key); [`validate`](Self::validate)'s.
    fn from_toml(text: &str) -> rsf::Result<Self> {
        let run = Self::parse_toml(text)?;
        run.validate()?;
        Ok(run)
    }

    /// The settings of a TOML text, not validated: serde's reading of the struct (a key
    /// left out keeps its default). A configuration whose defaults are not those of its
    /// parts (the 3-D slider's over the 2-D slider's) reads its own way.
    ///
    /// # Errors
    /// [`rsf::Error::SceneFile`] for a text that does not parse, an unknown key or a
    /// value of the wrong type (line, column and key).
    fn parse_toml(text: &str) -> rsf::Result<Self> {
        toml::from_str(text).map_err(|e| crate::scene_file::toml_error(text, &e))
    }

    /// The settings as a TOML text that [`from_toml`](Self::from_toml) reads back to the
    /// same value (every field; an unset optional one left out).
    fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

/// The settings `flags` with the keys of the TOML file `path` where `given` says the
/// setting was not given on the command line (a flag given wins over the file, the file
/// over the defaults), and the keys the file set that no flag overrode, sorted. Not
/// validated (the caller names a refused setting as its flag or the file's key).
///
/// # Errors
/// [`rsf::Error::SceneFile`] naming the path: it cannot be read, does not parse, has a key
/// that is no setting or a value of the wrong type.
pub fn merge_file<C: RunConfig>(
    path: &std::path::Path,
    flags: &C,
    given: impl Fn(&str) -> bool,
) -> rsf::Result<(C, Vec<String>)> {
    crate::scene_file::read(path, |text| {
        let toml_error = |e: toml::de::Error| crate::scene_file::toml_error(text, &e);
        // The file alone as the settings, for its errors' line, column and key (an
        // unknown key, a value of the wrong type).
        C::parse_toml(text)?;
        let mut table: toml::Table = toml::from_str(text).map_err(toml_error)?;
        let mut from_file: Vec<String> = table.keys().cloned().collect();
        let flags = toml::Table::try_from(flags)
            .map_err(|e| rsf::Error::SceneFile(format!("the flags as TOML: {e}")))?;
        for (key, value) in flags {
            if given(&key) || !table.contains_key(&key) {
                from_file.retain(|k| *k != key);
                table.insert(key, value);
            }
        }
        let run = toml::Value::Table(table)
            .try_into::<C>()
            .map_err(|e| rsf::Error::SceneFile(crate::scene_file::excerpt(e.message().trim())))?;
        from_file.sort();
        Ok((run, from_file))
    })
}

/// A setting's value written on a command line, read as its TOML value: a number, a
/// boolean, an inline table (`{ kind = "adaptive", tolerance = 1e-6 }`), and a bare word
/// as a string (`by-solver`) — the same values a TOML file gives the setting (a clap value
/// parser for the settings whose type has no `FromStr`).
///
/// # Errors
/// serde's message for a value the setting's type does not take.
pub fn toml_setting<T: DeserializeOwned>(text: &str) -> Result<T, String> {
    let value = toml::from_str::<toml::Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_owned()));
    value
        .try_into()
        .map_err(|e: toml::de::Error| format!("`{text}`: {}", e.message().trim()))
}

/// The fields of `settings` (their TOML keys) and their values as a command line writes
/// them (read back by the flags' parsers, [`toml_setting`] among them; a string without
/// quotes, a table inline): the defaults of the flags of a program whose settings start
/// from `settings`. Fields serde leaves out (an unset option, a switch that is off) are not
/// listed.
pub fn flag_defaults(settings: &impl Serialize) -> Vec<(String, String)> {
    let Ok(table) = toml::Table::try_from(settings) else {
        return Vec::new();
    };
    table
        .into_iter()
        .map(|(key, value)| {
            let value = match value {
                toml::Value::String(s) => s,
                v => v.to_string(),
            };
            (key, value)
        })
        .collect()
}

/// A step count written as an integer or in scientific notation (`1e5`): a whole number
/// in `[1, 1e12]` (a clap value parser).
///
/// # Errors
/// A message for anything else.
pub fn step_count(s: &str) -> Result<usize, String> {
    let x: f64 = s.parse().map_err(|e| format!("`{s}`: {e}"))?;
    if x >= 1.0 && x.fract() == 0.0 && x <= 1e12 {
        Ok(x as usize)
    } else {
        Err(format!("`{s}` is not a positive whole number of steps"))
    }
}

/// `--help` of a fault-ODE run's tolerance (its range the fault ODE's options check).
pub const TOLERANCE_HELP: &str =
    "Tolerance of the fault ODE, in (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1)";

/// `--help` of a fault-ODE run's kernel ([`KernelChoice`]).
pub const KERNEL_HELP: &str = "The operators condensed onto the fault: hierarchical (ℋ-matrices, rsf-hmatrix; the default) or dense (m² entries). Part of a checkpoint's fingerprint: a run checkpointed with one kernel is refused on --resume with the other";

/// `--help` of the hierarchical kernel's accuracy (`kernel_epsilon`, [`fault_kernel`]).
pub const KERNEL_EPSILON_HELP: &str = "Relative accuracy ε of the hierarchical kernel, in [1e-14, 1e-2] (default: the fault ODE's tolerance, within that range)";

/// `result` with a refusal named `name` (a setting that a library function checks under
/// its own parameter's name: the run's `tolerance` as the fault ODE options' `rtol`).
///
/// # Errors
/// `result`'s, an [`rsf::Error::InvalidParameter`] renamed `name`.
pub fn as_setting<T>(name: &str, result: rsf::Result<T>) -> rsf::Result<T> {
    result.map_err(|e| match e {
        rsf::Error::InvalidParameter { reason, .. } => invalid(name, reason),
        e => e,
    })
}

/// How a fault-ODE run stores its operators condensed onto the fault (`S`, and `S_N` with a
/// normal stress from slip): `dense` or `hierarchical` in flags, files and Python.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum KernelChoice {
    /// Dense (m² entries).
    Dense,
    /// ℋ-matrices (rsf-hmatrix): the default of the programs since issue 59 (the same
    /// events as the dense kernel at its accuracy, in a fraction of the time and memory).
    #[default]
    Hierarchical,
}

/// The fault kernel of `choice` with the hierarchical kernel's relative accuracy
/// `epsilon` (default: `tolerance`, the run's, within the kernel's range:
/// [`FaultKernel::matching`](rsf::fault_ode::FaultKernel::matching)).
///
/// # Errors
/// [`rsf::Error::InvalidParameter`] named `kernel_epsilon`: given with the dense kernel, or
/// outside `[MIN_KERNEL_EPSILON, MAX_KERNEL_EPSILON]` (the range
/// [`FaultKernel::validate`](rsf::fault_ode::FaultKernel::validate) applies).
pub fn fault_kernel(
    choice: KernelChoice,
    epsilon: Option<f64>,
    tolerance: f64,
) -> rsf::Result<rsf::fault_ode::FaultKernel> {
    use rsf::fault_ode::{FaultKernel, MAX_KERNEL_EPSILON, MIN_KERNEL_EPSILON};
    match (choice, epsilon) {
        (KernelChoice::Dense, None) => Ok(FaultKernel::Dense),
        (KernelChoice::Dense, Some(e)) => Err(invalid(
            "kernel_epsilon",
            format!(
                "{}: a setting of the hierarchical kernel: the dense kernel would ignore it",
                rsf_numeric::written(e)
            ),
        )),
        (KernelChoice::Hierarchical, None) => Ok(FaultKernel::matching(tolerance)),
        (KernelChoice::Hierarchical, Some(e)) => {
            let kernel = FaultKernel::hierarchical(e);
            kernel.validate().map_err(|_| {
                invalid(
                    "kernel_epsilon",
                    format!(
                        "{}: must be in [{}, {}] (a relative accuracy: below, the entries' \
                         round-off cannot meet it)",
                        rsf_numeric::written(e),
                        rsf_numeric::number(MIN_KERNEL_EPSILON),
                        rsf_numeric::number(MAX_KERNEL_EPSILON)
                    ),
                )
            })?;
            Ok(kernel)
        }
    }
}

/// `fingerprint` followed by `scene`'s fields, each named `scene.NAME` (a run
/// configuration's fingerprint: its settings, then its scene's parameters).
pub fn with_scene(mut fingerprint: Fingerprint, scene: &impl Serialize) -> Fingerprint {
    let scene = Fingerprint::of_serialized(scene).0;
    fingerprint
        .0
        .extend(scene.into_iter().map(|(k, v)| (format!("scene.{k}"), v)));
    fingerprint
}

/// Checks settings against their closed ranges: each `(name, value, (lo, hi), unit)`.
///
/// # Errors
/// [`rsf::Error::InvalidParameter`] named by the first setting outside its range (NaN is
/// outside every range): `VALUE: must be in [lo, hi] (unit)`, the value as written.
pub fn check_ranges(settings: &[(&str, f64, (f64, f64), &str)]) -> rsf::Result<()> {
    for &(name, value, (lo, hi), unit) in settings {
        if !(value >= lo && value <= hi) {
            let unit = if unit.is_empty() {
                String::new()
            } else {
                format!(" ({unit})")
            };
            return Err(invalid(
                name,
                format!(
                    "{}: must be in [{}, {}]{unit}",
                    rsf_numeric::written(value),
                    bound(lo),
                    bound(hi)
                ),
            ));
        }
    }
    Ok(())
}

/// A bound of a range for a message: the short form where it is the bound exactly, else
/// every digit (a value refused for lying just beyond it never reads as the bound).
pub fn bound(x: f64) -> String {
    let short = rsf_numeric::number(x);
    if short.parse::<f64>() == Ok(x) {
        short
    } else {
        rsf_numeric::written(x)
    }
}

#[cfg(test)]
mod tests {
    use super::check_ranges;

    #[test]
    fn a_range_refuses_nan_and_names_the_setting() {
        assert!(check_ranges(&[("dx", 5.0, (5.0, 400.0), "m")]).is_ok());
        for x in [f64::NAN, 4.999, 401.0, f64::INFINITY] {
            match check_ranges(&[("end", 1.0, (0.0, 2.0), ""), ("dx", x, (5.0, 400.0), "m")]) {
                Err(rsf::Error::InvalidParameter { name, reason }) => {
                    assert_eq!(name, "dx");
                    assert!(reason.ends_with("must be in [5, 400] (m)"), "{reason}");
                }
                other => panic!("{other:?}"),
            }
        }
    }
}
