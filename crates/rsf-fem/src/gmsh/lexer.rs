//! Sections and whitespace-separated tokens of an ASCII MSH file, with line numbers.

use crate::Error;

/// Longest token echoed in an error message.
const MAX_ECHO: usize = 40;

/// A `$Name … $EndName` section: its name and its body lines.
pub(super) struct Section<'a> {
    pub(super) name: &'a str,
    /// Body lines (between the two markers).
    pub(super) lines: &'a [&'a str],
    /// 1-based line number of `lines[0]`.
    pub(super) first_line: usize,
}

/// A located error (`line` is 1-based).
pub(super) fn error(line: Option<usize>, section: &str, message: impl Into<String>) -> Error {
    Error::Gmsh {
        line,
        section: section.to_owned(),
        message: message.into(),
    }
}

/// `token` shortened for an error message.
pub(super) fn echo(token: &str) -> String {
    if token.chars().count() <= MAX_ECHO {
        token.to_owned()
    } else {
        format!("{}…", token.chars().take(MAX_ECHO).collect::<String>())
    }
}

/// Splits the file into sections. Blank lines between sections are allowed; anything else
/// outside a section, an unterminated section or a stray `$End…` marker is an error.
pub(super) fn sections<'a>(lines: &'a [&'a str]) -> Result<Vec<Section<'a>>, Error> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if l.is_empty() {
            i += 1;
            continue;
        }
        let Some(name) = l.strip_prefix('$') else {
            return Err(error(
                Some(i + 1),
                "file",
                format!("expected a section marker `$Name`, found `{}`", echo(l)),
            ));
        };
        if name.is_empty() || name.starts_with("End") || name.contains(char::is_whitespace) {
            return Err(error(
                Some(i + 1),
                "file",
                format!("unexpected section marker `{}`", echo(l)),
            ));
        }
        let end = format!("$End{name}");
        let Some(len) = lines[i + 1..].iter().position(|m| m.trim() == end) else {
            return Err(error(
                Some(i + 1),
                name,
                format!("section `${name}` is not closed by `{end}`"),
            ));
        };
        out.push(Section {
            name,
            lines: &lines[i + 1..i + 1 + len],
            first_line: i + 2,
        });
        i += len + 2;
    }
    Ok(out)
}

/// Reads the tokens of a section one by one.
pub(super) struct Cursor<'a> {
    name: &'a str,
    lines: &'a [&'a str],
    first_line: usize,
    /// Index of the current line in `lines`.
    line: usize,
    /// Unread rest of the current line.
    rest: &'a str,
    /// 1-based line number of the last token returned.
    token_line: usize,
}

impl<'a> Cursor<'a> {
    pub(super) fn new(s: &Section<'a>) -> Self {
        Self {
            name: s.name,
            lines: s.lines,
            first_line: s.first_line,
            line: 0,
            rest: s.lines.first().copied().unwrap_or(""),
            token_line: s.first_line,
        }
    }

    /// 1-based line number of the last token read.
    pub(super) fn token_line(&self) -> usize {
        self.token_line
    }

    /// An error located at the last token read.
    pub(super) fn error(&self, message: impl Into<String>) -> Error {
        error(Some(self.token_line), self.name, message)
    }

    /// Skips blank space, moving to the next non-empty line if needed. Returns false at
    /// the end of the section.
    fn skip_space(&mut self) -> bool {
        loop {
            self.rest = self.rest.trim_start();
            if !self.rest.is_empty() {
                return true;
            }
            if self.line + 1 >= self.lines.len() {
                return false;
            }
            self.line += 1;
            self.rest = self.lines[self.line];
        }
    }

    /// The next whitespace-separated token; `what` names it for the error message.
    pub(super) fn token(&mut self, what: &str) -> Result<&'a str, Error> {
        if !self.skip_space() {
            return Err(error(
                Some(self.first_line + self.lines.len()),
                self.name,
                format!("section ends before {what}"),
            ));
        }
        let end = self
            .rest
            .find(char::is_whitespace)
            .unwrap_or(self.rest.len());
        let (t, rest) = self.rest.split_at(end);
        self.rest = rest;
        self.token_line = self.first_line + self.line;
        Ok(t)
    }

    /// The rest of the current line (trimmed), e.g. a quoted name.
    pub(super) fn rest_of_line(&mut self) -> &'a str {
        std::mem::take(&mut self.rest).trim()
    }

    fn parse<T: std::str::FromStr>(&mut self, what: &str, kind: &str) -> Result<T, Error> {
        let t = self.token(what)?;
        t.parse()
            .map_err(|_| self.error(format!("expected {what} ({kind}), found `{}`", echo(t))))
    }

    /// A non-negative integer (`size_t` in the format's description).
    pub(super) fn count(&mut self, what: &str) -> Result<usize, Error> {
        self.parse(what, "a non-negative integer")
    }

    /// A positive integer tag (node and element tags).
    pub(super) fn tag(&mut self, what: &str) -> Result<u64, Error> {
        let t: u64 = self.parse(what, "a positive integer")?;
        if t == 0 {
            return Err(self.error(format!("{what} must be positive (0 is reserved)")));
        }
        Ok(t)
    }

    /// A signed integer (entity tags, dimensions, element types).
    pub(super) fn int(&mut self, what: &str) -> Result<i32, Error> {
        self.parse(what, "an integer")
    }

    /// A finite floating-point number.
    pub(super) fn float(&mut self, what: &str) -> Result<f64, Error> {
        let x: f64 = self.parse(what, "a number")?;
        if !x.is_finite() {
            return Err(self.error(format!("{what} is not finite")));
        }
        Ok(x)
    }

    /// Fails if unread tokens remain.
    pub(super) fn finish(mut self) -> Result<(), Error> {
        if self.skip_space() {
            let t = self.token("trailing data")?;
            return Err(self.error(format!(
                "unexpected `{}` after the end of the section's data",
                echo(t)
            )));
        }
        Ok(())
    }
}
