//! What error messages quote of a user's value.

/// Most characters of a user's value an error message quotes.
pub const EXCERPT_CHARS: usize = 100;

/// `s` for an error message: at most [`EXCERPT_CHARS`] characters, with `…` if cut (a
/// 50 MB value must not become a 50 MB message).
///
/// ```
/// assert_eq!(rsf_numeric::excerpt("newmark"), "newmark");
/// assert_eq!(rsf_numeric::excerpt(&"x".repeat(1000)).chars().count(), 101);
/// ```
pub fn excerpt(s: &str) -> String {
    match s.char_indices().nth(EXCERPT_CHARS) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_owned(),
    }
}

/// A number for a message as a user would write it: `300`, `0.025`, `1e300` (never 301
/// digits), `NaN`; four significant digits where the shortest form is longer (a computed
/// bound `0.007217090069284064` as `7.217e-3`).
///
/// ```
/// assert_eq!(rsf_numeric::number(2000.0), "2000");
/// assert_eq!(rsf_numeric::number(1e300), "1e300");
/// assert_eq!(rsf_numeric::number(0.007217090069284064), "7.217e-3");
/// ```
pub fn number(x: f64) -> String {
    let s = if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    };
    if s.len() > 10 {
        format!("{x:.3e}")
    } else {
        s
    }
}

/// A user's value for a message exactly as parsed: the shorter of the shortest
/// round-trip texts `{x}` and `{x:e}` — what the user wrote up to notation (`1e-300`, never
/// 300 digits; `2000.0000001`, never rounded so that a refused value looks like its
/// bound), `NaN`, `inf`. [`number`] rounds to four digits: for computed quantities.
///
/// ```
/// assert_eq!(rsf_numeric::written(1e-300), "1e-300");
/// assert_eq!(rsf_numeric::written(2000.0000001), "2000.0000001");
/// assert_eq!(rsf_numeric::written(0.5), "0.5");
/// assert_eq!(rsf_numeric::written(1e300), "1e300");
/// assert_eq!(rsf_numeric::written(f64::NAN), "NaN");
/// assert_eq!("2000.0000001".parse::<f64>().unwrap(), 2000.0000001);
/// ```
pub fn written(x: f64) -> String {
    let (plain, exp) = (format!("{x}"), format!("{x:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

/// A name that is not one of a choice's names (a state law, an integrator, a solver, …),
/// as given on a command line or in a scene file. Every crate's error enum wraps this one
/// type, so the message reads the same wherever the name was parsed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownName {
    /// What was named (`"state law"`).
    pub what: &'static str,
    /// The name given (at most [`EXCERPT_CHARS`] characters of it).
    pub name: String,
    /// The accepted names, comma-separated, aliases in a parenthesis.
    pub expected: String,
}

impl std::fmt::Display for UnknownName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "unknown {} `{}` (expected {})",
            self.what, self.name, self.expected
        )
    }
}

impl std::error::Error for UnknownName {}

/// The choice named `s`: the element of `all` whose `name` is `s`, else the one an entry of
/// `aliases` gives for `s` (an older or alternative name).
///
/// # Errors
/// [`UnknownName`] for `what`, quoting an [`excerpt`] of `s` and listing the names.
///
/// ```
/// #[derive(Clone, Copy, Debug, PartialEq)]
/// enum Law { Aging, Slip }
/// let name = |l: Law| match l { Law::Aging => "aging", Law::Slip => "slip" };
/// let all = [Law::Aging, Law::Slip];
/// let parse = |s| rsf_numeric::parse_name("state law", s, &all, name, &[("ruina", Law::Slip)]);
/// assert_eq!(parse("slip"), Ok(Law::Slip));
/// assert_eq!(parse("ruina"), Ok(Law::Slip));
/// let e = parse("rate").unwrap_err();
/// assert_eq!(e.to_string(), "unknown state law `rate` (expected aging, slip (also: ruina))");
/// ```
pub fn parse_name<T: Copy>(
    what: &'static str,
    s: &str,
    all: &[T],
    name: impl Fn(T) -> &'static str,
    aliases: &[(&'static str, T)],
) -> Result<T, UnknownName> {
    if let Some(&t) = all.iter().find(|&&t| name(t) == s) {
        return Ok(t);
    }
    if let Some(&(_, t)) = aliases.iter().find(|(a, _)| *a == s) {
        return Ok(t);
    }
    let mut expected = all.iter().map(|&t| name(t)).collect::<Vec<_>>().join(", ");
    if !aliases.is_empty() {
        let names: Vec<_> = aliases.iter().map(|(a, _)| *a).collect();
        expected = format!("{expected} (also: {})", names.join(", "));
    }
    Err(UnknownName {
        what,
        name: excerpt(s),
        expected,
    })
}

/// `Display` (the name) and `FromStr` (by [`parse_name`]) for a choice `$ty` with a
/// method `name(self)` (or `name(&self)`) giving `&'static str`: `$what` names the choice
/// in messages, `$error` (which must implement `From<`[`UnknownName`]`>`) is the error of
/// `from_str`, `$all` lists every value and the optional `$aliases` pairs older or
/// alternative names with their value.
///
/// ```
/// #[derive(Clone, Copy, Debug, PartialEq)]
/// enum Law { Aging, Slip }
/// impl Law {
///     fn name(self) -> &'static str {
///         match self { Law::Aging => "aging", Law::Slip => "slip" }
///     }
/// }
/// rsf_numeric::display_and_parse_by_name!(
///     Law,
///     "state law",
///     rsf_numeric::UnknownName,
///     [Law::Aging, Law::Slip],
///     [("ruina", Law::Slip)]
/// );
/// assert_eq!("ruina".parse::<Law>(), Ok(Law::Slip));
/// assert_eq!(Law::Aging.to_string(), "aging");
/// assert!("rate".parse::<Law>().is_err());
/// ```
#[macro_export]
macro_rules! display_and_parse_by_name {
    ($ty:ty, $what:literal, $error:ty, $all:expr $(,)?) => {
        $crate::display_and_parse_by_name!($ty, $what, $error, $all, []);
    };
    ($ty:ty, $what:literal, $error:ty, $all:expr, $aliases:expr $(,)?) => {
        impl ::std::fmt::Display for $ty {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl ::std::str::FromStr for $ty {
            type Err = $error;

            /// One of the names (or an alias); another is an error listing them.
            fn from_str(s: &str) -> ::std::result::Result<Self, $error> {
                Ok($crate::parse_name(
                    $what,
                    s,
                    &$all,
                    |x: $ty| x.name(),
                    &$aliases,
                )?)
            }
        }
    };
}

/// `clap::ValueEnum` for a choice `$ty` with a constant `ALL` (every value) and a method
/// `name`: the values are the names, with the help text `$help` gives for `$value` (an
/// expression of type `&'static str`). The calling crate must depend on `clap`.
#[macro_export]
macro_rules! clap_value_enum {
    ($ty:ty, |$value:ident| $help:expr) => {
        impl clap::ValueEnum for $ty {
            fn value_variants<'a>() -> &'a [Self] {
                &Self::ALL
            }
            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                let $value = self;
                let help: &'static str = $help;
                Some(clap::builder::PossibleValue::new(self.name()).help(help))
            }
        }
    };
}
