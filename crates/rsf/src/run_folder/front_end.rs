//! How a front end names the settings of a run folder in its errors: the programs' flags
//! (`--overwrite`, `--resume CHECKPOINT`, `--out`) or the Python package's keyword
//! arguments (`overwrite=True`, `resume=CHECKPOINT`, `out`), so that an error tells the
//! user what to change in the call they made (issue 86).

use crate::error::Error;

/// The front end that starts a run: its errors name its own settings.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FrontEnd {
    /// A program's command line (`--overwrite`, `--resume CHECKPOINT`, `--out`).
    #[default]
    CommandLine,
    /// The Python package's keyword arguments (`overwrite=True`, `resume=CHECKPOINT`,
    /// `out`, `allow_change=`).
    Python,
}

/// The command line's names of a folder's settings and Python's, longest first (so that
/// `--resume CHECKPOINT` is spelt before `--resume`).
const PYTHON: [(&str, &str); 6] = [
    ("--resume CHECKPOINT", "`resume=CHECKPOINT`"),
    ("--allow-change", "`allow_change=`"),
    ("--overwrite", "`overwrite=True`"),
    ("--max-steps", "`steps=`"),
    ("--resume", "`resume`"),
    ("--out", "`out`"),
];

impl FrontEnd {
    /// `text` (written in the command line's terms) in this front end's terms.
    pub fn spell_text(self, text: &str) -> String {
        match self {
            Self::CommandLine => text.to_owned(),
            Self::Python => PYTHON.iter().fold(text.to_owned(), |t, (flag, keyword)| {
                t.replace(flag, keyword)
            }),
        }
    }

    /// The error `e` of a run folder (written in the command line's terms) in this front
    /// end's terms: the reasons of [`Error::Resume`], [`Error::FileExists`] and
    /// [`Error::InvalidParameter`] respelt; other errors unchanged.
    pub fn spell(self, e: Error) -> Error {
        if self == Self::CommandLine {
            return e;
        }
        match e {
            Error::Resume { path, reason } => Error::Resume {
                path,
                reason: self.spell_text(&reason),
            },
            Error::FileExists { path, reason } => Error::FileExists {
                path,
                reason: self.spell_text(&reason),
            },
            Error::InvalidParameter { name, reason } => Error::InvalidParameter {
                name,
                reason: self.spell_text(&reason),
            },
            e => e,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_names_its_keywords_and_the_command_line_its_flags() {
        let text = "pass --overwrite to replace them, --resume CHECKPOINT to continue that \
                    run, or another --out; without --resume";
        assert_eq!(FrontEnd::CommandLine.spell_text(text), text);
        assert_eq!(
            FrontEnd::Python.spell_text(text),
            "pass `overwrite=True` to replace them, `resume=CHECKPOINT` to continue that \
             run, or another `out`; without `resume`"
        );
    }
}
