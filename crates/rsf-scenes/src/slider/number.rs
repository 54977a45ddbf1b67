//! Numbers as error messages quote them.

/// `x` as `{}` prints it if that is short, else as `{:e}` (error messages quote at most
/// about 100 characters of a value).
pub(super) fn short_number(x: f64) -> String {
    let plain = x.to_string();
    if plain.len() <= 24 {
        plain
    } else {
        format!("{x:e}")
    }
}
