//! Scene files: read with the path, and their errors short — the file, line and column,
//! and the parser's message with long values excerpted (a 1e300 as `1e300`, not 301
//! digits; a 20 MB line as ≤ 100 characters of it); and the checks of the SEAS scenes'
//! parameters, each error naming the field and its value written short.

use std::path::Path;

use rsf::{Error, Result};

/// The longest excerpt of a value in a message (characters).
const EXCERPT: usize = 100;

/// Reads the scene file `path` and parses it with `parse`.
///
/// # Errors
/// [`Error::SceneFile`] naming the path: it cannot be read, or `parse`'s error (with line
/// and column).
pub(crate) fn read<T>(path: &Path, parse: impl FnOnce(&str) -> Result<T>) -> Result<T> {
    let cannot = |e: &dyn std::fmt::Display| {
        Error::SceneFile(format!("cannot read `{}`: {e}", path.display()))
    };
    // A regular file only (a FIFO would block forever, a device never end).
    let (mut file, len) =
        rsf::input_file::open_regular(path, "read the scene file").map_err(|e| match e {
            Error::File { source, .. } => cannot(&source),
            e => e,
        })?;
    let bytes = rsf::input_file::read_at_most(&mut file, len, path, "read the scene file")?;
    let text = String::from_utf8(bytes).map_err(|e| cannot(&e))?;
    parse(&text).map_err(|e| match e {
        Error::SceneFile(m) => Error::SceneFile(format!("`{}`, {m}", path.display())),
        e => e,
    })
}

/// The error of a TOML scene `text` that did not parse: `line L, column C: message`, the
/// message excerpted ([`excerpt`]).
pub(crate) fn toml_error(text: &str, e: &toml::de::Error) -> Error {
    let place = e.span().map(|span| {
        let start = span.start.min(text.len());
        let before = &text[..start];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        // The key of a `key = value` line the error points into.
        let line_text = text[start - before.rsplit('\n').next().map_or(0, str::len)..]
            .lines()
            .next()
            .unwrap_or("");
        let key = line_text
            .split_once('=')
            .map(|(k, _)| k.trim())
            .filter(|k| !k.is_empty() && k.len() <= 64 && !k.contains(char::is_whitespace));
        match key {
            Some(k) => format!("line {line}, column {column}, key `{k}`: "),
            None => format!("line {line}, column {column}: "),
        }
    });
    Error::SceneFile(format!(
        "{}{}",
        place.unwrap_or_default(),
        excerpt(e.message().trim())
    ))
}

/// The error of the value of `key` that did not parse: `key `k`: message`, excerpted.
pub(crate) fn key_error(key: &str, e: &toml::de::Error) -> Error {
    Error::SceneFile(format!("key `{key}`: {}", excerpt(e.message().trim())))
}

/// `message` with every long number written in exponent form and every other token
/// longer than [`EXCERPT`] characters cut to its first characters and its length.
pub(crate) fn excerpt(message: &str) -> String {
    message
        .split(' ')
        .map(|token| {
            let bare = token.trim_matches(|c| c == '`' || c == '"' || c == ',');
            if bare.len() <= 20 {
                return token.to_owned();
            }
            if let Ok(x) = bare.parse::<f64>() {
                return token.replace(bare, &format!("{x:e}"));
            }
            if token.chars().count() > EXCERPT {
                let head: String = token.chars().take(EXCERPT).collect();
                return format!("{head}… ({} characters)", token.chars().count());
            }
            token.to_owned()
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Checks that every field of a scene is positive and finite:
/// `positive_fields!(self; rho, c_s, …)` checks `self.rho`, `self.c_s`, … in that order
/// ([`positive`], each named as its field).
#[cfg(feature = "seas")]
macro_rules! positive_fields {
    ($scene:expr; $($field:ident),+ $(,)?) => {
        $crate::scene_file::positive(&[$((stringify!($field), $scene.$field)),+])
    };
}
#[cfg(feature = "seas")]
pub(crate) use positive_fields;

/// Checks that every value of `fields` (name, value) is positive and finite.
///
/// # Errors
/// [`Error::InvalidParameter`] naming the first that is not, with its value.
#[cfg(feature = "seas")]
pub(crate) fn positive(fields: &[(&str, f64)]) -> Result<()> {
    match fields.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        Some(&(name, v)) => Err(crate::invalid(
            name,
            format!("{} must be positive and finite", rsf_numeric::written(v)),
        )),
        None => Ok(()),
    }
}

/// Checks that `v`, the field `name`, is finite.
///
/// # Errors
/// [`Error::InvalidParameter`] naming it.
#[cfg(feature = "seas")]
pub(crate) fn finite(name: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(crate::invalid(name, "must be finite"))
    }
}

/// Checks that Poisson's ratio `nu` lies in `(−1, ½)`.
///
/// # Errors
/// [`Error::InvalidParameter`] named `nu`, with its value.
#[cfg(feature = "seas")]
pub(crate) fn poisson_ratio(nu: f64) -> Result<()> {
    if nu > -1.0 && nu < 0.5 {
        Ok(())
    } else {
        Err(crate::invalid(
            "nu",
            format!("{} must be in (-1, 0.5)", rsf_numeric::written(nu)),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_numbers_and_values_are_excerpted() {
        let digits = format!("`1{}.0`", "0".repeat(300));
        assert_eq!(
            excerpt(&format!(
                "invalid type: floating point {digits}, expected usize"
            )),
            "invalid type: floating point `1e300`, expected usize"
        );
        let long = format!("string \"{}\"", "x".repeat(2_000_000));
        let e = excerpt(&long);
        assert!(e.len() < 200 && e.contains("2000002 characters"), "{e}");
    }
}
