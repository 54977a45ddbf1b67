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
